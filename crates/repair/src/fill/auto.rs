//! `auto`: for each gap, every applicable method fills the gap and also artificial gaps of
//! the same length whose truth is known, and the fill that scores lowest there is used:
//! one method, or the blend of the best two or three weighted by inverse squared error.
//! Each donor method (rigid, pattern, PCA) enters twice on gaps up to 40 frames: tied to
//! the valid samples by the line through its two anchor residuals, and by a spline through
//! its residuals at several frames on each side (see `anchor`). From 40 frames PCA also
//! enters with a wide model (more markers, a longer window).
//!
//! Artificial gaps are cut first from the same marker, anywhere in the PCA training window
//! where it and its donors are valid (nearest the real gap first, non-overlapping first),
//! with the same donors, so scores describe the fill that will be used. When the marker has
//! too little room (short trials, long gaps), the real gap's frames are knocked out of
//! other markers valid there (each with its own donors), which tells how hard these frames
//! are for each method; long gaps are also scored on the marker's own shorter holes (then
//! among the donor methods only, since short holes flatter polynomials). The PCA model a
//! trial is scored with never saw the trial's hole.
//! Without any artificial gap, PCA is used for long gaps and the quintic for short ones.

use serde::Serialize;

use super::anchor::Raw;
use super::skeleton::Skeleton;
use super::{
    dist, fill_raw, fill_with, linear, step_ratio, FillMethod, FillOptions, FillOutcome, Plan,
    SkipReason, Span, Target, STEP_FACTOR,
};

/// Candidates for gaps with valid data on both sides.
const INTERIOR: [FillMethod; 8] = [
    FillMethod::Lagrange5,
    FillMethod::Spline,
    FillMethod::Rigid,
    FillMethod::Pca,
    FillMethod::Kalman,
    FillMethod::Pattern,
    FillMethod::Lagrange2,
    FillMethod::Linear,
];
/// Candidates at the trial's edges (no polynomial extrapolation).
const EDGE: [FillMethod; 4] = [
    FillMethod::Rigid,
    FillMethod::Pca,
    FillMethod::Kalman,
    FillMethod::Pattern,
];
/// Other markers tried at most when the target has too little room.
const OTHER_MARKERS: usize = 4;
/// Gap length from which the target's shorter holes stand in for missing room.
const LONG: usize = 20;
/// Donor fills are also tied to the samples by a spline through their residuals (see
/// `anchor`) on gaps up to this many frames; across longer gaps the spline wanders (on the
/// corpus evaluation it lost at 80 frames).
const SMOOTH_MAX: usize = 40;
/// Residuals per side the spline goes through (10 scored the same on the corpus
/// evaluation, at twice the cost).
const RESID_NODES: usize = 5;
/// Gap length from which PCA also enters with a wide model: the `WIDE_NEIGHBOURS` nearest
/// markers over ±`WIDE_WINDOW` frames (towards Gløersen & Federolf's whole-trial model),
/// which carries long gaps where the nearest markers alone do not. On the corpus
/// evaluation it took 2–5 % off `auto`'s errors at 40 and 80 frames, and 1–7 % at 20, where
/// it is not used: a model of 16 markers over 4 000 frames costs more than short gaps are
/// worth in batch repairs.
const WIDE_FROM: usize = 40;
const WIDE_NEIGHBOURS: usize = 16;
const WIDE_WINDOW: usize = 2000;
/// Gap length from which the Kalman smoother is a candidate, with the wide PCA model: it
/// trains a model of its own per group of artificial gaps and runs its covariance recursion
/// over each, which long gaps are worth and short ones are not. Weighed from 20 frames, it
/// took 2–4 % off `auto`'s errors at 20 frames on the corpus evaluation, and the
/// 100-marker pipeline bench (gaps of 2–30 frames) took 2.5× as long (user time of one
/// run, 4.6 s against 1.9 s); from 40 frames it adds 3 % there.
const KALMAN_FROM: usize = WIDE_FROM;
/// Gap length from which each fill is also held to the skeleton. From 20 frames instead,
/// on the corpus evaluation, walking gaps of 20 frames were 2–4 % better and full-body ones
/// 3 % worse (at 175 and 240 Hz the skeleton's distance ranges nearby miss the poses in the
/// gap and pull good fills off), and the 100-marker pipeline bench, whose gaps are up to
/// 30 frames, took 1.3× as long.
const SKELETON_FROM: usize = 40;
/// Most candidates blended.
const BLEND: usize = 3;
/// Candidates this many times worse than the best after the first third of the trials are
/// no longer scored.
const PRUNE: f64 = 3.0;

/// `auto`'s candidates for a gap: donor methods only at the trial's edges.
pub(super) fn candidates(span: Span) -> &'static [FillMethod] {
    if span.before.is_none() || span.after.is_none() {
        &EDGE
    } else {
        &INTERIOR
    }
}

