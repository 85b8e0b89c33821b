//! `c3dfix evaluate`: knock out known data, fill it with every method, and report the 3D
//! error per method and gap length.

use crate::commands::info::read_c3d;
use crate::commands::repair_io::{fill_method, marker_indices, method_name, mm_per_unit, trial};
use anyhow::{bail, Result};
use repair::{EvalConfig, FillMethod};
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Lengths of the artificial gaps, in frames.
    #[arg(long, value_delimiter = ',', default_value = "5,10,20,40,80")]
    pub gap_lengths: Vec<usize>,
    /// Markers that lose data (labels; default: all markers).
    #[arg(long, value_delimiter = ',')]
    pub markers: Option<Vec<String>>,
    /// Methods to compare (default: all).
    #[arg(long, value_delimiter = ',')]
    pub methods: Option<Vec<String>>,
    /// Artificial gaps (or groups of gaps) per length.
    #[arg(long, default_value_t = 40)]
    pub gaps_per_length: usize,
    /// Markers that lose overlapping frames together: 1, or 2–3 (a marker and its nearest
    /// neighbours) — the harder case.
    #[arg(long, default_value_t = 1)]
    pub group: usize,
    /// Seed of the gap placement.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<i32> {
    if !(1..=3).contains(&a.group) {
        bail!("--group must be 1, 2 or 3");
    }
    if a.gap_lengths.is_empty() || a.gap_lengths.contains(&0) {
        bail!("--gap-lengths must be positive frame counts");
    }
    let methods: Vec<FillMethod> = match &a.methods {
        Some(m) => m.iter().map(|s| fill_method(s)).collect::<Result<_>>()?,
        None => FillMethod::ALL.to_vec(),
    };
    let mut all = Vec::new();
    // Sample-weighted mean errors across files, per (gap length, method).
    let mut pooled: BTreeMap<(usize, String), (f64, usize, f64)> = BTreeMap::new();
    for f in &a.files {
        let c = read_c3d(f)?;
        let points = marker_indices(&c);
        if points.len() < 4 {
            bail!(
                "{}: needs at least 4 markers to evaluate, has {}",
                f.display(),
                points.len()
            );
        }
        // Errors are reported in mm whatever the file's units, so files pool.
        let mut t = trial(&c, &points, false)?;
        let k = mm_per_unit(&c.point_units());
        if k != 1.0 {
            for p in t.xyz.iter_mut().flatten() {
                *p = p.map(|x| x * k);
            }
        }
        let rows = match &a.markers {
            None => None,
            Some(names) => {
                let mut rows = Vec::new();
                for n in names {
                    let Some(i) = c.point_index(n.trim()) else {
                        bail!(
                            "{}: no marker {n:?}; the file has: {}",
                            f.display(),
                            c.point_labels().join(", ")
                        )
                    };
                    match points.iter().position(|&p| p == i) {
                        Some(r) => rows.push(r),
                        None => bail!("{}: {n} is a model output, not a marker", f.display()),
                    }
                }
                Some(rows)
            }
        };
        let cfg = EvalConfig {
            markers: rows,
            gap_lengths: a.gap_lengths.clone(),
            gaps_per_length: a.gaps_per_length,
            methods: methods.clone(),
            group: a.group,
            seed: a.seed,
            ..EvalConfig::default()
        };
        let ev = repair::evaluate(&t, &cfg).map_err(|e| anyhow::anyhow!("{}: {e}", f.display()))?;
        for s in &ev.scores {
            let e = pooled
                .entry((s.gap_len, method_name(s.method)))
                .or_insert((0.0, 0, 0.0));
            e.0 += s.mean * s.samples as f64;
            e.1 += s.samples;
            e.2 = e.2.max(s.max);
        }
        if !a.json {
            print_table(
                &f.display().to_string(),
                "mm",
                &a.gap_lengths,
                &methods,
                |len, m| ev.score(m, len).map(|s| (s.mean, s.failed)),
            );
        }
        all.push(serde_json::json!({"file": f.display().to_string(), "file_units": c.point_units(), "units": "mm", "evaluation": ev}));
    }
    let pooled_rows: Vec<_> = pooled
        .iter()
        .map(|((len, m), (sum, n, max))| {
            serde_json::json!({"gap_len": len, "method": m, "mean": if *n > 0 { sum / *n as f64 } else { f64::NAN }, "max": max, "samples": n})
        })
        .collect();
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(
                &serde_json::json!({"files": all, "pooled": pooled_rows})
            )?
        );
    } else if a.files.len() > 1 {
        print_table(
            "all files (sample-weighted)",
            "mm",
            &a.gap_lengths,
            &methods,
            |len, m| {
                pooled
                    .get(&(len, method_name(m)))
                    .filter(|(_, n, _)| *n > 0)
                    .map(|(s, n, _)| (s / *n as f64, 0))
            },
        );
    }
    Ok(0)
}

fn print_table(
    title: &str,
    units: &str,
    lengths: &[usize],
    methods: &[FillMethod],
    get: impl Fn(usize, FillMethod) -> Option<(f64, usize)>,
) {
    println!("{title}: mean 3D error ({units}) by gap length");
    print!("{:>6}", "gap");
    for m in methods {
        print!(" {:>10}", method_name(*m));
    }
    println!();
    for &len in lengths {
        print!("{len:>6}");
        for &m in methods {
            match get(len, m) {
                Some((mean, failed)) if mean.is_finite() => {
                    let mark = if failed > 0 { "*" } else { " " };
                    print!(" {mean:>9.2}{mark}");
                }
                _ => print!(" {:>10}", "-"),
            }
        }
        println!();
    }
    println!("  (* some artificial gaps could not be filled by that method)");
}
