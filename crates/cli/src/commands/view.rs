//! `c3dfix view`: a self-contained HTML page that plays the trial in 3D.

use crate::commands::info::read_c3d;
use crate::output::file_name as name;
use crate::output::write_atomic;
use anyhow::{bail, Context, Result};
use show::plot::marker_index;
use show::view::{file_page, skeleton, sticks};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The C3D file to show (the repaired one when comparing), or a .bvh skeleton.
    pub file: PathBuf,
    /// The original file: drawn beside FILE, with error vectors from each repaired marker
    /// (for a .bvh FILE: a BVH file with the same joints, e.g. the input of `keyframes`).
    #[arg(long)]
    pub against: Option<PathBuf>,
    /// Stick figure as a JSON list of [markerA, markerB] pairs (default: Plug-in Gait
    /// segments found among the labels).
    #[arg(long)]
    pub sticks: Option<PathBuf>,
    /// Output page (.html).
    /// Mark the events the detector finds (as `c3dfix events --from auto`) on the time bar
    /// besides the file's own, in another colour.
    #[arg(long)]
    pub detect_events: bool,
    #[arg(short, long)]
    pub output: PathBuf,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

/// True for a `.bvh` file name (any case): such files are skeletons, not C3D trials.
fn is_bvh(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("bvh"))
}

pub fn run(a: Args) -> Result<i32> {
    let inputs: Vec<&Path> = [
        Some(a.file.as_path()),
        a.against.as_deref(),
        a.sticks.as_deref(),
    ]
    .into_iter()
    .flatten()
    .collect();
    crate::output::refuse_input(&a.output, &inputs, "output")?;
    if is_bvh(&a.file) {
        return run_bvh(&a);
    }
    let c = read_c3d(&a.file)?;
    let fname = name(&a.file);
    let orig = a.against.as_deref().map(read_c3d).transpose()?;
    let oname = a.against.as_deref().map(name);
    let pairs = match &a.sticks {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            Some(sticks::from_json(
                &text,
                &path.display().to_string(),
                |m| marker_index(&c, m, &fname),
            )?)
        }
        None => None,
    };
    let html = file_page(
        &c,
        &a.file,
        &fname,
        orig.as_ref().zip(oname.as_deref()),
        pairs,
        a.detect_events,
        &mut |w| crate::console::errln!("c3dfix: warning: {}: {w}", a.file.display()),
    )?;
    write_atomic(&a.output, html.as_bytes(), a.force)?;
    Ok(0)
}

/// A BVH skeleton: bones from the hierarchy, `--against` another BVH of the same skeleton.
fn run_bvh(a: &Args) -> Result<i32> {
    if a.sticks.is_some() {
        bail!("--sticks is for C3D markers: a BVH file's bones come from its hierarchy");
    }
    if a.detect_events {
        bail!("--detect-events is for C3D trials: a BVH file has no foot markers to read");
    }
    let b = bvh::read(&a.file)?;
    let fname = name(&a.file);
    let orig = match &a.against {
        Some(p) if !is_bvh(p) => bail!(
            "--against {}: a BVH file needs a BVH file to compare with",
            p.display()
        ),
        Some(p) => Some((bvh::read(p)?, name(p))),
        None => None,
    };
    let html = skeleton::page((&b, &fname), orig.as_ref().map(|(o, n)| (o, n.as_str())))?;
    write_atomic(&a.output, html.as_bytes(), a.force)?;
    Ok(0)
}
