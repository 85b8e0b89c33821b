//! The last check of a labelling: two fragments of neighbouring markers seen together are
//! labelled only if the labels as given fit clearly better than the same two exchanged.
//! The votes judge each fragment against its neighbours as labelled so far, so a pair of
//! markers that the template places alike (a mirror pair of one segment, two markers
//! a few centimetres apart) can settle exchanged over a whole stretch, every frame voting
//! for the exchange; wrong costs more than unlabelled, so such a pair stays unlabelled.

use super::cost::marker_cost;
use super::fragments::Pieces;
use super::model::Model;
use super::options::LabelOptions;
use rayon::prelude::*;
use std::collections::BTreeSet;

/// Frames compared per pair of fragments (evenly spaced over the frames they share).
const FRAMES: usize = 40;

/// The fragments newly labelled (`fresh`: not the trial's own labels) whose exchange with
/// a neighbouring marker's fragment fits within `opts.exchange_margin` (mean squared
/// departure, in tolerances²) of the labels as given: `(fragment, its marker, the rival
/// marker)`. `labels[fragment]` are the labels as given.
pub(crate) fn doubtful(
    model: &Model,
    pc: &Pieces,
    labels: &[Option<usize>],
    fresh: &[bool],
    opts: &LabelOptions,
) -> Vec<(usize, usize, usize)> {
    if opts.exchange_margin <= 0.0 {
        return Vec::new();
    }
    let n = pc.frames();
    let (label, k) = (labels, model.markers);
    // Which fragment holds each marker in each frame, once (`NONE`: none).
    const NONE: u32 = u32::MAX;
    let mut held = vec![NONE; n * k];
    for (f, here) in pc.active.iter().enumerate() {
        for &g in here {
            if let Some(m) = label[g as usize] {
                if held[f * k + m] == NONE {
                    held[f * k + m] = g;
                }
            }
        }
    }
    let holder_at = |f: usize| {
        held[f * k..(f + 1) * k]
            .iter()
            .map(|&g| (g != NONE).then_some(g as usize))
    };
    // Pairs of fragments holding neighbouring markers in some frame.
    let mut pairs: BTreeSet<(usize, usize)> = BTreeSet::new();
    let step = n.div_ceil(2000).max(1);
    for f in (0..n).step_by(step) {
        let h: Vec<Option<usize>> = holder_at(f).collect();
        for &g in &pc.active[f] {
            let g = g as usize;
            let Some(a) = label[g] else { continue };
            for nb in &model.nb[a] {
                if let Some(j) = h[nb.other] {
                    if j != g {
                        pairs.insert((g.min(j), g.max(j)));
                    }
                }
            }
        }
    }
    // Each pair judged on its own (in parallel, collected in order: the same answer on
    // any number of threads).
    let judge = |i: usize, j: usize| -> Option<(usize, usize)> {
        let (a, b) = (label[i]?, label[j]?);
        if !fresh[i] && !fresh[j] {
            return None;
        }
        let (gi, gj) = (pc.frags[i], pc.frags[j]);
        let (lo, hi) = (gi.first.max(gj.first), gi.last.min(gj.last));
        if lo > hi {
            return None;
        }
        let every = (hi - lo + 1).div_ceil(FRAMES).max(1);
        let (mut as_given, mut exchanged, mut terms) = (0.0, 0.0, 0usize);
        for f in (lo..=hi).step_by(every) {
            let h = &held[f * k..(f + 1) * k];
            let (pi, pj) = (pc.at(i, f), pc.at(j, f));
            let at = |m: usize| (h[m] != NONE).then(|| pc.at(h[m] as usize, f));
            let swapped = |m: usize| {
                if m == a {
                    Some(pj)
                } else if m == b {
                    Some(pi)
                } else {
                    at(m)
                }
            };
            let (s1, t1) = marker_cost(model, a, pi, at, opts, f64::INFINITY);
            let (s2, t2) = marker_cost(model, b, pj, at, opts, f64::INFINITY);
            let (x1, u1) = marker_cost(model, a, pj, swapped, opts, f64::INFINITY);
            let (x2, u2) = marker_cost(model, b, pi, swapped, opts, f64::INFINITY);
            if t1 + t2 == 0 || u1 + u2 != t1 + t2 {
                continue;
            }
            as_given += s1 + s2;
            exchanged += x1 + x2;
            terms += t1 + t2;
        }
        let t = terms as f64;
        (terms > 0 && exchanged / t - as_given / t < opts.exchange_margin).then_some((i, j))
    };
    let pairs: Vec<(usize, usize)> = pairs.into_iter().collect();
    let doubtful: Vec<(usize, usize)> =
        pairs.par_iter().filter_map(|&(i, j)| judge(i, j)).collect();
    let mut out = Vec::new();
    for (i, j) in doubtful {
        for (x, y) in [(i, j), (j, i)] {
            if let (true, Some(marker), Some(rival)) = (fresh[x], label[x], label[y]) {
                out.push((x, marker, rival));
            }
        }
    }
    out
}
