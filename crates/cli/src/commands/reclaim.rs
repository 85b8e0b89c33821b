//! `c3dfix reclaim`: which unlabelled samples are a labelled marker's (issue 47), judged by
//! the marker's path at its gaps' ends and the distances it keeps to its segment; nothing is
//! changed (`repair --reclaim on` moves the settled ones).

use crate::commands::info::read_c3d;
use crate::console::outln;
use anyhow::Result;
use c3dfix::UnsettledWhy;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    pub file: PathBuf,
    /// Labels (a glob: `*` any text, `?` one character, case-insensitive) that also mark a
    /// point as unlabelled, beside the common placeholders (`*51`, `Unlabeled 3`, an empty
    /// label).
    #[arg(long, value_name = "PATTERN")]
    pub unlabelled: Option<repair::Glob>,
    /// Also treat samples whose coordinates are all exactly 0 as missing.
    #[arg(long)]
    pub zero_invalid: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let c = read_c3d(&a.file)?;
    let rule = a
        .unlabelled
        .clone()
        .map_or_else(repair::Unlabelled::common, repair::Unlabelled::with_pattern);
    let out = c3dfix::reclaim(&c, &a.file, &rule, a.zero_invalid)?;
    if a.json {
        let mut v = serde_json::to_value(&out)?;
        v["file"] = a.file.display().to_string().into();
        v["frames"] = c.frames().into();
        outln!("{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(0);
    }
    let samples: usize = out.settled.iter().map(|b| b.samples).sum();
    outln!(
        "{}: {} settled pieces ({} samples) and {} unsettled, from {} unlabelled points into {} labelled markers ({} pieces judged)",
        a.file.display(),
        out.settled.len(),
        samples,
        out.unsettled.len(),
        out.unlabelled,
        out.markers,
        out.pieces
    )?;
    for b in &out.settled {
        outln!(
            "  settled   {:<12} ← {:<8} frames {:>6}–{:<6} link rms {:.2} mm",
            b.marker,
            b.source,
            b.first_frame,
            b.last_frame,
            b.fit.rms_mm
        )?;
    }
    for u in &out.unsettled {
        let why = match &u.why {
            UnsettledWhy::Ambiguous {
                rival_marker,
                rival_source,
                rival_first_frame,
                rival_last_frame,
                ..
            } => format!(
                "ambiguous with {rival_marker} ← {rival_source} frames {rival_first_frame}–{rival_last_frame}"
            ),
            UnsettledWhy::FewLinks { checked_frames } => {
                format!("too few segment distances ({checked_frames} frames checked)")
            }
        };
        outln!(
            "  unsettled {:<12} ← {:<8} frames {:>6}–{:<6} {why}",
            u.marker,
            u.source,
            u.first_frame,
            u.last_frame
        )?;
    }
    Ok(0)
}
