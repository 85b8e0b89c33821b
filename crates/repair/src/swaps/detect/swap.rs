//! One swap found: a run of exchanged frames placed at its edges by the trajectories'
//! continuity, its link errors as labelled and undone, and its confidence.

use super::context::{median, Ctx};
use super::finds::{Evidence, Find, FindKind, SwapOptions};

/// Longest range of candidate frames for a swap's start over which the steps are summed
/// alike for every candidate ([`swap_find`]).
const EDGE_RANGE: usize = 64;

/// Most the continuity at a swap's edges adds to its link evidence (as the probability of
/// an independent witness): half, so that it cannot settle a swap whose links say little.
const EDGE_WEIGHT: f64 = 0.5;

/// The swap of `a` and `b` over the run `s0..=e0` whose frames `decided` the links decided:
/// its edges, its link errors labelled and undone, the continuity at its edges and its
/// confidence.
pub(super) fn swap_find(
    cx: &Ctx,
    a: usize,
    b: usize,
    s0: usize,
    e0: usize,
    decided: Vec<usize>,
    opts: &SwapOptions,
) -> Find {
    let (s, e) = swap_edges(cx, a, b, s0, e0, &decided);
    let (before, after) = link_errors(cx, a, b, &decided);
    let edges = edges_checked(cx, a, b, s, e);
    let Edges {
        smoother,
        checked,
        edge_step,
        ..
    } = edges;
    let confidence = swap_confidence(cx, (a, b), (s, e), &decided, (before, after), &edges);
    Find {
        kind: FindKind::Swap,
        markers: vec![a, b],
        first: s,
        last: e,
        confidence,
        settled: confidence >= opts.min_confidence,
        evidence: Evidence {
            links: cx.links[a].len() + cx.links[b].len(),
            frames_decided: decided.len(),
            link_error: before,
            link_error_undone: after,
            edges_smoother: smoother,
            edges_checked: checked,
            edge_step_mm: edge_step,
            offset_share: None,
        },
    }
}

/// The swap's first and last frames: undecided frames at the edges (both markers missing
/// or passing close) are given to the side where the exchanged trajectories run smoothest.
fn swap_edges(
    cx: &Ctx,
    a: usize,
    b: usize,
    s0: usize,
    e0: usize,
    decided: &[usize],
) -> (usize, usize) {
    let (first_dec, last_dec) = match (decided.first(), decided.last()) {
        (Some(&x), Some(&y)) => (x, y),
        _ => (s0, e0),
    };
    // The steps of both markers, the exchange applied over `s..=e`, summed over the
    // frames around `lo..=hi` (for the start, every candidate's range alike, so that a
    // leap the start leaves unexplained counts wherever it falls: a label that took the
    // other marker's point over that marker's gap has one step each way at the edge, and
    // a window around each candidate alone placed the start where least was seen, not
    // where the trajectories run smoothest). Ranges longer than [`EDGE_RANGE`] keep a
    // window of 2 frames around each candidate, so that the cost stays linear.
    let nf = cx.t.frames();
    let cost = |s: usize, e: usize, around: usize, lo: usize, hi: usize| -> f64 {
        let (lo, hi) = if hi - lo > EDGE_RANGE {
            (around, around)
        } else {
            (lo, hi)
        };
        (lo.saturating_sub(2)..=(hi + 2).min(nf - 1))
            .flat_map(|f| [a, b].map(|m| cx.step(m, f, (a, b), (s, e), true)))
            .flatten()
            .sum()
    };
    let starts = |x: usize| cost(x, e0, x, s0, first_dec);
    let s = (s0..=first_dec)
        .min_by(|&x, &y| starts(x).total_cmp(&starts(y)))
        .unwrap_or(first_dec);
    // Ties (no continuity to tell, as where the markers are missing) go to the trial's
    // end for a run that reaches it, to the last decided frame otherwise.
    let ends = last_dec..=e0;
    // The end is placed as the start where both markers are seen in the frame after the
    // run (a label leaving a missing marker's point as that marker reappears). A run that
    // ends at the trial's end or in a gap keeps a window around each candidate: summed
    // alike, runs to the trial's end ended short (tuned labs: near markers to the end
    // undone exactly 92.2 -> 78.4 %), and so did `nick_freeform_001.c3d`'s swap up to a
    // gap both markers share (frames 0-197 for 0-199, 0-based).
    let to_end = e0 + 1 == nf;
    let seen_after = !to_end && cx.ok[a][e0 + 1] && cx.ok[b][e0 + 1];
    let end_cost = |x: usize| {
        if seen_after {
            cost(s, x, x + 1, last_dec + 1, e0 + 1)
        } else {
            cost(s, x, x + 1, x + 1, x + 1)
        }
    };
    let by_cost = |x: &usize, y: &usize| end_cost(*x).total_cmp(&end_cost(*y));
    let e = if to_end {
        ends.rev().min_by(by_cost)
    } else {
        ends.min_by(by_cost)
    }
    .unwrap_or(last_dec);
    (s, e)
}

