//! How a donor method's prediction is tied to the marker's valid samples around the gap.
//!
//! A donor method (rigid, pattern, PCA) predicts the marker from other markers; its error
//! (the residual: sample − prediction) drifts slowly. The classic correction blends the two
//! anchor residuals linearly across the gap, so the fill meets the valid samples. The
//! residual is usually much smoother than the trajectory itself, so a cubic spline through
//! the residuals at several valid frames on each side follows its drift better than the
//! line does, on short gaps above all (a spline of the trajectory is the best single method
//! there). `auto` scores both variants on its artificial gaps and keeps what wins.

use super::data::{Span, Target};
use super::spline;

/// Most frames beyond the nearest valid ones looked at for context residuals, per node.
const REACH: usize = 3;

/// A donor method's raw prediction over the span and its residuals next to it.
#[derive(Debug, Clone)]
pub(crate) struct Raw {
    /// The prediction on `span.first..=span.last`.
    pub pred: Vec<[f64; 3]>,
    /// Residuals at valid frames before the span, nearest first (the anchor first).
    pub before: Vec<(usize, [f64; 3])>,
    /// Residuals at valid frames after the span, nearest first (the anchor first).
    pub after: Vec<(usize, [f64; 3])>,
}

impl Raw {
    /// Predicts the span with `predict` and gathers residuals at up to `per_side` frames on
    /// each side: the span's anchors, then valid target frames where `predict` succeeds,
    /// within `REACH × per_side` frames. `None` when the span cannot be predicted.
    pub fn gather(
        t: &Target,
        span: Span,
        per_side: usize,
        mut predict: impl FnMut(usize) -> Option<[f64; 3]>,
    ) -> Option<Raw> {
        let pred: Option<Vec<[f64; 3]>> = (span.first..=span.last).map(&mut predict).collect();
        let pred = pred?;
        let mut resid = |f: usize| {
            let p = predict(f)?;
            let a = t.at(f);
            Some((f, [a[0] - p[0], a[1] - p[1], a[2] - p[2]]))
        };
        let reach = REACH * per_side.max(1);
        let mut before = Vec::new();
        if let Some(b) = span.before {
            before.extend(resid(b));
            if !before.is_empty() {
                for f in (b.saturating_sub(reach)..b).rev() {
                    if before.len() >= per_side {
                        break;
                    }
                    if t.ok(f) {
                        before.extend(resid(f));
                    }
                }
            }
        }
        let mut after = Vec::new();
        if let Some(a) = span.after {
            after.extend(resid(a));
            if !after.is_empty() {
                for f in a + 1..(a + 1 + reach).min(t.data.frames) {
                    if after.len() >= per_side {
                        break;
                    }
                    if t.ok(f) {
                        after.extend(resid(f));
                    }
                }
            }
        }
        Some(Raw {
            pred,
            before,
            after,
        })
    }

    /// The prediction plus the anchor residuals blended linearly across the gap (a
    /// constant with one anchor), so the fill meets the valid samples at both edges.
    pub fn anchored(&self, span: Span) -> Vec<[f64; 3]> {
        let eb = self.before.first();
        let ea = self.after.first();
        self.pred
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let f = span.first + i;
                let c = match (eb, ea) {
                    (Some(&(fb, b)), Some(&(fa, a))) => {
                        let w = (f - fb) as f64 / (fa - fb) as f64;
                        [
                            b[0] + w * (a[0] - b[0]),
                            b[1] + w * (a[1] - b[1]),
                            b[2] + w * (a[2] - b[2]),
                        ]
                    }
                    (Some(&(_, b)), None) => b,
                    (None, Some(&(_, a))) => a,
                    (None, None) => [0.0; 3],
                };
                [p[0] + c[0], p[1] + c[1], p[2] + c[2]]
            })
            .collect()
    }

    /// The prediction plus a not-a-knot cubic spline through the residuals on both sides.
    /// `None` at the trial's edges or with fewer than two residuals on a side (then the
    /// spline says nothing the line does not).
    pub fn smoothed(&self, span: Span) -> Option<Vec<[f64; 3]>> {
        if self.before.len() < 2 || self.after.len() < 2 {
            return None;
        }
        let frames: Vec<usize> = self
            .before
            .iter()
            .rev()
            .chain(&self.after)
            .map(|x| x.0)
            .collect();
        let y: Vec<[f64; 3]> = self
            .before
            .iter()
            .rev()
            .chain(&self.after)
            .map(|x| x.1)
            .collect();
        let c = spline::through(&frames, &y, self.before.len(), span)?;
        Some(
            self.pred
                .iter()
                .zip(c)
                .map(|(p, c)| [p[0] + c[0], p[1] + c[1], p[2] + c[2]])
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::data::Data;
    use super::super::step::max_steps;
    use super::super::test_util::with_gap;
    use super::*;

    /// A prediction off by a cubic drift: the spline through the residuals removes the
    /// drift exactly, the line only at the anchors.
    #[test]
    fn spline_through_residuals_removes_a_cubic_drift() {
        let truth = |f: usize| [f as f64, (0.1 * f as f64).sin() * 50.0, 3.0];
        let drift = |f: usize| {
            let x = (f as f64 - 50.0) / 10.0;
            [0.2 * x.powi(3), -x * x, 0.5 * x]
        };
        let (xyz, valid) = with_gap(vec![(0..100).map(truth).collect()], 45, 59);
        let steps = max_steps(&xyz, &valid);
        let t = Target {
            m: 0,
            data: Data::new(&xyz, &valid, &steps),
            hole: None,
        };
        let span = Span::new(45, 59, 100);
        let predict = |f: usize| {
            let (p, e) = (truth(f), drift(f));
            Some([p[0] - e[0], p[1] - e[1], p[2] - e[2]])
        };
        let raw = Raw::gather(&t, span, 6, predict).unwrap();
        assert_eq!(raw.before.len(), 6);
        assert_eq!(raw.before[0].0, 44);
        assert_eq!(raw.after[0].0, 60);
        let err = |v: &[[f64; 3]]| {
            v.iter()
                .enumerate()
                .map(|(i, p)| super::super::dist(*p, truth(45 + i)))
                .fold(0.0, f64::max)
        };
        let s = raw.smoothed(span).unwrap();
        assert!(err(&s) < 1e-9, "spline {}", err(&s));
        let l = raw.anchored(span);
        assert!(err(&l) > 0.5, "line {}", err(&l));
        // At the trial's edge there is no spline, and the line is a constant shift.
        let edge = Span::new(0, 9, 100);
        let (xyz, valid) = with_gap(vec![(0..100).map(truth).collect()], 0, 9);
        let t = Target {
            m: 0,
            data: Data::new(&xyz, &valid, &steps),
            hole: None,
        };
        let raw = Raw::gather(&t, edge, 6, predict).unwrap();
        assert!(raw.smoothed(edge).is_none());
        assert_eq!(raw.anchored(edge).len(), 10);
    }
}
