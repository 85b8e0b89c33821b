//! Labelling a trial from a template (issue 47 item 2): which template marker each of a
//! trial's trajectory fragments is, from one labelled trial of the same marker set.
//!
//! The template says which markers keep which distances (its segments, found from its own
//! frames: no marker set is written into the code) and which quadruples keep their
//! handedness (what tells left from right: a mirror labelling keeps every distance). The
//! trial's trajectories are cut into fragments ([`Fragment`]: runs of recorded samples,
//! cut again where a trajectory leaps further in a frame than a marker moves). Then:
//!
//! 1. **Seed.** Where nothing is labelled yet, a few frames with the most points are
//!    matched to the template from nothing (a beam search over the markers, each placed on
//!    the point that keeps its distances to those placed before it); their fragments take
//!    those labels.
//! 2. **Votes.** In every frame read, each recorded fragment is matched to the marker whose
//!    distances it keeps best to the fragments labelled so far (one marker per fragment and
//!    one fragment per marker in a frame, lowest costs first); each match is a vote, and a
//!    fragment takes the label most of its frames vote for. Passes repeat until no label
//!    changes, so labels spread from fragment to overlapping fragment over the whole trial.
//! 3. **One fragment per label at a time.** Fragments of one label that overlap in time
//!    keep the one with the most votes; the others stay unlabelled.
//! 4. **Exchanges.** Two fragments newly labelled as neighbouring markers and seen together
//!    keep their labels only if the labels fit clearly better than the two exchanged
//!    ([`Reason::Exchangeable`]): votes judged against neighbours as labelled can settle
//!    two markers the template places alike exchanged over a whole stretch.
//!
//! A template of another subject can be fitted to the trial's size first
//! ([`LabelOptions::fit_scale`], not the default: measured in docs/label.md).
//!
//! A fragment the votes do not settle (too few frames, too few votes, a rival label close)
//! stays unlabelled with its reason ([`Reason`]): extra points (reflections, ghosts) keep
//! no marker's distances and stay so. A fragment the trial already labels keeps its label
//! unless nearly all its frames vote for one other marker and almost none for its own
//! ([`Outcome::Relabelled`]). Deterministic: the same input gives the same answer.

mod cost;
mod exchange;
mod fragments;
mod model;
mod options;
mod scale;
mod seed;
mod vote;

pub use fragments::Fragment;
pub use options::LabelOptions;

use crate::Trial;
use serde::Serialize;

/// What became of a fragment.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Outcome {
    /// An unlabelled fragment got a label.
    Labelled,
    /// The trial's label was kept.
    Kept,
    /// The trial's label was changed: nearly all its frames match another marker.
    Relabelled { from: usize },
    /// Left unlabelled.
    Unlabelled {
        #[serde(flatten)]
        reason: Reason,
    },
}

/// Why a fragment stays unlabelled.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Reason {
    /// Read in too few frames to judge.
    Short { checked: usize },
    /// No frame matched it to any marker (a reflection, a ghost, or a marker the template
    /// lacks).
    NoMatch { checked: usize },
    /// Too few of its frames agree on a marker.
    Weak {
        marker: usize,
        votes: usize,
        checked: usize,
    },
    /// Two markers get close votes.
    Contested {
        marker: usize,
        votes: usize,
        rival: usize,
        rival_votes: usize,
    },
    /// Another fragment of the same marker at the same time had more votes.
    Overlap { marker: usize, with: Fragment },
    /// Its label and a neighbouring marker's fragment's label fit about as well
    /// exchanged as given.
    Exchangeable { marker: usize, rival: usize },
    /// Its votes name a marker the trial labels already, but the fragment does not sit on
    /// that marker's path at its gap's ends (reclaiming's check,
    /// [`crate::reclaim::judge`]): set by a caller that checks it, left where it was.
    OffPath { marker: usize },
}

