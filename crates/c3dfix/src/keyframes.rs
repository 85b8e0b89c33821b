//! Keyframe reduction of a BVH motion as one job: the motion reduced to keys by the chosen
//! method, the error of rebuilding it from them measured, and the rebuilt motion written
//! where asked. The `bvh` crate holds the algorithms; this is the door both fronts call, so
//! the report a person reads is the same from the command line and from Python.

use crate::error::{Error, Result};
use bvh::error_metric::{Effectors, Evaluator};
use bvh::interp::{Interp, Interpolator};
use bvh::keyframes::{check_values, greedy, optimal, rms, Target};
use serde::Serialize;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// How the keys are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum KeyMethod {
    /// Drop the cheapest key repeatedly (fast).
    #[default]
    Greedy,
    /// Dynamic programming over key sets (slower, least error).
    Optimal,
}

impl KeyMethod {
    /// The method's name as people write it.
    pub fn name(self) -> &'static str {
        match self {
            KeyMethod::Greedy => "greedy",
            KeyMethod::Optimal => "optimal",
        }
    }
}

impl fmt::Display for KeyMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for KeyMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "greedy" => Ok(KeyMethod::Greedy),
            "optimal" => Ok(KeyMethod::Optimal),
            _ => Err(Error::options(format!(
                "unknown keyframe method {s:?}: expected greedy or optimal"
            ))),
        }
    }
}

/// What a keyframe reduction is asked to do, checked where it runs.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyframeOptions {
    /// A number of keys, or the largest RMS distance allowed (file units).
    pub target: Target,
    pub method: KeyMethod,
    /// How rotations are interpolated between keys.
    pub interp: Interp,
    /// Which points the error compares: End Sites, or every joint too.
    pub effectors: Effectors,
    /// Optimal method: the longest gap allowed between keys (`None`: no limit).
    pub max_segment: Option<usize>,
    /// Optimal method: search every key set, however long it takes.
    pub exact: bool,
    /// Where the motion rebuilt from the keys (every frame) is written, if anywhere.
    pub output: Option<PathBuf>,
    /// Replace an existing output.
    pub force: bool,
}

/// What a reduction found, as both fronts report it. Field order is the report's.
#[derive(Debug, Clone, Serialize)]
pub struct KeyframeReport {
    pub file: String,
    pub method: KeyMethod,
    pub interp: &'static str,
    /// `end-sites` or `all-joints`.
    pub effectors: &'static str,
    pub frames: usize,
    /// Key frame indices, 0-based.
    pub keys: Vec<usize>,
    /// True when no key set meeting the same target has a smaller error (optimal method,
    /// exhaustive search); false for greedy and for the coarse-to-fine search.
    pub proven_optimal: bool,
    /// Optimal method: grid step of its first search in frames (1: exhaustive).
    pub search_step: Option<usize>,
    pub total_error: f64,
    pub mean_frame_error: f64,
    pub rms_distance: f64,
    pub max_frame_error: f64,
    pub frame_errors: Vec<f64>,
    /// Greedy accumulated error as frames are removed: (removed frames, total error).
    pub greedy_curve: Vec<(usize, f64)>,
    /// The rebuilt motion's path, when written.
    pub output: Option<String>,
    /// The error curves' picture, when a front drew one (the library draws nothing).
    pub plot: Option<String>,
}

/// A reduction's report, with the greedy run behind it (the picture of the error curves
/// reuses it rather than reducing again).
#[derive(Debug, Clone)]
pub struct Keyframed {
    pub report: KeyframeReport,
    pub run: greedy::GreedyRun,
}

/// The name `effectors` is reported by.
fn effectors_name(e: Effectors) -> &'static str {
    match e {
        Effectors::EndSites => "end-sites",
        Effectors::AllJoints => "all-joints",
    }
}

/// Reduce the motion `b`, read from `path`, to keys as `opts` asks, and write the rebuilt
/// motion to `opts.output` (atomically) when given.
pub fn keyframes(b: &bvh::Bvh, path: &Path, opts: &KeyframeOptions) -> Result<Keyframed> {
    let failed = |source| Error::Keyframes {
        path: path.to_path_buf(),
        source,
    };
    check_values(b).map_err(failed)?;
    let eval = Evaluator::new(Interpolator::new(b, opts.interp), opts.effectors);
    let run = greedy::run(&eval);
    let (reduction, proven_optimal, search_step) = match opts.method {
        KeyMethod::Greedy => (
            greedy::reduce_run(&eval, &run, opts.target).map_err(failed)?,
            false,
            None,
        ),
        KeyMethod::Optimal => {
            let options = optimal::Options {
                max_segment: opts.max_segment.filter(|&f| f > 0),
                strategy: match opts.exact {
                    true => optimal::Strategy::Exhaustive,
                    false => optimal::Strategy::Auto,
                },
            };
            let s = optimal::search(&eval, &run, opts.target, options).map_err(failed)?;
            (s.reduction, s.exact, Some(s.step))
        }
    };
    let frame_errors = eval.frame_errors(&reduction.keys);
    let frames = b.motion.frames();
    let total: f64 = frame_errors.iter().sum();
    let max = frame_errors.iter().copied().fold(0.0, f64::max);
    if let Some(out) = &opts.output {
        let rebuilt = bvh::Bvh {
            skeleton: b.skeleton.clone(),
            motion: eval.interpolator().resample(&reduction.keys),
        };
        crate::save::refuse_input(out, &[path], "output")?;
        crate::save::write_atomic(out, bvh::write(&rebuilt).as_bytes(), opts.force)?;
    }
    let report = KeyframeReport {
        file: path.display().to_string(),
        method: opts.method,
        interp: opts.interp.name(),
        effectors: effectors_name(opts.effectors),
        frames,
        keys: reduction.keys,
        proven_optimal,
        search_step,
        total_error: total,
        mean_frame_error: total / frames.max(1) as f64,
        rms_distance: rms(&eval, total),
        max_frame_error: max,
        frame_errors,
        greedy_curve: run.curve(),
        output: opts.output.as_ref().map(|p| p.display().to_string()),
        plot: None,
    };
    Ok(Keyframed { report, run })
}
