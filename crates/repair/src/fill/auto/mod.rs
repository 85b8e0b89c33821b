//! `auto`: for each gap, every applicable method fills the gap and also artificial gaps of
//! the same length whose truth is known, and the fill that scores lowest there is used:
//! one method, or the blend of the best k (any k) weighted by inverse squared error.
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
//!
//! The parts live apart: `holes` cuts the artificial gaps and scores each candidate on
//! them, `model` turns the scores into an expected error, and `steps` slows a fill that
//! moves the marker faster than it ever does; this file holds the candidates and the
//! choice among them.

mod holes;
mod kind;
mod model;
pub(super) mod steps;

use super::skeleton::Skeleton;
use super::{
    dist, fill_raw, fill_with, linear, step_ratio, FillMethod, FillOptions, FillOutcome, Plan,
    SkipReason, Span, Target, STEP_FACTOR,
};
use crate::profile::{self, Count, Method, Work};
use holes::{other_markers, same_marker, score, Scoring, RESID_NODES};
use kind::Kind;
pub use model::{calibrated, features, gap_donors, log_ratio, Diag, GapDonors, FEATURES};
use model::{deviation, donor_index, drift, prior};
use steps::slowed;

/// Candidates for gaps with valid data on both sides.
///
/// Linear and the quadratic were candidates too; without them `auto`'s mean errors per
/// cell of `fill_eval` (set × markers × length) on the tuned labs were 13 % lower to 2.4 %
/// higher (lower in 10 of 20 cells, the same in 2), and on the held-apart labs 3.3 % lower
/// to 1.3 % higher: they did not pay.
const INTERIOR: [FillMethod; 7] = [
    FillMethod::Lagrange5,
    FillMethod::Spline,
    FillMethod::Rigid,
    FillMethod::Pca,
    FillMethod::Kalman,
    FillMethod::Pattern,
    FillMethod::Gloersen,
];
/// Candidates at the trial's edges (no polynomial extrapolation).
const EDGE: [FillMethod; 5] = [
    FillMethod::Rigid,
    FillMethod::Pca,
    FillMethod::Kalman,
    FillMethod::Pattern,
    FillMethod::Gloersen,
];
/// Gap length from which a gap is scored on the full number of artificial gaps (shorter
/// ones on half) and the target's shorter holes stand in for missing room. 5 (every length
/// the evaluation measures) instead of 20 was chosen leave-one-lab-out (`fill_eval
/// --nested`: 10 instead of 20 in 26 of 26 folds, 5 instead of 10 in 22): held-apart
/// walking cells at 5 and 10 frames up to 4.7 % better, full-body ones up to 3 % worse,
/// expected errors within 2× 0.5 points more often; the pipeline bench took 1.08× as long.
const LONG: usize = 5;
/// Donor fills are also tied to the samples by a spline through their residuals (see
/// `anchor`) on gaps up to this many frames; across longer gaps the spline wanders. Up to 20
/// or up to 80 frames instead were each chosen in 0 of 26 folds of `fill_eval --nested`
/// (up to 20: held-apart cells at 40 frames 0.7 % better to 2.8 % worse, tuned ones 2–5 %
/// worse; up to 80: held-apart cells at 80 frames 0.4–3.5 % worse).
const SMOOTH_MAX: usize = 40;
/// Gap length from which PCA also enters with a wide model: the `WIDE_NEIGHBOURS` nearest
/// markers over ±`WIDE_WINDOW` frames (towards Gløersen & Federolf's whole-trial model),
/// which carries long gaps where the nearest markers alone do not. From 80 frames instead
/// was chosen in 0 of 26 folds of `fill_eval --nested` (cells at 40 frames 0.2 % better to
/// 2.6 % worse); from 20 frames (with the published PCA from 20) in 26 of 26, for held-apart
/// cells at 20 frames 0.8 % better to 1 % worse, but the pipeline bench, whose gaps are up
/// to 30 frames, took 2× as long (1.17 s, over its 1 s limit): it stays at 40.
const WIDE_FROM: usize = 40;
/// The wide model's markers: all of the plan's nearest (see `plan::NEAREST`); 12 instead of
/// 16 was chosen in 1 of 26 folds, and 24 with the plan's pool of 24 in 25 of 26.
const WIDE_NEIGHBOURS: usize = 24;
/// The wide model's window, frames either side: ±4 000 instead of ±2 000 was chosen in 25
/// of 26 folds (±1 000 in 1), all cells within 0.5 % (only trials of more than 4 000
/// frames differ); the pipeline bench took 1.04× as long.
const WIDE_WINDOW: usize = 4000;
/// Gap length from which the Kalman smoother is a candidate: it trains a model of its own
/// per group of artificial gaps and runs its covariance recursion over each, which long
/// gaps are worth and short ones are not. Weighed from 20 frames, it took 2–4 % off
/// `auto`'s errors at 20 frames on the corpus evaluation, and the 100-marker pipeline bench
/// (gaps of 2–30 frames) took 2.5× as long (user time of one run, 4.6 s against 1.9 s),
/// beyond what the bench may take; from 80 frames instead of 40 was chosen in 0 of 26
/// folds of `fill_eval --nested` (held-apart cells at 40 frames 2.5 % better to 1.4 %
/// worse, tuned ones up to 3.5 % worse).
const KALMAN_FROM: usize = 40;
/// Gap length from which Gløersen & Federolf's published PCA is a candidate: the shortest
/// the evaluation measures. It entered at 40 frames before; each step down was chosen in 26
/// of 26 folds of `fill_eval --nested`, the held-apart cells of the length it opened 5–10 %
/// better at 20 frames, 0.4–5 % at 10, and 1.6 % better to 1.7 % worse at 5 (from 80
/// instead of 40: 0 of 26 folds, held-apart cells at 40 frames 8–15 % worse). The pipeline
/// bench is above [`GLOERSEN_BUDGET`], so its time is unchanged; on trials below the cap
/// each gap costs two eigen-decompositions of every marker's coordinates per artificial gap
/// (the evaluation's gaps of 20 frames took 189 s instead of 6 s on 2 cores, about 60 ms a
/// gap). From 10 again, for its price (issue 35: the 671 corpus fills of 5–9 frames), was
/// measured on the held-apart labs (`fill_eval --held-apart --gaps 10`): 5-frame cells
/// 0.6 % better to 3.1 % worse (full body, one marker), beyond the 2 % allowed; not kept.
const GLOERSEN_FROM: usize = 5;
/// Largest frames × (3 × markers)² of a trial on which `auto` weighs the published PCA: its
/// covariance of every coordinate over the whole trial and two eigen-decompositions, per
/// artificial gap, grow with it. A cost cap, not an accuracy choice: every trial of the
/// evaluation's corpora is below it (the largest, 4 921 frames × 64 markers, is 1.8 × 10⁸),
/// and the pipeline bench's 10 000 frames × 100 markers (9 × 10⁸), whose few gaps that
/// merge to 40 frames or more took it from 0.6 s to 7.7 s, is above it. So no figure of the
/// evaluation depends on it and no lab chose it.
const GLOERSEN_BUDGET: f64 = 2.5e8;