/// One fragment's answer. `label` and `given` are template marker indices.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FragmentLabel {
    #[serde(flatten)]
    pub fragment: Fragment,
    pub label: Option<usize>,
    /// The label the trial gave it, if any.
    pub given: Option<usize>,
    #[serde(flatten)]
    pub outcome: Outcome,
    /// Frames read and frames that voted for its label.
    pub checked: usize,
    pub votes: usize,
}

/// Every fragment of the trial, by row and frame, with its answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Labelling {
    pub fragments: Vec<FragmentLabel>,
    /// Whether the labels were seeded from nothing (the trial labelled nothing the
    /// template knows).
    pub seeded: bool,
    /// Vote passes run.
    pub passes: usize,
    /// The factor the template's distances were multiplied by to fit the trial's body (1:
    /// as recorded).
    pub scale: f64,
}

/// Input the labelling cannot work on.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LabelError {
    #[error("the template records none of its {0} markers")]
    EmptyTemplate(usize),
    #[error("{what}: {got} entries, expected {expected}")]
    Shape {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("trial row {row} is given label {label}, beyond the template's {markers} markers")]
    Given {
        row: usize,
        label: usize,
        markers: usize,
    },
    #[error("sample rate {0} Hz must be finite and above 0")]
    Rate(f64),
    #[error("{what} of {value} must be finite and above 0")]
    Scale { what: &'static str, value: f64 },
}

/// Label the fragments of `trial` from `template`. `given[row]` is the template marker a
/// trial row is already labelled as (`None`: unlabelled). Each trial's `mm_per_unit`
/// converts its coordinates to millimetres. Samples with a coordinate that is not finite
/// count as missing.
pub fn label(
    template: &Trial,
    template_mm_per_unit: f64,
    trial: &Trial,
    trial_mm_per_unit: f64,
    given: &[Option<usize>],
    opts: &LabelOptions,
) -> Result<Labelling, LabelError> {
    for (what, value) in [
        ("the template's millimetres per unit", template_mm_per_unit),
        ("the trial's millimetres per unit", trial_mm_per_unit),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(LabelError::Scale { what, value });
        }
    }
    for (what, t) in [("template", template), ("trial", trial)] {
        t.check().map_err(|_| LabelError::Shape {
            what: if what == "template" {
                "the template's masks"
            } else {
                "the trial's masks"
            },
            got: t.valid.len(),
            expected: t.xyz.len(),
        })?;
    }
    if given.len() != trial.markers() {
        return Err(LabelError::Shape {
            what: "given labels",
            got: given.len(),
            expected: trial.markers(),
        });
    }
    let k = template.markers();
    if let Some((row, &Some(label))) = given
        .iter()
        .enumerate()
        .find(|(_, g)| g.is_some_and(|l| l >= k))
    {
        return Err(LabelError::Given {
            row,
            label,
            markers: k,
        });
    }
    if !(trial.rate_hz.is_finite() && trial.rate_hz > 0.0) {
        return Err(LabelError::Rate(trial.rate_hz));
    }
    let tm = template.in_mm(template_mm_per_unit);
    // Until the trial's own frames are labelled, the template's distances are all there
    // is, and another subject's differ by more than the trial's skin moves.
    let first = LabelOptions {
        floor_share: opts.first_floor_share.max(opts.floor_share),
        ..*opts
    };
    let model = model::Model::learn(&tm, &first);
    if !model.present.iter().any(|&p| p) {
        return Err(LabelError::EmptyTemplate(k));
    }
    let pc = fragments::Pieces::cut(
        trial,
        trial_mm_per_unit,
        opts.max_speed_mm_s / trial.rate_hz,
    );
    let frags = &pc.frags;
    let given_of: Vec<Option<usize>> = frags.iter().map(|g| given[g.row]).collect();
    let seeded = !given_of.iter().any(|g| g.is_some_and(|m| model.present[m]));
    let scale = if opts.fit_scale {
        scale::fit(&model, &pc, &given_of, &first)
    } else {
        1.0
    };
    let (tm, model) = if scale == 1.0 {
        (tm, model)
    } else {
        let tm = template.in_mm(template_mm_per_unit * scale);
        let model = model::Model::learn(&tm, &first);
        (tm, model)
    };
    let mut labels = if seeded {
        seed_labels(&model, &pc, None, opts)
    } else {
        given_of.clone()
    };
    let step = if opts.step > 0 {
        opts.step
    } else {
        (pc.frames() / 2500).clamp(1, 4)
    };
    let mut model = model;
    let mut passes = 0;
    let mut answers;
    let mut round = 0;
    loop {
        let (a, l, p) = run_passes(&model, &pc, &given_of, labels, step, opts);
        answers = a;
        labels = l;
        passes += p;
        if seeded && round == 0 && !opts.seed_all {
            // Seeds where the labels have not reached, then the passes again.
            let more = seed_labels(&model, &pc, Some(&labels), opts);
            if more != labels {
                let (a, l, p) = run_passes(&model, &pc, &given_of, more, step, opts);
                answers = a;
                labels = l;
                passes += p;
            }
        }
        if round == opts.relearn {
            break;
        }
        round += 1;
        let base = if opts.relearn_template {
            tm.clone()
        } else {
            Trial {
                rate_hz: tm.rate_hz,
                xyz: vec![Vec::new(); tm.markers()],
                valid: vec![Vec::new(); tm.markers()],
            }
        };
        model = model::Model::learn(&with_trial(&base, &pc, &labels), opts);
    }
    exchanges(&model, &pc, &mut answers, opts);
    Ok(Labelling {
        fragments: answers,
        seeded,
        passes,
        scale,
    })
}

