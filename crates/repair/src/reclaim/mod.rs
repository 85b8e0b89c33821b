//! Reclaiming (issue 47): a labelled marker's real positions put back into its gaps from
//! unlabelled trajectories, before any fill.
//!
//! A camera system that loses a marker and finds it again often starts a new trajectory it
//! cannot name (`*51`, see [`crate::unlabelled`]) while the labelled one has a gap. Each
//! stretch where an unlabelled trajectory is recorded inside a labelled marker's gap is a
//! *piece*, judged on the evidence of the trial alone ([`judge`]):
//!
//! - the distances the marker keeps to the markers of its segment, learned from the trial's
//!   own frames as the swap finder learns them ([`crate::swaps::learn_links`]; no marker set
//!   is written into the code): the piece's samples must keep them, frame by frame;
//! - the marker's own path at the gap's ends: where the piece starts at the gap's first frame
//!   (or ends at its last), its first (last) sample must sit where the marker's position and
//!   velocity before (after) the gap carry it; where the unlabelled trajectory goes on past
//!   the gap, it must be the marker there too (a second reconstruction of it), not another
//!   point;
//! - no rival fitting as well: another unlabelled piece for the same marker and frames, or
//!   the same unlabelled samples for another marker's gap, that fits within
//!   [`ReclaimOptions::margin`] of the best leaves both unsettled, so one
//!   unlabelled sample serves one marker.
//!
//! Settled pieces are [`Move`]s: the caller moves those samples, as recorded, from the
//! unlabelled point into the marker. What fits but is not settled is reported
//! ([`Unsettled`]), never moved. Frames are 0-based; the arrays are in the trial's units and
//! the thresholds in mm (`mm_per_unit` converts).

mod decide;
mod finds;
mod pieces;
mod score;

use crate::swaps::{learn_links, LearnedLinks, Link, Relearned};
use crate::Trial;
use rayon::prelude::*;
use std::borrow::Cow;

pub use finds::{Fit, Move, Piece, ReclaimOptions, Reclaims, Unsettled, Verdict, Why};

/// The links' parameters: the swap finder's defaults (`SwapOptions`), so that a repair's
/// swap stage learns the same links and hands them on ([`find_reclaims_sharing`]).
const LINK_SPREAD_MM: f64 = 2.5;
const LINK_SUPPORT: f64 = 0.5;
const LINKS_PER_MARKER: usize = 8;

/// The pieces of `candidates` inside the gaps of `markers`, judged. `markers.valid` says
/// which samples are the marker's data (a caller leaves its own earlier fills out); a gap is
/// a run of the others. `candidates` are the unlabelled trajectories, same frames. Arrays in
/// the trials' units, `mm_per_unit` to millimetres. Samples with a coordinate that is not
/// finite count as missing.
pub fn find_reclaims(
    markers: &Trial,
    candidates: &Trial,
    mm_per_unit: f64,
    opts: &ReclaimOptions,
) -> Reclaims {
    find_reclaims_sharing(markers, candidates, mm_per_unit, opts, None)
}

/// [`find_reclaims`] with the links an earlier stage learned on these markers (as the
/// swap finder of a repair does, [`crate::swaps::find_swaps_learned`]): only the pairs of
/// markers whose samples differ are learned again ([`LearnedLinks::learn_again`]), for the
/// same result.
///
/// Only the pieces that can be moved are judged: with [`ReclaimOptions::min_ends`] at
/// least 1, a piece must start or end within [`ReclaimOptions::path_frames`] of its gap's
/// edge, and the others (most of them: the stretches of every unlabelled point across a
/// marker's long gap) are counted, not scored. They would be scored off for want of an end.
pub fn find_reclaims_sharing(
    markers: &Trial,
    candidates: &Trial,
    mm_per_unit: f64,
    opts: &ReclaimOptions,
    known: Option<&LearnedLinks>,
) -> Reclaims {
    let n = markers.frames();
    if markers.markers() == 0 || candidates.markers() == 0 || n == 0 || candidates.frames() != n {
        return Reclaims::default();
    }
    let (m, u) = (in_mm(markers, mm_per_unit), in_mm(candidates, mm_per_unit));
    // Learned when a piece first passes the path: a trial whose pieces all stray from it
    // (or that has none) needs no links.
    let links = std::cell::OnceCell::new();
    let learn = || segment_links_with(&m, opts, known);
    let runs = pieces::Runs::of(&u);
    let mut live = Vec::new();
    let total = runs.each_near_end(&m, opts, |p| {
        let fit = score::score(&p, &m, &u, || &links.get_or_init(learn).0[p.marker], opts);
        if fit.verdict != Verdict::Off {
            live.push((p, fit));
        }
    });
    let mut out = decide::decide(&live, opts);
    out.pieces = total;
    out.link_pairs = links.get().map(|l| l.1).unwrap_or_default();
    out
}

