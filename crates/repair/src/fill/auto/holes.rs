//! `auto`'s artificial gaps: where they are cut (in the target's own data, else over the
//! real gap's frames in other markers) and how every candidate scores on them.

use super::super::anchor::Raw;
use super::super::skeleton::Skeleton;
use super::super::{
    dist, fill_raw, fill_with, step_ratio, FillMethod, FillOptions, Plan, Span, Target, STEP_FACTOR,
};
use super::kind::Kind;
use super::model::{deviation, donor_index, drift};
use super::steps::slowed;
use crate::profile::{self, Count, Method, Work};

/// Other markers tried at most when the target has too little room. Each costs a plan and,
/// from `GLOERSEN_FROM` frames, a published-PCA model of its own (their holes are in
/// different markers, so they share none): on 03_rolling a fifth of the published PCA's
/// time. 3 instead of 4 (issue 35, `docs/price.md`), `fill_eval --methods auto --gaps 10`
/// against 4: held-apart cells 1.8 % better to 1.1 % worse, tuned ones 1.1 % better to
/// 1.1 % worse, the calibration within half a point; 2 was 4.1 % worse on the tuned labs'
/// walking gaps of 80 frames in 2–3 markers. 8 instead of 4 was chosen in 0 of 26 folds
/// of `fill_eval --nested`.
const OTHER_MARKERS: usize = 3;
/// Residuals per side the spline goes through: 8 instead of 5 was chosen in 25 of 26 folds
/// of `fill_eval --nested` (3 in 1), every cell within 0.5 % of 5's: it hardly matters.
pub(super) const RESID_NODES: usize = 8;
/// Candidates this many times worse than the best after the first third of the trials are
/// no longer scored, except the runner-up (see `holes::score`). 5 instead of 3 was chosen
/// in 26 of 26 folds of `fill_eval --nested` (tuned labs' cells 3.3 % better to 0.8 %
/// worse, held-apart ones within 1 %), at no cost on the pipeline bench.
const PRUNE: f64 = 5.0;

/// An artificial gap: the marker, the span handed to the methods (its anchors), and the
/// hole (frames treated as invalid and scored); `plan` is `None` for the target's own plan.
pub(super) struct Trial {
    m: usize,
    span: Span,
    pub hole: (usize, usize),
    pub plan: Option<usize>,
}

/// What the candidates are scored with: the target, its plan and the plans of other
/// markers' holes, the wide PCA model's plan (long gaps), the real gap's skeleton.
pub(super) struct Scoring<'a> {
    pub t: &'a Target<'a>,
    pub plan: &'a Plan,
    pub plans: &'a [Plan],
    pub opts: &'a FillOptions,
    pub wide_plan: Option<&'a Plan>,
    pub wide_opts: &'a FillOptions,
    pub real_sk: Option<&'a Skeleton>,
}

/// The candidates' predictions over the artificial gaps where every candidate succeeded
/// (`preds[c]`, compared on the same samples), the true samples there, the number of holes
/// scored, and over them the sum of the truth's mean deviation from the line between the
/// anchors and per donor method the sum and count of its residuals' drift.
pub(super) struct Scores {
    pub preds: Vec<Vec<[f64; 3]>>,
    pub truth: Vec<[f64; 3]>,
    pub scored: usize,
    pub bend_holes: f64,
    pub drift_holes: [(f64, usize); 3],
}

