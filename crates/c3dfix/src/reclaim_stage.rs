//! Reclaiming (issue 47): the labelled markers' real positions taken back from the points a
//! capture system left unlabelled, a repair stage after the swaps and before the fills, and
//! what `c3dfix reclaim` lists. The judging is the repair crate's
//! ([`repair::reclaim`]); this module names the points by label, numbers frames as the file
//! does, and moves the settled samples in the file itself.
//!
//! A settled piece's samples are moved as the library decodes them (coordinates, residual
//! and camera mask): the marker gets the recorded sample, flags and all, and the unlabelled
//! point is marked missing there; nothing is recomputed. What the evidence does not settle
//! is reported and changes nothing.

use crate::error::{Error, Result};
use crate::markers::{mm_per_unit, split_unlabelled};
use crate::options::ReclaimMode;
use crate::trial::{to_trial_and, Others};
use repair::reclaim::{find_reclaims_sharing, Fit, Piece, ReclaimOptions, Why};
use serde::Serialize;
use std::path::Path;

/// What the stage did with a settled piece.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReclaimAction {
    /// Its samples were moved into the marker.
    Moved,
    /// Listed only (not asked to move, or the command that only looks).
    Reported,
    /// Settled, but the marker is outside the repair's `markers`.
    OutOfScope,
}

/// One settled piece: the unlabelled samples that are the marker's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReclaimBrief {
    /// The labelled marker and the unlabelled point the samples are in.
    pub marker: String,
    pub source: String,
    /// First and last frame, in the file's numbering.
    pub first_frame: usize,
    pub last_frame: usize,
    pub samples: usize,
    pub action: ReclaimAction,
    pub fit: Fit,
    /// Point indices (0-based) of the marker and the source, and 0-based frames.
    #[serde(skip)]
    pub point: usize,
    #[serde(skip)]
    pub source_point: usize,
    #[serde(skip)]
    pub first_index: usize,
    #[serde(skip)]
    pub last_index: usize,
}

/// Why an unsettled piece was not moved, in labels and the file's frames.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "why", rename_all = "snake_case")]
pub enum UnsettledWhy {
    /// Another piece fits as well: `rival_marker` ← `rival_source` over its frames.
    Ambiguous {
        rival_marker: String,
        rival_source: String,
        rival_first_frame: usize,
        rival_last_frame: usize,
        rival_cost: f64,
    },
    /// The marker's path fits, too few segment distances could be checked.
    FewLinks { checked_frames: usize },
}

/// One piece that fits and is not settled.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UnsettledBrief {
    pub marker: String,
    pub source: String,
    pub first_frame: usize,
    pub last_frame: usize,
    #[serde(flatten)]
    pub why: UnsettledWhy,
    pub fit: Fit,
}

/// One move a repair made, as the file's record keeps it (the record's row, so it lives there).
pub use crate::rerun::Reclaimed;

/// The stage's (or the command's) outcome.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Reclaim {
    /// Labelled markers and unlabelled points of the trial.
    pub markers: usize,
    pub unlabelled: usize,
    /// Stretches of unlabelled samples inside labelled gaps that were judged.
    pub pieces: usize,
    /// Samples moved into markers.
    pub samples_moved: usize,
    pub settled: Vec<ReclaimBrief>,
    pub unsettled: Vec<UnsettledBrief>,
    /// What was moved, for the record.
    #[serde(skip)]
    pub moved: Vec<Reclaimed>,
    /// Pairs of markers whose links the judging learned, of all: those the swap stage had
    /// learned on the same samples were taken from it
    /// ([`repair::swaps::LearnedLinks::learn_again`]).
    #[serde(skip)]
    pub link_pairs: repair::swaps::Relearned,
}

/// The trial's labelled markers and unlabelled points, read once, and which of the
/// markers' samples are data.
pub(crate) struct Points<'a> {
    pub labelled: &'a [usize],
    pub unlabelled: &'a [usize],
    /// `data[row][frame]` of the labelled markers' trial.
    pub data: &'a [Vec<bool>],
    /// Samples at exactly (0, 0, 0) count as missing.
    pub zero_invalid: bool,
    /// The links an earlier stage learned from the labelled markers (the swap stage's),
    /// for the judging to learn again only the pairs whose samples differ.
    pub links: Option<&'a repair::swaps::LearnedLinks>,
}

