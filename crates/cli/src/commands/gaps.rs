//! `c3dfix gaps`: every gap of every marker.

use crate::commands::info::read_c3d;
use crate::console::outln;
use anyhow::Result;
use c3dfix::markers::marker_indices;
use c3dfix::trial::validity;
use serde::Serialize;
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

#[derive(Serialize)]
struct GapOut {
    label: String,
    /// 1-based frame numbers as the file counts them.
    first_frame: usize,
    last_frame: usize,
    length: usize,
    at_start: bool,
    at_end: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let c = read_c3d(&a.file)?;
    if c.point_count() == 0 {
        anyhow::bail!("{}: the file has no points", a.file.display());
    }
    let points = marker_indices(&c);
    let v = validity(&c, &points, a.zero_invalid);
    let labels = c.point_labels();
    let first = c.first_frame();
    let mut out = Vec::new();
    for (row, &i) in points.iter().enumerate() {
        for g in repair::find_gaps(&v.valid[row], row) {
            out.push(GapOut {
                label: labels[i].clone(),
                first_frame: first + g.first,
                last_frame: first + g.last,
                length: g.len,
                at_start: g.at_start,
                at_end: g.at_end,
            });
        }
    }
    if a.json {
        let v = serde_json::json!({
            "file": a.file.display().to_string(),
            "frames": c.frames(),
            "markers": points.len(),
            "gaps": out,
        });
        outln!("{}", serde_json::to_string_pretty(&v)?)?;
    } else {
        outln!(
            "{}: {} gaps in {} markers ({} frames)",
            a.file.display(),
            out.len(),
            points.len(),
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
