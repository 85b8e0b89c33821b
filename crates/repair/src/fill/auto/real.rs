//! The real gap's candidate fills: every applicable method's fill of the gap itself (a
//! donor method's also smoothed, and PCA's wide model on long gaps), each kept as it is,
//! slowed to the step rule, or dropped as implausible; then, on long gaps, each held to the
//! skeleton as a candidate of its own. What `auto` then scores on the artificial gaps.

use super::holes::RESID_NODES;
use super::kind::Kind;
use super::model::{donor_index, drift};
use super::steps::slowed;
use crate::fill::skeleton::Skeleton;
use crate::fill::{
    dist, fill_raw, fill_with, linear, step_ratio, FillMethod, FillOptions, Plan, SkipReason, Span,
    Target, STEP_FACTOR,
};
use crate::profile::{self, Method, Work};

/// Donor fills are also tied to the samples by a spline through their residuals (see
/// `anchor`) on gaps up to this many frames; across longer gaps the spline wanders. Up to 20
/// or up to 80 frames instead were each chosen in 0 of 26 folds of `fill_eval --nested`
/// (up to 20: held-apart cells at 40 frames 0.7 % better to 2.8 % worse, tuned ones 2–5 %
/// worse; up to 80: held-apart cells at 80 frames 0.4–3.5 % worse).
const SMOOTH_MAX: usize = 40;

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

/// Fills of the gap, each with the method that made it.
pub(super) type Fills = Vec<(FillMethod, Vec<[f64; 3]>)>;

/// The mean distance between two fills of the same frames.
pub(super) fn apart(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter().zip(b).map(|(p, q)| dist(*p, *q)).sum::<f64>() / a.len().max(1) as f64
}

/// The candidates gathered so far, with what those dropped said.
pub(super) struct Candidates {
    pub fills: Fills,
    /// `kinds[c]`: what kind of fill candidate `c` is, beside its method.
    pub kinds: Vec<Kind>,
    /// The first reason a method gave for not filling.
    reason: Option<SkipReason>,
    /// The smallest step ratio of the fills dropped as implausible.
    implausible: f64,
    /// Per donor method (see [`donor_index`]), its residuals' drift across the real gap.
    pub drift_real: [Option<f64>; 3],
}

impl Candidates {
    /// Keep `v`, `m`'s fill, as it is when it moves the marker no faster than the step
    /// rule allows, else slowed to it, else not at all.
    fn keep(&mut self, t: &Target, span: Span, m: FillMethod, v: Vec<[f64; 3]>, kind: Kind) {
        let r = step_ratio(t, span, &v);
        if r <= STEP_FACTOR {
            self.fills.push((m, v));
            self.kinds.push(kind);
        } else if let Some(d) = slowed(t, span, &v) {
            self.kinds.push(Kind {
                moved: apart(&v, &d),
                ..kind
            });
            self.fills.push((m, d));
        } else {
            self.implausible = self.implausible.min(r);
        }
    }

    /// Every candidate of `cands` filling the real gap, then the wide PCA model's (`wide`:
    /// its plan and options) when there is one.
    pub(super) fn gather(
        t: &Target,
        span: Span,
        plan: &Plan,
        opts: &FillOptions,
        cands: &[FillMethod],
        wide: Option<(&Plan, &FillOptions)>,
    ) -> Candidates {
        let len = span.len();
        let mut c = Candidates {
            fills: Vec::new(),
            kinds: Vec::new(),
            reason: None,
            implausible: f64::INFINITY,
            drift_real: [None; 3],
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
                            c.drift_real[i] = drift(&raw);
                        }
                        c.keep(t, span, m, raw.anchored(span), Kind::default());
                        if let Some(v) = raw.smoothed(span).filter(|_| span.len() <= SMOOTH_MAX) {
                            let kind = Kind {
                                smooth: true,
                                ..Kind::default()
                            };
                            c.keep(t, span, m, v, kind);
                        }
                    }
                    Err(r) => {
                        c.reason.get_or_insert(r);
                    }
                }
                continue;
            }
            let v = fill_with(m, t, span, plan, opts);
            drop(time);
            match v {
                Ok(v) => c.keep(t, span, m, v, Kind::default()),
                Err(r) => {
                    c.reason.get_or_insert(r);
                }
            }
        }
        if let Some((w, wide_opts)) = wide {
            let time = profile::time(Work::Real(Method::PcaWide));
            let raw = fill_raw(FillMethod::Pca, t, span, w, wide_opts, 1);
            drop(time);
            if let Ok(raw) = raw {
                let kind = Kind {
                    wide: true,
                    ..Kind::default()
                };
                c.keep(t, span, FillMethod::Pca, raw.anchored(span), kind);
            }
        }
        c
    }

    /// The candidates as they stand, or why the gap cannot be filled: when every donor
    /// fill at the trial's edge was implausible and `auto` chooses (`many`), the last valid
    /// sample held; with none at all, the step rule's verdict or the first method's reason.
    pub(super) fn settle(mut self, t: &Target, span: Span, many: bool) -> Result<Self, SkipReason> {
        let edge = span.before.is_none() || span.after.is_none();
        if self.fills.is_empty() && self.implausible.is_finite() && edge && many {
            // Every donor fill at the edge is implausible: hold the last valid sample.
            if let Ok(v) = linear::hold(t, span) {
                self.fills.push((FillMethod::Hold, v));
                self.kinds.push(Kind::default());
            }
        }
        if self.fills.is_empty() {
            return Err(if self.implausible.is_finite() {
                SkipReason::Implausible {
                    step_ratio: self.implausible,
                }
            } else {
                self.reason.unwrap_or(SkipReason::NoContext)
            });
        }
        Ok(self)
    }

    /// Without the polynomials, when the artificial gaps had to be shorter than the real one
    /// and a donor method is there: shorter holes flatter polynomials, which are far off on
    /// long gaps anyway.
    pub(super) fn drop_polynomials(&mut self) {
        if self.fills.iter().any(|(m, _)| !m.is_polynomial()) {
            let poly: Vec<bool> = self.fills.iter().map(|(m, _)| m.is_polynomial()).collect();
            let mut k = poly.iter();
            self.kinds.retain(|_| !*k.next().unwrap_or(&false));
            self.fills.retain(|(m, _)| !m.is_polynomial());
        }
    }

    /// Long gaps: each fill also held to the skeleton (Tits et al. 2018), as a candidate of
    /// its own, so the artificial gaps say whether the constraint helps here. Short gaps
    /// drift too little for it to matter. The skeleton, when made, for the scoring.
    pub(super) fn held_to_skeleton(
        &mut self,
        t: &Target,
        span: Span,
        plan: &Plan,
        opts: &FillOptions,
    ) -> Option<Skeleton> {
        let sk = if span.len() >= SKELETON_FROM {
            Skeleton::new(t, span, plan, opts)
        } else {
            None
        }?;
        for c in 0..self.fills.len() {
            let kind = self.kinds[c];
            if self.fills[c].0 == FillMethod::Hold || kind.smooth || kind.wide {
                continue;
            }
            let mut v = self.fills[c].1.clone();
            if sk.apply(t, span, &mut v) && step_ratio(t, span, &v) <= STEP_FACTOR {
                self.fills.push((self.fills[c].0, v));
                // A slowed fill held to the skeleton is still not its method's own.
                self.kinds.push(Kind {
                    skel: true,
                    moved: kind.moved,
                    ..Kind::default()
                });
            }
        }
        Some(sk)
    }
}
