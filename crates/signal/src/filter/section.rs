//! One second-order Butterworth section (low- or high-pass) run forward and backward: the
//! "4th-order zero-lag" filter of Winter and the gait papers, over each finite run of a
//! signal with gaps (why it is not scipy's design: the [module](super) page).

use super::filtfilt::zero_phase;

/// Which band a [`Section`] keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pass {
    Low,
    High,
}

/// A second-order Butterworth section: coefficients `(b, a)` (`a[0] = 1`) from the bilinear
/// transform with pre-warping in closed form, and the padding its zero-phase run uses.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    b: [f64; 3],
    a: [f64; 3],
    /// Three periods of the cut-off, in samples: long enough for the start-up transient of
    /// a low cut-off to fall outside the samples kept.
    pad: usize,
}

impl Section {
    /// The section at `cutoff_hz` for samples at `rate` Hz; the cut-off must be above 0 and
    /// below Nyquist (see [`zero_lag`] for what is done otherwise).
    pub fn butterworth(rate: f64, cutoff_hz: f64, pass: Pass) -> Section {
        let k = (std::f64::consts::PI * cutoff_hz / rate).tan();
        let q = std::f64::consts::FRAC_1_SQRT_2;
        let norm = 1.0 / (1.0 + k / q + k * k);
        let b = match pass {
            Pass::Low => [k * k * norm, 2.0 * k * k * norm, k * k * norm],
            Pass::High => [norm, -2.0 * norm, norm],
        };
        let a = [
            1.0,
            2.0 * (k * k - 1.0) * norm,
            (1.0 - k / q + k * k) * norm,
        ];
        let pad = 3usize.saturating_mul((rate / cutoff_hz).ceil() as usize);
        Section { b, a, pad }
    }

    /// Zero-phase filtering of a run of known samples in place: padded by three periods of
    /// the cut-off, shortened to the run's length less one when the run is shorter.
    pub fn filtfilt(&self, run: &mut [f64]) {
        let pad = self.pad.min(run.len().saturating_sub(1));
        zero_phase(run, pad, |x| self.pass(x));
    }

    /// One pass in direct form I, in place, starting from the steady state of the first
    /// sample (as scipy's lfilter_zi), so a constant signal passes without a transient.
    fn pass(&self, x: &mut [f64]) {
        let (b, a) = (&self.b, &self.a);
        let x0 = x.first().copied().unwrap_or(0.0);
        let dc = (b[0] + b[1] + b[2]) / (a[0] + a[1] + a[2]);
        let (mut x1, mut x2, mut y1, mut y2) = (x0, x0, dc * x0, dc * x0);
        for v in x.iter_mut() {
            let y = b[0] * *v + b[1] * x1 + b[2] * x2 - a[1] * y1 - a[2] * y2;
            (x2, x1, y2, y1) = (x1, *v, y1, y);
            *v = y;
        }
    }
}

/// Zero-lag Butterworth filter: a [`Section`] run forward and backward, i.e. fourth order
/// overall, over each finite run of `x` separately (NaN stays NaN). A cut-off at or above
/// the Nyquist frequency, or not positive, returns `x` unchanged (low-pass) or zeros
/// (high-pass) on the finite samples.
pub fn zero_lag(x: &[f64], rate: f64, cutoff_hz: f64, pass: Pass) -> Vec<f64> {
    let mut out = vec![f64::NAN; x.len()];
    let nyquist = rate / 2.0;
    let usable = cutoff_hz > 0.0 && cutoff_hz < nyquist && cutoff_hz.is_finite();
    let section = usable.then(|| Section::butterworth(rate, cutoff_hz, pass));
    for (a, b) in finite_runs(x) {
        let (run, o) = (&x[a..b], &mut out[a..b]);
        match (&section, pass) {
            (Some(s), _) => {
                o.copy_from_slice(run);
                s.filtfilt(o);
            }
            (None, Pass::Low) => o.copy_from_slice(run),
            (None, Pass::High) => o.fill(0.0),
        }
    }
    out
}

/// Finite runs of `x`: `(start, end)` ranges of consecutive finite samples.
pub fn finite_runs(x: &[f64]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < x.len() {
        if !x[i].is_finite() {
            i += 1;
            continue;
        }
        let start = i;
        while i < x.len() && x[i].is_finite() {
            i += 1;
        }
        out.push((start, i));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Amplitude of a sine of `f` Hz after the filter, away from the ends.
    fn gain(f: f64, cutoff: f64, pass: Pass) -> f64 {
        let rate = 100.0;
        let x: Vec<f64> = (0..2000)
            .map(|i| (2.0 * std::f64::consts::PI * f * i as f64 / rate).sin())
            .collect();
        let y = zero_lag(&x, rate, cutoff, pass);
        y[500..1500].iter().fold(0.0, |m: f64, v| m.max(v.abs()))
    }

    #[test]
    fn zero_lag_gains_and_gaps() {
        // Two passes of a second-order section: the gain at the cut-off is 1/2 (−6 dB).
        assert!((gain(2.0, 2.0, Pass::Low) - 0.5).abs() < 0.01);
        assert!((gain(2.0, 2.0, Pass::High) - 0.5).abs() < 0.01);
        assert!(gain(0.2, 2.0, Pass::High) < 0.001);
        assert!((gain(0.2, 2.0, Pass::Low) - 1.0).abs() < 0.01);
        assert!(gain(20.0, 2.0, Pass::Low) < 0.001);
        // A ramp (walking progression) is removed by the high-pass, zero-lag; NaN stays.
        let mut x: Vec<f64> = (0..300).map(|i| 10.0 * i as f64).collect();
        x[100] = f64::NAN;
        let y = zero_lag(&x, 100.0, 1.0, Pass::High);
        assert!(y[100].is_nan());
        assert!(
            y[150..290].iter().all(|v| v.abs() < 0.01),
            "{:?}",
            &y[150..160]
        );
        // An unusable cut-off: the low-pass passes the samples, the high-pass zeros them.
        assert_eq!(
            zero_lag(&[1.0, f64::NAN, 2.0], 100.0, 60.0, Pass::Low)[2],
            2.0
        );
        assert_eq!(
            zero_lag(&[1.0, 2.0], 100.0, 0.0, Pass::High),
            vec![0.0, 0.0]
        );
    }
}
