//! Labelling a trial from a template (issue 47 item 2): `c3dfix label TRIAL --template
//! LABELLED`. The judging is the repair crate's ([`repair::label`], on plain arrays); this
//! module matches the two files' markers by name, writes the answer into the trial as an
//! ordinary labelled C3D and records it (docs/label.md).
//!
//! Writing: each template marker the trial does not have yet becomes the name of one of
//! its unlabelled points (the one holding most of that marker's samples, among those whose
//! other samples can go elsewhere), and every fragment labelled so is moved into that point
//! as recorded (coordinates, residual, camera mask, bit for bit; the point it left is
//! marked missing there). Fragments left unlabelled stay in unlabelled points. Nothing is
//! recomputed and every parameter but POINT:LABELS and the C3DFIX record is kept. The record
//! (`C3DFIX:LABEL`, `C3DFIX:LABELLED`) makes a later `label` change nothing.

use crate::error::{Error, Result};
use crate::markers::{mm_per_unit, split_unlabelled};
use crate::trial::to_trial;
use repair::label::{FragmentLabel, LabelOptions, Outcome, Reason};
use serde::Serialize;
use std::collections::HashMap;
use std::path::Path;

/// What `label` takes besides the two trials.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LabelSettings {
    /// Which points are unlabelled (the common placeholders, or also a pattern).
    pub unlabelled: repair::Unlabelled,
    /// Samples at exactly (0, 0, 0) count as missing.
    pub zero_invalid: bool,
    /// The labelling's constants.
    pub options: LabelOptions,
}

/// What became of the trial.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LabelStatus {
    /// Labels were judged (and those settled written).
    Labelled,
    /// The trial has no unlabelled point: nothing to do, nothing changed.
    NothingUnlabelled,
    /// The file's C3DFIX record says it was labelled already: nothing changed.
    AlreadyLabelled,
}

/// Why a fragment stays unlabelled, in the files' names and frames.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "why", rename_all = "snake_case")]
pub enum Unlabelled {
    /// Read in too few frames to judge.
    Short { frames_read: usize },
    /// No frame matched it to any marker (a reflection, a ghost, a marker the template
    /// lacks).
    NoMatch { frames_read: usize },
    /// Too few of its frames agree on a marker.
    Weak {
        marker: String,
        votes: usize,
        frames_read: usize,
    },
    /// Two markers get close votes.
    Contested {
        marker: String,
        votes: usize,
        rival: String,
        rival_votes: usize,
    },
    /// Another fragment of the same marker at the same time had more votes.
    Overlap {
        marker: String,
        with_point: String,
        with_first_frame: usize,
        with_last_frame: usize,
    },
    /// Labelled, but no point could take the marker's name without mixing another
    /// marker's samples into it: left where it was.
    NoFreePoint { marker: String },
    /// Its votes name a marker the trial labels already, but it does not sit on that
    /// marker's path at its gap's ends (reclaiming's check): left where it was.
    OffPath { marker: String },
    /// It and a neighbouring marker's fragment seen with it fit about as well with their
    /// labels exchanged: which is which is not settled.
    Exchangeable { marker: String, rival: String },
}

/// What became of one fragment.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum FragmentOutcome {
    /// An unlabelled fragment got the label.
    Labelled { label: String },
    /// The trial's label, confirmed or not contradicted.
    Kept { label: String },
    /// The trial's label changed: nearly all its frames match another marker.
    Relabelled { label: String, from: String },
    /// Left unlabelled.
    Unlabelled {
        #[serde(flatten)]
        why: Unlabelled,
    },
}

/// One fragment of the trial: a run of one point's samples.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FragmentBrief {
    /// The point it was recorded in, by its label in the input.
    pub point: String,
    /// First and last frame, in the file's numbering.
    pub first_frame: usize,
    pub last_frame: usize,
    pub samples: usize,
    #[serde(flatten)]
    pub outcome: FragmentOutcome,
    /// Frames read and frames that voted for its label.
    pub frames_read: usize,
    pub votes: usize,
    /// The point it is in after labelling (its label in the output).
    pub written_to: String,
}

