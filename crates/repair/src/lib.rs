//! Format-agnostic trajectory repair (issue 3): gaps, fills, spikes, filters, evaluation.
//!
//! Works on plain arrays and validity masks: a [`Trial`] is markers × frames of `[f64; 3]`
//! with one `bool` per sample. Knows nothing about C3D; the caller decides which samples are
//! missing (for C3D files, `c3d::is_missing` is the one rule) and writes back the samples
//! [`RepairReport::changes`] marks. Configuration is built and validated once ([`RepairConfig`]); data-driven
//! problems are reported, never panics.
//!
//! ```
//! use repair::{repair_trial, FillOptions, FilterSpec, RepairConfig, SpikeOptions, Trial};
//!
//! // Two markers, 300 frames at 100 Hz; marker 0 loses frames 100..=119.
//! let xyz: Vec<Vec<[f64; 3]>> = (0..2)
//!     .map(|m| (0..300).map(|f| [f as f64, 10.0 * m as f64, (f as f64 * 0.05).sin()]).collect())
//!     .collect();
//! let mut valid = vec![vec![true; 300]; 2];
//! valid[0][100..120].iter_mut().for_each(|v| *v = false);
//! let mut trial = Trial::new(100.0, xyz, valid)?;
//!
//! let cfg = RepairConfig::new(
//!     Some(SpikeOptions::default()),
//!     FillOptions::default(),
//!     Some(FilterSpec::Butterworth { order: 4, cutoff_hz: 6.0 }),
//! )?;
//! let report = repair_trial(&mut trial, &cfg)?;
//! assert_eq!(report.gaps.len(), 1);
//! assert!(trial.valid[0].iter().all(|&v| v));
//! // Samples the writer must flag as interpolated:
//! let filled = report.changes[0].iter().filter(|&&c| c & repair::change::FILLED != 0).count();
//! assert_eq!(filled, 20);
//! # Ok::<(), repair::RepairError>(())
//! ```

pub mod error;
pub mod evaluate;
pub mod fill;
pub mod filter;
pub mod gaps;
pub mod label;
mod linalg;
pub mod names;
pub mod pipeline;
pub mod profile;
pub mod reclaim;
mod rng;
pub mod spikes;
pub mod swaps;
/// Synthetic gait-like trials for this crate's tests, benches and `repair_synthetic` example
/// (feature `synth`, which the crate's own dev-dependency on itself turns on): no part of
/// the runtime API.
#[cfg(any(test, feature = "synth"))]
pub mod synth;
pub mod unlabelled;

pub use error::{RepairError, Result};
pub use evaluate::{
    calibration, evaluate, Calibration, EvalConfig, Evaluation, GapScore, MethodScore,
};
pub use fill::{FillMethod, FillOptions, FillOutcome, SkipKind, SkipReason, Storage};
pub use filter::{FilterSpec, Iir};
pub use gaps::{find_gaps, Gap};
pub use names::{ParseError, SpikeSpec};
pub use pipeline::{change, repair_trial, repair_trial_after, Earlier, RepairConfig, RepairReport};
pub use spikes::{SpikeMode, SpikeOptions};
pub use swaps::{find_swaps, Find, FindKind, SwapOptions};
pub use unlabelled::{Glob, Unlabelled};

/// Marker trajectories of one trial: `xyz[marker][frame]` and `valid[marker][frame]`.
/// Invalid samples' coordinates are ignored (whatever they hold).
#[derive(Debug, Clone, PartialEq)]
pub struct Trial {
    /// Sample rate in Hz (used only by the filters).
    pub rate_hz: f64,
    pub xyz: Vec<Vec<[f64; 3]>>,
    pub valid: Vec<Vec<bool>>,
}

impl Trial {
    /// The trial in millimetres (`mm_per_unit` converts), with samples whose coordinates
    /// are not finite marked missing: how reclaiming and labelling read a trial, whose
    /// thresholds are lengths in mm.
    pub(crate) fn in_mm(&self, mm_per_unit: f64) -> Trial {
        let xyz: Vec<Vec<[f64; 3]>> = self
            .xyz
            .iter()
            .map(|r| r.iter().map(|p| p.map(|v| v * mm_per_unit)).collect())
            .collect();
        let valid = xyz
            .iter()
            .zip(&self.valid)
            .map(|(r, v)| {
                r.iter()
                    .zip(v)
                    .map(|(p, &ok)| ok && p.iter().all(|c| c.is_finite()))
                    .collect()
            })
            .collect();
        Trial {
            rate_hz: self.rate_hz,
            xyz,
            valid,
        }
    }

    /// A trial whose markers all have the same number of frames, with masks to match.
    pub fn new(rate_hz: f64, xyz: Vec<Vec<[f64; 3]>>, valid: Vec<Vec<bool>>) -> Result<Trial> {
        let t = Trial {
            rate_hz,
            xyz,
            valid,
        };
        t.check()?;
        Ok(t)
    }

    pub fn markers(&self) -> usize {
        self.xyz.len()
    }

    pub fn frames(&self) -> usize {
        self.xyz.first().map_or(0, Vec::len)
    }

    /// Shape check: every marker has `frames()` samples and a mask of the same length.
    pub fn check(&self) -> Result<()> {
        let n = self.frames();
        if self.valid.len() != self.xyz.len() {
            return Err(RepairError::Shape {
                marker: self.valid.len().min(self.xyz.len()),
                what: "marker count of masks",
                got: self.valid.len(),
                expected: self.xyz.len(),
            });
        }
        for (m, (x, v)) in self.xyz.iter().zip(&self.valid).enumerate() {
            if x.len() != n {
                return Err(RepairError::Shape {
                    marker: m,
                    what: "coordinates",
                    got: x.len(),
                    expected: n,
                });
            }
            if v.len() != n {
                return Err(RepairError::Shape {
                    marker: m,
                    what: "mask",
                    got: v.len(),
                    expected: n,
                });
            }
        }
        Ok(())
    }
}