/// Scores every candidate (`fills`, with the kind of each) on `trials`; candidates far
/// behind the best after the first third of the trials, except the runner-up, are dropped
/// from both lists.
pub(super) fn score(
    ctx: &Scoring,
    trials: &[Trial],
    fills: &mut Vec<(FillMethod, Vec<[f64; 3]>)>,
    kinds: &mut Vec<Kind>,
) -> Scores {
    let t = ctx.t;
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
    for tr in trials {
        if scored == first_look && fills.len() > 1 {
            prune(fills, &mut preds, kinds, &truth);
        }
        let tt = Target {
            m: tr.m,
            hole: Some(tr.hole),
            data: t.data,
        };
        let (got, raws) = hole_fills(ctx, tr, &tt, fills, kinds);
        if got.len() < fills.len() {
            continue;
        }
        scored += 1;
        profile::count(Count::Scored);
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
    Scores {
        preds,
        truth,
        scored,
        bend_holes,
        drift_holes,
    }
}

/// Drops the candidates already far behind the best on the holes scored so far (their
/// predictions `preds` against `truth`) from every list.
fn prune(
    fills: &mut Vec<(FillMethod, Vec<[f64; 3]>)>,
    preds: &mut Vec<Vec<[f64; 3]>>,
    kinds: &mut Vec<Kind>,
    truth: &[[f64; 3]],
) {
    let err: Vec<f64> = preds
        .iter()
        .map(|p| p.iter().zip(truth).map(|(a, b)| dist(*a, *b)).sum::<f64>())
        .collect();
    // The runner-up stays whatever its score: how far the two best fills of the
    // real gap are apart is the expected error's best evidence, lost with it.
    let mut sorted = err.clone();
    sorted.sort_by(f64::total_cmp);
    let cut = (PRUNE * sorted[0]).max(sorted[1]);
    let keep: Vec<bool> = err.iter().map(|&e| e <= cut).collect();
    if keep.iter().any(|k| !k) {
        let mut k = keep.iter();
        fills.retain(|_| *k.next().unwrap_or(&true));
        let mut k = keep.iter();
        preds.retain(|_| *k.next().unwrap_or(&true));
        let mut k = keep.iter();
        kinds.retain(|_| *k.next().unwrap_or(&true));
    }
}

/// Every candidate's fill of the artificial hole `tr` (the trial `tt` with the hole made),
/// in the order of `fills`, scored as it would be used; it stops at the first candidate
/// that cannot fill it. With the fills, each donor method's raw prediction, shared by its
/// variants.
#[allow(clippy::type_complexity)]
fn hole_fills(
    ctx: &Scoring,
    tr: &Trial,
    tt: &Target,
    fills: &[(FillMethod, Vec<[f64; 3]>)],
    kinds: &[Kind],
) -> (Vec<Vec<[f64; 3]>>, Vec<(FillMethod, Option<Raw>)>) {
    let Scoring {
        plan,
        plans,
        opts,
        wide_plan,
        wide_opts,
        real_sk,
        ..
    } = *ctx;
    let p = tr.plan.map_or(plan, |i| &plans[i]);
    let mut got: Vec<Vec<[f64; 3]>> = Vec::with_capacity(fills.len());
    let mut sk: Option<Option<Skeleton>> = None;
    // Each donor method's raw prediction of this trial, shared by its variants.
    let mut raws: Vec<(FillMethod, Option<Raw>)> = Vec::new();
    for (c, (m, _)) in fills.iter().enumerate() {
        // A constrained candidate follows its method's plain fill of this trial.
        let kind = kinds[c];
        let base = if kind.skel {
            (0..c).find(|&b| {
                let k = kinds[b];
                !k.skel && !k.smooth && !k.wide && fills[b].0 == *m
            })
        } else {
            None
        };
        // The wide model on the target's own holes; elsewhere (or where its donors are
        // not valid) it is scored as the plain PCA fill.
        let method = if kind.wide {
            Method::PcaWide
        } else {
            Method::of(*m)
        };
        let time = profile::time(Work::Scored(method));
        let wide_fill = match (&wide_plan, kind.wide, tr.plan) {
            (Some(w), true, None) => fill_raw(*m, tt, tr.span, w, wide_opts, 1)
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
                        let ctx = if kinds
                            .iter()
                            .zip(fills.iter())
                            .any(|(k, f)| k.smooth && f.0 == *m)
                        {
                            RESID_NODES
                        } else {
                            1
                        };
                        raws.push((*m, fill_raw(*m, tt, tr.span, p, opts, ctx).ok()));
                        raws.len() - 1
                    }
                };
                match &raws[i].1 {
                    Some(r) if kind.smooth => {
                        Ok(r.smoothed(tr.span).unwrap_or_else(|| r.anchored(tr.span)))
                    }
                    Some(r) => Ok(r.anchored(tr.span)),
                    None => Err(()),
                }
            }
            None => fill_with(*m, tt, tr.span, p, opts).map_err(|_| ()),
        };
        drop(time);
        let Ok(mut v) = made else {
            break;
        };
        if kind.skel {
            let s = sk.get_or_insert_with(|| match (tr.plan, &real_sk) {
                (None, Some(r)) => r.without(tr.hole, tr.span.len()),
                _ => Skeleton::new(tt, tr.span, p, opts),
            });
            if let Some(s) = s {
                s.apply(tt, tr.span, &mut v);
            }
        }
        // Scored as it would be used: slowed down where it is too fast.
        if step_ratio(tt, tr.span, &v) > STEP_FACTOR {
            if let Some(d) = slowed(tt, tr.span, &v) {
                v = d;
            }
        }
        got.push(v);
    }
    (got, raws)
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
pub(super) fn same_marker(
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
pub(super) fn other_markers(
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
