//! The order statistics of the evaluations' tables, in one place: the medians and
//! percentiles they print were computed by three copies before.
//!
//! Two readings, each kept where its figures were made with it: [`quantile`] interpolates
//! between order statistics (numpy's default; the event tables), [`rank`] takes the order
//! statistic at a fraction of the count (the upper median for 1/2; the fill and swap
//! tables, which print a sample that was measured).

/// `x` sorted by `f64::total_cmp`.
pub fn sorted(x: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = x.into_iter().collect();
    v.sort_by(f64::total_cmp);
    v
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

/// The upper median of `x` (see [`rank`]); None for no values.
pub fn median(x: impl IntoIterator<Item = f64>) -> Option<f64> {
    rank(&sorted(x), 1, 2)
}
