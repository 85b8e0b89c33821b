//! Small helpers on sampled signals with NaN for missing samples: gait's own (short gaps,
//! carried ends, moving average, peaks, the stride's period, derivatives, the lowest value in
//! a window), and the filter and quantile every event method reads, which live in the
//! `signal` crate beside repair's.

/// Zero-lag 4th-order Butterworth (a second-order section forward and backward) over each
/// finite run; why it is not repair's scipy filter: `signal::filter`'s page.
pub use ::signal::filter::{zero_lag as butterworth, Pass};
/// The value at quantile `q` (0–1) of the finite values, nearest rank; None when none.
pub use ::signal::order::nearest_quantile as quantile;

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

/// Bridge runs of NaN no longer than `max` samples with the cubic (Hermite) that meets
/// the samples either side with their slopes (each from its last two known samples);
/// runs at the ends, longer ones, or without two known samples on each side stay NaN.
/// A foot marker lost for a few frames around its strike (a plate's edge, the other
/// foot) peaks inside the gap: the cubic keeps the turn that a straight line would put on
/// the gap's edge.
pub fn bridge_short(x: &mut [f64], max: usize) {
    let n = x.len();
    let mut i = 0;
    while i < n {
        if x[i].is_finite() {
            i += 1;
            continue;
        }
        let start = i;
        while i < n && !x[i].is_finite() {
            i += 1;
        }
        if start < 2 || i + 1 >= n || i - start > max {
            continue;
        }
        let (a0, a1, b0, b1) = (x[start - 2], x[start - 1], x[i], x[i + 1]);
        if !(a0.is_finite() && b1.is_finite()) {
            continue;
        }
        // Positions in samples from `start - 1` (0) to `i` (h); slopes per sample.
        let h = (i - start + 1) as f64;
        let (m0, m1) = ((a1 - a0) * h, (b1 - b0) * h);
        for (k, slot) in x[start..i].iter_mut().enumerate() {
            let t = (k + 1) as f64 / h;
            let (t2, t3) = (t * t, t * t * t);
            *slot = (2.0 * t3 - 3.0 * t2 + 1.0) * a1
                + (t3 - 2.0 * t2 + t) * m0
                + (-2.0 * t3 + 3.0 * t2) * b0
                + (t3 - t2) * m1;
        }
    }
}