/// A point that took a template marker's name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Renamed {
    pub from: String,
    pub to: String,
}

/// The outcome of [`label`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LabelReport {
    pub status: LabelStatus,
    /// The template's labelled markers, and how many of them the trial labels already.
    pub template_markers: usize,
    pub in_common: usize,
    /// The trial's labelled markers the template lacks (left as they are).
    pub not_in_template: Vec<String>,
    pub unlabelled_points: usize,
    /// Whether the labels were found from nothing (the trial labelled no template marker).
    pub seeded: bool,
    /// Samples of the unlabelled points now labelled, and left unlabelled.
    pub labelled_samples: usize,
    pub left_samples: usize,
    /// Fragments whose given label changed.
    pub relabelled: usize,
    /// Samples moved between points.
    pub moved_samples: usize,
    pub renamed: Vec<Renamed>,
    pub fragments: Vec<FragmentBrief>,
    /// The file written, when one was, and whether its bytes are the input's.
    pub output: Option<String>,
    pub unchanged: bool,
}

impl LabelReport {
    fn unchanged(status: LabelStatus) -> LabelReport {
        LabelReport {
            status,
            template_markers: 0,
            in_common: 0,
            not_in_template: Vec::new(),
            unlabelled_points: 0,
            seeded: false,
            labelled_samples: 0,
            left_samples: 0,
            relabelled: 0,
            moved_samples: 0,
            renamed: Vec::new(),
            fragments: Vec::new(),
            output: None,
            unchanged: true,
        }
    }
}

/// A label without a subject prefix and blanks, in capitals: how two files' names meet.
fn bare(label: &str) -> String {
    label
        .rsplit(':')
        .next()
        .unwrap_or(label)
        .trim()
        .to_ascii_uppercase()
}

/// The file's labelled markers by bare name; two points of one name are an error.
fn by_name(c: &c3d::C3d, points: &[usize], path: &Path) -> Result<HashMap<String, usize>> {
    let labels = c.point_labels();
    let mut out: HashMap<String, usize> = HashMap::new();
    for &p in points {
        if let Some(q) = out.insert(bare(&labels[p]), p) {
            return Err(Error::Trial {
                path: path.to_path_buf(),
                what: format!(
                    "two points are labelled {:?} (points {} and {}): labels must name one marker each",
                    labels[p].trim(),
                    q + 1,
                    p + 1
                ),
            });
        }
    }
    Ok(out)
}