/// The size of the published PCA's model on the target's trial (see [`GLOERSEN_BUDGET`]).
fn gloersen_cost(t: &Target) -> f64 {
    let cols = 3.0 * t.data.xyz.len() as f64;
    t.data.frames as f64 * cols * cols
}

/// Gap length from which each fill is also held to the skeleton. From 20 frames instead,
/// on the corpus evaluation, walking gaps of 20 frames were 2–4 % better and full-body ones
/// 3 % worse (at 175 and 240 Hz the skeleton's distance ranges nearby miss the poses in the
/// gap and pull good fills off), and the 100-marker pipeline bench, whose gaps are up to
/// 30 frames, took 1.3× as long.
const SKELETON_FROM: usize = 40;

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
    pub fourth: Option<(FillMethod, f64)>,
    pub expected_error: Option<f64>,
    /// Whether the fill (or a part of the blend) was held to the skeleton.
    pub skeleton: bool,
    /// What the expected error was made from (see [`Diag`]).
    pub diag: Option<Diag>,
}

impl Choice {
    fn single(method: FillMethod) -> Choice {
        Choice {
            method,
            second: None,
            third: None,
            fourth: None,
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
            blended_with_3: self.fourth.map(|s| s.0),
            weight_3: self.fourth.map(|s| s.1),
            expected_error: self.expected_error,
            skeleton: self.skeleton,
        }
    }
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
    let edge = span.before.is_none() || span.after.is_none();
    let len = span.len();
    // Short gaps: polynomials and donors differ clearly, half the trials tell them apart.
    let want = if len >= LONG {
        opts.auto_trials
    } else {
        opts.auto_trials.div_ceil(2)
    };
    let enough = want.div_ceil(2);
    let cut = profile::time(Work::Holes);
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
    drop(cut);
    profile::count_n(Count::Holes, trials.len());
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
        .then(|| {
            profile::count(Count::WidePlan);
            Plan::build(t, span, &wide_opts)
        })
        .filter(|w| w.pca.len() > plan.pca.len());
    if let Some(w) = &wide_plan {
        let _ = w
            .exclude
            .set(plan.exclude.get().cloned().unwrap_or_default());
    }
    let apart = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter().zip(b).map(|(p, q)| dist(*p, *q)).sum::<f64>() / a.len().max(1) as f64
    };
    let mut fills: Vec<(FillMethod, Vec<[f64; 3]>)> = Vec::new();
    // kinds[c]: what kind of fill candidate c is, beside its method.
    let mut kinds: Vec<Kind> = Vec::new();
    let mut reason = None;
    let mut implausible = f64::INFINITY;
    // Per donor method (see `donor_index`), its residuals' drift across the real gap.
    let mut drift_real = [None; 3];
    let mut keep = |m: FillMethod, v: Vec<[f64; 3]>, kind: Kind, fills: &mut Vec<_>| {
        let r = step_ratio(t, span, &v);
        if r <= STEP_FACTOR {
            fills.push((m, v));
            kinds.push(kind);
        } else if let Some(d) = slowed(t, span, &v) {
            kinds.push(Kind {
                moved: apart(&v, &d),
                ..kind
            });
            fills.push((m, d));
        } else {
            implausible = implausible.min(r);
        }
    };
    for &m in cands {
        // `auto` weighs the smoother on long gaps only; asked for alone, it fills any.
        if m == FillMethod::Kalman && len < KALMAN_FROM && cands.len() > 1 {
            continue;
        }
        // Gløersen & Federolf's whole-trial model, from `GLOERSEN_FROM` frames: two
        // eigen-decompositions of every marker's coordinates per artificial gap.
        if m == FillMethod::Gloersen
            && cands.len() > 1
            && (len < GLOERSEN_FROM || gloersen_cost(t) > GLOERSEN_BUDGET)
        {
            continue;
        }
        let time = profile::time(Work::Real(Method::of(m)));
        if m.is_donor() {
            let raw = fill_raw(m, t, span, plan, opts, RESID_NODES);
            drop(time);
            match raw {
                Ok(raw) => {
                    if let Some(i) = donor_index(m) {
                        drift_real[i] = drift(&raw);
                    }
                    keep(m, raw.anchored(span), Kind::default(), &mut fills);
                    if let Some(v) = raw.smoothed(span).filter(|_| span.len() <= SMOOTH_MAX) {
                        let kind = Kind {
                            smooth: true,
                            ..Kind::default()
                        };
                        keep(m, v, kind, &mut fills);
                    }
                }
                Err(r) => {
                    reason.get_or_insert(r);
                }
            }
            continue;
        }
        let v = fill_with(m, t, span, plan, opts);
        drop(time);
        match v {
            Ok(v) => keep(m, v, Kind::default(), &mut fills),
            Err(r) => {
                reason.get_or_insert(r);
            }
        }
    }
    if let Some(w) = &wide_plan {
        let time = profile::time(Work::Real(Method::PcaWide));
        let raw = fill_raw(FillMethod::Pca, t, span, w, &wide_opts, 1);
        drop(time);
        if let Ok(raw) = raw {
            let kind = Kind {
                wide: true,
                ..Kind::default()
            };
            keep(FillMethod::Pca, raw.anchored(span), kind, &mut fills);
        }
    }
    if fills.is_empty() && implausible.is_finite() && edge && cands.len() > 1 {
        // Every donor fill at the edge is implausible: hold the last valid sample.
        if let Ok(v) = linear::hold(t, span) {
            fills.push((FillMethod::Hold, v));
            kinds.push(Kind::default());
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
        kinds.retain(|_| !*k.next().unwrap_or(&false));
        fills.retain(|(m, _)| !m.is_polynomial());
    }
    // Long gaps: each fill also held to the skeleton (Tits et al. 2018), as a candidate of
    // its own, so the artificial gaps say whether the constraint helps here. Short gaps
    // drift too little for it to matter.
    let real_sk = if len >= SKELETON_FROM {
        Skeleton::new(t, span, plan, opts)
    } else {
        None
    };
    {
        if let Some(sk) = &real_sk {
            for c in 0..fills.len() {
                if fills[c].0 == FillMethod::Hold || kinds[c].smooth || kinds[c].wide {
                    continue;
                }
                let mut v = fills[c].1.clone();
                if sk.apply(t, span, &mut v) && step_ratio(t, span, &v) <= STEP_FACTOR {
                    fills.push((fills[c].0, v));
                    // A slowed fill held to the skeleton is still not its method's own.
                    kinds.push(Kind {
                        skel: true,
                        moved: kinds[c].moved,
                        ..Kind::default()
                    });
                }
            }
        }
    }

    let ctx = Scoring {
        t,
        plan,
        plans: &plans,
        opts,
        wide_plan: wide_plan.as_ref(),
        wide_opts: &wide_opts,
        real_sk: real_sk.as_ref(),
    };
    let holes = score(&ctx, &trials, &mut fills, &mut kinds);
    let (preds, truth, scored) = (&holes.preds, &holes.truth, holes.scored);
    let (bend_holes, drift_holes) = (holes.bend_holes, holes.drift_holes);
    if truth.is_empty() {
        let (v, mut choice) = fallback(fills, len);
        choice.expected_error = Some(prior(t, len));
        return Ok((v, choice));
    }
    let choosing = profile::time(Work::Choose);
    let Chosen {
        err: e,
        blend,
        order,
    } = choose(preds, truth);
    drop(choosing);
    let out: Vec<[f64; 3]> = (0..len)
        .map(|i| combine(&blend, |c| fills[c].1[i]))
        .collect();

    let others: Vec<(FillMethod, f64)> = blend[1..].iter().map(|&(c, w)| (fills[c].0, w)).collect();
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
        step: Some(step_ratio(t, span, &out)),
        // How far the step rule moved the fill from its methods' predictions.
        slowed: Some(blend.iter().map(|&(c, w)| w * kinds[c].moved).sum::<f64>())
            .filter(|&d| d > 0.0),
    };
    let choice = Choice {
        skeleton: blend.iter().any(|&(c, _)| kinds[c].skel),
        method: fills[blend[0].0].0,
        second: others.first().copied(),
        third: others.get(1).copied(),
        fourth: others.get(2).copied(),
        expected_error: Some(calibrated(&diag)),
        diag: Some(diag),
    };
    Ok((out, choice))
}

