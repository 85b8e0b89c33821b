//! Fills that move the marker faster than it ever does, slowed down.

use super::super::{linear, step_ratio, Span, Target, STEP_FACTOR};

/// A fill too fast for the marker, slowed down: the largest share `a` of its deviation
/// from the straight line across the gap (from the held anchor at the trial's edges) whose
/// steps all stay within [`STEP_FACTOR`] times the marker's largest recorded step. The
/// largest step is convex in `a`, so bisection finds it. `None` when even the line is too
/// fast (or the marker has no recorded step).
pub(super) fn slowed(t: &Target, span: Span, v: &[[f64; 3]]) -> Option<Vec<[f64; 3]>> {
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
