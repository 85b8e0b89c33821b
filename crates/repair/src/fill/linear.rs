//! Straight line between the valid samples on either side of the gap.

use super::data::{Span, Target};
use super::outcome::{Fill, SkipReason};

pub(super) fn fill(t: &Target, span: Span) -> Fill {
    let (b, a) = match (
        t.before(span.first, 1).first(),
        t.after(span.last, 1).first(),
    ) {
        (Some(&b), Some(&a)) => (b, a),
        _ => return Err(SkipReason::TouchesEdge),
    };
    let (pb, pa) = (t.at(b), t.at(a));
    Ok((span.first..=span.last)
        .map(|f| {
            let w = (f - b) as f64 / (a - b) as f64;
            [
                pb[0] + w * (pa[0] - pb[0]),
                pb[1] + w * (pa[1] - pb[1]),
                pb[2] + w * (pa[2] - pb[2]),
            ]
        })
        .collect())
}

/// The one anchor of a gap at the trial's edge, held through the gap (steps of zero, so
/// always plausible; `auto`'s last resort there).
pub(super) fn hold(t: &Target, span: Span) -> Fill {
    let anchor = match (span.before, span.after) {
        (Some(b), None) => b,
        (None, Some(a)) => a,
        _ => return Err(SkipReason::NoContext),
    };
    if !t.ok(anchor) {
        return Err(SkipReason::NoContext);
    }
    Ok(vec![t.at(anchor); span.len()])
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::super::FillMethod;

    #[test]
    fn straight_line_is_exact() {
        let line = |f: usize| [1.0 + 2.0 * f as f64, -3.0 * f as f64, 7.0];
        let (xyz, valid) = with_gap(vec![(0..50).map(line).collect()], 20, 29);
        let v = fill(&xyz, &valid, 20, 29, FillMethod::Linear).unwrap();
        assert_eq!(v.len(), 10);
        assert!(max_err(&v, line, 20) < 1e-12);
    }
}
