//! `c3dfix keyframes`: reduce a BVH motion to key frames and rebuild it by interpolation.

use std::path::PathBuf;

use anyhow::Result;
use bvh::error_metric::Effectors;
use bvh::interp::Interp;
use bvh::keyframes::Target;
use c3dfix::{KeyMethod, KeyframeOptions, KeyframeReport};

use crate::console::outln;
use crate::output::write_atomic;
use show::plot::{render_keyframe_curves, KeyframeCurves};

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Method {
    /// Drop the cheapest key repeatedly (fast).
    Greedy,
    /// Dynamic programming over key sets (slower, least error): exhaustive when that is quick
    /// (or with --exact), otherwise coarse-to-fine and never worse than greedy.
    Optimal,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum InterpArg {
    /// Slerp each joint's rotation.
    Quat,
    /// Linear in each Euler angle.
    Euler,
}

impl From<InterpArg> for Interp {
    fn from(a: InterpArg) -> Interp {
        match a {
            InterpArg::Quat => Interp::Quat,
            InterpArg::Euler => Interp::Euler,
        }
    }
}

#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("target").required(true).args(["keys", "max_error"])))]
pub struct Args {
    /// The BVH file to reduce.
    pub input: PathBuf,
    /// Keep exactly this many key frames, first and last included (2 to the number of frames).
    #[arg(long, value_name = "N")]
    pub keys: Option<usize>,
    /// Keep as few keys as possible with an RMS End Site distance at most this (file units,
    /// 0 to 1e9).
    #[arg(long, value_name = "MM", value_parser = crate::ranges::keyframe_error)]
    pub max_error: Option<f64>,
    #[arg(long, value_enum, default_value = "greedy")]
    pub method: Method,
    #[arg(long, value_enum, default_value = "quat")]
    pub interp: InterpArg,
    /// Optimal method: longest gap allowed between keys (0 to 4294967295 frames; 0, the
    /// default: no limit).
    #[arg(long, value_name = "FRAMES", value_parser = crate::ranges::max_segment)]
    pub max_segment: Option<usize>,
    /// Optimal method: search every key set exhaustively, however long it takes (by default
    /// only when that is quick, else coarse-to-fine).
    #[arg(long)]
    pub exact: bool,
    /// Measure error on every joint, not only End Sites.
    #[arg(long)]
    pub all_joints: bool,
    /// Write the motion rebuilt from the keys (every frame) to this BVH file.
    #[arg(short, long, value_name = "OUT.bvh")]
    pub output: Option<PathBuf>,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
    /// Overwrite existing output files.
    #[arg(long)]
    pub force: bool,
    /// Draw accumulated error against removed frames (greedy, Euler and quaternion) as SVG.
    #[arg(long, value_name = "CURVE.svg")]
    pub plot: Option<PathBuf>,
}

pub fn run(a: Args) -> Result<i32> {
    let b = bvh::read(&a.input)?;
    let target = match (a.keys, a.max_error) {
        (Some(k), _) => Target::Keys(k),
        (None, Some(e)) => Target::MaxError(e),
        (None, None) => anyhow::bail!("give --keys or --max-error"),
    };
    let opts = KeyframeOptions {
        target,
        method: match a.method {
            Method::Greedy => KeyMethod::Greedy,
            Method::Optimal => KeyMethod::Optimal,
        },
        interp: a.interp.into(),
        effectors: if a.all_joints {
            Effectors::AllJoints
        } else {
            Effectors::EndSites
        },
        // 0 is no limit.
        max_segment: a.max_segment,
        exact: a.exact,
        output: a.output.clone(),
        force: a.force,
    };
    let done = c3dfix::keyframes(&b, &a.input, &opts)?;
    let mut report = done.report;
    if let Some(path) = &a.plot {
        let name = crate::output::file_name(&a.input);
        let curves =
            KeyframeCurves::gather(&b, opts.effectors, name, Some((opts.interp, &done.run)));
        let svg = render_keyframe_curves(&curves)?;
        write_atomic(path, svg.as_bytes(), a.force)?;
        report.plot = Some(path.display().to_string());
    }
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        print_text(&report)?;
    }
    Ok(0)
}

fn print_text(r: &KeyframeReport) -> Result<()> {
    outln!("{}: {} frames", r.file, r.frames)?;
    outln!(
        "{} keys ({}, {} interpolation, error on {}):",
        r.keys.len(),
        r.method,
        r.interp,
        r.effectors
    )?;
    let keys: Vec<String> = r.keys.iter().map(|k| k.to_string()).collect();
    outln!("  keys (0-based frames): {}", keys.join(" "))?;
    match r.search_step {
        Some(1) => outln!("  proven optimal (exhaustive search)")?,
        Some(step) => outln!(
            "  not proven optimal: coarse-to-fine search from a {step}-frame grid, never worse than greedy (--exact searches exhaustively, slowly)"
        )?,
        None => {}
    }
    outln!(
        "  total error {:.6} (sum of squared distances), mean per frame {:.6}, max per frame {:.6}, RMS distance {:.6}",
        r.total_error, r.mean_frame_error, r.max_frame_error, r.rms_distance
    )?;
    // About ten points of the curve, enough to see where the error takes off.
    let step = (r.greedy_curve.len() / 10).max(1);
    let points: Vec<String> = r
        .greedy_curve
        .iter()
        .step_by(step)
        .chain(r.greedy_curve.last())
        .map(|(removed, e)| format!("{removed}:{e:.3}"))
        .collect();
    outln!(
        "  greedy curve (removed frames:total error): {}",
        points.join(" ")
    )?;
    let errors: Vec<String> = r.frame_errors.iter().map(|e| format!("{e:.4}")).collect();
    outln!("  error per frame: {}", errors.join(" "))?;
    if let Some(o) = &r.output {
        outln!("  wrote {o}")?;
    }
    if let Some(p) = &r.plot {
        outln!("  plotted {p}")?;
    }
    Ok(())
}
