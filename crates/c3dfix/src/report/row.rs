//! One trial's row: the trial as given, its repaired copy, and what the repair did, each
//! from the library's own report of it.

use super::pictures::{self, Fill, Pictures};
use crate::gaps::gaps;
use crate::markers::split_unlabelled;
use crate::rerun::Record;
use crate::tally::Tally;
use crate::{Direction, EventOptions, ForceOptions, ForcePlatforms, GaitOptions, RepairBrief};
use repair::SkipKind;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One trial to report on, with what is known of its repair.
#[derive(Debug, Clone, Default)]
pub struct TrialInput {
    /// The trial as recorded (as named).
    pub input: PathBuf,
    /// Its repaired copy, if any.
    pub repaired: Option<PathBuf>,
    /// The repair's own summary, when the report is made by the run that repaired it: `Err`
    /// holds why the repair failed.
    pub summary: Option<std::result::Result<RepairBrief, String>>,
}

/// One trial: what it holds, what its repair did, and the first thing worth a look.
#[derive(Debug, Clone, Serialize, PartialEq, Default)]
pub struct TrialRow {
    /// The trial as named.
    pub file: String,
    /// Its file name.
    pub name: String,
    /// Why the trial could not be read (the other fields are then empty).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The repaired copy, when one was given or written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repaired: Option<String>,
    /// Why the repaired copy could not be read, or the repair failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repaired_error: Option<String>,
    pub frames: usize,
    /// The file's first frame number; every frame in the row is in the file's numbering.
    pub first_frame: usize,
    pub rate: f32,
    pub duration_s: f64,
    /// Labelled markers (model outputs and unlabelled points left out): what every number
    /// of the row speaks of, as the repair does.
    pub markers: usize,
    /// Unlabelled points (`*51`, `Unlabeled 3`, an empty label: [`repair::Unlabelled`]'s
    /// common spellings), counted apart: candidates for reclaiming, not markers with gaps.
    pub unlabelled: usize,
    /// Marker samples (markers × frames).
    pub samples: usize,
    /// Marker samples missing in the trial as given.
    pub missing_before: usize,
    /// Marker samples missing in the repaired copy.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub missing_after: Option<usize>,
    /// Gaps of the markers in the trial as given.
    pub gaps_before: usize,
    /// Where the repair's numbers come from: `summary` (the repair's own, made by this run)
    /// or `record` (the repaired file's C3DFIX group); none without a repair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repair_source: Option<&'static str>,
    /// Gaps the repair filled and left, and the left ones per reason (`too_long`,
    /// `uncertain`, `touches_edge`, `no_donors`, …).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub filled: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub left: Option<usize>,
    pub left_because: Tally<SkipKind>,
    /// Of the gaps left, those at the trial's first or last frame.
    pub left_at_trial_end: usize,
    /// Largest expected error of a fill, mm (the repair's summary; a file records none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm_max: Option<f64>,
    /// Label swaps and jumps found (the repair's summary only: a file records those undone).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub swaps_found: Option<usize>,
    pub swaps_undone: usize,
    pub jumps_to_gaps: usize,
    /// Spikes removed (the repair's summary only: a file records the setting, not the count).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spikes: Option<usize>,
    /// Events by source: `file` (the EVENT group), `plate` and `kinematics` (detected).
    pub events: BTreeMap<String, usize>,
    /// Why events could not be detected, or gait parameters not computed (a trial that is
    /// no walk says so here, not among the warnings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub events_note: Option<String>,
    /// Gait-cycle parameters from the file's own Foot Strike / Foot Off events, if any.
    pub gait: Vec<GaitValue>,
    pub plates: Vec<PlateRow>,
    /// Plates named in FORCE_PLATFORM and not computed, with why.
    pub plates_refused: Vec<String>,
    /// What the reader, the plates and the event detector noticed.
    pub warnings: Vec<String>,
    /// The lab's up ([`crate::axes::up`]).
    pub up: Option<Direction>,
    /// The first problem worth a look, in words; none for a clean trial.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub problem: Option<String>,
    /// The trial's view page, a file name (written beside the report by the page writer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub view: Option<String>,
    pub pictures: Pictures,
}

