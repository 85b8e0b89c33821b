//! Small helpers on sampled signals with NaN for missing samples.

/// Fill runs of NaN no longer than `max` samples by linear interpolation between the
/// samples either side (runs at the ends or longer stay NaN). Used for the pelvis, whose
/// short gaps would otherwise cut the walking direction.
pub fn fill_short(x: &mut [[f64; 3]], max: usize) {
    let n = x.len();
    let ok = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    let mut i = 0;
    while i < n {
        if ok(&x[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < n && !ok(&x[i]) {
            i += 1;
        }
        if start == 0 || i == n || i - start > max {
            continue;
        }
        let (a, b) = (x[start - 1], x[i]);
        let span = (i - start + 1) as f64;
        for (k, slot) in x[start..i].iter_mut().enumerate() {
            let t = (k + 1) as f64 / span;
            for d in 0..3 {
                slot[d] = a[d] + (b[d] - a[d]) * t;
            }
        }
    }
}

/// Zero-phase smoothing by a centred moving average of `2 * half + 1` samples over the
/// finite samples in reach (NaN stays NaN).
pub fn smooth(x: &[f64], half: usize) -> Vec<f64> {
    if half == 0 {
        return x.to_vec();
    }
    let n = x.len();
    (0..n)
        .map(|i| {
            if !x[i].is_finite() {
                return f64::NAN;
            }
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(n));
            let (s, c) = x[a..b]
                .iter()
                .filter(|v| v.is_finite())
                .fold((0.0, 0usize), |(s, c), v| (s + v, c + 1));
            s / c as f64
        })
        .collect()
}

/// The value at quantile `q` (0–1) of the finite values, None when there are none.
pub fn quantile(x: &[f64], q: f64) -> Option<f64> {
    let mut v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let k = ((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    Some(v[k])
}

/// Sub-sample position of an extremum at `i` from the parabola through its neighbours.
pub fn parabolic(y0: f64, y1: f64, y2: f64) -> f64 {
    let den = y0 - 2.0 * y1 + y2;
    if den.abs() < 1e-12 || !den.is_finite() {
        0.0
    } else {
        (0.5 * (y0 - y2) / den).clamp(-0.5, 0.5)
    }
}

/// Local maxima of `x`: samples larger than every finite sample within `half` on each
/// side (ties broken towards the earlier), with finite neighbours on both sides, rising at
/// least `prominence` above the lowest sample within `reach` on each side. Returns
/// fractional positions (parabolic interpolation).
pub fn maxima(x: &[f64], half: usize, reach: usize, prominence: f64) -> Vec<f64> {
    let n = x.len();
    let mut out = Vec::new();
    for i in 1..n.saturating_sub(1) {
        let v = x[i];
        if !(v.is_finite() && x[i - 1].is_finite() && x[i + 1].is_finite()) {
            continue;
        }
        let (a, b) = (i.saturating_sub(half), (i + half + 1).min(n));
        let is_max = (a..b)
            .all(|j| j == i || !x[j].is_finite() || (if j < i { x[j] < v } else { x[j] <= v }));
        if !is_max {
            continue;
        }
        // Prominence on each side, within the finite run around the peak.
        let side_min = |range: &mut dyn Iterator<Item = usize>| {
            let mut m = f64::INFINITY;
            for j in range {
                if !x[j].is_finite() {
                    break;
                }
                m = m.min(x[j]);
            }
            m
        };
        let left = side_min(&mut (i.saturating_sub(reach)..i).rev());
        let right = side_min(&mut (i + 1..(i + reach + 1).min(n)));
        if v - left >= prominence && v - right >= prominence {
            out.push(i as f64 + parabolic(x[i - 1], v, x[i + 1]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_and_peaks() {
        let mut x = vec![
            [0.0; 3],
            [f64::NAN; 3],
            [f64::NAN; 3],
            [3.0; 3],
            [f64::NAN; 3],
        ];
        fill_short(&mut x, 2);
        assert_eq!(x[1], [1.0; 3]);
        assert_eq!(x[2], [2.0; 3]);
        assert!(x[4][0].is_nan());
        let s: Vec<f64> = (0..200).map(|i| (i as f64 * 0.1).sin()).collect();
        let m = maxima(&s, 10, 30, 0.5);
        // sin peaks at pi/2 + 2 k pi: samples 15.7, 78.5, 141.4.
        assert_eq!(m.len(), 3);
        assert!((m[0] - 15.708).abs() < 0.05, "{m:?}");
        assert!((m[2] - 141.372).abs() < 0.05, "{m:?}");
        assert_eq!(quantile(&[3.0, f64::NAN, 1.0, 2.0], 0.5), Some(2.0));
    }
}
