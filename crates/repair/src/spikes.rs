//! Spike detection with the Hampel identifier on each coordinate, over valid samples only.
//!
//! Defaults: `half_window` 5 (11-sample window) and `nsigma` 3. MATLAB's hampel uses 3 and
//! 3; the wider window keeps the median robust when optical swaps or reflections corrupt
//! several consecutive frames (up to 5 of 11), at 100–200 Hz it still spans well under a
//! gait event, and a sample on a smooth trajectory is its window's median anyway.
//! The classic identifier judges raw coordinates, so along an axis where the marker moves
//! fast the window's trend inflates the MAD: walking at 12 mm/frame, a spike along the
//! direction of travel must exceed roughly 150 mm to be caught. With `detrend` (off by
//! default here, on in the command-line tool, which pairs it with a `min_deviation` of a
//! few mm: on noise-free data the residuals' MAD collapses) each sample is first predicted from its neighbours — the median of the symmetric
//! pair means (x[f−j] + x[f+j]) / 2, j = 1..K, which cancels any linear trend and shrugs off
//! a spike among them — and the Hampel rule is applied to the residuals x − prediction: a
//! 35 mm spike on a marker walking at 12 mm/frame is then found like any other.

use serde::Serialize;
// The mean of the middle two for an even count, as MATLAB's median (Hampel filters are
// usually checked against MATLAB's hampel).
use signal::order::median;

use crate::error::{RepairError, Result};

/// What happens to a detected spike.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpikeMode {
    /// The whole sample becomes invalid, so the fill step refills it.
    Gap,
    /// Outlying coordinates are replaced by their window median (MATLAB's hampel).
    Median,
}

/// Largest half window K: a window of 2001 samples (10 s at 200 Hz) is far wider than any
/// spike, and the bound keeps window buffers and index arithmetic small whatever is asked.
pub const MAX_HALF_WINDOW: usize = 1000;

/// Hampel settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpikeOptions {
    /// Samples on each side of the centre (K), 1 to [`MAX_HALF_WINDOW`].
    pub half_window: usize,
    /// Outlier threshold in scaled MADs (1.4826 × MAD).
    pub nsigma: f64,
    /// Deviations from the median at or below this (data units) are never outliers.
    /// 0 (default) is MATLAB's rule; a few mm keeps measurement noise on a still
    /// coordinate, whose MAD is tiny, from being flagged.
    pub min_deviation: f64,
    pub mode: SpikeMode,
    /// Judge residuals from a local robust prediction instead of raw coordinates (see the
    /// module notes); `false` is the classic identifier, as MATLAB's hampel.
    pub detrend: bool,
}

impl Default for SpikeOptions {
    fn default() -> Self {
        SpikeOptions {
            half_window: 5,
            nsigma: 3.0,
            min_deviation: 0.0,
            mode: SpikeMode::Gap,
            detrend: false,
        }
    }
}

impl SpikeOptions {
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_HALF_WINDOW).contains(&self.half_window) {
            return Err(RepairError::Option(format!(
                "spike half window {} must be from 1 to {MAX_HALF_WINDOW}",
                self.half_window
            )));
        }
        if !(self.nsigma > 0.0 && self.nsigma.is_finite()) {
            return Err(RepairError::Option("spike nsigma must be above 0".into()));
        }
        if !(self.min_deviation >= 0.0 && self.min_deviation.is_finite()) {
            return Err(RepairError::Option(
                "spike min_deviation must be 0 or more".into(),
            ));
        }
        Ok(())
    }
}

/// One detected spike.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Spike {
    pub marker: usize,
    pub frame: usize,
    /// Which coordinates (x, y, z) were outliers.
    pub axes: [bool; 3],
    /// What `Median` mode writes: the window medians of the coordinates (classic), or the
    /// robust predictions of the outlying ones (detrended).
    pub median: [f64; 3],
}

/// Fewest valid samples in a window for a verdict.
const MIN_WINDOW: usize = 3;

