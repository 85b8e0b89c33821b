//! Order statistics: the medians and quantiles every crate reads, in one place (repair's
//! spikes, swaps and evaluation, gait's calibrations and thresholds, the evaluations'
//! tables each had their own copy).
//!
//! They are not one rule but several, each kept where its numbers were made with it:
//! - [`median`]: the mean of the middle two for an even count (MATLAB's and numpy's
//!   median): the Hampel filter's window, gait's calibration offsets, the fill evaluation.
//! - [`upper_median`] and [`lower_median`]: the order statistic at half the count, a sample
//!   that was measured (swaps' steps and scores).
//! - [`nearest_quantile`]: the order statistic nearest `q` of the count less one, over the
//!   finite values (gait's thresholds and ranges).
//! - [`quantile`]: numpy's default, linear between order statistics (the event tables).
//! - [`rank`] and [`at_rank`]: the order statistic at a given rank (the fill and swap tables,
//!   the reclaim's link tolerance).
//!
//! Values are ordered by [`f64::total_cmp`]. Selecting rather than sorting gives the same
//! number: the element of a rank in a total order is one value, however the others lie.

/// `x` sorted by [`f64::total_cmp`].
pub fn sorted(x: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = x.into_iter().collect();
    v.sort_by(f64::total_cmp);
    v
}

/// The element of rank `k` (0 the smallest) of `v`, which is reordered around it; None when
/// `k` is past the end.
pub fn at_rank(v: &mut [f64], k: usize) -> Option<f64> {
    (k < v.len()).then(|| *v.select_nth_unstable_by(k, f64::total_cmp).1)
}

/// The median, the mean of the middle two for an even count; `v` is reordered. None for no
/// values.
pub fn median(v: &mut [f64]) -> Option<f64> {
    let n = v.len();
    let mid = n / 2;
    let hi = at_rank(v, mid)?;
    if n % 2 == 1 {
        Some(hi)
    } else {
        let lo = v[..mid].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some((lo + hi) / 2.0)
    }
}

/// The median of `sorted` (ascending), the mean of the middle two for an even count, as
/// [`median`] without reordering. None for no values.
pub fn sorted_median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some((sorted[n / 2 - 1] + sorted[n / 2]) / 2.0),
    }
}

/// The upper median: the element at half the count once sorted; `v` is reordered. None for
/// no values.
pub fn upper_median(v: &mut [f64]) -> Option<f64> {
    at_rank(v, v.len() / 2)
}

/// The lower median: the element at half the count less one once sorted; `v` is reordered.
/// None for no values.
pub fn lower_median(v: &mut [f64]) -> Option<f64> {
    at_rank(v, v.len().checked_sub(1)? / 2)
}

/// The value at quantile `q` (0–1, clamped) of the finite values of `x`: the order statistic
/// at `q` of the count less one, rounded to the nearest rank. None when none is finite.
pub fn nearest_quantile(x: &[f64], q: f64) -> Option<f64> {
    let mut v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let k = ((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    Some(v[k])
}

/// The `q` quantile of `x` by linear interpolation between order statistics (numpy's
/// default); NaN for no values.
pub fn quantile(x: &[f64], q: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let v = sorted(x.iter().copied());
    let pos = (v.len() - 1) as f64 * q;
    let (i, f) = (pos.floor() as usize, pos - pos.floor());
    if i + 1 < v.len() {
        v[i] * (1.0 - f) + v[i + 1] * f
    } else {
        v[i]
    }
}

/// The order statistic of `sorted` (ascending) at `num / den` of its count, `sorted[len ·
/// num / den]` in integers: the upper median for 1/2, the 90th percentile for 9/10. None
/// for no values.
pub fn rank(sorted: &[f64], num: usize, den: usize) -> Option<f64> {
    sorted.get(sorted.len() * num / den).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&mut []), None);
        assert_eq!(sorted_median(&[1.0, 2.0, 3.0, 4.0]), Some(2.5));
        assert_eq!(sorted_median(&[]), None);
        assert_eq!(upper_median(&mut [4.0, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(lower_median(&mut [4.0, 1.0, 3.0, 2.0]), Some(2.0));
        assert_eq!(lower_median(&mut [5.0]), Some(5.0));
        assert_eq!(lower_median(&mut []), None);
        assert_eq!(at_rank(&mut [1.0], 1), None);
    }

    #[test]
    fn quantiles_nearest_and_interpolated() {
        assert_eq!(nearest_quantile(&[3.0, f64::NAN, 1.0, 2.0], 0.5), Some(2.0));
        assert_eq!(nearest_quantile(&[f64::NAN], 0.5), None);
        assert_eq!(nearest_quantile(&[1.0, 2.0, 3.0, 4.0], 2.0), Some(4.0));
        assert_eq!(quantile(&[1.0, 2.0, 3.0, 4.0], 0.5), 2.5);
        assert!(quantile(&[], 0.5).is_nan());
        assert_eq!(rank(&[1.0, 2.0, 3.0], 1, 2), Some(2.0));
        assert_eq!(rank(&[1.0, 2.0, 3.0], 1, 1), None);
    }
}