/// One plate of a trial, as [`crate::info::PlateInfo`] gives it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PlateRow {
    /// 1-based, as FORCE_PLATFORM numbers it.
    pub index: usize,
    #[serde(rename = "type")]
    pub kind: i32,
    pub contacts: usize,
    /// Largest push over the trial (N), its unloaded level removed.
    pub peak_force: f64,
}

/// One gait-cycle parameter ([`gait::params::Parameter`]).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct GaitValue {
    pub context: String,
    pub name: String,
    pub value: f64,
    pub unit: String,
}

/// Expected errors above this (mm) are worth a look: a quarter of the default
/// `max_expected_error` (20 mm), so a fill kept yet far from sure is shown, not hidden among
/// the clean trials. A choice of presentation, not fitted on any lab.
pub const LOOK_AT_ERROR_MM: f64 = 5.0;

/// The row of one trial; never fails: what cannot be read is said in the row.
pub(super) fn row(t: &TrialInput) -> TrialRow {
    let name = t
        .input
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| t.input.display().to_string());
    let mut r = TrialRow {
        file: t.input.display().to_string(),
        name,
        repaired: t.repaired.as_ref().map(|p| p.display().to_string()),
        ..TrialRow::default()
    };
    let c = match crate::open_mapped(&t.input) {
        Ok(c) => c,
        Err(e) => {
            r.error = Some(e.to_string());
            r.problem = Some(format!("cannot be read: {e}"));
            return r;
        }
    };
    trial_numbers(&c, &mut r);
    let before = labelled_gaps(&c);
    r.gaps_before = before.len();
    r.missing_before = before.iter().map(|g| g.length).sum();
    let copy = t
        .repaired
        .as_deref()
        .and_then(|p| match crate::open_mapped(p) {
            Ok(rc) => Some(rc),
            Err(e) => {
                r.repaired_error = Some(e.to_string());
                None
            }
        });
    let after = copy.as_ref().map(labelled_gaps);
    r.missing_after = after.as_ref().map(|a| a.iter().map(|g| g.length).sum());
    let mut fills = Vec::new();
    match &t.summary {
        Some(Ok(b)) if b.summary.skipped.is_none() => from_summary(b, &mut r, &mut fills),
        Some(Ok(_)) => {}
        Some(Err(e)) => r.repaired_error = Some(e.clone()),
        None => from_record(copy.as_ref().unwrap_or(&c), &mut r),
    }
    // Events, plates and gait of the repaired copy when there is one: what the lab goes on
    // with.
    let shown = copy.as_ref().unwrap_or(&c);
    let shown_path = match &copy {
        Some(_) => t.repaired.as_deref().unwrap_or(&t.input),
        None => &t.input,
    };
    let fp = plates(&c, &mut r);
    let marks = events(shown, shown_path, &mut r);
    r.pictures = pictures::Pictures {
        coverage: pictures::coverage(&c, &before, after.as_deref(), &fills),
        forces: fp
            .as_ref()
            .map(|fp| pictures::forces(fp, r.up))
            .unwrap_or_default(),
        events: marks,
        fills: copy
            .as_ref()
            .map(|rc| {
                pictures::worst_fills(&c, rc, &before, after.as_deref().unwrap_or(&[]), &fills)
            })
            .unwrap_or_default(),
    };
    r.problem = first_problem(&r);
    r
}

/// The gaps of `c`'s labelled markers: an unlabelled point's absences are no marker's
/// missing samples (most `*NN` points are seen a fraction of the trial by nature).
fn labelled_gaps(c: &c3d::C3d) -> Vec<crate::GapInfo> {
    let rule = repair::Unlabelled::common();
    let mut g = gaps(c, false);
    g.retain(|x| !rule.is_unlabelled(&x.label));
    g
}