/// Label the unlabelled points of `c` from `template` and write the settled labels into
/// `c` (see the module's documentation). `path` and `template_path` name the files in
/// errors and in the record. A trial with no unlabelled point, or labelled before (its
/// C3DFIX record), is left as it is.
pub fn label(
    c: &mut c3d::C3d,
    path: &Path,
    template: &c3d::C3d,
    template_path: &Path,
    settings: &LabelSettings,
) -> Result<LabelReport> {
    if c.param(crate::rerun::GROUP, "LABEL").is_some() {
        return Ok(LabelReport::unchanged(LabelStatus::AlreadyLabelled));
    }
    let Matched {
        tsplit,
        split,
        common,
        not_in_template,
    } = match_markers(c, path, template, template_path, settings)?;
    let labels = c.point_labels();
    let tlabels = template.point_labels();
    let mut report = LabelReport::unchanged(LabelStatus::NothingUnlabelled);
    report.template_markers = tsplit.labelled.len();
    report.in_common = common.len();
    report.not_in_template = not_in_template;
    report.unlabelled_points = split.unlabelled.len();
    if split.unlabelled.is_empty() {
        return Ok(report);
    }
    report.status = LabelStatus::Labelled;
    let rows: Vec<usize> = common
        .iter()
        .map(|&(p, _)| p)
        .chain(split.unlabelled.iter().copied())
        .collect();
    let given: Vec<Option<usize>> = common
        .iter()
        .map(|&(_, t)| Some(t))
        .chain(split.unlabelled.iter().map(|_| None))
        .collect();
    let trial = to_trial(c, &rows, settings.zero_invalid)?;
    let tt = to_trial(template, &tsplit.labelled, settings.zero_invalid)?;
    let found = forkpool::install(|| {
        repair::label::label(
            &tt,
            mm_per_unit(&template.point_units()),
            &trial,
            mm_per_unit(&c.point_units()),
            &given,
            &settings.options,
        )
    })
    .map_err(|e| Error::Trial {
        path: path.to_path_buf(),
        what: format!("cannot label from {}: {e}", template_path.display()),
    })?;
    let mut found = found;
    crate::label_gaps::keep_on_path(
        &mut found.fragments,
        &trial,
        &common,
        mm_per_unit(&c.point_units()),
    );
    report.seeded = found.seeded;
    let tname = |m: usize| -> String { bare_keep_case(&tlabels[tsplit.labelled[m]]) };
    let plan = crate::label_write::plan(
        &found.fragments,
        &rows,
        &common,
        &split.unlabelled,
        template.point_count(),
    );
    let prefix = subject_prefix(&labels, &split.labelled);
    crate::label_write::apply(
        c,
        path,
        &plan,
        &found.fragments,
        &rows,
        &|m| format!("{prefix}{}", tname(m)),
        template_path,
    )?;
    let written = Written {
        fragments: &found.fragments,
        plan: &plan,
        rows: &rows,
        trial: &trial,
        labels: &labels,
    };
    fragment_briefs(c, &written, &tname, &mut report);
    report.moved_samples = plan.moved_samples(&found.fragments, &rows, &trial);
    report.renamed = plan
        .renamed
        .iter()
        .map(|&(p, m)| Renamed {
            from: labels[p].trim().to_string(),
            to: format!("{prefix}{}", tname(m)),
        })
        .collect();
    Ok(report)
}

/// The trial's markers matched by name with the template's.
struct Matched {
    /// The template's labelled and unlabelled points.
    tsplit: crate::markers::Split,
    /// The trial's.
    split: crate::markers::Split,
    /// (trial point, template marker row) of every marker both have.
    common: Vec<(usize, usize)>,
    /// The trial's labelled markers the template lacks.
    not_in_template: Vec<String>,
}

/// Match the trial's labelled markers with the template's by name, refusing a template
/// without labelled markers, duplicate names and marker sets that do not go together.
fn match_markers(
    c: &c3d::C3d,
    path: &Path,
    template: &c3d::C3d,
    template_path: &Path,
    settings: &LabelSettings,
) -> Result<Matched> {
    let tsplit = split_unlabelled(template, &settings.unlabelled);
    if tsplit.labelled.is_empty() {
        return Err(Error::Trial {
            path: template_path.to_path_buf(),
            what: "the template has no labelled marker".into(),
        });
    }
    let tnames = by_name(template, &tsplit.labelled, template_path)?;
    let split = split_unlabelled(c, &settings.unlabelled);
    // Checked for its refusal of duplicate names; the trial's markers are matched below.
    by_name(c, &split.labelled, path)?;
    let labels = c.point_labels();
    let tindex: HashMap<usize, usize> = tsplit
        .labelled
        .iter()
        .enumerate()
        .map(|(i, &p)| (p, i))
        .collect();
    let mut common: Vec<(usize, usize)> = Vec::new();
    let mut not_in_template = Vec::new();
    for &p in &split.labelled {
        match tnames.get(&bare(&labels[p])) {
            Some(tp) => common.push((p, tindex[tp])),
            None => not_in_template.push(labels[p].trim().to_string()),
        }
    }
    check_marker_sets(
        &split.labelled,
        &common,
        &not_in_template,
        template,
        &tsplit.labelled,
        path,
        template_path,
    )?;
    Ok(Matched {
        tsplit,
        split,
        common,
        not_in_template,
    })
}