/// Vote passes from `labels` until no label changes (at most `opts.passes`): the answers,
/// the labels and the passes run.
fn run_passes(
    model: &model::Model,
    pc: &fragments::Pieces,
    given_of: &[Option<usize>],
    mut labels: Vec<Option<usize>>,
    step: usize,
    opts: &LabelOptions,
) -> (Vec<FragmentLabel>, Vec<Option<usize>>, usize) {
    let mut answers = Vec::new();
    let mut passes = 0;
    let frags = &pc.frags;
    let mut cache = vote::Cache::new(pc.frames(), step);
    while passes < opts.passes.max(1) {
        passes += 1;
        let v = vote::vote(model, pc, &labels, &mut cache, opts);
        answers = decide(frags, given_of, &labels, &v, opts);
        let next: Vec<Option<usize>> = answers.iter().map(|a: &FragmentLabel| a.label).collect();
        let changed: Vec<usize> = (0..next.len()).filter(|&i| next[i] != labels[i]).collect();
        if changed.is_empty() {
            break;
        }
        cache.forget(frags, Some(&changed));
        labels = next;
    }
    (answers, labels, passes)
}

/// The template's frames followed by the trial's frames as labelled so far: the geometry
/// learned again from both keeps what the template shows and what this subject and this
/// motion do (a static template keeps every pair; the trial shows which ones move).
fn with_trial(template: &Trial, pc: &fragments::Pieces, labels: &[Option<usize>]) -> Trial {
    let (k, n0, n) = (template.markers(), template.frames(), pc.frames());
    let mut xyz = template.xyz.clone();
    let mut valid = template.valid.clone();
    for m in 0..k {
        xyz[m].resize(n0 + n, [0.0; 3]);
        valid[m].resize(n0 + n, false);
    }
    for (i, (g, l)) in pc.frags.iter().zip(labels).enumerate() {
        if let Some(m) = *l {
            for f in g.first..=g.last {
                xyz[m][n0 + f] = *pc.at(i, f);
                valid[m][n0 + f] = true;
            }
        }
    }
    Trial {
        rate_hz: template.rate_hz,
        xyz,
        valid,
    }
}

