//! One jump found: a marker's span of broken frames placed at its leaps, the change of its
//! links across its edges, the steady-offset witness, and its confidence; and the jump of a
//! marker with few links found by its two opposite leaps alone.

use super::context::{median, norm, Ctx};
use super::finds::{Evidence, Find, FindKind, SwapOptions};

/// Confidence of a jump found by continuity alone whose second leap takes back the first
/// exactly.
const LEAP_ONLY_CONFIDENCE: f64 = 0.75;

/// A jump found by continuity alone is noise when the median leap inside it is above this
/// share of its smaller edge leap ...
const QUIET_SHARE: f64 = 0.25;
/// ... and its confidence is then multiplied by this (as when its leaps are small).
const NOISY: f64 = 0.5;

/// Frames either side of a jump's edge over which its links' change across the edge is
/// measured ([`Ctx::link_change`]).
const EDGE_WINDOW: usize = 3;

/// A jump's links must change across its edges by at least twice this (in tolerances, the
/// lower median over its links) to count in full; below this, not at all.
const LINK_CHANGE_FLOOR: f64 = 0.5;

/// Frames either side of a jump's edge searched for its leap.
const EDGE_SEARCH: usize = 3;

/// Most the steady-offset witness adds to a jump's link evidence (as the probability of an
/// independent witness): half, as a swap's edges ([`EDGE_WEIGHT`]), so that it cannot
/// settle a jump alone (0.3 from the links and edges, as a jump whose links barely break,
/// becomes 0.65 with a full witness: reported, not settled).
const OFFSET_WEIGHT: f64 = 0.5;

/// The jump of `a` over the span `s..=e` of broken frames (`decided` those the links
/// decided): its edges at its leaps, its links' evidence, the continuity at its edges, the
/// steady-offset witness and its confidence.
pub(super) fn jump_find(
    cx: &Ctx,
    a: usize,
    s: usize,
    e: usize,
    decided: Vec<usize>,
    opts: &SwapOptions,
) -> Find {
    let before = median(
        decided
            .iter()
            .filter_map(|&f| cx.score(a, f, None))
            .collect(),
    );
    let (s, e) = jump_edges(cx, a, s, e);
    // The steps at the edges against the marker's usual steps.
    let (smoother, checked, edge_step) = edge_leaps(cx, a, s, e);
    // The links' change across the edges (the larger of the two that can be measured):
    // the links must break at the edge, not only be broken, for the break to be the
    // jump's ([`Ctx::link_change`]).
    let change = link_change_at_edges(cx, a, s, e);
    let at_edge = change.map_or(1.0, |c| {
        ((c - LINK_CHANGE_FLOOR) / LINK_CHANGE_FLOOR).clamp(0.0, 1.0)
    });
    let p_link = (1.0 - (-2.0 * (before - 1.0).max(0.0)).exp()) * at_edge;
    let inside = decided.iter().filter(|&&f| f >= s && f <= e).count();
    let share = (inside as f64 / (e + 1 - s) as f64).sqrt();
    // A label that lands on another point leaves its path twice, going and coming back;
    // skin moving or a marker wobbling does neither.
    // No edge to check (the episode runs from a gap or the trial's end to another): the
    // links alone, which a marker set that bends slowly (a trunk at the trial's ends) also
    // breaks, and no report.
    let p_cont = match (smoother, checked) {
        (0, 0) => 0.3,
        (b, c) if b == c => 1.0,
        (1, _) => 0.4,
        _ => 0.1,
    };
    // Both edges breaking is not enough alone: the links must say the marker left its
    // place over the episode's frames.
    let links_say = (p_cont * (0.3 + 0.7 * p_link * share)).clamp(0.0, 1.0);
    // The steady offset between two cancelling leaps is a second witness beside the
    // links, as a swap's edges are (an offset across the links changes their lengths
    // little, and a long jump's links then break barely past their tolerance).
    // Measured only where it could lift the find to a report: a witness is at most 1, and
    // most spans of jump frames (a strained pose, a marker settling after a gap) stay
    // under the report with a full one; they are dropped, and measuring the offset (every
    // frame of the span carried by the link partners' motion) was most of their cost.
    let most = (1.0 - (1.0 - links_say) * (1.0 - OFFSET_WEIGHT)).clamp(0.0, 1.0);
    let witness = if most < opts.min_report {
        None
    } else {
        cx.offset_witness(a, s, e).map(|o| o.share())
    };
    let g = witness.unwrap_or(0.0);
    let confidence = (1.0 - (1.0 - links_say) * (1.0 - OFFSET_WEIGHT * g)).clamp(0.0, 1.0);
    Find {
        kind: FindKind::Jump,
        markers: vec![a],
        first: s,
        last: e,
        confidence,
        settled: confidence >= opts.min_confidence,
        evidence: Evidence {
            links: cx.links[a].len(),
            frames_decided: inside,
            link_error: before,
            link_error_undone: 0.0,
            edges_smoother: smoother,
            edges_checked: checked,
            edge_step_mm: edge_step,
            offset_share: witness,
        },
    }
}