/// What the labelling decided and wrote, for the report's fragment lines.
struct Written<'a> {
    fragments: &'a [FragmentLabel],
    plan: &'a crate::label_write::Plan,
    rows: &'a [usize],
    trial: &'a repair::Trial,
    /// The trial's labels before the labelling.
    labels: &'a [String],
}

/// One line per fragment in `report` (where it was, what became of it, where it was
/// written) and the counts of samples labelled, relabelled and left.
fn fragment_briefs(
    c: &c3d::C3d,
    w: &Written<'_>,
    tname: &dyn Fn(usize) -> String,
    report: &mut LabelReport,
) {
    let labels_after = c.point_labels();
    for (i, a) in w.fragments.iter().enumerate() {
        let g = &a.fragment;
        let point = w.rows[g.row];
        let samples = w.trial.valid[g.row][g.first..=g.last]
            .iter()
            .filter(|&&v| v)
            .count();
        let outcome = outcome(a, w.plan, i, tname, w.labels, w.rows, c);
        let unlabelled_point = a.given.is_none();
        match &outcome {
            FragmentOutcome::Labelled { .. } | FragmentOutcome::Relabelled { .. } => {
                report.labelled_samples += usize::from(unlabelled_point) * samples;
                report.relabelled += usize::from(!unlabelled_point);
            }
            FragmentOutcome::Unlabelled { .. } => report.left_samples += samples,
            FragmentOutcome::Kept { .. } => {}
        }
        report.fragments.push(FragmentBrief {
            point: w.labels[point].trim().to_string(),
            first_frame: c.frame_number(g.first),
            last_frame: c.frame_number(g.last),
            samples,
            outcome,
            frames_read: a.checked,
            votes: a.votes,
            written_to: labels_after[w.plan.final_point[i]].trim().to_string(),
        });
    }
}

/// A template label as written, without blanks or subject prefix.
fn bare_keep_case(label: &str) -> String {
    label.rsplit(':').next().unwrap_or(label).trim().to_string()
}

/// The subject prefix (`Name:`) of the trial's labelled markers, if they have one.
fn subject_prefix(labels: &[String], labelled: &[usize]) -> String {
    labelled
        .first()
        .and_then(|&p| {
            labels[p]
                .trim()
                .rsplit_once(':')
                .map(|(a, _)| format!("{a}:"))
        })
        .unwrap_or_default()
}

/// Refuse a template of another marker set: the trial's labelled markers must be mostly
/// the template's.
#[allow(clippy::too_many_arguments)]
fn check_marker_sets(
    labelled: &[usize],
    common: &[(usize, usize)],
    missing: &[String],
    template: &c3d::C3d,
    tlabelled: &[usize],
    path: &Path,
    template_path: &Path,
) -> Result<()> {
    if labelled.is_empty() {
        return Ok(());
    }
    let tl = template.point_labels();
    let theirs = || {
        let mut v: Vec<String> = tlabelled
            .iter()
            .map(|&p| tl[p].trim().to_string())
            .collect();
        if v.len() > 12 {
            v.truncate(12);
            v.push("…".into());
        }
        v.join(", ")
    };
    let ours = || {
        let mut v = missing.to_vec();
        if v.len() > 12 {
            v.truncate(12);
            v.push("…".into());
        }
        v.join(", ")
    };
    if common.is_empty() {
        return Err(Error::Trial {
            path: path.to_path_buf(),
            what: format!(
                "no marker in common with the template {}: the trial labels {}; the template {}",
                template_path.display(),
                ours(),
                theirs()
            ),
        });
    }
    if missing.len() * 2 > labelled.len() {
        return Err(Error::Trial {
            path: path.to_path_buf(),
            what: format!(
                "the template {} is of another marker set: {} of the trial's {} labelled markers are not in it ({}); the template has {}",
                template_path.display(),
                missing.len(),
                labelled.len(),
                ours(),
                theirs()
            ),
        });
    }
    Ok(())
}