/// First labels from the frames with the most points, one such frame in each of
/// `opts.seed_frames` stretches of the trial: each fragment takes the marker most of those
/// frames give it.
fn seed_labels(
    model: &model::Model,
    pc: &fragments::Pieces,
    so_far: Option<&[Option<usize>]>,
    opts: &LabelOptions,
) -> Vec<Option<usize>> {
    let (frags, active) = (&pc.frags, &pc.active);
    let n = active.len();
    let seconds = n as f64 / pc.rate_hz;
    // One frame per `seed_every_s`; or, without `seed_all`, 8 over the trial first and
    // then one per `seed_every_s` where most of the fragments recorded are still unlabelled.
    let parts = match so_far {
        None if !opts.seed_all => 8,
        None => ((seconds / opts.seed_every_s) as usize).clamp(1, opts.seed_frames.max(1)),
        Some(_) => ((seconds / opts.seed_every_s) as usize).clamp(1, opts.seed_frames.max(1)),
    };
    let unlabelled_most = |f: usize| {
        so_far.is_none_or(|l| {
            let open = active[f]
                .iter()
                .filter(|&&g| l[g as usize].is_none())
                .count();
            open >= 3 && 2 * open > active[f].len()
        })
    };
    let mut frames: Vec<usize> = (0..parts)
        .filter_map(|i| {
            let (a, b) = (i * n / parts, ((i + 1) * n / parts).min(n));
            (a..b).max_by(|&x, &y| active[x].len().cmp(&active[y].len()).then(y.cmp(&x)))
        })
        .filter(|&f| unlabelled_most(f))
        .collect();
    frames.dedup();
    use rayon::prelude::*;
    // Frames in runs of `seed_chain`: the first of a run matched from nothing, each next one
    // with the fragments the one before placed kept where they are (the search places the
    // rest). Runs are fixed by the frames alone, so the answer is the same on any threads.
    let chain = opts.seed_chain.max(1);
    let found: Vec<(usize, Vec<Option<usize>>)> = frames
        .par_chunks(chain)
        .flat_map_iter(|run| {
            let mut before: Vec<(u32, usize)> = Vec::new();
            let mut out = Vec::with_capacity(run.len());
            for &f in run {
                let points: Vec<[f64; 3]> =
                    active[f].iter().map(|&g| *pc.at(g as usize, f)).collect();
                let fixed: Vec<(usize, usize)> = active[f]
                    .iter()
                    .enumerate()
                    .filter_map(|(p, g)| before.iter().find(|(h, _)| h == g).map(|&(_, m)| (m, p)))
                    .collect();
                let at = seed::seed(model, &points, &fixed, opts);
                before = at
                    .iter()
                    .enumerate()
                    .filter_map(|(m, p)| p.map(|p| (active[f][p], m)))
                    .collect();
                out.push((f, at));
            }
            out
        })
        .collect();
    let mut votes: Vec<Vec<(usize, u32)>> = vec![Vec::new(); frags.len()];
    for (f, at) in found {
        for (m, p) in at.iter().enumerate() {
            if let Some(p) = p {
                let g = active[f][*p] as usize;
                match votes[g].iter_mut().find(|(x, _)| *x == m) {
                    Some(e) => e.1 += 1,
                    None => votes[g].push((m, 1)),
                }
            }
        }
    }
    votes
        .iter()
        .enumerate()
        .map(|(g, v)| {
            so_far.and_then(|l| l[g]).or_else(|| {
                v.iter()
                    .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
                    .map(|&(m, _)| m)
            })
        })
        .collect()
}

/// Leave unlabelled the fragments newly labelled that fit about as well with a neighbouring
/// marker's fragment's label as with their own ([`exchange::doubtful`]).
fn exchanges(
    model: &model::Model,
    pc: &fragments::Pieces,
    answers: &mut [FragmentLabel],
    opts: &LabelOptions,
) {
    let labels: Vec<Option<usize>> = answers.iter().map(|a| a.label).collect();
    let fresh: Vec<bool> = answers
        .iter()
        .map(|a| a.outcome == Outcome::Labelled)
        .collect();
    for (x, marker, rival) in exchange::doubtful(model, pc, &labels, &fresh, opts) {
        if answers[x].label.is_some() {
            answers[x].label = None;
            answers[x].outcome = Outcome::Unlabelled {
                reason: Reason::Exchangeable { marker, rival },
            };
        }
    }
}