/// Hampel outliers of one marker; only valid samples are judged and take part in windows.
/// Detection uses the original values throughout (replacements do not feed back).
pub fn detect(xyz: &[[f64; 3]], valid: &[bool], marker: usize, opts: &SpikeOptions) -> Vec<Spike> {
    if opts.detrend {
        return detect_detrended(xyz, valid, marker, opts);
    }
    let n = xyz.len().min(valid.len());
    let k = opts.half_window;
    let mut buf: Vec<f64> = Vec::with_capacity(2 * k + 1);
    let mut out = Vec::new();
    for f in 0..n {
        if !valid[f] {
            continue;
        }
        let (lo, hi) = (f.saturating_sub(k), (f + k).min(n - 1));
        let mut axes = [false; 3];
        let mut median = [0.0; 3];
        for c in 0..3 {
            let x = xyz[f][c];
            // One pass over the window: its size, and how much of it lies on either side of
            // the sample.
            let (mut len, mut below, mut above) = (0usize, 0usize, 0usize);
            for g in lo..=hi {
                if valid[g] {
                    let v = xyz[g][c];
                    len += 1;
                    below += usize::from(v < x);
                    above += usize::from(v > x);
                }
            }
            if len < MIN_WINDOW {
                break;
            }
            // The sample is its window's median when no more than half the window lies on
            // either side of it: then its deviation is 0, decided without sorting.
            if len % 2 == 1 && below <= len / 2 && above <= len / 2 {
                median[c] = x;
                continue;
            }
            buf.clear();
            buf.extend((lo..=hi).filter(|&g| valid[g]).map(|g| xyz[g][c]));
            let (outlier, med) = hampel(x, &mut buf, opts.min_deviation, opts.nsigma);
            median[c] = med;
            axes[c] = outlier;
        }
        if axes.iter().any(|&a| a) {
            out.push(Spike {
                marker,
                frame: f,
                axes,
                median,
            });
        }
    }
    out
}

/// Fewest symmetric pairs for a robust prediction; with fewer (near the ends of a valid
/// run) the sample is not judged.
const MIN_PAIRS: usize = 2;

/// The robust prediction of sample `f` from its neighbours: the median of the means of
/// symmetric valid pairs (f − j, f + j), j = 1..=k. `None` with fewer than [`MIN_PAIRS`].
fn predict(
    x: impl Fn(usize) -> f64,
    valid: &[bool],
    f: usize,
    k: usize,
    buf: &mut Vec<f64>,
) -> Option<f64> {
    let n = valid.len();
    buf.clear();
    for j in 1..=k {
        if j > f || f + j >= n {
            break;
        }
        if valid[f - j] && valid[f + j] {
            buf.push(0.5 * (x(f - j) + x(f + j)));
        }
    }
    if buf.len() < MIN_PAIRS {
        return None;
    }
    median(buf)
}

/// The Hampel rule on residuals from [`predict`]: a sample is an outlier when its residual
/// lies more than `nsigma` scaled MADs from the median residual of its window.
fn detect_detrended(
    xyz: &[[f64; 3]],
    valid: &[bool],
    marker: usize,
    opts: &SpikeOptions,
) -> Vec<Spike> {
    let n = xyz.len().min(valid.len());
    let valid = &valid[..n];
    let k = opts.half_window;
    let mut buf = Vec::with_capacity(2 * k + 1);
    // Residuals and predictions per coordinate (NaN where no prediction could be made).
    let mut resid = vec![[f64::NAN; 3]; n];
    let mut pred = vec![[f64::NAN; 3]; n];
    for f in 0..n {
        if !valid[f] {
            continue;
        }
        for c in 0..3 {
            if let Some(p) = predict(|g| xyz[g][c], valid, f, k, &mut buf) {
                pred[f][c] = p;
                resid[f][c] = xyz[f][c] - p;
            }
        }
    }
    let mut out = Vec::new();
    for f in 0..n {
        let mut axes = [false; 3];
        for c in 0..3 {
            let r = resid[f][c];
            // Residuals at rounding level (exact, noise-free data) are never outliers.
            let floor = opts.min_deviation.max(1e-9 * xyz[f][c].abs().max(1.0));
            if r.is_nan() || r.abs() <= floor {
                continue;
            }
            let (lo, hi) = (f.saturating_sub(k), (f + k).min(n - 1));
            buf.clear();
            buf.extend((lo..=hi).map(|g| resid[g][c]).filter(|v| !v.is_nan()));
            if buf.len() < MIN_WINDOW {
                continue;
            }
            axes[c] = hampel(r, &mut buf, floor, opts.nsigma).0;
        }
        if axes.iter().any(|&a| a) {
            let mut median = xyz[f];
            for c in 0..3 {
                if axes[c] {
                    median[c] = pred[f][c];
                }
            }
            out.push(Spike {
                marker,
                frame: f,
                axes,
                median,
            });
        }
    }
    out
}

