//! Fills that move the marker faster than it ever does, slowed down; and the last check
//! every fill passes before it is written, on the fill as the file will store it.

use super::super::{linear, step_ratio, Span, Storage, Target, STEP_FACTOR};

/// A fill too fast for the marker, slowed down: the largest share `a` of its deviation
/// from the straight line across the gap (from the held anchor at the trial's edges) whose
/// steps all stay within [`STEP_FACTOR`] times the marker's largest recorded step. The
/// largest step is convex in `a`, so bisection finds it. `None` when even the line is too
/// fast (or the marker has no recorded step).
pub(super) fn slowed(t: &Target, span: Span, v: &[[f64; 3]]) -> Option<Vec<[f64; 3]>> {
    let _time = crate::profile::time(crate::profile::Work::Slowing);
    slowed_to(t, span, v, STEP_FACTOR)
}

/// [`slowed`] to `factor` times the marker's largest recorded step.
fn slowed_to(t: &Target, span: Span, v: &[[f64; 3]], factor: f64) -> Option<Vec<[f64; 3]>> {
    let base = match (span.before, span.after) {
        (Some(_), Some(_)) => crate::fill::linear::fill(t, span).ok()?,
        _ => linear::hold(t, span).ok()?,
    };
    let mix = |a: f64| -> Vec<[f64; 3]> {
        base.iter()
            .zip(v)
            .map(|(b, p)| [0, 1, 2].map(|k| b[k] + a * (p[k] - b[k])))
            .collect()
    };
    if step_ratio(t, span, &base) > factor || t.data.max_step[t.m] <= 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..20 {
        let mid = 0.5 * (lo + hi);
        if step_ratio(t, span, &mix(mid)) <= factor {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(mix(lo))
}

/// The fill `v` of `span` as it will be stored, held to the step rule: no step (joins to the
/// anchors included) above [`STEP_FACTOR`] times the marker's largest recorded step, measured
/// on the stored values. Every fill the pipeline writes passes here (`fill_planned`), after
/// any blend, skeleton constraint or second-pass refill. A fill checked at exactly the
/// limit before storage can end above it once its coordinates are rounded to 32-bit floats
/// or to an integer file's POINT:SCALE (a read-back measured 1.50003× on three of 6 266
/// fills of `../c3d-more`, and on a marker that barely moves the rounding is a large share
/// of its largest step), so the stored form is what is checked. A fill above the limit is
/// slowed towards the straight line between its anchors, to ever smaller factors until its
/// stored form holds; `Err` with its stored step ratio when even the stored line does not.
pub(crate) fn as_stored(
    t: &Target,
    span: Span,
    v: Vec<[f64; 3]>,
    storage: Storage,
) -> Result<Vec<[f64; 3]>, f64> {
    let stored =
        |v: &[[f64; 3]]| -> Vec<[f64; 3]> { v.iter().map(|&p| storage.stored(p)).collect() };
    let first = stored(&v);
    let r = step_ratio(t, span, &first);
    if r <= STEP_FACTOR {
        return Ok(first);
    }
    let mut factor = STEP_FACTOR.min(r);
    for _ in 0..30 {
        factor *= 0.9;
        match slowed_to(t, span, &v, factor) {
            Some(w) => {
                let w = stored(&w);
                if step_ratio(t, span, &w) <= STEP_FACTOR {
                    return Ok(w);
                }
            }
            None => break,
        }
    }
    let line = match (span.before, span.after) {
        (Some(_), Some(_)) => linear::fill(t, span).ok(),
        _ => linear::hold(t, span).ok(),
    };
    match line.map(|l| stored(&l)) {
        Some(l) if step_ratio(t, span, &l) <= STEP_FACTOR => Ok(l),
        _ => Err(r),
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::{max_steps, Data};
    use super::*;

    /// A fill under the limit in memory, 2× over it once an integer file rounds it to its
    /// scale: held to the rule as stored, and returned as stored.
    #[test]
    fn a_fill_is_held_to_the_step_rule_as_an_integer_file_stores_it() {
        let xyz: Vec<Vec<[f64; 3]>> = vec![(0..20).map(|f| [f as f64 * 0.1, 0.0, 0.0]).collect()];
        let mut valid = vec![vec![true; 20]];
        valid[0][8..=11].fill(false);
        let steps = max_steps(&xyz, &valid);
        let t = Target {
            m: 0,
            data: Data::new(&xyz, &valid, &steps),
            hole: None,
        };
        let span = Span::new(8, 11, 20);
        let v = vec![
            [0.84, 0.0, 0.0],
            [0.989, 0.0, 0.0],
            [1.04, 0.0, 0.0],
            [1.14, 0.0, 0.0],
        ];
        assert!((step_ratio(&t, span, &v) - 1.49).abs() < 1e-6);
        let storage = Storage::Integer { scale: 0.1 };
        let naive: Vec<[f64; 3]> = v.iter().map(|&p| storage.stored(p)).collect();
        assert!((step_ratio(&t, span, &naive) - 2.0).abs() < 1e-4);
        let held = as_stored(&t, span, v.clone(), storage).expect("the stored line holds");
        assert!(step_ratio(&t, span, &held) <= STEP_FACTOR);
        assert!(held.iter().all(|&p| storage.stored(p) == p));
        // Kept in memory, a fill that holds is left as it is, and one that does not is
        // slowed down.
        assert_eq!(as_stored(&t, span, v.clone(), Storage::Exact), Ok(v));
        let slowed = as_stored(&t, span, naive, Storage::Exact).expect("slowed");
        assert!(step_ratio(&t, span, &slowed) <= STEP_FACTOR);
    }
}