/// What the trial is: frames, rate, markers, up, the reader's warnings.
fn trial_numbers(c: &c3d::C3d, r: &mut TrialRow) {
    r.frames = c.frames();
    r.first_frame = c.first_frame();
    r.rate = c.point_rate();
    r.duration_s = if r.rate > 0.0 {
        r.frames as f64 / r.rate as f64
    } else {
        0.0
    };
    let split = split_unlabelled(c, &repair::Unlabelled::common());
    r.markers = split.labelled.len();
    r.unlabelled = split.unlabelled.len();
    r.samples = r.markers * r.frames;
    r.up = crate::axes::up(c).map(|u| u.up);
    r.warnings = c.warnings().iter().map(|w| w.to_string()).collect();
}

/// The repair's numbers from its own summary; `fills` gets every filled gap with its
/// expected error.
fn from_summary(b: &RepairBrief, r: &mut TrialRow, fills: &mut Vec<Fill>) {
    let s = &b.summary;
    r.repair_source = Some("summary");
    r.filled = Some(s.filled);
    r.left = Some(s.left);
    r.left_because = s.left_because.clone();
    r.left_at_trial_end = b
        .gap_list
        .iter()
        .filter(|g| g.reason.is_some() && g.at_trial_end)
        .count();
    r.expected_error_mm_max = s.expected_error_mm_max;
    r.swaps_found = Some(b.swap_list.len());
    r.swaps_undone = s.swaps_undone;
    r.jumps_to_gaps = s.jumps_to_gaps;
    r.spikes = Some(s.spikes);
    fills.extend(
        b.gap_list
            .iter()
            .filter(|g| g.method.is_some())
            .map(|g| Fill {
                label: g.label.clone(),
                first_frame: g.first_frame,
                last_frame: g.last_frame,
                expected_error_mm: g.expected_error_mm,
            }),
    );
}

/// The repair's numbers from what the file records (`C3DFIX`), if it records a repair.
fn from_record(c: &c3d::C3d, r: &mut TrialRow) {
    let rec = Record::read(c);
    if rec.fill.is_none() && rec.filled.is_empty() && rec.left.is_empty() {
        return;
    }
    r.repair_source = Some("record");
    r.filled = Some(rec.filled.len());
    r.left = Some(rec.left.len());
    let last = c.frames().saturating_sub(1);
    for l in &rec.left {
        r.left_because.add(l.reason.kind(), 1);
        if l.first_index == 0 || l.last_index == last {
            r.left_at_trial_end += 1;
        }
    }
    r.swaps_undone = rec.undone.iter().filter(|u| u.points.len() == 2).count();
    r.jumps_to_gaps = rec.undone.iter().filter(|u| u.points.len() == 1).count();
}

/// The plates of the trial as given (a repair never touches analog data): contacts, peak
/// push, the plates refused and why. `None` when FORCE_PLATFORM names none.
fn plates(c: &c3d::C3d, r: &mut TrialRow) -> Option<ForcePlatforms> {
    let params = c.platform_params();
    if params.plates.is_empty() {
        for p in params.problems {
            r.plates_refused.push(
                crate::PlateWarning {
                    plate: p.plate,
                    parameter: p.parameter,
                    message: p.message,
                }
                .to_string(),
            );
        }
        return None;
    }
    match crate::force_platforms(c, &ForceOptions::default()) {
        Ok(fp) => {
            r.plates = fp
                .platforms
                .iter()
                .map(|p| PlateRow {
                    index: p.index,
                    kind: p.kind,
                    contacts: p.contacts.len(),
                    peak_force: p.peak_force,
                })
                .collect();
            let computed: Vec<usize> = fp.platforms.iter().map(|p| p.index).collect();
            for w in &fp.warnings {
                if w.plate != 0 && !computed.contains(&w.plate) {
                    r.plates_refused.push(w.to_string());
                } else {
                    r.warnings.push(w.to_string());
                }
            }
            Some(fp)
        }
        Err(e) => {
            r.plates_refused.push(e.to_string());
            None
        }
    }
}

