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
mod real;
pub(super) mod steps;

use super::{
    dist, step_ratio, FillMethod, FillOptions, FillOutcome, Plan, SkipReason, Span, Target,
};
use crate::profile::{self, Count, Work};
use holes::{other_markers, same_marker, score, Scoring};
use kind::Kind;
pub use model::{
    accel_ratio, calibrated, features, gap_donors, log_ratio, speed_ratio, Diag, GapDonors,
    FEATURES, LEADS,
};
use model::{deviation, prior};
use real::{apart, Candidates, Fills};

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
    let len = span.len();
    let (trials, plans, shortened) = artificial_holes(t, span, plan, opts);
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
    let wide = wide_plan.as_ref().map(|w| (w, &wide_opts));
    let mut c =
        Candidates::gather(t, span, plan, opts, cands, wide).settle(t, span, cands.len() > 1)?;
    if shortened {
        c.drop_polynomials();
    }
    let real_sk = c.held_to_skeleton(t, span, plan, opts);
    let ctx = Scoring {
        t,
        plan,
        plans: &plans,
        opts,
        wide_plan: wide_plan.as_ref(),
        wide_opts: &wide_opts,
        real_sk: real_sk.as_ref(),
    };
    let drift_real = c.drift_real;
    let (mut fills, mut kinds) = (c.fills, c.kinds);
    let holes = score(&ctx, &trials, &mut fills, &mut kinds);
    if holes.truth.is_empty() {
        let (v, mut choice) = fallback(fills, len);
        choice.expected_error = Some(prior(t, len));
        return Ok((v, choice));
    }
    Ok(chosen(t, span, &fills, &kinds, &holes, &drift_real))
}

/// The artificial gaps a gap's candidates are scored on, with the plans of those cut in
/// other markers, and whether they had to be shorter than the gap. Short gaps: polynomials
/// and donors differ clearly, half the trials tell them apart.
fn artificial_holes(
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
) -> (Vec<holes::Trial>, Vec<Plan>, bool) {
    let len = span.len();
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
    (trials, plans, shortened)
}

/// The fill `auto` chooses from the scored candidates ([`choose`]), and its expected error
/// from the evidence the choice leaves ([`Diag`]).
fn chosen(
    t: &Target,
    span: Span,
    fills: &Fills,
    kinds: &[Kind],
    holes: &holes::Scores,
    drift_real: &[Option<f64>; 3],
) -> (Vec<[f64; 3]>, Choice) {
    let len = span.len();
    let (preds, truth, scored) = (&holes.preds, &holes.truth, holes.scored);
    let (bend_holes, drift_holes) = (holes.bend_holes, holes.drift_holes);
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
        accel: accel_ratio(&t.data.xyz[t.m], |f| t.ok(f), span.first, len),
        speed: speed_ratio(&t.data.xyz[t.m], |f| t.ok(f), span.first, len),
        lead: Some(fills[blend[0].0].0),
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
    (out, choice)
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