/// What `auto` chose for one gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Choice {
    pub method: FillMethod,
    /// Methods blended in, with their shares (the first method has the rest).
    pub second: Option<(FillMethod, f64)>,
    pub third: Option<(FillMethod, f64)>,
    pub expected_error: Option<f64>,
    /// Whether the fill (or a part of the blend) was held to the skeleton.
    pub skeleton: bool,
    /// What the expected error was made from (see [`Diag`]).
    pub diag: Option<Diag>,
}

/// The evidence behind an expected error: the choice's mean error on the artificial gaps
/// (`scored`), and how far the two best-scored candidates' fills of the real gap are apart
/// (`spread`: their mean distance; 0 with one candidate). Both in the data's units.
///
/// The rest says how much harder the real gap is than the holes that scored it, from what
/// is known there: how far the best and the third-best fills are apart (`spread3`, data
/// units); how far the two best candidates' predictions were apart on the holes
/// (`spread_holes`, data units: where they agreed there but not on the real gap, the gap is
/// unlike the holes); how far the fill strays from the straight line between its anchors
/// relative to how far the truth strayed from it in the holes (`bend`: what polynomial
/// errors scale with); and how far the donor methods' residuals drift from one anchor to
/// the other relative to the holes (`drift`, geometric mean over the donor methods: the
/// linear tie to the anchors assumes a steady drift, so a large one means an error the
/// anchors only partly correct).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Diag {
    pub scored: f64,
    pub spread: f64,
    pub len: usize,
    pub spread3: Option<f64>,
    pub spread_holes: Option<f64>,
    pub bend: Option<f64>,
    pub drift: Option<f64>,
    /// Whether the gap was filled again in the second pass (see `fill_gaps`) with a
    /// neighbour's first-pass fill as a donor; the evidence above is the first pass's.
    pub refilled: bool,
    /// For a refilled gap: the second pass's score on its artificial gaps over the first's.
    pub rescored: Option<f64>,
    /// For a refilled gap: the largest first-pass score among its nearest donors' fills
    /// that overlap it, over `scored` (a refill is no better than what it leans on).
    pub donor_err: Option<f64>,
    /// For a refilled gap: the largest share of its frames where one of its nearest donors
    /// is a fill rather than a recording.
    pub share: Option<f64>,
    /// For a refilled gap: the second pass's spread (see above) over the first's.
    pub respread: Option<f64>,
}

impl Choice {
    fn single(method: FillMethod) -> Choice {
        Choice {
            method,
            second: None,
            third: None,
            expected_error: None,
            skeleton: false,
            diag: None,
        }
    }

    pub fn outcome(&self) -> FillOutcome {
        FillOutcome::Filled {
            method: self.method,
            blended_with: self.second.map(|s| s.0),
            weight: self.second.map(|s| s.1),
            blended_with_2: self.third.map(|s| s.0),
            weight_2: self.third.map(|s| s.1),
            expected_error: self.expected_error,
            skeleton: self.skeleton,
        }
    }
}

/// An artificial gap: the marker, the span handed to the methods (its anchors), and the
/// hole (frames treated as invalid and scored); `plan` is `None` for the target's own plan.
struct Trial {
    m: usize,
    span: Span,
    hole: (usize, usize),
    plan: Option<usize>,
}

/// Fills `span` with the best of `cands` (one method, or a blend for `auto`), after
/// dropping candidates whose fill moves the marker implausibly fast; the choice carries its
/// expected error, scored on artificial gaps nearby.
pub(super) fn fill(
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
    cands: &[FillMethod],
) -> Result<(Vec<[f64; 3]>, Choice), SkipReason> {
    fill_checked(t, span, plan, opts, cands, true)
}

