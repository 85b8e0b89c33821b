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

use crate::swaps::{learn_links, LearnedLinks, Link, LinksOnDemand};
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
    // A marker's links are learned when one of its pieces first passes the path: most
    // markers have none (a trial whose pieces all stray from the path needs no links), and
    // a marker's links are its own pairs' alone.
    let params = (LINK_SPREAD_MM, LINK_SUPPORT, LINKS_PER_MARKER);
    let demand = LinksOnDemand::new(&m, params, known);
    let links: Vec<std::cell::OnceCell<Vec<Link>>> = vec![Default::default(); m.markers()];
    // A link is in both its markers' lists: its tolerance is found once.
    let q95s = std::cell::RefCell::new(std::collections::HashMap::new());
    let runs = pieces::Runs::of(&u);
    let mut live = Vec::new();
    let total = runs.each_near_end(&m, opts, |p| {
        let mine = || {
            let learn = || {
                let q95 = |lo, hi, d0| {
                    let mut known = q95s.borrow_mut();
                    *known
                        .entry((lo, hi))
                        .or_insert_with(|| departure_q95(&m, lo, hi, d0, &mut Vec::new()))
                };
                with_tolerance(p.marker, demand.of(p.marker), opts, q95)
            };
            &links[p.marker].get_or_init(learn)[..]
        };
        let fit = score::score(&p, &m, &u, mine, opts);
        if fit.verdict != Verdict::Off {
            live.push((p, fit));
        }
    });
    let mut out = decide::decide(&live, opts);
    out.pieces = total;
    out.link_pairs = demand.relearned();
    out
}

/// Marker `a`'s links with the tolerance [`segment_links`] gives them, those above
/// [`ReclaimOptions::max_link_tol_mm`] dropped. `q95` gives a pair's
/// [`departure_q95`] (`lo < hi`, the link's distance).
fn with_tolerance(
    a: usize,
    mut links: Vec<Link>,
    opts: &ReclaimOptions,
    mut q95: impl FnMut(usize, usize, f64) -> Option<f64>,
) -> Vec<Link> {
    for l in &mut links {
        if let Some(q) = q95(a.min(l.other), a.max(l.other), l.d0_mm) {
            l.tol_mm = l.tol_mm.max(q);
        }
    }
    links.retain(|l| l.tol_mm <= opts.max_link_tol_mm);
    links
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
    // A sum of three numbers is finite only when each is (a NaN or an infinity carries
    // through; two finite ones that overflow make it say no, and the copy is then made):
    // one test per sample rather than three.
    let finite = || {
        t.xyz.iter().zip(&t.valid).all(|(r, v)| {
            r.iter()
                .zip(v)
                .all(|(p, &ok)| !ok || (p[0] + p[1] + p[2]).is_finite())
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
    let links = learn_links(m, LINK_SPREAD_MM, LINK_SUPPORT, LINKS_PER_MARKER);
    links
        .into_par_iter()
        .enumerate()
        .map(|(a, ls)| {
            let mut dev = Vec::new();
            with_tolerance(a, ls, opts, |lo, hi, d0| {
                departure_q95(m, lo, hi, d0, &mut dev)
            })
        })
        .collect()
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