/// Each edge of the jump `s..=e` moved to the largest leap within a few frames, when that
/// is a break: the frames a link decides can stop short of the edge (an offset along a link
/// changes its length little), and the jump's samples are the ones between the two leaps.
fn jump_edges(cx: &Ctx, a: usize, s: usize, e: usize) -> (usize, usize) {
    let nf = cx.t.frames();
    let near = |edge: usize, lo: usize, hi: usize| -> usize {
        (edge.saturating_sub(EDGE_SEARCH).max(lo)..=(edge + EDGE_SEARCH).min(hi))
            .filter_map(|f| Some((cx.leap(a, f)?, f)))
            .filter(|&(l, _)| l > cx.break_mm(a))
            .max_by(|x, y| x.0.total_cmp(&y.0))
            .map_or(edge, |(_, f)| f)
    };
    let s = near(s, 1, e);
    let e = if e + 1 < nf {
        near(e + 1, s + 1, nf - 1) - 1
    } else {
        e
    };
    (s, e)
}

/// The marker's steps at the jump's edges: (edges that break, edges checked, the largest
/// step).
fn edge_leaps(cx: &Ctx, a: usize, s: usize, e: usize) -> (usize, usize, f64) {
    let nf = cx.t.frames();
    let (mut smoother, mut checked, mut edge_step) = (0, 0, 0.0f64);
    for f in [s, e + 1] {
        if f >= nf {
            continue;
        }
        if let Some(st) = cx.step(a, f, (a, a), (0, 0), false) {
            checked += 1;
            edge_step = edge_step.max(st);
            if st > cx.break_mm(a) {
                smoother += 1;
            }
        }
    }
    (smoother, checked, edge_step)
}

/// The links' change across the jump's edges, the larger of the two that can be measured
/// ([`Ctx::link_change`] over [`EDGE_WINDOW`] frames either side).
fn link_change_at_edges(cx: &Ctx, a: usize, s: usize, e: usize) -> Option<f64> {
    let nf = cx.t.frames();
    let w = EDGE_WINDOW;
    [
        (s > 0).then(|| cx.link_change(a, s..(s + w).min(e + 1), s.saturating_sub(w)..s)),
        (e + 1 < nf).then(|| {
            cx.link_change(
                a,
                (e + 1).saturating_sub(w).max(s)..e + 1,
                e + 1..(e + 1 + w).min(nf),
            )
        }),
    ]
    .into_iter()
    .flatten()
    .flatten()
    .fold(None, |acc: Option<f64>, c| {
        Some(acc.map_or(c, |x| x.max(c)))
    })
}

/// A jump of a marker with fewer than two links, found by continuity alone between two
/// opposite leaps ([`Ctx::leap_pairs`]): how nearly the second leap takes back the first
/// (a label on another point and back: exactly; a foot striking the ground and leaving it:
/// seldom) is the confidence, at most [`LEAP_ONLY_CONFIDENCE`].
pub(super) fn leap_jump_find(cx: &Ctx, a: usize, s: usize, e: usize, opts: &SwapOptions) -> Find {
    let (v1, v2) = (cx.leap_vec(a, s), cx.leap_vec(a, e + 1));
    let closure = match (v1, v2) {
        (Some(v1), Some(v2)) => {
            let sum: [f64; 3] = std::array::from_fn(|c| v1[c] + v2[c]);
            1.0 - norm(&sum) / norm(&v1).min(norm(&v2)).max(f64::MIN_POSITIVE)
        }
        _ => 0.0,
    };
    let (smoother, checked, edge_step) = edge_leaps(cx, a, s, e);
    // A label on another point follows that point, as smooth as any marker: its two leaps
    // stand out of a quiet span. Leaps amid leaps as large are a noisy trajectory (a fast
    // arm seen by few cameras), which closes on itself as often as not.
    let inner: Vec<f64> = (s + 2..e).filter_map(|f| cx.leap(a, f)).collect();
    let edge = match (v1, v2) {
        (Some(v1), Some(v2)) => norm(&v1).min(norm(&v2)),
        _ => 0.0,
    };
    let quiet = if !inner.is_empty() && median(inner) > QUIET_SHARE * edge {
        NOISY
    } else {
        1.0
    };
    // With no link to confirm it, a leap just past a break is as likely a glitch of the
    // cameras (two of them, opposite by chance, frames apart) as a label on another point:
    // continuity alone calls a jump whose leaps are both at least twice a break.
    let plain = if edge >= 2.0 * cx.break_mm(a) {
        1.0
    } else {
        NOISY
    };
    // A marker with links (two or three, none deciding): the span must also hold a steady
    // offset from the link partners, the leaps' own (none measured: no find).
    let witness = (cx.links[a].len() >= 2).then(|| cx.offset_witness(a, s, e));
    let steady = match witness {
        None => 1.0,
        Some(w) => w.map_or(0.0, |o| o.steady),
    };
    let confidence =
        (LEAP_ONLY_CONFIDENCE * closure.max(0.0) * quiet * plain * steady).clamp(0.0, 1.0);
    Find {
        kind: FindKind::Jump,
        markers: vec![a],
        first: s,
        last: e,
        confidence,
        settled: confidence >= opts.min_confidence,
        evidence: Evidence {
            links: cx.links[a].len(),
            frames_decided: 0,
            // The error of the one link, if any (one link cannot say which of its two
            // markers strayed), for a find that is reported: most spans between opposite
            // leaps are not, and this is the costliest part of their evidence.
            link_error: if confidence >= opts.min_report {
                median((s..=e).filter_map(|f| cx.score(a, f, None)).collect())
            } else {
                0.0
            },
            link_error_undone: 0.0,
            edges_smoother: smoother,
            edges_checked: checked,
            edge_step_mm: edge_step,
            offset_share: witness.flatten().map(|o| o.share()),
        },
    }
}
