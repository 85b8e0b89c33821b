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
mod score;

use crate::swaps::learn_links;
use crate::Trial;

pub use finds::{Fit, Move, Piece, ReclaimOptions, Reclaims, Unsettled, Verdict, Why};

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
    let scored = judge(markers, candidates, mm_per_unit, opts);
    let mut out = decide::decide(&scored, opts);
    out.pieces = scored.len();
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
    let (m, u) = (markers.in_mm(mm_per_unit), candidates.in_mm(mm_per_unit));
    let links = segment_links(&m, opts);
    pieces(&m, &u)
        .into_iter()
        .map(|p| (p, score::score(&p, &m, &u, &links[p.marker], opts)))
        .collect()
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
pub fn segment_links(m: &Trial, opts: &ReclaimOptions) -> Vec<Vec<crate::swaps::Link>> {
    let max_tol_mm = opts.max_link_tol_mm;
    let mut links = learn_links(m, 2.5, 0.5, 8);
    let n = m.frames();
    let step = n.div_ceil(2000).max(1);
    for (a, ls) in links.iter_mut().enumerate() {
        for l in ls.iter_mut() {
            let mut dev: Vec<f64> = (0..n)
                .step_by(step)
                .filter(|&f| m.valid[a][f] && m.valid[l.other][f])
                .map(|f| {
                    let (p, q) = (&m.xyz[a][f], &m.xyz[l.other][f]);
                    let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2))
                        .sqrt();
                    (d - l.d0_mm).abs()
                })
                .collect();
            if dev.is_empty() {
                continue;
            }
            let k = (dev.len() * 95 / 100).min(dev.len() - 1);
            if let Some(q95) = signal::order::at_rank(&mut dev, k) {
                l.tol_mm = l.tol_mm.max(q95);
            }
        }
        ls.retain(|l| l.tol_mm <= max_tol_mm);
    }
    links
}

/// Every stretch of an unlabelled trajectory recorded inside a gap of a marker.
fn pieces(m: &Trial, u: &Trial) -> Vec<Piece> {
    let mut out = Vec::new();
    for (marker, mv) in m.valid.iter().enumerate() {
        for g in crate::gaps::find_gaps(mv, marker) {
            for (source, uv) in u.valid.iter().enumerate() {
                let mut f = g.first;
                while f <= g.last {
                    if !uv[f] {
                        f += 1;
                        continue;
                    }
                    let first = f;
                    while f <= g.last && uv[f] {
                        f += 1;
                    }
                    out.push(Piece {
                        marker,
                        source,
                        first,
                        last: f - 1,
                    });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests;