/// A fragment's answer in names.
fn outcome(
    a: &FragmentLabel,
    plan: &crate::label_write::Plan,
    i: usize,
    tname: &dyn Fn(usize) -> String,
    labels: &[String],
    rows: &[usize],
    c: &c3d::C3d,
) -> FragmentOutcome {
    if let (Some(m), false) = (a.label, plan.written[i]) {
        return FragmentOutcome::Unlabelled {
            why: Unlabelled::NoFreePoint { marker: tname(m) },
        };
    }
    match a.outcome {
        Outcome::Labelled => FragmentOutcome::Labelled {
            label: a.label.map(tname).unwrap_or_default(),
        },
        Outcome::Kept => FragmentOutcome::Kept {
            label: a.label.map(tname).unwrap_or_default(),
        },
        Outcome::Relabelled { from } => FragmentOutcome::Relabelled {
            label: a.label.map(tname).unwrap_or_default(),
            from: tname(from),
        },
        Outcome::Unlabelled { reason } => FragmentOutcome::Unlabelled {
            why: match reason {
                Reason::Short { checked } => Unlabelled::Short {
                    frames_read: checked,
                },
                Reason::NoMatch { checked } => Unlabelled::NoMatch {
                    frames_read: checked,
                },
                Reason::Weak {
                    marker,
                    votes,
                    checked,
                } => Unlabelled::Weak {
                    marker: tname(marker),
                    votes,
                    frames_read: checked,
                },
                Reason::Contested {
                    marker,
                    votes,
                    rival,
                    rival_votes,
                } => Unlabelled::Contested {
                    marker: tname(marker),
                    votes,
                    rival: tname(rival),
                    rival_votes,
                },
                Reason::OffPath { marker } => Unlabelled::OffPath {
                    marker: tname(marker),
                },
                Reason::Exchangeable { marker, rival } => Unlabelled::Exchangeable {
                    marker: tname(marker),
                    rival: tname(rival),
                },
                Reason::Overlap { marker, with } => Unlabelled::Overlap {
                    marker: tname(marker),
                    with_point: labels[rows[with.row]].trim().to_string(),
                    with_first_frame: c.frame_number(with.first),
                    with_last_frame: c.frame_number(with.last),
                },
            },
        },
    }
}

/// `c3dfix label TRIAL --template LABELLED -o OUT` (or in place) from paths, with the checks
/// and the atomic write of `repair`: the command and Python's `label_file` call this. A run
/// that changes nothing in place leaves the file alone (`unchanged`).
pub fn label_file(
    input: &Path,
    template: &Path,
    dest: &crate::files::Destination,
    settings: &LabelSettings,
) -> Result<LabelReport> {
    let out = dest.path(input)?;
    if !dest.in_place {
        crate::save::refuse_own_input(input, &out)?;
    }
    let overwrite = dest.force || dest.in_place;
    crate::save::check_destination(&out, overwrite)?;
    let backup = if dest.backup {
        crate::save::new_backup(input)
    } else {
        None
    };
    let mut c = crate::trial::open_mapped(input)?;
    let t = crate::trial::open(template)?;
    let mut report = label(&mut c, input, &t, template, settings)?;
    let bytes = c.encoded().map_err(|source| Error::C3d {
        path: input.to_path_buf(),
        source,
    })?;
    report.output = Some(out.display().to_string());
    report.unchanged = c.source_bytes() == Some(&bytes[..]);
    if report.unchanged && crate::save::same_file(input, &out) {
        return Ok(report);
    }
    let outs = crate::save::replacing(&out, &bytes, overwrite, backup.as_deref());
    crate::save::write_all(&outs)?;
    Ok(report)
}