/// Each fragment's answer from one pass's votes, then one fragment per label at a time.
fn decide(
    frags: &[Fragment],
    given: &[Option<usize>],
    before: &[Option<usize>],
    v: &vote::Votes,
    opts: &LabelOptions,
) -> Vec<FragmentLabel> {
    let mut out: Vec<FragmentLabel> = frags
        .iter()
        .enumerate()
        .map(|(i, &fragment)| {
            let checked = v.checked[i] as usize;
            let mut vs = v.votes[i].clone();
            vs.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
            let best = vs.first().map(|&(m, c)| (m, c as usize));
            let second = vs.get(1).map(|&(m, c)| (m, c as usize));
            let judged = judge(checked, best, second, opts);
            let votes_for = |m: usize| vs.iter().find(|x| x.0 == m).map_or(0, |x| x.1 as usize);
            let (label, outcome) = match (given[i], judged) {
                (None, Ok(m)) => (Some(m), Outcome::Labelled),
                // No frame judged it this pass: what it had stands.
                (None, Err(Reason::Short { .. })) if before[i].is_some() => {
                    (before[i], Outcome::Labelled)
                }
                (None, Err(reason)) => (None, Outcome::Unlabelled { reason }),
                (Some(g), Ok(m))
                    if m != g
                        && votes_for(m) as f64 >= opts.relabel_share * checked as f64
                        && votes_for(g) * 10 <= checked =>
                {
                    (Some(m), Outcome::Relabelled { from: g })
                }
                (Some(g), _) => (Some(g), Outcome::Kept),
            };
            let votes = label.map_or(best.map_or(0, |b| b.1), votes_for);
            FragmentLabel {
                fragment,
                label,
                given: given[i],
                outcome,
                checked,
                votes,
            }
        })
        .collect();
    one_per_label(&mut out);
    out
}

/// The label a fragment's votes settle, or why none.
fn judge(
    checked: usize,
    best: Option<(usize, usize)>,
    second: Option<(usize, usize)>,
    opts: &LabelOptions,
) -> Result<usize, Reason> {
    if checked < opts.min_checked {
        return Err(Reason::Short { checked });
    }
    let Some((marker, votes)) = best else {
        return Err(Reason::NoMatch { checked });
    };
    if (votes as f64) < opts.min_share * checked as f64 || votes < opts.min_checked {
        return Err(Reason::Weak {
            marker,
            votes,
            checked,
        });
    }
    if let Some((rival, rival_votes)) = second {
        if (rival_votes as f64) * opts.margin > votes as f64 {
            return Err(Reason::Contested {
                marker,
                votes,
                rival,
                rival_votes,
            });
        }
    }
    Ok(marker)
}

/// Fragments of one label that overlap in time: the trial's own labels first, then the
/// most votes, keep it; the others stay unlabelled.
fn one_per_label(out: &mut [FragmentLabel]) {
    let mut order: Vec<usize> = (0..out.len()).filter(|&i| out[i].label.is_some()).collect();
    order.sort_by(|&a, &b| {
        let (x, y) = (&out[a], &out[b]);
        x.label
            .cmp(&y.label)
            .then((y.outcome == Outcome::Kept).cmp(&(x.outcome == Outcome::Kept)))
            .then(y.votes.cmp(&x.votes))
            .then(a.cmp(&b))
    });
    let mut kept: Vec<usize> = Vec::new();
    for i in order {
        let m = out[i].label;
        let rival = kept
            .iter()
            .copied()
            .find(|&j| out[j].label == m && out[j].fragment.overlaps(&out[i].fragment));
        match (rival, m) {
            (Some(j), Some(marker)) => {
                let with = out[j].fragment;
                out[i].label = None;
                out[i].outcome = Outcome::Unlabelled {
                    reason: Reason::Overlap { marker, with },
                };
            }
            _ => kept.push(i),
        }
    }
}

#[cfg(test)]
mod tests;