/// Judge the unlabelled points of `c` against the gaps of its labelled markers and, for
/// [`ReclaimMode::On`], move the settled pieces' samples in `c` and in `trial` (the repair's
/// trial of `points.labelled`). `points.data` says which of the trial's samples are the
/// marker's data (its own earlier fills are not: they are gaps here as for every stage).
/// `in_scope` says which points a repair may change. `others` holds the unlabelled points as
/// read with the trial (decoded here if only their validity was read); the samples moved
/// leave them as they leave the file.
pub(crate) fn run(
    c: &mut c3d::C3d,
    name: &Path,
    mode: ReclaimMode,
    points: &Points<'_>,
    trial: &mut repair::Trial,
    others: &mut Others,
    in_scope: &dyn Fn(usize) -> bool,
) -> Result<Reclaim> {
    let mut out = Reclaim {
        markers: points.labelled.len(),
        unlabelled: points.unlabelled.len(),
        ..Reclaim::default()
    };
    if mode == ReclaimMode::Off || points.unlabelled.is_empty() || points.labelled.is_empty() {
        return Ok(out);
    }
    // Markers without a gap (every sample data, and finite) leave no piece to judge: the
    // unlabelled points are not read.
    let whole = |(v, x): (&Vec<bool>, &Vec<[f64; 3]>)| {
        v.iter()
            .zip(x)
            .all(|(&ok, p)| ok && p.iter().all(|c| c.is_finite()))
    };
    if points.data.iter().zip(&trial.xyz).all(whole) {
        return Ok(out);
    }
    let mut cands = others.lend(c, points.unlabelled, points.zero_invalid)?;
    let mm = mm_per_unit(&c.point_units());
    // The markers judged are the trial's coordinates with the data's validity: the trial
    // lends its coordinates for the judging (its validity set aside meanwhile) rather than
    // a copy of them being made.
    let mut valid = points.data.to_vec();
    std::mem::swap(&mut trial.valid, &mut valid);
    let found = forkpool::install(|| {
        find_reclaims_sharing(trial, &cands, mm, &ReclaimOptions::default(), points.links)
    });
    std::mem::swap(&mut trial.valid, &mut valid);
    out.pieces = found.pieces;
    out.link_pairs = found.link_pairs;
    let labels = c.point_labels();
    let name_of = |p: usize| labels[p].trim().to_string();
    let marker = |pc: &Piece| points.labelled[pc.marker];
    let source = |pc: &Piece| points.unlabelled[pc.source];
    for mv in &found.moves {
        let pc = &mv.piece;
        let action = if mode != ReclaimMode::On {
            ReclaimAction::Reported
        } else if !in_scope(marker(pc)) {
            ReclaimAction::OutOfScope
        } else {
            ReclaimAction::Moved
        };
        out.settled.push(ReclaimBrief {
            marker: name_of(marker(pc)),
            source: name_of(source(pc)),
            first_frame: c.frame_number(pc.first),
            last_frame: c.frame_number(pc.last),
            samples: pc.len(),
            action,
            fit: mv.fit,
            point: marker(pc),
            source_point: source(pc),
            first_index: pc.first,
            last_index: pc.last,
        });
    }
    for u in &found.unsettled {
        let pc = &u.piece;
        let why = match u.why {
            Why::Ambiguous { rival, rival_cost } => UnsettledWhy::Ambiguous {
                rival_marker: name_of(marker(&rival)),
                rival_source: name_of(source(&rival)),
                rival_first_frame: c.frame_number(rival.first),
                rival_last_frame: c.frame_number(rival.last),
                rival_cost,
            },
            Why::FewLinks { checked_frames } => UnsettledWhy::FewLinks { checked_frames },
        };
        out.unsettled.push(UnsettledBrief {
            marker: name_of(marker(pc)),
            source: name_of(source(pc)),
            first_frame: c.frame_number(pc.first),
            last_frame: c.frame_number(pc.last),
            why,
            fit: u.fit,
        });
    }
    let moves: Vec<&ReclaimBrief> = out
        .settled
        .iter()
        .filter(|b| b.action == ReclaimAction::Moved)
        .collect();
    out.moved = moves
        .iter()
        .map(|b| Reclaimed {
            point: b.point,
            source: b.source_point,
            first: b.first_index,
            last: b.last_index,
        })
        .collect();
    out.moved.sort();
    out.samples_moved = move_samples(c, &out.moved).map_err(|source| Error::C3d {
        path: name.to_path_buf(),
        source,
    })?;
    // The same move in the trial: the marker's row takes the samples as decoded, and the
    // unlabelled point loses them as it does in the file.
    for (b, mv) in moves.iter().zip(found.moves.iter().filter(|m| {
        let pc = &m.piece;
        mode == ReclaimMode::On && in_scope(marker(pc))
    })) {
        let (row, src) = (mv.piece.marker, mv.piece.source);
        for f in b.first_index..=b.last_index {
            trial.xyz[row][f] = cands.xyz[src][f];
            trial.valid[row][f] = true;
            cands.valid[src][f] = false;
        }
    }
    others.put_back(cands);
    Ok(out)
}

