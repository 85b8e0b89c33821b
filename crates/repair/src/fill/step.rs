//! The step rule: no fill may move a marker faster than [`STEP_FACTOR`] times its own
//! largest recorded step.

use super::data::{dist, Span, Target};

/// Per marker, the largest distance between two consecutive valid samples (0 without any
/// such pair). Fills are held to [`STEP_FACTOR`] times this.
pub(crate) fn max_steps(xyz: &[Vec<[f64; 3]>], valid: &[Vec<bool>]) -> Vec<f64> {
    xyz.iter()
        .zip(valid)
        .map(|(x, v)| {
            let mut m = 0.0f64;
            for f in 1..x.len().min(v.len()) {
                if v[f] && v[f - 1] {
                    m = m.max(dist(x[f], x[f - 1]));
                }
            }
            m
        })
        .collect()
}

/// A fill step between consecutive frames above this many times the marker's largest
/// recorded step makes the fill implausible (issue 10).
pub const STEP_FACTOR: f64 = 1.5;

/// The largest step of `fill` (frames `span.first..`) including the joins to the anchors,
/// as a multiple of the marker's largest recorded step (0 when it has none recorded).
pub(crate) fn step_ratio(t: &Target, span: Span, fill: &[[f64; 3]]) -> f64 {
    let limit = t.data.max_step[t.m];
    if limit <= 0.0 || fill.is_empty() {
        return 0.0;
    }
    let mut worst = 0.0f64;
    for w in fill.windows(2) {
        worst = worst.max(dist(w[0], w[1]));
    }
    if let Some(b) = span.before.filter(|&f| t.ok(f)) {
        worst = worst.max(dist(t.at(b), fill[0]));
    }
    if let Some(a) = span.after.filter(|&f| t.ok(f)) {
        worst = worst.max(dist(fill[fill.len() - 1], t.at(a)));
    }
    worst / limit
}