/// Extend `x` past its first and last known samples by up to `max` samples each, along
/// the straight line through the known sample at the end and the one `fit` samples
/// inwards (constant velocity). Used for the pelvis, which moves steadily over a quarter
/// of a stride, where it is captured later than (or lost before) the feet.
pub fn extend_ends(x: &mut [[f64; 3]], max: usize, fit: usize) {
    let ok = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    let n = x.len();
    let (Some(first), Some(last)) = (x.iter().position(ok), x.iter().rposition(ok)) else {
        return;
    };
    let fit = fit.max(1);
    if first + fit < n && ok(&x[first + fit]) {
        let (a, b) = (x[first], x[first + fit]);
        let start = first.saturating_sub(max);
        for (k, slot) in x[start..first].iter_mut().enumerate() {
            let t = (first - start - k) as f64 / fit as f64;
            for d in 0..3 {
                slot[d] = a[d] - (b[d] - a[d]) * t;
            }
        }
    }
    if last >= fit && ok(&x[last - fit]) {
        let (a, b) = (x[last], x[last - fit]);
        let end = (last + 1 + max).min(n);
        for (k, slot) in x[last + 1..end].iter_mut().enumerate() {
            let t = (k + 1) as f64 / fit as f64;
            for d in 0..3 {
                slot[d] = a[d] - (b[d] - a[d]) * t;
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

/// The lowest finite value of `x` over `[a, b)` (clamped to `x`, empty when `b` is before
/// `a`), NaN if none.
pub fn lowest(x: &[f64], a: f64, b: f64) -> f64 {
    let n = x.len();
    let (a, b) = ((a.max(0.0) as usize).min(n), (b.max(0.0) as usize).min(n));
    x[a..b.max(a)]
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NAN, f64::min)
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
    maxima_cut(x, half, reach, prominence, None)
}

/// What a maximum needs on a side that a gap or the trial's edge cuts short of `reach`
/// ([`maxima_cut`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cut {
    /// Known samples after (or before) the peak, up to the cut, at least.
    pub min_samples: usize,
    /// The fall over those samples, as a fraction of the full prominence, at least, where
    /// a gap cuts the side.
    pub min_fall: f64,
    /// The same where the trial's edge cuts it. A marker's last samples before a gap can
    /// be its worst (it is being lost), so a gap's side needs a clear fall; the capture's
    /// start or end hides nothing of the marker, so a fall above its noise is a turn seen.
    pub edge_min_fall: f64,
}

/// As [`maxima`], and with `cut`, a peak next to a gap or the trial's edge: a side that
/// ends within `reach` (a missing sample or the end of `x`) needs only `cut`'s fall over
/// `cut`'s samples, while the other side still needs the full `prominence`. A foot that
/// lands just after the capture starts, or just before its markers drop out, peaks
/// there as anywhere; what the cut hides is how far it falls after.
pub fn maxima_cut(
    x: &[f64],
    half: usize,
    reach: usize,
    prominence: f64,
    cut: Option<Cut>,
) -> Vec<f64> {
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
        // Prominence on each side, within the finite run around the peak: (the lowest
        // sample, how many samples were seen, whether the run ended before `reach`, and
        // whether a gap ended it rather than the trial's edge).
        let side = |range: &mut dyn Iterator<Item = usize>, avail: usize| {
            let mut m = f64::INFINITY;
            let mut seen = 0;
            for j in range {
                if !x[j].is_finite() {
                    return (m, seen, true, true);
                }
                m = m.min(x[j]);
                seen += 1;
            }
            (m, seen, avail < reach, false)
        };
        let left = side(&mut (i.saturating_sub(reach)..i).rev(), i);
        let right = side(&mut (i + 1..(i + reach + 1).min(n)), n - 1 - i);
        let full = |s: (f64, usize, bool, bool)| v - s.0 >= prominence;
        let partial = |s: (f64, usize, bool, bool)| {
            cut.is_some_and(|c| {
                let fall = if s.3 { c.min_fall } else { c.edge_min_fall };
                s.2 && s.1 >= c.min_samples && v - s.0 >= fall * prominence
            })
        };
        let ok = (full(left) && full(right))
            || (full(left) && partial(right))
            || (partial(left) && full(right));
        if ok {
            out.push(i as f64 + parabolic(x[i - 1], v, x[i + 1]));
        }
    }
    out
}

/// Maxima of `x` at or just beyond its ends, which [`maxima_cut`] cannot see (it needs
/// two samples on a cut side): where the trial starts (or ends) on a falling side, the
/// parabola through its first (last) three samples, opening downwards, peaks between
/// `beyond` samples outside the trial and 1.5 samples inside (nearer the edge than the
/// third sample, which [`maxima_cut`] covers), the higher of the two edge samples is above
/// every other within `half`, and the signal falls from it by the full `prominence`
/// within `reach`. Positions are fractional and may lie outside `0..len` (by at most
/// `beyond`): an event there is the trial's only if the estimate's own offset brings it
/// in. A lab that crops its trials at its events puts its first strike on the first
/// frame; the extreme that marks it lies a few milliseconds before.
pub fn edge_maxima(x: &[f64], half: usize, reach: usize, prominence: f64, beyond: f64) -> Vec<f64> {
    let n = x.len();
    if n < 3 || beyond <= 0.0 {
        return Vec::new();
    }
    // The peak's position from `at(0)` inwards (negative: beyond it) for samples read
    // from the edge inwards in `at`.
    let edge = |at: &dyn Fn(usize) -> f64| -> Option<f64> {
        let (y0, y1, y2) = (at(0), at(1), at(2));
        if !(y0.is_finite() && y1.is_finite() && y2.is_finite()) {
            return None;
        }
        let den = y0 - 2.0 * y1 + y2;
        if den >= 0.0 || !den.is_finite() {
            return None;
        }
        let pos = 1.0 + 0.5 * (y0 - y2) / den;
        if !(-beyond..1.5).contains(&pos) {
            return None;
        }
        let top = y0.max(y1);
        let mut low = f64::INFINITY;
        for k in 2..=reach.min(n - 1) {
            let v = at(k);
            if !v.is_finite() {
                break;
            }
            if k <= half && v >= top {
                return None;
            }
            low = low.min(v);
        }
        (top - low >= prominence).then_some(pos)
    };
    let mut out = Vec::new();
    if let Some(p) = edge(&|k| x[k]) {
        out.push(p);
    }
    if let Some(p) = edge(&|k| x[n - 1 - k]) {
        out.push((n - 1) as f64 - p);
    }
    out
}

/// The period (samples) of a roughly periodic `x`: the first peak of its autocorrelation
/// (mean removed, over the pairs of finite samples) among lags `min..=max`, taken where the
/// correlation reaches at least half the best in that range and 0.3. `None` for a signal
/// without such a repeat.
pub fn period(x: &[f64], min: usize, max: usize) -> Option<usize> {
    let finite: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.len() < 2 || min == 0 || min > max {
        return None;
    }
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    let d: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let corr = |lag: usize| -> f64 {
        let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
        for i in 0..d.len().saturating_sub(lag) {
            let (a, b) = (d[i], d[i + lag]);
            if a.is_finite() && b.is_finite() {
                sxy += a * b;
                sxx += a * a;
                syy += b * b;
            }
        }
        if sxx > 0.0 && syy > 0.0 {
            sxy / (sxx * syy).sqrt()
        } else {
            f64::NAN
        }
    };
    let max = max.min(d.len().saturating_sub(2));
    if min + 1 > max {
        return None;
    }
    let r: Vec<f64> = (min - 1..=max + 1).map(corr).collect();
    let best = r
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NAN, f64::max);
    if best.is_nan() || best < 0.3 {
        return None;
    }
    (1..r.len() - 1)
        .find(|&k| r[k].is_finite() && r[k] >= 0.5 * best && r[k] >= r[k - 1] && r[k] >= r[k + 1])
        .map(|k| k + min - 1)
}

