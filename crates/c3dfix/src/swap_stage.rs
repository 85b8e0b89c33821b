//! The first stage of a repair (issue 34): label swaps and jumps found in the file and, under
//! `--swaps fix`, undone in it before spikes, fill and filter see the trial.
//!
//! A settled swap is undone by exchanging the two points' samples back over its frames in the
//! file itself (coordinates, residual and camera mask, as decoded by the library's one rule),
//! so the undone samples are the recorded ones, flags and all; nothing is recomputed. A
//! settled jump's samples become a gap, which the fill stage fills or leaves (then they are
//! written missing). Finds the evidence does not settle, and finds that touch a marker
//! outside `--markers`, are reported and change nothing.

use crate::error::{Error, Result};
use crate::options::SwapsMode;
use crate::rerun::Undone;
use crate::swaps::{swaps_with, SwapFind};
use repair::swaps::{FindKind, SwapOptions};
use serde::Serialize;
use std::path::Path;

/// What the stage did with one find.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SwapAction {
    /// A swap whose samples were exchanged back.
    Undone,
    /// A jump whose samples were made a gap for the fill stage.
    Gap,
    /// Listed only: not settled, not asked to fix, or overlapping a find acted on.
    Reported,
    /// Settled, but a marker of it is outside `--markers`: the repair may not change it.
    OutOfScope,
}

/// One find in a repair's report: the find (frames in the file's numbering, with its
/// evidence) and what the repair did with it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SwapBrief {
    #[serde(flatten)]
    pub find: SwapFind,
    pub action: SwapAction,
}

/// The stage's outcome.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stage {
    pub briefs: Vec<SwapBrief>,
    /// Jumped samples to be made a gap: `(point, first, last)`, 0-based frames.
    pub gaps: Vec<(usize, usize, usize)>,
    /// What was undone, for the file's record.
    pub undone: Vec<Undone>,
    /// Samples whose values the exchanges changed in the file.
    pub exchanged: usize,
    /// Why the trial was not checked (too little to judge), if so.
    pub note: Option<String>,
    /// The links the finding learned from the markers, for the reclaim stage to take
    /// where its markers sample the same ([`repair::swaps::LearnedLinks::learn_again`]).
    pub links: Option<repair::swaps::LearnedLinks>,
}

/// Find swaps and jumps among the markers of `c` and, for [`SwapsMode::Fix`], exchange the
/// settled swaps back in `c` and list the settled jumps as gaps to make. `in_scope` says
/// which points (0-based) the repair may change. A trial with too little to judge (fewer
/// than 2 markers or 3 frames, every sample missing) is not an error here: the repair goes
/// on and the note says why nothing was checked.
///
/// `trial` is the repair's trial of the file's markers, `points` (as
/// [`crate::markers::marker_indices`] gives them) its rows: the finding reads it, and a swap
/// undone is exchanged back in it as in the file, so the later stages read the undone
/// samples.
pub fn run(
    c: &mut c3d::C3d,
    name: &Path,
    mode: SwapsMode,
    in_scope: &dyn Fn(usize) -> bool,
    points: &[usize],
    trial: &mut repair::Trial,
) -> Result<Stage> {
    let mut stage = Stage::default();
    if mode == SwapsMode::Off {
        return Ok(stage);
    }
    let (found, links) = match swaps_with(
        c,
        name,
        &SwapOptions::default(),
        Some((points, &mut *trial)),
    ) {
        Ok(f) => f,
        Err(Error::Trial { what, .. }) => {
            stage.note = Some(what);
            return Ok(stage);
        }
        Err(e) => return Err(e),
    };
    stage.links = links;
    // The most confident first: a find overlapping one acted on (a marker and frames in
    // common) is left reported, since the first exchange already moved its samples.
    let mut finds = found.swaps;
    finds.sort_by(|a, b| b.confidence.total_cmp(&a.confidence));
    let mut acted: Vec<(Vec<usize>, usize, usize)> = Vec::new();
    let mut pairs = Vec::new();
    for f in finds {
        let overlaps = acted.iter().any(|(pts, a, b)| {
            f.first_index <= *b && *a <= f.last_index && f.points.iter().any(|p| pts.contains(p))
        });
        let action = if mode != SwapsMode::Fix || !f.settled || overlaps {
            SwapAction::Reported
        } else if !f.points.iter().all(|&p| in_scope(p)) {
            SwapAction::OutOfScope
        } else {
            match (f.kind, f.points.as_slice()) {
                (FindKind::Swap, &[a, b]) => {
                    pairs.push((a, b, f.first_index, f.last_index));
                    SwapAction::Undone
                }
                (FindKind::Jump, &[a]) => {
                    stage.gaps.push((a, f.first_index, f.last_index));
                    SwapAction::Gap
                }
                _ => SwapAction::Reported,
            }
        };
        if matches!(action, SwapAction::Undone | SwapAction::Gap) {
            acted.push((f.points.clone(), f.first_index, f.last_index));
            stage.undone.push(Undone {
                points: f.points.clone(),
                first: f.first_index,
                last: f.last_index,
            });
        }
        stage.briefs.push(SwapBrief { find: f, action });
    }
    stage
        .briefs
        .sort_by_key(|b| (b.find.first_index, b.find.points.clone()));
    stage.undone.sort();
    stage.exchanged = exchange(c, &pairs).map_err(|source| Error::C3d {
        path: name.to_path_buf(),
        source,
    })?;
    // The same exchange in the trial: its rows hold the samples as decoded, so exchanging
    // them gives what reading the exchanged file would.
    let row = |p: usize| points.iter().position(|&q| q == p);
    for &(a, b, first, last) in &pairs {
        if let (Some(ra), Some(rb)) = (row(a), row(b)) {
            for f in first..=last.min(trial.frames().saturating_sub(1)) {
                let (pa, pb) = (trial.xyz[ra][f], trial.xyz[rb][f]);
                trial.xyz[ra][f] = pb;
                trial.xyz[rb][f] = pa;
                let (va, vb) = (trial.valid[ra][f], trial.valid[rb][f]);
                trial.valid[ra][f] = vb;
                trial.valid[rb][f] = va;
            }
        }
    }
    Ok(stage)
}

/// Exchange the samples of points `a` and `b` over frames `first..=last` (0-based,
/// inclusive) for each `(a, b, first, last)`, in the file: each sample as the library
/// decodes it (coordinates, residual, camera mask) goes to the other point. Exchanging twice
/// gives the file's own values back. Returns the samples written.
pub fn exchange(c: &mut c3d::C3d, pairs: &[(usize, usize, usize, usize)]) -> c3d::Result<usize> {
    if pairs.is_empty() {
        return Ok(0);
    }
    let samples = crate::trial::gather_samples(c, |view, frame, f, out| {
        for &(a, b, first, last) in pairs {
            if (first..=last).contains(&frame) && a < view.count && b < view.count {
                let (pa, ra, ma) = view.sample(f, a);
                let (pb, rb, mb) = view.sample(f, b);
                out.push((frame, a, pb, rb, mb));
                out.push((frame, b, pa, ra, ma));
            }
        }
    });
    c.patch_points(samples)
}
