//! `c3dfix gaps`: every gap of every marker.

use crate::commands::info::read_c3d;
use crate::console::outln;
use anyhow::Result;
use c3dfix::markers::marker_indices;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    pub file: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also treat samples whose coordinates are all exactly 0 as missing.
    #[arg(long)]
    pub zero_invalid: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let c = read_c3d(&a.file)?;
    if c.point_count() == 0 {
        anyhow::bail!("{}: the file has no points", a.file.display());
    }
    let out = c3dfix::gaps(&c, a.zero_invalid);
    let markers = marker_indices(&c).len();
    if a.json {
        let v = serde_json::json!({
            "file": a.file.display().to_string(),
            "frames": c.frames(),
            "markers": markers,
            "gaps": out,
        });
        outln!("{}", serde_json::to_string_pretty(&v)?)?;
    } else {
        outln!(
            "{}: {} gaps in {} markers ({} frames)",
            a.file.display(),
            out.len(),
            markers,
            c.frames()
        )?;
        for g in &out {
            let edge = match (g.at_start, g.at_end) {
                (true, true) => "  (whole trial)",
                (true, false) => "  (at start)",
                (false, true) => "  (at end)",
                _ => "",
            };
            outln!(
                "  {:<24} frames {:>6}–{:<6} {:>5} frames{edge}",
                g.label,
                g.first_frame,
                g.last_frame,
                g.length
            )?;
        }
    }
    Ok(0)
}
