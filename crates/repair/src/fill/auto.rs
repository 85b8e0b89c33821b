//! `auto`: for each gap, every applicable method fills the gap and also artificial gaps of
//! the same length cut from the same marker's valid data nearby (same donors, whose truth
//! is known). The method with the lowest mean error is used, or the inverse-error-weighted
//! blend of the best two when that scores lower still. Without room for artificial gaps,
//! a fixed preference order decides.

use super::{
    fill_with, Fill, FillMethod, FillOptions, FillOutcome, Plan, SkipReason, Span, Target,
};

/// Candidates for gaps with valid data on both sides.
const INTERIOR: [FillMethod; 6] = [
    FillMethod::Spline,
    FillMethod::Rigid,
    FillMethod::Pca,
    FillMethod::Pattern,
    FillMethod::Lagrange2,
    FillMethod::Linear,
];
/// Candidates at the trial's edges (no polynomial extrapolation).
const EDGE: [FillMethod; 3] = [FillMethod::Rigid, FillMethod::Pca, FillMethod::Pattern];
/// Positions tried per side when looking for room for artificial gaps.
const TRIES: usize = 6;

/// What `auto` chose for one gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Choice {
    pub method: FillMethod,
    pub second: Option<(FillMethod, f64)>,
    pub expected_error: Option<f64>,
}

impl Choice {
    pub fn outcome(&self) -> FillOutcome {
        FillOutcome::Filled {
            method: self.method,
            blended_with: self.second.map(|s| s.0),
            weight: self.second.map(|s| s.1),
            expected_error: self.expected_error,
        }
    }
}

/// An artificial gap: the span handed to the methods and the frames scored.
pub(super) struct Trial {
    pub span: Span,
    pub hole: (usize, usize),
}

pub(super) fn fill(
    t: &Target,
    span: Span,
    plan: &Plan,
    trials: &[Trial],
    opts: &FillOptions,
) -> Result<(Vec<[f64; 3]>, Choice), SkipReason> {
    let edge = span.before.is_none() || span.after.is_none();
    let cands: &[FillMethod] = if edge { &EDGE } else { &INTERIOR };
    let mut fills: Vec<(FillMethod, Vec<[f64; 3]>)> = Vec::new();
    let mut reason = None;
    for &m in cands {
        match fill_with(m, t, span, plan, opts) {
            Ok(v) => fills.push((m, v)),
            Err(r) => {
                reason.get_or_insert(r);
            }
        }
    }
    if fills.is_empty() {
        return Err(reason.unwrap_or(SkipReason::NoContext));
    }
    if fills.len() == 1 {
        let (m, v) = fills.remove(0);
        let choice = Choice {
            method: m,
            second: None,
            expected_error: None,
        };
        return Ok((v, choice));
    }

    // errs[c][i]: per-sample errors of candidate c over the artificial gaps where every
    // candidate succeeded (so all are compared on the same samples).
    let mut errs: Vec<Vec<f64>> = vec![Vec::new(); fills.len()];
    let mut preds: Vec<Vec<[f64; 3]>> = vec![Vec::new(); fills.len()];
    let mut truth: Vec<[f64; 3]> = Vec::new();
    for tr in trials {
        let tt = Target {
            hole: Some(tr.hole),
            ..*t
        };
        let got: Vec<Fill> = fills
            .iter()
            .map(|(m, _)| fill_with(*m, &tt, tr.span, plan, opts))
            .collect();
        if got.iter().any(|g| g.is_err()) {
            continue;
        }
        let skip = tr.hole.0 - tr.span.first;
        let len = tr.hole.1 - tr.hole.0 + 1;
        truth.extend((tr.hole.0..=tr.hole.1).map(|f| t.at(f)));
        for (c, g) in got.into_iter().enumerate() {
            if let Ok(v) = g {
                preds[c].extend_from_slice(&v[skip..skip + len]);
            }
        }
    }
    if truth.is_empty() {
        let v = fallback(fills, span.len());
        return Ok(v);
    }
    for c in 0..fills.len() {
        errs[c] = preds[c]
            .iter()
            .zip(&truth)
            .map(|(p, q)| dist(*p, *q))
            .collect();
    }
    let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len() as f64;
    let mut order: Vec<(f64, usize)> = errs.iter().map(|e| mean(e)).zip(0..).collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (e1, c1) = order[0];
    let (e2, c2) = order[1];
    let mut choice = Choice {
        method: fills[c1].0,
        second: None,
        expected_error: Some(e1),
    };
    let mut out = fills[c1].1.clone();
    if e1 > 0.0 && e2.is_finite() {
        // Inverse-error weights: the second method's share is e1 / (e1 + e2).
        let w2 = e1 / (e1 + e2);
        let eb = mean(
            &preds[c1]
                .iter()
                .zip(&preds[c2])
                .zip(&truth)
                .map(|((a, b), q)| dist(mix(*a, *b, w2), *q))
                .collect::<Vec<_>>(),
        );
        if eb < e1 {
            for (o, b) in out.iter_mut().zip(&fills[c2].1) {
                *o = mix(*o, *b, w2);
            }
            choice.second = Some((fills[c2].0, w2));
            choice.expected_error = Some(eb);
        }
    }
    Ok((out, choice))
}