/// Move the samples of each `(point ← source, first..=last)` in the file: the marker takes
/// each sample as the library decodes it (coordinates, residual, camera mask) and the
/// source is marked missing there. Returns the marker samples written.
fn move_samples(c: &mut c3d::C3d, moved: &[Reclaimed]) -> c3d::Result<usize> {
    if moved.is_empty() {
        return Ok(0);
    }
    let samples = crate::trial::gather_samples(c, |view, frame, f, out| {
        for m in moved {
            if (m.first..=m.last).contains(&frame) && m.point < view.count && m.source < view.count
            {
                let (p, r, k) = view.sample(f, m.source);
                out.push((frame, m.point, p, r, k));
                let (xyz, r, k) = c3d::Mark::Missing.stored();
                out.push((frame, m.source, xyz, r, k));
            }
        }
    });
    let n = samples.len() / 2;
    c.patch_points(samples)?;
    Ok(n)
}

/// What reclaiming would do on `c`, changing nothing: `c3dfix reclaim`. `unlabelled` is the
/// rule of which points are unlabelled; samples at exactly (0, 0, 0) count as missing with
/// `zero_invalid`. The marker's own earlier fills (the file's C3DFIX record) are gaps here,
/// as for the repair.
pub fn reclaim(
    c: &c3d::C3d,
    path: &Path,
    unlabelled: &repair::Unlabelled,
    zero_invalid: bool,
) -> Result<Reclaim> {
    let split = split_unlabelled(c, unlabelled);
    let (mut trial, mut others) =
        to_trial_and(c, &split.labelled, &split.unlabelled, true, zero_invalid)?;
    let data = own_data(c, &split.labelled, &trial);
    let mut copy = c.clone();
    run(
        &mut copy,
        path,
        ReclaimMode::Report,
        &Points {
            labelled: &split.labelled,
            unlabelled: &split.unlabelled,
            data: &data,
            zero_invalid,
            links: None,
        },
        &mut trial,
        &mut others,
        &|_| false,
    )
}

/// Which samples of `trial` (rows: `points`) are the markers' data: the valid ones, less the
/// stretches the file's C3DFIX record says c3dfix filled (no data, docs/reruns.md).
pub(crate) fn own_data(c: &c3d::C3d, points: &[usize], trial: &repair::Trial) -> Vec<Vec<bool>> {
    let mut data = trial.valid.clone();
    for &(p, a, b) in &crate::rerun::Record::read(c).filled {
        if let Some(r) = points.iter().position(|&q| q == p) {
            let end = b.min(trial.frames().saturating_sub(1));
            if a <= end {
                data[r][a..=end].fill(false);
            }
        }
    }
    data
}