/// The file's events and the detector's (counted by source), and the gait parameters of the
/// file's own events; the marks the force picture draws.
fn events(c: &c3d::C3d, path: &Path, r: &mut TrialRow) -> Vec<pictures::Mark> {
    let mut marks = Vec::new();
    let own = c.events();
    if !own.is_empty() {
        r.events.insert("file".into(), own.len());
    }
    for e in &own {
        if e.time.is_finite() {
            marks.push(pictures::Mark::new(&e.context, &e.label, e.time, false));
        }
    }
    match crate::detect_events(c, &EventOptions::default(), path) {
        Ok(d) => {
            for e in &d.events {
                *r.events.entry(e.source.name().to_string()).or_default() += 1;
                marks.push(pictures::Mark::new(
                    e.side.context(),
                    e.kind.label(),
                    e.time,
                    true,
                ));
            }
        }
        Err(e) => r.events_note = Some(strip_path(&e.to_string(), path)),
    }
    if !crate::event_labels::file_gait_events(c).is_empty() {
        match crate::gait_parameters(c, &GaitOptions::default(), path) {
            Ok(g) => {
                r.gait = g
                    .parameters
                    .iter()
                    .map(|p| GaitValue {
                        context: p.context.to_string(),
                        name: p.name.to_string(),
                        value: p.value,
                        unit: p.unit.to_string(),
                    })
                    .collect()
            }
            Err(e) => {
                let e = strip_path(&e.to_string(), path);
                r.events_note = Some(match r.events_note.take() {
                    Some(n) => format!("{n}; gait parameters: {e}"),
                    None => format!("gait parameters: {e}"),
                });
            }
        }
    }
    marks
}

/// A library message without the file's name in front (the row names the file).
fn strip_path(msg: &str, path: &Path) -> String {
    let p = format!("{}: ", path.display());
    msg.strip_prefix(&p).unwrap_or(msg).to_string()
}

/// The first thing a person should look at, in words; `None` for a clean trial.
fn first_problem(r: &TrialRow) -> Option<String> {
    if let Some(e) = &r.repaired_error {
        return Some(format!("repaired copy: {e}"));
    }
    let reasons = |m: &Tally<SkipKind>| {
        m.iter()
            .map(|(k, n)| format!("{n} {}", k.name().replace('_', " ")))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let left = r.left.unwrap_or(0);
    if left > r.left_at_trial_end {
        return Some(format!(
            "{} left inside the trial, of {} ({})",
            gaps_word(left - r.left_at_trial_end),
            gaps_word(left),
            reasons(&r.left_because)
        ));
    }
    let found = r.swaps_found.unwrap_or(0);
    if found > r.swaps_undone + r.jumps_to_gaps {
        return Some(format!(
            "{} label swaps or jumps found and not undone",
            found - r.swaps_undone - r.jumps_to_gaps
        ));
    }
    if let Some(e) = r.expected_error_mm_max.filter(|&e| e > LOOK_AT_ERROR_MM) {
        return Some(format!("a fill may be off by {e:.1} mm"));
    }
    if left > 0 {
        return Some(format!(
            "{} left at the trial's ends ({})",
            gaps_word(left),
            reasons(&r.left_because)
        ));
    }
    if let Some(p) = r.plates_refused.first() {
        return Some(format!("plate refused: {p}"));
    }
    if r.repair_source.is_none() && r.missing_before > 0 {
        return Some(format!(
            "{} samples missing in {}, not repaired",
            r.missing_before,
            gaps_word(r.gaps_before)
        ));
    }
    if r.missing_after.is_some_and(|m| m > 0) {
        return Some(format!(
            "{} samples still missing",
            r.missing_after.unwrap_or(0)
        ));
    }
    r.warnings.first().map(|w| format!("warning: {w}"))
}

/// "1 gap", "2 gaps".
fn gaps_word(n: usize) -> String {
    format!("{n} gap{}", if n == 1 { "" } else { "s" })
}
