//! Cubic spline through valid samples around the gap, with not-a-knot end conditions (as
//! scipy's CubicSpline default), so any cubic is reproduced exactly; 3 nodes give the
//! parabola and 2 the line, the not-a-knot limits.

use super::data::{Span, Target};
use super::outcome::{Fill, SkipReason};
use super::poly::lagrange_eval;
use crate::linalg::solve_band_in_place;

pub(super) fn fill(t: &Target, span: Span, per_side: usize) -> Fill {
    let before = t.before(span.first, per_side);
    let after = t.after(span.last, per_side);
    if before.is_empty() || after.is_empty() {
        return Err(SkipReason::TouchesEdge);
    }
    let frames: Vec<usize> = before.iter().rev().chain(after.iter()).copied().collect();
    let y: Vec<[f64; 3]> = frames.iter().map(|&f| t.at(f)).collect();
    through(&frames, &y, before.len(), span).ok_or(SkipReason::Degenerate)
}

/// The not-a-knot spline through `(frames[i], y[i])` evaluated on the span's frames, which
/// all lie between node `n_before - 1` and node `n_before` (nodes sorted, at least one on
/// each side). `None` if the system is singular.
pub(super) fn through(
    frames: &[usize],
    y: &[[f64; 3]],
    n_before: usize,
    span: Span,
) -> Option<Vec<[f64; 3]>> {
    let centre = (span.first + span.last) as f64 / 2.0;
    let x: Vec<f64> = frames.iter().map(|&f| f as f64 - centre).collect();
    let n = x.len();
    let at = |f: usize| f as f64 - centre;
    if n <= 3 {
        return Some(
            (span.first..=span.last)
                .map(|f| lagrange_eval(&x, y, at(f)))
                .collect(),
        );
    }
    let m = second_derivatives(&x, y)?;
    // Every gap frame lies in the one interval between the nearest nodes on each side.
    let i = n_before - 1;
    let h = x[i + 1] - x[i];
    Some(
        (span.first..=span.last)
            .map(|f| {
                let (l, r) = (x[i + 1] - at(f), at(f) - x[i]);
                let mut out = [0.0; 3];
                for k in 0..3 {
                    out[k] = m[i][k] * l.powi(3) / (6.0 * h)
                        + m[i + 1][k] * r.powi(3) / (6.0 * h)
                        + (y[i][k] / h - m[i][k] * h / 6.0) * l
                        + (y[i + 1][k] / h - m[i + 1][k] * h / 6.0) * r;
                }
                out
            })
            .collect(),
    )
}

/// Second derivatives at the knots for the not-a-knot spline (n >= 4), all three
/// coordinates at once.
fn second_derivatives(x: &[f64], y: &[[f64; 3]]) -> Option<Vec<[f64; 3]>> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let mut a = vec![0.0; n * n];
    let mut rhs = vec![0.0; n * 3];
    // Not-a-knot: the third derivative is continuous at x[1] and x[n-2].
    a[0] = h[1];
    a[1] = -(h[0] + h[1]);
    a[2] = h[0];
    let r = n - 1;
    a[r * n + n - 3] = h[n - 2];
    a[r * n + n - 2] = -(h[n - 3] + h[n - 2]);
    a[r * n + n - 1] = h[n - 3];
    for i in 1..n - 1 {
        a[i * n + i - 1] = h[i - 1];
        a[i * n + i] = 2.0 * (h[i - 1] + h[i]);
        a[i * n + i + 1] = h[i];
        for k in 0..3 {
            rhs[i * 3 + k] =
                6.0 * ((y[i + 1][k] - y[i][k]) / h[i] - (y[i][k] - y[i - 1][k]) / h[i - 1]);
        }
    }
    // Tridiagonal but for the not-a-knot rows, which reach two places off the diagonal.
    if !solve_band_in_place(&mut a, n, &mut rhs, 3, 2) {
        return None;
    }
    Some(rhs.chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::super::FillMethod;

    #[test]
    fn cubic_is_exact_and_sine_is_close() {
        let c = |f: usize| {
            let x = (f as f64 - 40.0) / 10.0;
            [x.powi(3) - 2.0 * x, 0.5 * x.powi(3) + x * x, -x.powi(3)]
        };
        let (mut xyz, mut valid) = with_gap(vec![(0..80).map(c).collect()], 35, 50);
        // Irregular context: another invalid sample among the nodes.
        valid[0][30] = false;
        xyz[0][30] = [f64::NAN; 3];
        let v = fill(&xyz, &valid, 35, 50, FillMethod::Spline).unwrap();
        assert!(max_err(&v, c, 35) < 1e-9, "{}", max_err(&v, c, 35));
        let l = fill(&xyz, &valid, 35, 50, FillMethod::Linear).unwrap();
        assert!(max_err(&l, c, 35) > 1.0);

        let s = |f: usize| [100.0 * (f as f64 * 0.05).sin(), 0.0, 0.0];
        let (xyz, valid) = with_gap(vec![(0..100).map(s).collect()], 40, 49);
        let v = fill(&xyz, &valid, 40, 49, FillMethod::Spline).unwrap();
        assert!(max_err(&v, s, 40) < 0.05, "{}", max_err(&v, s, 40));
    }
}