/// The Hampel rule for `x` against its `window` (which it reorders): an outlier when it lies
/// more than `floor` and more than `nsigma` scaled MADs (1.4826 × MAD) from the window's
/// median. Returns the verdict and the median.
fn hampel(x: f64, window: &mut [f64], floor: f64, nsigma: f64) -> (bool, f64) {
    let med = median(window).unwrap_or(f64::NAN);
    let dev = (x - med).abs();
    // Within the floor (or equal to the median) a sample is never an outlier: skip the MAD.
    if dev <= floor || dev.is_nan() {
        return (false, med);
    }
    for v in window.iter_mut() {
        *v = (*v - med).abs();
    }
    let mad = median(window).unwrap_or(f64::NAN);
    (dev > nsigma * 1.4826 * mad, med)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_known_spike_and_only_it() {
        let mut xyz: Vec<[f64; 3]> = (0..100)
            .map(|f| {
                let t = f as f64 * 0.05;
                [
                    100.0 * t.sin(),
                    50.0 * t.cos() + 0.3 * ((f * 7919) % 13) as f64,
                    3.0 * t,
                ]
            })
            .collect();
        xyz[40][1] += 60.0;
        let mut valid = vec![true; 100];
        valid[60] = false;
        xyz[60] = [1e9; 3]; // invalid samples never enter a window
        let s = detect(&xyz, &valid, 7, &SpikeOptions::default());
        assert_eq!(s.len(), 1, "{s:?}");
        assert_eq!(
            (s[0].marker, s[0].frame, s[0].axes),
            (7, 40, [false, true, false])
        );
        assert!((s[0].median[1] - (xyz[40][1] - 60.0)).abs() < 3.0);
    }

    #[test]
    fn detrended_finds_a_spike_along_fast_motion_that_classic_misses() {
        // Walking along x at 12 mm/frame with 0.3 mm noise; a 35 mm spike along x at frame 60.
        let mut seed = 7u64;
        let mut noise = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.6
        };
        let mut xyz: Vec<[f64; 3]> = (0..200)
            .map(|f| {
                let t = f as f64 / 100.0;
                [
                    12.0 * f as f64 + noise(),
                    50.0 * (6.0 * t).sin() + noise(),
                    900.0 + noise(),
                ]
            })
            .collect();
        xyz[60][0] += 35.0;
        let valid = vec![true; 200];
        let classic = SpikeOptions {
            detrend: false,
            min_deviation: 5.0,
            ..SpikeOptions::default()
        };
        let detrended = SpikeOptions {
            min_deviation: 5.0,
            detrend: true,
            ..SpikeOptions::default()
        };
        assert!(detect(&xyz, &valid, 0, &classic).is_empty());
        let found = detect(&xyz, &valid, 0, &detrended);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].frame, 60);
        assert_eq!(found[0].axes, [true, false, false]);
        // The replacement is the prediction: within noise of the true 720 mm.
        assert!(
            (found[0].median[0] - 720.0).abs() < 1.5,
            "{}",
            found[0].median[0]
        );
    }
}