/// [`fill`]; with `estimate` false the first candidate that fills is returned as it is,
/// unchecked and without an expected error (evaluations of single methods).
pub(super) fn fill_checked(
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
    cands: &[FillMethod],
    estimate: bool,
) -> Result<(Vec<[f64; 3]>, Choice), SkipReason> {
    let edge = span.before.is_none() || span.after.is_none();
    if !estimate {
        let mut reason = None;
        for &m in cands {
            match fill_with(m, t, span, plan, opts) {
                Ok(v) => return Ok((v, Choice::single(m))),
                Err(r) => {
                    reason.get_or_insert(r);
                }
            }
        }
        return Err(reason.unwrap_or(SkipReason::NoContext));
    }
    let len = span.len();
    // Short gaps: polynomials and donors differ clearly, half the trials tell them apart.
    let want = if len >= LONG {
        opts.auto_trials
    } else {
        opts.auto_trials.div_ceil(2)
    };
    let enough = want.div_ceil(2);
    let mut trials = same_marker(t, span, plan, len, want, opts);
    let full = trials.len();
    let mut plans: Vec<Plan> = Vec::new();
    let mut shortened = false;
    if full < enough {
        // Too little room for the gap's length: the marker's own shorter holes (for long
        // gaps) say which donors serve it; the real gap's frames in other markers say how
        // hard these frames are.
        if len >= LONG {
            let mut l = len / 2;
            while l >= 5 && trials.len() < enough {
                let more = same_marker(t, span, plan, l, want - trials.len(), opts);
                shortened |= !more.is_empty();
                trials.extend(more);
                l /= 2;
            }
        }
        other_markers(t, span, plan, want - full, opts, &mut trials, &mut plans);
    }
    // PCA may train one scoring model without several of the target's holes (and fills
    // the real gap with the model of the nearest ones: see `pca`), so this comes before
    // the candidates fill the real gap.
    let _ = plan.exclude.set(
        trials
            .iter()
            .filter(|tr| tr.plan.is_none())
            .map(|tr| tr.hole)
            .collect(),
    );
    // The wide PCA model's plan (long gaps), scored on the same artificial holes.
    let wide_opts = FillOptions {
        pca_neighbours: WIDE_NEIGHBOURS.max(opts.pca_neighbours),
        pca_window: WIDE_WINDOW.max(opts.pca_window),
        ..opts.clone()
    };
    let wide_plan = (len >= WIDE_FROM && cands.contains(&FillMethod::Pca))
        .then(|| Plan::build(t, span, &wide_opts))
        .filter(|w| w.pca.len() > plan.pca.len());
    if let Some(w) = &wide_plan {
        let _ = w
            .exclude
            .set(plan.exclude.get().cloned().unwrap_or_default());
    }
    // wide[c]: candidate c is PCA with the wide model.
    let mut wide: Vec<bool> = Vec::new();
    let mut fills: Vec<(FillMethod, Vec<[f64; 3]>)> = Vec::new();
    // smooth[c]: candidate c is its donor method's prediction tied to the samples by a
    // spline through the residuals (see `anchor`) instead of the line.
    let mut smooth: Vec<bool> = Vec::new();
    let mut reason = None;
    let mut implausible = f64::INFINITY;
    // Per donor method (see `donor_index`), its residuals' drift across the real gap.
    let mut drift_real = [None; 3];
    let mut keep = |m: FillMethod, v: Vec<[f64; 3]>, sm: bool, wd: bool, fills: &mut Vec<_>| {
        let r = step_ratio(t, span, &v);
        if r <= STEP_FACTOR {
            fills.push((m, v));
            smooth.push(sm);
            wide.push(wd);
        } else if let Some(d) = slowed(t, span, &v) {
            fills.push((m, d));
            smooth.push(sm);
            wide.push(wd);
        } else {
            implausible = implausible.min(r);
        }
    };
    for &m in cands {
        // `auto` weighs the smoother on long gaps only; asked for alone, it fills any.
        if m == FillMethod::Kalman && len < KALMAN_FROM && cands.len() > 1 {
            continue;
        }
        if m.is_donor() {
            match fill_raw(m, t, span, plan, opts, RESID_NODES) {
                Ok(raw) => {
                    if let Some(i) = donor_index(m) {
                        drift_real[i] = drift(&raw);
                    }
                    keep(m, raw.anchored(span), false, false, &mut fills);
                    if let Some(v) = raw.smoothed(span).filter(|_| span.len() <= SMOOTH_MAX) {
                        keep(m, v, true, false, &mut fills);
                    }
                }
                Err(r) => {
                    reason.get_or_insert(r);
                }
            }
            continue;
        }
        match fill_with(m, t, span, plan, opts) {
            Ok(v) => keep(m, v, false, false, &mut fills),
            Err(r) => {
                reason.get_or_insert(r);
            }
        }
    }
    if let Some(w) = &wide_plan {
        if let Ok(raw) = fill_raw(FillMethod::Pca, t, span, w, &wide_opts, 1) {
            keep(FillMethod::Pca, raw.anchored(span), false, true, &mut fills);
        }
    }
    if fills.is_empty() && implausible.is_finite() && edge && cands.len() > 1 {
        // Every donor fill at the edge is implausible: hold the last valid sample.
        if let Ok(v) = linear::hold(t, span) {
            fills.push((FillMethod::Hold, v));
            smooth.push(false);
            wide.push(false);
        }
    }
    if fills.is_empty() {
        return Err(if implausible.is_finite() {
            SkipReason::Implausible {
                step_ratio: implausible,
            }
        } else {
            reason.unwrap_or(SkipReason::NoContext)
        });
    }

    // Shorter holes flatter polynomials, which are far off on long gaps anyway.
    if shortened && fills.iter().any(|(m, _)| !m.is_polynomial()) {
        let poly: Vec<bool> = fills.iter().map(|(m, _)| m.is_polynomial()).collect();
        let mut k = poly.iter();
        smooth.retain(|_| !*k.next().unwrap_or(&false));
        let mut k = poly.iter();
        wide.retain(|_| !*k.next().unwrap_or(&false));
        fills.retain(|(m, _)| !m.is_polynomial());
    }
    // Long gaps: each fill also held to the skeleton (Tits et al. 2018), as a candidate of
    // its own, so the artificial gaps say whether the constraint helps here. Short gaps
    // drift too little for it to matter.
    let mut skel = vec![false; fills.len()];
    let real_sk = if len >= SKELETON_FROM {
        Skeleton::new(t, span, plan, opts)
    } else {
        None
    };
    {
        if let Some(sk) = &real_sk {
            for c in 0..fills.len() {
                if fills[c].0 == FillMethod::Hold || smooth[c] || wide[c] {
                    continue;
                }
                let mut v = fills[c].1.clone();
                if sk.apply(t, span, &mut v) && step_ratio(t, span, &v) <= STEP_FACTOR {
                    fills.push((fills[c].0, v));
                    skel.push(true);
                    smooth.push(false);
                    wide.push(false);
                }
            }
        }
    }

    // preds[c]: candidate c's predictions over the artificial gaps where every candidate
    // succeeded (so all are compared on the same samples), truth: the true samples.
    let mut preds: Vec<Vec<[f64; 3]>> = vec![Vec::new(); fills.len()];
    let mut truth: Vec<[f64; 3]> = Vec::new();
    // After the first third of the trials, candidates already far behind the best are dropped:
    // with weights 1 / error², one PRUNE times worse would carry under 1/PRUNE² of the
    // weight, and scoring it further (PCA above all) is most of auto's cost.
    let first_look = trials.len().div_ceil(3).max(2);
    let mut scored = 0;
    // Over the scored holes: the sum of the truth's mean deviation from the line between
    // the anchors, and per donor method the sum and count of its residuals' drift.
    let mut bend_holes = 0.0;
    let mut drift_holes = [(0.0, 0usize); 3];
    for tr in &trials {
        if scored == first_look && fills.len() > 1 {
            let err: Vec<f64> = preds
                .iter()
                .map(|p| p.iter().zip(&truth).map(|(a, b)| dist(*a, *b)).sum::<f64>())
                .collect();
            let best = err.iter().copied().fold(f64::INFINITY, f64::min);
            let keep: Vec<bool> = err.iter().map(|&e| e <= PRUNE * best).collect();
            if keep.iter().any(|k| !k) {
                let mut k = keep.iter();
                fills.retain(|_| *k.next().unwrap_or(&true));
                let mut k = keep.iter();
                preds.retain(|_| *k.next().unwrap_or(&true));
                let mut k = keep.iter();
                skel.retain(|_| *k.next().unwrap_or(&true));
                let mut k = keep.iter();
                smooth.retain(|_| *k.next().unwrap_or(&true));
                let mut k = keep.iter();
                wide.retain(|_| *k.next().unwrap_or(&true));
            }
        }
        let tt = Target {
            m: tr.m,
            hole: Some(tr.hole),
            data: t.data,
        };
        let p = tr.plan.map_or(plan, |i| &plans[i]);
        let mut got: Vec<Vec<[f64; 3]>> = Vec::with_capacity(fills.len());
        let mut sk: Option<Option<Skeleton>> = None;
        // Each donor method's raw prediction of this trial, shared by its variants.
        let mut raws: Vec<(FillMethod, Option<Raw>)> = Vec::new();
        for (c, (m, _)) in fills.iter().enumerate() {
            // A constrained candidate follows its method's plain fill of this trial.
            let base = if skel[c] {
                (0..c).find(|&b| !skel[b] && !smooth[b] && !wide[b] && fills[b].0 == *m)
            } else {
                None
            };
            // The wide model on the target's own holes; elsewhere (or where its donors are
            // not valid) it is scored as the plain PCA fill.
            let wide_fill = match (&wide_plan, wide[c], tr.plan) {
                (Some(w), true, None) => fill_raw(*m, &tt, tr.span, w, &wide_opts, 1)
                    .ok()
                    .map(|r| r.anchored(tr.span)),
                _ => None,
            };
            let made = match base {
                Some(b) => Ok(got[b].clone()),
                None if wide_fill.is_some() => Ok(wide_fill.unwrap_or_default()),
                None if m.is_donor() => {
                    let i = match raws.iter().position(|r| r.0 == *m) {
                        Some(i) => i,
                        None => {
                            let ctx = if smooth.iter().zip(&fills).any(|(&s, f)| s && f.0 == *m) {
                                RESID_NODES
                            } else {
                                1
                            };
                            raws.push((*m, fill_raw(*m, &tt, tr.span, p, opts, ctx).ok()));
                            raws.len() - 1
                        }
                    };
                    match &raws[i].1 {
                        Some(r) if smooth[c] => {
                            Ok(r.smoothed(tr.span).unwrap_or_else(|| r.anchored(tr.span)))
                        }
                        Some(r) => Ok(r.anchored(tr.span)),
                        None => Err(()),
                    }
                }
                None => fill_with(*m, &tt, tr.span, p, opts).map_err(|_| ()),
            };
            let Ok(mut v) = made else {
                break;
            };
            if skel[c] {
                let s = sk.get_or_insert_with(|| match (tr.plan, &real_sk) {
                    (None, Some(r)) => r.without(tr.hole, tr.span.len()),
                    _ => Skeleton::new(&tt, tr.span, p, opts),
                });
                if let Some(s) = s {
                    s.apply(&tt, tr.span, &mut v);
                }
            }
            // Scored as it would be used: slowed down where it is too fast.
            if step_ratio(&tt, tr.span, &v) > STEP_FACTOR {
                if let Some(d) = slowed(&tt, tr.span, &v) {
                    v = d;
                }
            }
            got.push(v);
        }
        if got.len() < fills.len() {
            continue;
        }
        scored += 1;
        let whole: Vec<[f64; 3]> = (tr.span.first..=tr.span.last).map(|f| tt.at(f)).collect();
        bend_holes += deviation(&tt, tr.span, &whole).unwrap_or(0.0);
        for (m, r) in &raws {
            if let (Some(i), Some(d)) = (donor_index(*m), r.as_ref().and_then(drift)) {
                drift_holes[i].0 += d;
                drift_holes[i].1 += 1;
            }
        }
        let skip = tr.hole.0 - tr.span.first;
        let n = tr.hole.1 - tr.hole.0 + 1;
        truth.extend((tr.hole.0..=tr.hole.1).map(|f| tt.at(f)));
        for (c, v) in got.into_iter().enumerate() {
            preds[c].extend_from_slice(&v[skip..skip + n]);
        }
    }
    if truth.is_empty() {
        let (v, mut choice) = fallback(fills, len);
        choice.expected_error = Some(prior(t, len));
        return Ok((v, choice));
    }
    let score = |blend: &[(usize, f64)]| {
        let e: f64 = truth
            .iter()
            .enumerate()
            .map(|(i, q)| dist(combine(blend, |c| preds[c][i]), *q))
            .sum();
        e / truth.len() as f64
    };
    let mut order: Vec<(f64, usize)> = (0..fills.len()).map(|c| (score(&[(c, 1.0)]), c)).collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The best method alone, or the best two or three blended with weights 1 / error²
    // (inverse expected variance), whichever scores lowest.
    let mut best = (order[0].0, vec![(order[0].1, 1.0)]);
    for k in 2..=order.len().min(BLEND) {
        let inv: Vec<f64> = order[..k]
            .iter()
            .map(|&(e, _)| 1.0 / e.max(1e-12).powi(2))
            .collect();
        let total: f64 = inv.iter().sum();
        if !total.is_finite() {
            break;
        }
        let blend: Vec<(usize, f64)> = order[..k]
            .iter()
            .zip(&inv)
            .map(|(&(_, c), w)| (c, w / total))
            .collect();
        let e = score(&blend);
        if e < best.0 {
            best = (e, blend);
        }
    }
    let (e, blend) = best;
    let out: Vec<[f64; 3]> = (0..len)
        .map(|i| combine(&blend, |c| fills[c].1[i]))
        .collect();

    let others: Vec<(FillMethod, f64)> = blend[1..].iter().map(|&(c, w)| (fills[c].0, w)).collect();
    let apart = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter().zip(b).map(|(p, q)| dist(*p, *q)).sum::<f64>() / a.len().max(1) as f64
    };
    let best_fill = &fills[order[0].1].1;
    let spread = order
        .get(1)
        .map_or(0.0, |&(_, c)| apart(best_fill, &fills[c].1));
    let bend_real = deviation(t, span, &out);
    let mut ln_drift = (0.0, 0);
    for (real, holes) in drift_real.iter().zip(drift_holes) {
        if let (Some(r), true) = (real, holes.1 > 0 && holes.0 > 0.0) {
            ln_drift.0 += (r / (holes.0 / holes.1 as f64)).clamp(0.05, 20.0).ln();
            ln_drift.1 += 1;
        }
    }
    let diag = Diag {
        scored: e,
        spread,
        len,
        spread3: order.get(2).map(|&(_, c)| apart(best_fill, &fills[c].1)),
        spread_holes: order
            .get(1)
            .map(|&(_, c)| apart(&preds[order[0].1], &preds[c])),
        bend: bend_real
            .filter(|_| bend_holes > 0.0)
            .map(|b| b / (bend_holes / scored as f64)),
        drift: (ln_drift.1 > 0).then(|| (ln_drift.0 / ln_drift.1 as f64).exp()),
        refilled: false,
        rescored: None,
        donor_err: None,
        share: None,
        respread: None,
    };
    let choice = Choice {
        skeleton: blend.iter().any(|&(c, _)| skel[c]),
        method: fills[blend[0].0].0,
        second: others.first().copied(),
        third: others.get(1).copied(),
        expected_error: Some(calibrated(&diag)),
        diag: Some(diag),
    };
    Ok((out, choice))
}