/// Every piece with its fit, before any is settled: what [`find_reclaims`] decides on, for
/// evaluations that ask why a piece was not moved.
pub fn judge(
    markers: &Trial,
    candidates: &Trial,
    mm_per_unit: f64,
    opts: &ReclaimOptions,
) -> Vec<(Piece, Fit)> {
    let n = markers.frames();
    if markers.markers() == 0 || candidates.markers() == 0 || n == 0 || candidates.frames() != n {
        return Vec::new();
    }
    let (m, u) = (in_mm(markers, mm_per_unit), in_mm(candidates, mm_per_unit));
    let links = segment_links(&m, opts);
    pieces::all(&m, &u)
        .into_iter()
        .map(|p| (p, score::score(&p, &m, &u, || &links[p.marker], opts)))
        .collect()
}

/// `t` in mm with samples whose coordinates are not finite missing ([`Trial::in_mm`]);
/// `t` itself when that changes nothing (millimetres already, every valid sample finite),
/// as in most trials: no copy of its arrays. Multiplying by 1 leaves every finite number's
/// bits as they were, and only valid samples are read.
fn in_mm(t: &Trial, mm_per_unit: f64) -> Cow<'_, Trial> {
    let finite = || {
        t.xyz.iter().zip(&t.valid).all(|(r, v)| {
            r.iter()
                .zip(v)
                .all(|(p, &ok)| !ok || p.iter().all(|c| c.is_finite()))
        })
    };
    if mm_per_unit == 1.0 && finite() {
        Cow::Borrowed(t)
    } else {
        Cow::Owned(t.in_mm(mm_per_unit))
    }
}

/// Each marker's links with the tolerance the trial itself shows: the swap finder's links
/// (pairs whose distance clusters tightly in most frames) keep that distance only in part
/// of a trial when they span a joint or sit on moving skin, so each link's tolerance here
/// is the 95th percentile of its distance's departure over every frame where both markers
/// are recorded, and at least the finder's own. A frame of the true marker then strays
/// beyond a link's tolerance one time in twenty, wherever the gap falls. A link whose
/// tolerance comes out above `max_tol_mm` keeps no distance worth the name (a joint between
/// the markers) and is dropped.
///
/// `m` in mm; public for evaluations that compare distances after reclaiming with these.
pub fn segment_links(m: &Trial, opts: &ReclaimOptions) -> Vec<Vec<Link>> {
    segment_links_with(m, opts, None).0
}

/// [`segment_links`], learning again only what `known` does not hold of `m`, and how many
/// pairs that was.
fn segment_links_with(
    m: &Trial,
    opts: &ReclaimOptions,
    known: Option<&LearnedLinks>,
) -> (Vec<Vec<Link>>, Relearned) {
    let (mut links, relearned) = match known {
        Some(k) => k.learn_again(m, LINK_SPREAD_MM, LINK_SUPPORT, LINKS_PER_MARKER),
        None => {
            let all = m.markers() * m.markers().saturating_sub(1) / 2;
            let links = learn_links(m, LINK_SPREAD_MM, LINK_SUPPORT, LINKS_PER_MARKER);
            let done = Relearned {
                pairs: all,
                learned: all,
            };
            (links, done)
        }
    };
    // A link is in both its markers' lists (unless one list was cut to its best), with the
    // same distance, and its departures are the same numbers either way round (a
    // difference and its negation square alike): each pair's percentile is found once,
    // pairs in parallel.
    let mut pairs: Vec<(usize, usize, f64)> = links
        .iter()
        .enumerate()
        .flat_map(|(a, ls)| {
            ls.iter()
                .map(move |l| (a.min(l.other), a.max(l.other), l.d0_mm))
        })
        .collect();
    pairs.sort_by_key(|p| (p.0, p.1));
    pairs.dedup_by(|x, y| (x.0, x.1) == (y.0, y.1));
    let q95: Vec<Option<f64>> = pairs
        .par_iter()
        .map_init(Vec::new, |dev, &(a, b, d0)| departure_q95(m, a, b, d0, dev))
        .collect();
    for (a, ls) in links.iter_mut().enumerate() {
        for l in ls.iter_mut() {
            let key = (a.min(l.other), a.max(l.other));
            let i = pairs.partition_point(|p| (p.0, p.1) < key);
            if let Some(q) = q95.get(i).copied().flatten() {
                l.tol_mm = l.tol_mm.max(q);
            }
        }
        ls.retain(|l| l.tol_mm <= opts.max_link_tol_mm);
    }
    (links, relearned)
}

/// The 95th percentile of |distance − `d0`| between markers `a` and `b` over the frames
/// where both are recorded (every frame up to 2 000, evenly spaced beyond); `None` for no
/// such frame. `dev` is a buffer.
fn departure_q95(m: &Trial, a: usize, b: usize, d0: f64, dev: &mut Vec<f64>) -> Option<f64> {
    let n = m.frames();
    let step = n.div_ceil(2000).max(1);
    dev.clear();
    dev.extend(
        (0..n)
            .step_by(step)
            .filter(|&f| m.valid[a][f] && m.valid[b][f])
            .map(|f| {
                let (p, q) = (&m.xyz[a][f], &m.xyz[b][f]);
                let d =
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
                (d - d0).abs()
            }),
    );
    if dev.is_empty() {
        return None;
    }
    let k = (dev.len() * 95 / 100).min(dev.len() - 1);
    signal::order::at_rank(dev, k)
}

#[cfg(test)]
mod tests;