/// Derivative per second by central differences (one-sided at the ends of each finite run;
/// NaN where a sample or both neighbours are missing).
pub fn derivative(x: &[f64], rate: f64) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| {
            if !x[i].is_finite() {
                return f64::NAN;
            }
            let prev = (i > 0).then(|| x[i - 1]).filter(|v| v.is_finite());
            let next = x.get(i + 1).copied().filter(|v| v.is_finite());
            match (prev, next) {
                (Some(a), Some(b)) => (b - a) * rate / 2.0,
                (Some(a), None) => (x[i] - a) * rate,
                (None, Some(b)) => (b - x[i]) * rate,
                (None, None) => f64::NAN,
            }
        })
        .collect()
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

    #[test]
    fn a_peak_at_a_cut_needs_its_fall_there() {
        // A cosine of 100 peaking at samples 5 and 65: the first is cut on its left by the
        // trial's start, 5 samples falling 13.4 before it.
        let s: Vec<f64> = (0..120)
            .map(|i| 100.0 * (2.0 * std::f64::consts::PI * (i as f64 - 5.0) / 60.0).cos())
            .collect();
        assert_eq!(maxima(&s, 10, 20, 50.0), vec![65.0]);
        let cut = |min_fall| {
            Some(Cut {
                min_samples: 2,
                min_fall,
                edge_min_fall: min_fall,
            })
        };
        let m = maxima_cut(&s, 10, 20, 50.0, cut(0.1));
        assert_eq!(m.len(), 2, "{m:?}");
        assert!(
            (m[0] - 5.0).abs() < 0.05 && (m[1] - 65.0).abs() < 0.05,
            "{m:?}"
        );
        // 13.4 is less than 0.3 × 50.
        assert_eq!(maxima_cut(&s, 10, 20, 50.0, cut(0.3)), vec![65.0]);
        // A gap 3 samples after a peak cuts it as the edge does (the fall there 4.9, one
        // tenth of 50 needs 5; 0.05 takes it).
        let mut g = s.clone();
        for v in g.iter_mut().skip(69).take(30) {
            *v = f64::NAN;
        }
        assert_eq!(maxima(&g, 10, 20, 50.0), Vec::<f64>::new());
        assert_eq!(maxima_cut(&g, 10, 20, 50.0, cut(0.1)).len(), 1);
        assert_eq!(maxima_cut(&g, 10, 20, 50.0, cut(0.05)).len(), 2);
    }

    #[test]
    fn a_peak_cut_by_the_trials_edge_needs_less_fall_than_one_cut_by_a_gap() {
        // A cosine of 100 peaking at sample 117 of 120: 2 samples after it fall 1.1.
        let s: Vec<f64> = (0..120)
            .map(|i| 100.0 * (2.0 * std::f64::consts::PI * (i as f64 - 117.0) / 60.0).cos())
            .collect();
        let cut = |min_fall, edge_min_fall| {
            Some(Cut {
                min_samples: 2,
                min_fall,
                edge_min_fall,
            })
        };
        let last = |m: Vec<f64>| m.last().copied().unwrap_or(f64::NAN);
        assert!((last(maxima_cut(&s, 10, 20, 50.0, cut(0.1, 0.02))) - 117.0).abs() < 0.05);
        assert!((last(maxima_cut(&s, 10, 20, 50.0, cut(0.1, 0.1))) - 57.0).abs() < 0.05);
        // The same peak before a gap keeps the gap's fall.
        let mut g = s.clone();
        g.extend([f64::NAN; 5]);
        g.extend(s.iter().take(20));
        assert!((last(maxima_cut(&g[..125], 10, 20, 50.0, cut(0.1, 0.02))) - 57.0).abs() < 0.05);
    }

    #[test]
    fn a_peak_just_beyond_the_ends_is_found_by_its_parabola() {
        // Peaks 1.5 samples before the start and after the end (sample 118.5); the
        // parabola through three samples of the cosine places them within 0.2.
        let s: Vec<f64> = (0..117)
            .map(|i| 100.0 * (2.0 * std::f64::consts::PI * (i as f64 + 1.5) / 60.0).cos())
            .collect();
        let m = edge_maxima(&s, 10, 20, 50.0, 3.0);
        assert_eq!(m.len(), 2, "{m:?}");
        assert!(
            (m[0] + 1.5).abs() < 0.2 && (m[1] - 118.5).abs() < 0.2,
            "{m:?}"
        );
        // Farther out than allowed: none.
        assert!(edge_maxima(&s, 10, 20, 50.0, 1.0).is_empty());
        // A start that rises (a minimum beyond it) or falls too little gives none.
        let rising: Vec<f64> = s.iter().map(|v| -v).collect();
        assert!(edge_maxima(&rising, 10, 20, 50.0, 3.0).is_empty());
        assert!(edge_maxima(&s, 10, 20, 500.0, 3.0).is_empty());
        // A peak one sample inside the end, with one sample after it, is the edge's too
        // (maxima_cut needs two); one three samples inside is not (maxima_cut's).
        let inside = |at: f64| -> Vec<f64> {
            let s: Vec<f64> = (0..117)
                .map(|i| 100.0 * (2.0 * std::f64::consts::PI * (i as f64 - at) / 60.0).cos())
                .collect();
            edge_maxima(&s, 10, 20, 50.0, 3.0)
        };
        let m = inside(115.0);
        assert!(m.len() == 1 && (m[0] - 115.0).abs() < 0.2, "{m:?}");
        assert!(inside(113.0).is_empty());
    }

    #[test]
    fn a_short_gap_is_bridged_by_a_cubic_that_keeps_its_turn() {
        // A parabola peaking at sample 10, samples 8 to 12 lost: the cubic through the
        // slopes either side peaks inside the gap, where a straight line would be flat.
        let p = |i: f64| 100.0 - (i - 10.0).powi(2);
        let mut x: Vec<f64> = (0..20).map(|i| p(i as f64)).collect();
        for v in x.iter_mut().skip(8).take(5) {
            *v = f64::NAN;
        }
        let mut short = x.clone();
        bridge_short(&mut short, 4);
        assert!(short[10].is_nan(), "a gap longer than max stays");
        bridge_short(&mut x, 5);
        let top = (0..20).max_by(|&a, &b| x[a].total_cmp(&x[b])).unwrap();
        assert_eq!(top, 10, "{x:?}");
        assert!((x[10] - 100.0).abs() < 2.0, "{x:?}");
        // A gap at an end stays.
        let mut e = vec![f64::NAN, f64::NAN, 1.0, 2.0, 3.0];
        bridge_short(&mut e, 5);
        assert!(e[0].is_nan() && e[1].is_nan());
    }

    #[test]
    fn ends_are_carried_at_constant_velocity() {
        let mut x: Vec<[f64; 3]> = (0..10).map(|i| [10.0 * i as f64, 5.0, 900.0]).collect();
        for i in [0, 1, 2, 3, 8, 9] {
            x[i] = [f64::NAN; 3];
        }
        extend_ends(&mut x, 3, 2);
        assert!(x[0][0].is_nan());
        assert_eq!(x[1], [10.0, 5.0, 900.0]);
        assert_eq!(x[3], [30.0, 5.0, 900.0]);
        assert_eq!(x[9], [90.0, 5.0, 900.0]);
    }

    #[test]
    fn derivative_by_central_differences() {
        let d = derivative(&[0.0, 1.0, f64::NAN, 3.0, 5.0], 10.0);
        assert_eq!(d[0], 10.0);
        assert_eq!(d[1], 10.0);
        assert!(d[2].is_nan());
        assert_eq!(d[3], 20.0);
    }

    #[test]
    fn the_period_is_the_first_repeat() {
        // A 2.7 s stride at 50 Hz (Eb015's pace) with a gap: 135 samples.
        let mut x: Vec<f64> = (0..450)
            .map(|i| (2.0 * std::f64::consts::PI * i as f64 / 135.0).sin() * 250.0)
            .collect();
        for v in x.iter_mut().skip(200).take(20) {
            *v = f64::NAN;
        }
        let p = super::period(&x, 30, 200).unwrap();
        assert!((134..=136).contains(&p), "{p}");
        // Noise-free constant: no repeat to find.
        assert_eq!(super::period(&[1.0; 100], 10, 50), None);
    }
}