/// A fill too fast for the marker, slowed down: the largest share `a` of its deviation
/// from the straight line across the gap (from the held anchor at the trial's edges) whose
/// steps all stay within [`STEP_FACTOR`] times the marker's largest recorded step. The
/// largest step is convex in `a`, so bisection finds it. `None` when even the line is too
/// fast (or the marker has no recorded step).
fn slowed(t: &Target, span: Span, v: &[[f64; 3]]) -> Option<Vec<[f64; 3]>> {
    let base = match (span.before, span.after) {
        (Some(_), Some(_)) => super::linear::fill(t, span).ok()?,
        _ => linear::hold(t, span).ok()?,
    };
    let mix = |a: f64| -> Vec<[f64; 3]> {
        base.iter()
            .zip(v)
            .map(|(b, p)| [0, 1, 2].map(|k| b[k] + a * (p[k] - b[k])))
            .collect()
    };
    if step_ratio(t, span, &base) > STEP_FACTOR || t.data.max_step[t.m] <= 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..20 {
        let mid = 0.5 * (lo + hi);
        if step_ratio(t, span, &mix(mid)) <= STEP_FACTOR {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(mix(lo))
}

/// Mean distance of `v` (samples over `span`'s frames) from the straight line between the
/// target's anchors (from the held anchor at the trial's edges): how far the marker bends
/// away from what the simplest fill assumes.
fn deviation(t: &Target, span: Span, v: &[[f64; 3]]) -> Option<f64> {
    let line = match (span.before, span.after) {
        (Some(_), Some(_)) => linear::fill(t, span).ok()?,
        _ => linear::hold(t, span).ok()?,
    };
    Some(line.iter().zip(v).map(|(a, b)| dist(*a, *b)).sum::<f64>() / v.len().max(1) as f64)
}

/// The slot of a donor method in per-method tallies. The Kalman smoother has none: its
/// residuals are its own smoothed estimate's, near zero at the anchors whatever the gap.
fn donor_index(m: FillMethod) -> Option<usize> {
    match m {
        FillMethod::Rigid => Some(0),
        FillMethod::Pattern => Some(1),
        FillMethod::Pca => Some(2),
        _ => None,
    }
}

/// How far a donor prediction's residual moves from one anchor to the other (at the
/// trial's edges: the one anchor's residual, which the fill keeps throughout).
fn drift(r: &Raw) -> Option<f64> {
    match (r.before.first(), r.after.first()) {
        (Some(b), Some(a)) => Some(dist(b.1, a.1)),
        (Some((_, e)), None) | (None, Some((_, e))) => Some(dist(*e, [0.0; 3])),
        _ => None,
    }
}

/// The weighted sum of candidates' predictions (weights sum to 1).
fn combine(blend: &[(usize, f64)], pred: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
    let mut o = [0.0; 3];
    for &(c, w) in blend {
        let p = pred(c);
        for k in 0..3 {
            o[k] += w * p[k];
        }
    }
    o
}

/// Without artificial gaps to judge by: the quintic (then the spline) for short interior
/// gaps, PCA (then rigid) otherwise — the best methods a priori on gait data.
fn fallback(mut fills: Vec<(FillMethod, Vec<[f64; 3]>)>, len: usize) -> (Vec<[f64; 3]>, Choice) {
    let pref: &[FillMethod] = if len <= 10 {
        &[
            FillMethod::Lagrange5,
            FillMethod::Spline,
            FillMethod::Pca,
            FillMethod::Rigid,
        ]
    } else {
        &[FillMethod::Pca, FillMethod::Rigid, FillMethod::Spline]
    };
    let pick = pref
        .iter()
        .find_map(|m| fills.iter().position(|(f, _)| f == m))
        .unwrap_or(0);
    let (method, v) = fills.swap_remove(pick);
    (v, Choice::single(method))
}

/// The expected error of a choice from its mean error on the artificial gaps.
///
/// Artificial gaps nearby miss what happens in the real gap's own frames, and the choice
/// that scored best on them flatters itself, so the score alone was over-confident on 14 %
/// of real trials' gaps. Where the candidates disagree on the real gap, its error is larger
/// than their scores say, the more so the further they disagree; longer gaps are scored on
/// fewer, shorter stand-ins; and what can be seen of the real gap says how much harder it
/// is than the holes that scored it (see [`Diag`]). So ln(expected / scored) =
/// β · x + c₁ · exp(γ · x) + c₀ over the features x of [`features`]: β by median regression
/// of ln(real / scored) on the real trials of the evaluation (`cargo run --release -p
/// repair --example fill_eval`, which also checks the model fitted leave-one-lab-out); γ by
/// least squares of the log of the fitted residuals' size, so exp(γ · x) says how far a gap
/// like this one strays from its median; c₁ widens the margin of such gaps (the value that
/// puts most gaps within 2×) and c₀ leaves 5 % of the gaps above twice their estimate: the
/// estimate is meant to vouch for a fill. One shared margin instead sets every gap's by the
/// least predictable ones, and left 17.5 % of gaps below half their estimate.
///
/// A gap filled again in the second pass keeps the first pass's evidence, with `refilled`
/// set, `rescored` and `respread` (the second pass's score and spread over the first's),
/// and what the refill leans on (`donor_err`, `share`): the second pass's own scores come
/// from artificial gaps with recorded donors where the real gap has filled ones, and alone
/// were over-confident on 10–16 % of gaps; a second pass that scores far better than the
/// first is believed only down to a ratio of about e⁻¹ (the hinge).
///
/// Leave-one-lab-out (each lab's gaps judged by a model fitted to the other labs'):
/// Spearman 0.943, 80.4 % of gaps within 2× of their estimate, 5.0 % above twice it (the
/// shipped model on the gaps it was fitted to: 79.8 %, 5.0 %). Without `respread`, 80.1 %;
/// with one shared margin and without the hinge and the donors' evidence, 77.6 %; with the
/// spread, length and square alone 74.3 %. Features that did not help (leave-one-lab-out
/// within 2× unchanged or lower): the marker's pace at the anchors and across the gap
/// against the holes', the error of the holes most like the real gap in bend, the spread,
/// median and geometric mean of the holes' errors, their number, and twice as many holes
/// (+0.4 points at 1.4× the cost). A gradient-boosted model of the features without
/// `respread`, its margin chosen the same way, did no better (79.8 %, against 80.1 %).
pub(crate) fn calibrated(d: &Diag) -> f64 {
    const BETA: [f64; FEATURES] = [
        0.0975, 0.2878, -0.0265, 0.0577, 0.1334, -0.1600, 0.1121, 0.2356, -0.1882, 0.4457, -0.4710,
        0.0883, 0.2940, 0.0899,
    ];
    const GAMMA: [f64; FEATURES] = [
        -1.2829, -0.0054, -0.0494, 0.0735, -0.0179, 0.0907, -0.0124, -0.0738, -0.0473, 0.0943,
        -0.3082, -0.0561, 0.0798, -0.0597,
    ];
    const C1: f64 = 1.5;
    const C0: f64 = -0.2814;
    d.scored.max(1e-12) * log_ratio(&features(d), &BETA, &GAMMA, C1, C0).exp()
}

/// ln(expected / scored) for features `x` under `auto`'s expected-error model (shared with the
/// evaluation that fits it).
pub fn log_ratio(
    x: &[f64; FEATURES],
    beta: &[f64; FEATURES],
    gamma: &[f64; FEATURES],
    c1: f64,
    c0: f64,
) -> f64 {
    let dot = |w: &[f64; FEATURES]| w.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
    dot(beta) + c1 * dot(gamma).clamp(-20.0, 20.0).exp() + c0
}

/// Number of the expected-error model's features.
pub const FEATURES: usize = 14;

/// The expected-error model's features (see [`calibrated`]), shared with the evaluation
/// that fits it: 1, ln q, ln(len), (ln q)², ln q₃, ln h, ln bend, ln drift, refilled,
/// ln rescored, min(ln rescored + 1, 0), ln donor_err, share, ln respread; with
/// q = spread / scored, q₃ = spread3 / scored, h = spread_holes / scored, every ratio
/// clamped to [0.05, 20] and taken as 1 where it is unknown (fewer than three or two
/// candidates, holes without bend, no donor method, not refilled), and share 0 where
/// unknown. The square lets the estimate grow faster when the candidates disagree far
/// beyond their scores.
pub(crate) fn features(d: &Diag) -> [f64; FEATURES] {
    let s = d.scored.max(1e-12);
    let ln = |r: Option<f64>| r.map_or(0.0, |r| r.clamp(0.05, 20.0).ln());
    let q = ln(Some(d.spread / s));
    let rescored = ln(d.rescored);
    [
        1.0,
        q,
        (d.len as f64).ln(),
        q * q,
        ln(d.spread3.map(|v| v / s)),
        ln(d.spread_holes.map(|v| v / s)),
        ln(d.bend),
        ln(d.drift),
        f64::from(u8::from(d.refilled)),
        rescored,
        (rescored + 1.0).min(0.0),
        ln(d.donor_err),
        d.share.unwrap_or(0.0),
        ln(d.respread),
    ]
}

/// Expected error without any artificial gap to score on: a quarter of the distance the
/// marker travels over the gap's length at its mean recorded speed (a coarse, cautious
/// guess, used only when the marker has no room for even a shorter trial gap).
fn prior(t: &Target, len: usize) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for f in 1..t.data.frames {
        if t.ok(f) && t.ok(f - 1) {
            sum += dist(t.at(f), t.at(f - 1));
            n += 1;
        }
    }
    let mean = if n > 0 { sum / n as f64 } else { 0.0 };
    0.25 * mean * (len + 1) as f64
}

/// The span of an artificial hole `a..=b`, one-sided like the real gap when that touches
/// an edge of the trial.
fn trial_span(real: Span, a: usize, b: usize, n: usize) -> Span {
    let mut s = Span::new(a, b, n);
    if real.before.is_none() {
        s.before = None;
    }
    if real.after.is_none() {
        s.after = None;
    }
    s
}

/// Up to `want` artificial gaps of the real gap's length in the target's own data, within
/// the PCA training window, where the target is valid on the hole and its anchors and
/// every donor of the plan is valid too; at least `2 + len / 2` frames from the real gap.
/// Nearest the real gap first; non-overlapping holes before half-overlapping ones.
fn same_marker(
    t: &Target,
    span: Span,
    plan: &Plan,
    len: usize,
    want: usize,
    opts: &FillOptions,
) -> Vec<Trial> {
    let n = t.data.frames;
    let sep = 2 + len / 2;
    let half = opts.pca_window.max(5 * span.len());
    let lo = span.first.saturating_sub(half);
    let hi = (span.last + half).min(n - 1);
    let mut donors: Vec<usize> = plan.rigid.clone();
    donors.extend(plan.pca.iter().map(|&(j, _)| j));
    donors.extend(plan.pattern);
    donors.sort_unstable();
    donors.dedup();
    let good: Vec<bool> = (lo..=hi)
        .map(|f| t.ok(f) && donors.iter().all(|&j| t.data.ok(j, f)))
        .collect();
    let (need_before, need_after) = (span.before.is_some(), span.after.is_some());
    // Maximal runs of good frames; holes `a..=b` with the anchors that the real gap has
    // inside the run.
    let mut cands: Vec<(usize, usize, usize)> = Vec::new(); // (distance, a, phase)
    let mut f = lo;
    while f <= hi {
        if !good[f - lo] {
            f += 1;
            continue;
        }
        let r0 = f;
        while f <= hi && good[f - lo] {
            f += 1;
        }
        let r1 = f - 1;
        let a0 = r0 + usize::from(need_before);
        let Some(a1) = (r1 + 1).checked_sub(len + usize::from(need_after)) else {
            continue;
        };
        if a0 > a1 {
            continue;
        }
        for (phase, start) in [(0, a0), (1, a0 + len.div_ceil(2))] {
            let mut a = start;
            while a <= a1 {
                let b = a + len - 1;
                let d = if b < span.first {
                    span.first - b
                } else {
                    a.saturating_sub(span.last)
                };
                if d > sep {
                    cands.push((d, a, phase));
                }
                a += len + 1;
            }
        }
    }
    cands.sort_unstable_by_key(|&(d, a, phase)| (phase, d, a));
    cands
        .into_iter()
        .take(want)
        .map(|(_, a, _)| Trial {
            m: t.m,
            span: trial_span(span, a, a + len - 1, n),
            hole: (a, a + len - 1),
            plan: None,
        })
        .collect()
}

/// Up to `want` (at most [`OTHER_MARKERS`]) artificial gaps over the real gap's own frames
/// in the markers nearest the target that are valid there, each with a plan of its own
/// made without the hole.
fn other_markers(
    t: &Target,
    span: Span,
    plan: &Plan,
    want: usize,
    opts: &FillOptions,
    trials: &mut Vec<Trial>,
    plans: &mut Vec<Plan>,
) {
    let (lo, hi) = span.outer();
    let mut ms: Vec<usize> = plan.pca.iter().map(|&(j, _)| j).collect();
    for &j in &plan.rigid {
        if !ms.contains(&j) {
            ms.push(j);
        }
    }
    for j in ms {
        if plans.len() >= want.min(OTHER_MARKERS) {
            break;
        }
        if !t.data.ok_through(j, lo, hi) {
            continue;
        }
        let tt = Target {
            m: j,
            data: t.data,
            hole: Some((span.first, span.last)),
        };
        plans.push(Plan::build(&tt, span, opts));
        trials.push(Trial {
            m: j,
            span,
            hole: (span.first, span.last),
            plan: Some(plans.len() - 1),
        });
    }
}
