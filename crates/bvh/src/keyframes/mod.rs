//! Keyframe reduction: choose which frames to keep so that interpolating between them stays
//! close to the original motion. The first and last frames are always keys.
//!
//! Error is the sum over frames of [`crate::error_metric`]'s per-frame error (squared
//! distances, in file units squared). An error *bound* is given as a root-mean-square distance
//! per compared point and frame, in file units, so that it reads like a tolerance:
//! `total ≤ bound² · frames · points`.

pub mod greedy;
pub mod optimal;

use crate::error_metric::Evaluator;

/// What the reduction aims for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// Exactly this many keys (at least 2).
    Keys(usize),
    /// As few keys as possible with an RMS point distance no larger than this (file units).
    MaxError(f64),
}

/// The outcome of a reduction.
#[derive(Debug, Clone, PartialEq)]
pub struct Reduction {
    /// Key frame indices (0-based, sorted, first and last frame included).
    pub keys: Vec<usize>,
    /// Total error of the motion rebuilt from the keys.
    pub total_error: f64,
}

/// Why a reduction cannot be done.
///
/// More kinds may come in later versions, so matches need a `_` arm.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KeyframeError {
    #[error("keyframe reduction needs at least 2 frames, the motion has {0}")]
    TooFewFrames(usize),
    #[error("{keys} keys requested, but it must be between 2 and the {frames} frames")]
    BadKeyCount { keys: usize, frames: usize },
    #[error("the error bound must be a finite number ≥ 0, got {0}")]
    BadErrorBound(f64),
    #[error("a maximum segment length of {max_segment} frames cannot cover {frames} frames with {keys} keys")]
    SegmentCapTooSmall {
        max_segment: usize,
        frames: usize,
        keys: usize,
    },
}

/// The total-error bound that an RMS bound means for this motion.
pub fn total_bound(eval: &Evaluator, rms: f64) -> f64 {
    rms * rms * eval.frames() as f64 * eval.points_per_frame() as f64
}

/// The RMS point distance that a total error means for this motion.
pub fn rms(eval: &Evaluator, total: f64) -> f64 {
    let n = eval.frames() as f64 * eval.points_per_frame() as f64;
    if n > 0.0 {
        (total.max(0.0) / n).sqrt()
    } else {
        0.0
    }
}

fn check(eval: &Evaluator, target: Target) -> Result<(), KeyframeError> {
    let n = eval.frames();
    if n < 2 {
        return Err(KeyframeError::TooFewFrames(n));
    }
    match target {
        Target::Keys(k) if k < 2 || k > n => Err(KeyframeError::BadKeyCount { keys: k, frames: n }),
        Target::MaxError(e) if !(e.is_finite() && e >= 0.0) => Err(KeyframeError::BadErrorBound(e)),
        _ => Ok(()),
    }
}