/// Without artificial gaps to judge by: donors first for long gaps, the spline for short.
fn fallback(mut fills: Vec<(FillMethod, Vec<[f64; 3]>)>, len: usize) -> (Vec<[f64; 3]>, Choice) {
    let pref: &[FillMethod] = if len <= 10 {
        &[FillMethod::Spline, FillMethod::Rigid, FillMethod::Pca]
    } else {
        &[FillMethod::Rigid, FillMethod::Pca, FillMethod::Spline]
    };
    let pick = pref
        .iter()
        .find_map(|m| fills.iter().position(|(f, _)| f == m))
        .unwrap_or(0);
    let (method, v) = fills.swap_remove(pick);
    let choice = Choice {
        method,
        second: None,
        expected_error: None,
    };
    (v, choice)
}

fn mix(a: [f64; 3], b: [f64; 3], w: f64) -> [f64; 3] {
    [
        a[0] + w * (b[0] - a[0]),
        a[1] + w * (b[1] - a[1]),
        a[2] + w * (b[2] - a[2]),
    ]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Artificial gaps of the gap's length in the target's valid data: up to `per_side` on each
/// side for an interior gap, leaving a few valid samples between them and the real gap; for
/// a gap at a trial edge, the gap extended inwards by its length (same one-sided situation).
pub(super) fn artificial(t: &Target, span: Span, per_side: usize) -> Vec<Trial> {
    let n = t.data.frames;
    let len = span.len();
    let ok_run = |a: usize, b: usize| (a..=b).all(|f| t.ok(f));
    let mut out = Vec::new();
    match (span.before, span.after) {
        (Some(_), Some(_)) => {
            let step = len + 2;
            let gap0 = 2 + len / 2;
            let mut found = 0;
            for j in 0..TRIES {
                // Before: hole a..=b ends `g` valid frames before the gap.
                let g = gap0 + j * step;
                let Some(b) = span.first.checked_sub(1 + g) else {
                    break;
                };
                let Some(a) = (b + 1).checked_sub(len) else {
                    break;
                };
                if a >= 1 && ok_run(a - 1, b + 1) {
                    out.push(Trial {
                        span: Span::new(a, b, n),
                        hole: (a, b),
                    });
                    found += 1;
                    if found == per_side {
                        break;
                    }
                }
            }
            found = 0;
            for j in 0..TRIES {
                let a = span.last + 1 + gap0 + j * step;
                let b = a + len - 1;
                if b + 1 >= n {
                    break;
                }
                if ok_run(a - 1, b + 1) {
                    out.push(Trial {
                        span: Span::new(a, b, n),
                        hole: (a, b),
                    });
                    found += 1;
                    if found == per_side {
                        break;
                    }
                }
            }
        }
        (None, Some(after)) => {
            let b = after + len - 1;
            if b + 1 < n && ok_run(after, b + 1) {
                out.push(Trial {
                    span: Span::new(span.first, b, n),
                    hole: (after, b),
                });
            }
        }
        (Some(before), None) => {
            if let Some(a) = (before + 1).checked_sub(len) {
                if a >= 1 && ok_run(a - 1, before) {
                    out.push(Trial {
                        span: Span::new(a, span.last, n),
                        hole: (a, before),
                    });
                }
            }
        }
        (None, None) => {}
    }
    out
}