/// The pair's link errors over the decided frames, labelled and undone (upper medians).
fn link_errors(cx: &Ctx, a: usize, b: usize, decided: &[usize]) -> (f64, f64) {
    // Frames where one marker is missing weigh as both (the sums are of two markers').
    let full = if cx.has_links(a) && cx.has_links(b) {
        2.0
    } else {
        1.0
    };
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for &f in decided {
        if let Some((x, y, n)) = cx.pair_scores(a, b, f) {
            before.push(x * full / n);
            after.push(y * full / n);
        }
    }
    (median(before), median(after))
}

/// Continuity at each edge of `s..=e`, labelled against undone.
struct Edges {
    /// Edges where undoing makes the steps smaller, of those checked.
    smoother: usize,
    checked: usize,
    /// The largest labelled step at an edge.
    edge_step: f64,
    /// The least share of the labelled steps that undoing removes at an edge, where both
    /// markers leap there (the labelled steps above both breaks); 0 otherwise.
    leap_gain: f64,
}

fn edges_checked(cx: &Ctx, a: usize, b: usize, s: usize, e: usize) -> Edges {
    let nf = cx.t.frames();
    let (mut smoother, mut checked, mut edge_step) = (0, 0, 0.0f64);
    let mut leap_gain = 1.0f64;
    for f in [s, e + 1] {
        if f == 0 || f >= nf || (f == e + 1 && e + 1 >= nf) {
            continue;
        }
        // Both markers' steps; where one marker is missing at the edge (a label that took
        // the other's point over its gap), the one step each way that spans it.
        let steps = |apply: bool| [a, b].map(|m| cx.step(m, f, (a, b), (s, e), apply));
        let (lab, und) = (steps(false), steps(true));
        let n = |v: &[Option<f64>; 2]| v.iter().flatten().count();
        let both = n(&lab) == 2 && n(&und) == 2;
        let one = n(&lab) == 1 && n(&und) == 1;
        let sum = |v: &[Option<f64>; 2]| v.iter().flatten().sum::<f64>();
        if both || one {
            let (l, u) = (sum(&lab), sum(&und));
            checked += 1;
            edge_step = edge_step.max(l);
            if u < l {
                smoother += 1;
            }
            // The breaks of the markers whose labelled steps were measured.
            let brk: f64 = [a, b]
                .iter()
                .zip(&lab)
                .filter(|(_, st)| st.is_some())
                .map(|(&m, _)| cx.break_mm(m))
                .sum();
            let leaps = l > brk;
            leap_gain = leap_gain.min(if leaps { 1.0 - u / l } else { 0.0 });
        }
    }
    if checked == 0 {
        leap_gain = 0.0;
    }
    Edges {
        smoother,
        checked,
        edge_step,
        leap_gain,
    }
}

/// The swap's confidence: the link evidence (its strength, the share of the judged frames
/// it decided, the edges' agreement) and the edges' leaps as a second witness; without
/// decided frames, continuity alone.
fn swap_confidence(
    cx: &Ctx,
    (a, b): (usize, usize),
    (s, e): (usize, usize),
    decided: &[usize],
    (before, after): (f64, f64),
    edges: &Edges,
) -> f64 {
    let Edges {
        smoother,
        checked,
        leap_gain,
        ..
    } = *edges;
    let strength = (before - after).max(0.0);
    let p_link = 1.0 - (-strength / 2.0).exp();
    // The share of the frames the links could judge (both markers, or one, seen with a
    // link) that they decided: frames where nothing can be judged (both markers missing,
    // as often near a trial's end) neither confirm a swap nor weaken it.
    let judged = (s..=e)
        .filter(|&f| cx.pair_scores(a, b, f).is_some())
        .count();
    let share = (decided.len() as f64 / judged.max(1) as f64)
        .min(1.0)
        .sqrt();
    if decided.is_empty() {
        // Continuity alone: two trajectories leaping into each other's places at every
        // edge is a swap a person would call, but one with no link to confirm it.
        if checked > 0 && smoother == checked {
            0.6
        } else {
            0.3
        }
    } else {
        let p_cont = if checked == 0 || smoother == checked {
            1.0
        } else if smoother == 0 {
            0.5
        } else {
            0.8
        };
        // The two trajectories leaping into each other's places at every edge is evidence
        // of its own, beside the links: a long swap of two markers of one segment keeps
        // their own link whole and mends the others only in the frames where they are
        // seen, and the edges then say what the links say weakly.
        let p_edges = EDGE_WEIGHT * leap_gain.max(0.0);
        1.0 - (1.0 - p_link * share * p_cont) * (1.0 - p_edges)
    }
    .clamp(0.0, 1.0)
}