/// The choice on the artificial gaps (`preds[c]`: candidate c's predictions of `truth`): the
/// best candidate alone, or the best k blended with weights 1 / error² (inverse expected
/// variance), whichever k scores lowest there; with its mean error and the candidates by
/// their own errors, best first.
///
/// No limit on k: each step up was chosen on the tuned labs' cells of `fill_eval` and in
/// every fold of `fill_eval --nested` (each lab by the other labs' preference). Up to 4
/// instead of 3 was 0–4.3 % better (one cell 0.1 % worse), 5 instead of 4 0–2.3 % better
/// (one 1.9 % worse), any instead of 5 up to 4.2 % better (one 0.6 % worse); up to 2 was
/// 1–8 % worse than 3. Weights of 1 / error² give a candidate far behind next to nothing.
fn choose(preds: &[Vec<[f64; 3]>], truth: &[[f64; 3]]) -> Chosen {
    let score = |blend: &[(usize, f64)]| {
        let e: f64 = truth
            .iter()
            .enumerate()
            .map(|(i, q)| dist(combine(blend, |c| preds[c][i]), *q))
            .sum();
        e / truth.len().max(1) as f64
    };
    let mut order: Vec<(f64, usize)> = (0..preds.len()).map(|c| (score(&[(c, 1.0)]), c)).collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best = (order[0].0, vec![(order[0].1, 1.0)]);
    for k in 2..=order.len() {
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
    Chosen {
        err: best.0,
        blend: best.1,
        order,
    }
}

/// A choice among the candidates (see [`choose`]).
struct Chosen {
    /// Its mean error on the artificial gaps.
    err: f64,
    /// The candidates blended, with their shares (one with share 1 for a single method).
    blend: Vec<(usize, f64)>,
    /// Every candidate's own mean error there, with its index, best first.
    order: Vec<(f64, usize)>,
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
