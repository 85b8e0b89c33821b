//! Lagrange polynomials through the valid samples nearest the gap, as evenly split between
//! both sides as the data allows (at least one on each side: never extrapolate).

use super::data::{Span, Target};
use super::outcome::{Fill, SkipReason};

/// Frames of the `n` nodes: nearest first, alternating sides, topping up from the side
/// that has more when the other runs out.
pub(super) fn nodes(t: &Target, span: Span, n: usize) -> Result<Vec<usize>, SkipReason> {
    let before = t.before(span.first, n);
    let after = t.after(span.last, n);
    if before.is_empty() || after.is_empty() {
        return Err(SkipReason::TouchesEdge);
    }
    if before.len() + after.len() < n {
        return Err(SkipReason::NoContext);
    }
    let mut nb = n.div_ceil(2).min(before.len());
    let na = (n - nb).min(after.len());
    nb = n - na;
    let mut out: Vec<usize> = before[..nb].iter().rev().copied().collect();
    out.extend_from_slice(&after[..na]);
    Ok(out)
}

/// Evaluates the interpolating polynomial through `(x[i], y[i])` at `at` (Lagrange form;
/// abscissae are centred by the caller for conditioning).
pub(super) fn lagrange_eval(x: &[f64], y: &[[f64; 3]], at: f64) -> [f64; 3] {
    let mut out = [0.0; 3];
    for i in 0..x.len() {
        let mut w = 1.0;
        for j in 0..x.len() {
            if i != j {
                w *= (at - x[j]) / (x[i] - x[j]);
            }
        }
        for k in 0..3 {
            out[k] += w * y[i][k];
        }
    }
    out
}

/// Polynomial of degree `n - 1` through `n` nodes.
pub(super) fn lagrange(t: &Target, span: Span, n: usize) -> Fill {
    let frames = nodes(t, span, n)?;
    let centre = (span.first + span.last) as f64 / 2.0;
    let x: Vec<f64> = frames.iter().map(|&f| f as f64 - centre).collect();
    let y: Vec<[f64; 3]> = frames.iter().map(|&f| t.at(f)).collect();
    Ok((span.first..=span.last)
        .map(|f| lagrange_eval(&x, &y, f as f64 - centre))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::super::method::FillMethod;
    use super::super::outcome::SkipReason;
    use super::super::test_util::*;

    #[test]
    fn quadratic_is_exact_with_lagrange2() {
        let q = |f: usize| {
            let x = f as f64;
            [0.5 * x * x - 3.0 * x + 2.0, -0.1 * x * x, 4.0 + x]
        };
        let (xyz, valid) = with_gap(vec![(0..60).map(q).collect()], 25, 40);
        let v = fill(&xyz, &valid, 25, 40, FillMethod::Lagrange2).unwrap();
        assert!(max_err(&v, q, 25) < 1e-9);
        // Linear cannot do it: the check above is not vacuous.
        let l = fill(&xyz, &valid, 25, 40, FillMethod::Linear).unwrap();
        assert!(max_err(&l, q, 25) > 1.0);
    }

    #[test]
    fn quintic_is_exact_with_lagrange5() {
        let p = |f: usize| {
            let x = (f as f64 - 30.0) / 10.0;
            let v = 1.0 - 2.0 * x + 0.5 * x.powi(2) + 0.3 * x.powi(3) - 0.2 * x.powi(4)
                + 0.05 * x.powi(5);
            [v, 2.0 * v, -v]
        };
        let (xyz, valid) = with_gap(vec![(0..60).map(p).collect()], 22, 37);
        let v = fill(&xyz, &valid, 22, 37, FillMethod::Lagrange5).unwrap();
        assert!(max_err(&v, p, 22) < 1e-9);
        let q = fill(&xyz, &valid, 22, 37, FillMethod::Lagrange2).unwrap();
        assert!(max_err(&q, p, 22) > 1e-3);
    }

    #[test]
    fn uneven_context_tops_up_from_the_other_side() {
        // Only one valid sample before the gap: 1 + 5 nodes, still exact on a quintic.
        let p = |f: usize| {
            let x = f as f64 / 10.0;
            [x.powi(5) - x.powi(2), x, 1.0]
        };
        let mut xyz = vec![(0..40).map(p).collect::<Vec<_>>()];
        let mut valid = vec![vec![true; 40]];
        valid[0][0] = false;
        xyz[0][0] = [f64::NAN; 3];
        valid[0][2..10].iter_mut().for_each(|v| *v = false);
        let v = fill(&xyz, &valid, 2, 9, FillMethod::Lagrange5).unwrap();
        assert!(max_err(&v, p, 2) < 1e-9);
        // A gap at the trial's start is refused.
        assert_eq!(
            fill(&xyz, &valid, 0, 0, FillMethod::Lagrange5),
            Err(SkipReason::TouchesEdge)
        );
    }
}
