//! `c3dfix view`: a self-contained HTML page that plays the trial in 3D.

use crate::commands::info::read_c3d;
use crate::output::write_atomic;
use crate::plot::marker_index;
use crate::view::{page, sticks};
use anyhow::{Context, Result};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The C3D file to show (the repaired one when comparing).
    pub file: PathBuf,
    /// The original file: drawn beside FILE, with error vectors from each repaired marker.
    #[arg(long)]
    pub against: Option<PathBuf>,
    /// Stick figure as a JSON list of [markerA, markerB] pairs (default: Plug-in Gait
    /// segments found among the labels).
    #[arg(long)]
    pub sticks: Option<PathBuf>,
    /// Output page (.html).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let c = read_c3d(&a.file)?;
    let fname = crate::output::file_name(&a.file);
    let orig = a.against.as_deref().map(read_c3d).transpose()?;
    let oname = a.against.as_deref().map(crate::output::file_name);
    let pairs = match &a.sticks {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            sticks::from_json(&text, &path.display().to_string(), |m| {
                marker_index(&c, m, &fname)
            })?
        }
        None => sticks::plug_in_gait(&c.point_labels()),
    };
    let html = page((&c, &fname), orig.as_ref().zip(oname.as_deref()), pairs)?;
    write_atomic(&a.output, html.as_bytes(), a.force)?;
    Ok(0)
}
