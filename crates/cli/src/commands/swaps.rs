//! `c3dfix swaps`: marker label swaps and label jumps, found from the distances the markers
//! of one segment keep and the continuity of each trajectory.

use crate::commands::info::read_c3d;
use crate::console::outln;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    pub file: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let c = read_c3d(&a.file)?;
    let opts = repair::swaps::SwapOptions::default();
    let out = c3dfix::swaps(&c, &a.file, &opts)?;
    if a.json {
        let v = serde_json::json!({
            "file": a.file.display().to_string(),
            "frames": out.frames,
            "markers": out.markers,
            "swaps": out.swaps,
            "warnings": out.warnings,
        });
        outln!("{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(0);
    }
    let settled = out.swaps.iter().filter(|x| x.settled).count();
    outln!(
        "{}: {} finds ({} settled) in {} markers ({} frames)",
        a.file.display(),
        out.swaps.len(),
        settled,
        out.markers,
        out.frames
    )?;
    for w in &out.warnings {
        outln!("  warning: {w}")?;
    }
    for x in &out.swaps {
        let kind = match x.kind {
            repair::swaps::FindKind::Swap => "swap",
            repair::swaps::FindKind::Jump => "jump",
        };
        outln!(
            "  {kind} {:<30} frames {:>6}–{:<6} confidence {:.2}{}",
            x.markers.join(" ↔ "),
            x.first_frame,
            x.last_frame,
            x.confidence,
            if x.settled { "" } else { "  (reported only)" }
        )?;
    }
    Ok(0)
}
