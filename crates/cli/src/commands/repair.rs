//! `c3dfix repair`: spikes → fill → filter on one file, written back as a valid C3D.

use crate::commands::repair_io::{self, RepairArgs};
use anyhow::Result;
use c3dfix::save::{check_destination, write_atomic};
use c3dfix::{SaveOptions, Summary};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    pub input: PathBuf,
    /// Where to write the repaired file.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Replace the input file (atomically).
    #[arg(long)]
    pub in_place: bool,
    /// With --in-place: keep the original as FILE.bak (an existing backup is kept as is).
    #[arg(long)]
    pub backup: bool,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
    /// Write the full report (every gap and what filled it, spikes, filter segments) here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub repair: RepairArgs,
}

pub fn run(a: Args) -> Result<i32> {
    let out = repair_io::output_path(&a.input, &a.output, a.in_place)?;
    if a.backup && !a.in_place {
        anyhow::bail!("--backup goes with --in-place");
    }
    a.repair.check()?;
    let save = SaveOptions {
        force: a.force || a.in_place,
        backup: a.backup,
    };
    // Every destination is checked before the first is written, so that a run writes all
    // of its outputs or none.
    check_destination(&out, save.force)?;
    if let Some(r) = &a.report {
        check_destination(r, true)?;
    }
    let done = c3dfix::repair_file(&a.input, &out, &a.repair.options(), &save)?;
    let s = &done.summary;
    if let Some(r) = &a.report {
        write_atomic(
            r,
            serde_json::to_string_pretty(&done.report())?.as_bytes(),
            true,
        )?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(s)?);
    } else {
        print_summary(s);
    }
    Ok(0)
}

/// The few lines a person reads after a repair.
pub fn print_summary(s: &Summary) {
    println!("repaired {} -> {}", s.file, s.output);
    let by: Vec<String> = s
        .filled_by
        .iter()
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    let left: Vec<String> = s
        .left_because
        .iter()
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    println!(
        "  gaps     {} found in {} markers: {} filled ({}), {} left{}",
        s.gaps,
        s.markers,
        s.filled,
        if by.is_empty() {
            "-".into()
        } else {
            by.join(", ")
        },
        s.left,
        if left.is_empty() {
            String::new()
        } else {
            format!(" ({})", left.join(", "))
        }
    );
    if s.spikes > 0 {
        println!("  spikes   {} found", s.spikes);
    }
    if s.segments_filtered + s.segments_too_short > 0 {
        println!(
            "  filter   {} segments filtered, {} too short (left unfiltered)",
            s.segments_filtered, s.segments_too_short
        );
    }
    println!(
        "  changed  {} samples in {} markers",
        s.samples_changed, s.markers_changed
    );
    if s.model_outputs_left > 0 {
        println!(
            "  kept     {} model outputs (angles, forces, …) untouched",
            s.model_outputs_left
        );
    }
    if let Some(b) = &s.backup {
        println!("  backup   {b}");
    }
}
