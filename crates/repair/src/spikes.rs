//! Spike detection with the Hampel identifier on each coordinate, over valid samples only.
//!
//! Defaults: `half_window` 5 (11-sample window) and `nsigma` 3. MATLAB's hampel uses 3 and
//! 3; the wider window keeps the median robust when optical swaps or reflections corrupt
//! several consecutive frames (up to 5 of 11), at 100–200 Hz it still spans well under a
//! gait event, and a sample on a smooth trajectory is its window's median anyway.
//! The identifier judges raw coordinates, so along an axis where the marker moves fast the
//! window's trend inflates the MAD: walking at 12 mm/frame, a spike along the direction of
//! travel must exceed roughly 150 mm to be caught, while vertical or lateral ones of a few
//! centimetres are.

use serde::Serialize;

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

/// Hampel settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpikeOptions {
    /// Samples on each side of the centre (K).
    pub half_window: usize,
    /// Outlier threshold in scaled MADs (1.4826 × MAD).
    pub nsigma: f64,
    /// Deviations from the median at or below this (data units) are never outliers.
    /// 0 (default) is MATLAB's rule; a few mm keeps measurement noise on a still
    /// coordinate, whose MAD is tiny, from being flagged.
    pub min_deviation: f64,
    pub mode: SpikeMode,
}

impl Default for SpikeOptions {
    fn default() -> Self {
        SpikeOptions {
            half_window: 5,
            nsigma: 3.0,
            min_deviation: 0.0,
            mode: SpikeMode::Gap,
        }
    }
}

impl SpikeOptions {
    pub fn validate(&self) -> Result<()> {
        if self.half_window == 0 {
            return Err(RepairError::Option(
                "spike half_window must be at least 1".into(),
            ));
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
    /// Window medians of the coordinates (what `Median` mode writes).
    pub median: [f64; 3],
}

/// Fewest valid samples in a window for a verdict.
const MIN_WINDOW: usize = 3;

/// Hampel outliers of one marker; only valid samples are judged and take part in windows.
/// Detection uses the original values throughout (replacements do not feed back).
pub fn detect(xyz: &[[f64; 3]], valid: &[bool], marker: usize, opts: &SpikeOptions) -> Vec<Spike> {
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
            buf.clear();
            buf.extend((lo..=hi).filter(|&g| valid[g]).map(|g| xyz[g][c]));
            if buf.len() < MIN_WINDOW {
                break;
            }
            let x = xyz[f][c];
            if buf.len() % 2 == 1 {
                // The sample is its window's median when no more than half the window lies
                // on either side of it: then its deviation is 0, decided without sorting.
                let below = buf.iter().filter(|&&v| v < x).count();
                let above = buf.iter().filter(|&&v| v > x).count();
                if below <= buf.len() / 2 && above <= buf.len() / 2 {
                    median[c] = x;
                    continue;
                }
            }
            let med = median_of(&mut buf);
            median[c] = med;
            let dev = (x - med).abs();
            // A sample equal to its median is never an outlier: skip the MAD.
            if dev <= opts.min_deviation || dev.is_nan() {
                continue;
            }
            for v in buf.iter_mut() {
                *v = (*v - med).abs();
            }
            let s = 1.4826 * median_of(&mut buf);
            axes[c] = dev > opts.nsigma * s;
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

/// Median (mean of the middle two for even counts, as MATLAB's median).
fn median_of(v: &mut [f64]) -> f64 {
    let n = v.len();
    let mid = n / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    let hi = *m;
    if n % 2 == 1 {
        hi
    } else {
        let lo = v[..mid].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo + hi) / 2.0
    }
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
    fn median_matches_matlab_convention() {
        assert_eq!(median_of(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median_of(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
    }
}
