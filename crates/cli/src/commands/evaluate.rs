//! `c3dfix evaluate`: knock out known data, fill it with every method, and report the 3D
//! error per method and gap length.

use crate::console::{out, outln};
use crate::ranges;
use anyhow::Result;
use c3dfix::EvaluateOptions;
use repair::FillMethod;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Lengths of the artificial gaps, in frames (each 1 to 1 000 000).
    #[arg(long, value_delimiter = ',', default_value = "5,10,20,40,80", value_parser = ranges::gap_length)]
    pub gap_lengths: Vec<usize>,
    /// Markers that lose data (labels; default: all markers).
    #[arg(long, value_delimiter = ',')]
    pub markers: Option<Vec<String>>,
    /// Methods to compare (default: all).
    #[arg(long, value_delimiter = ',', value_parser = crate::ranges::choice::<FillMethod>)]
    pub methods: Option<Vec<FillMethod>>,
    /// Artificial gaps (or groups of gaps) per length, 1 to 10 000.
    #[arg(long, default_value_t = 40, value_parser = ranges::gaps_per_length)]
    pub gaps_per_length: usize,
    /// Markers that lose overlapping frames together: 1, or 2–3 (a marker and its nearest
    /// neighbours) — the harder case.
    #[arg(long, default_value_t = 1)]
    pub group: usize,
    /// Seed of the gap placement (any whole number from 0 to 2^64 − 1).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let opts = EvaluateOptions {
        gap_lengths: a.gap_lengths.clone(),
        markers: a.markers.clone(),
        methods: a.methods.clone(),
        gaps_per_length: a.gaps_per_length,
        group: a.group,
        seed: a.seed,
    };
    let methods = opts.fill_methods();
    let mut printed: Result<()> = Ok(());
    let ev = c3dfix::evaluate(&a.files, &opts, |fe| {
        if !a.json && printed.is_ok() {
            printed = print_table(&fe.file, &fe.units, &a.gap_lengths, &methods, |len, m| {
                fe.evaluation.score(m, len).map(|s| (s.mean, s.failed))
            });
        }
    })?;
    printed?;
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&ev)?)?;
    } else if a.files.len() > 1 {
        print_table(
            "all files (sample-weighted, in mm whatever each file's unit)",
            "mm",
            &a.gap_lengths,
            &methods,
            |len, m| {
                ev.pooled
                    .iter()
                    .find(|p| p.gap_len == len && p.method == m.to_string() && p.samples > 0)
                    .map(|p| (p.mean, 0))
            },
        )?;
    }
    Ok(0)
}

fn print_table(
    title: &str,
    units: &str,
    lengths: &[usize],
    methods: &[FillMethod],
    get: impl Fn(usize, FillMethod) -> Option<(f64, usize)>,
) -> Result<()> {
    outln!("{title}: mean 3D error ({units}) by gap length")?;
    out!("{:>6}", "gap")?;
    for m in methods {
        out!(" {:>10}", m)?;
    }
    outln!()?;
    for &len in lengths {
        out!("{len:>6}")?;
        for &m in methods {
            match get(len, m) {
                Some((mean, failed)) if mean.is_finite() => {
                    let mark = if failed > 0 { "*" } else { " " };
                    out!(" {mean:>9.2}{mark}")?;
                }
                _ => out!(" {:>10}", "-")?,
            }
        }
        outln!()?;
    }
    outln!("  (* some artificial gaps could not be filled by that method)")
}
