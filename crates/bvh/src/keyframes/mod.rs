//! Keyframe reduction: choose which frames to keep so that interpolating between them stays
//! close to the original motion. The first and last frames are always keys.
//!
//! Error is the sum over frames of [`crate::error_metric`]'s per-frame error (squared
//! distances, in file units squared). An error *bound* is given as a root-mean-square distance
//! per compared point and frame, in file units, so that it reads like a tolerance:
//! `total ≤ bound² · frames · points`.

mod dp;
pub mod greedy;
pub mod optimal;

use crate::error_metric::Evaluator;
use crate::skeleton::Bvh;

/// Largest magnitude accepted for a channel value or an offset (file units, or degrees).
/// Anything beyond is a corrupt file rather than a motion (10⁹ mm is a thousand kilometres,
/// 10⁹ degrees millions of turns), and squared distances built from it would overflow the
/// error sums into infinities and NaN.
pub const MAX_ABS_VALUE: f64 = 1e9;

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
    #[error(
        "{place}: {value:e} is not a plausible value (keyframes accepts magnitudes up to 1e9)"
    )]
    AbsurdValue { place: String, value: f64 },
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

/// Refuse non-finite or absurdly large offsets and channel values (see [`MAX_ABS_VALUE`]),
/// naming the first one: the joint and, for motion values, the frame (0-based) and channel.
pub fn check_values(bvh: &Bvh) -> Result<(), KeyframeError> {
    let bad = |v: f64| v.is_nan() || v.abs() > MAX_ABS_VALUE;
    for joint in &bvh.skeleton.joints {
        if let Some(&v) = joint.offset.iter().find(|&&v| bad(v)) {
            return Err(KeyframeError::AbsurdValue {
                place: format!("OFFSET of joint `{}`", joint.name),
                value: v,
            });
        }
        if let Some(&v) = joint.end_site.iter().flatten().find(|&&v| bad(v)) {
            return Err(KeyframeError::AbsurdValue {
                place: format!("End Site OFFSET of joint `{}`", joint.name),
                value: v,
            });
        }
    }
    let motion = &bvh.motion;
    for (i, &v) in motion.values.iter().enumerate() {
        if bad(v) {
            let (frame, column) = (i / motion.channels.max(1), i % motion.channels.max(1));
            let channel = bvh.skeleton.joints.iter().find_map(|j| {
                let k = column.checked_sub(j.first_channel)?;
                j.channels.get(k).map(|c| (j.name.as_str(), c.name()))
            });
            let place = match channel {
                Some((joint, ch)) => format!("MOTION frame {frame}, joint `{joint}`, {ch}"),
                None => format!("MOTION frame {frame}, value {}", column + 1),
            };
            return Err(KeyframeError::AbsurdValue { place, value: v });
        }
    }
    Ok(())
}

fn check(eval: &Evaluator, target: Target) -> Result<(), KeyframeError> {
    check_values(eval.interpolator().bvh())?;
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
