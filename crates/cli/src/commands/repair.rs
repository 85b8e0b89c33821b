//! `c3dfix repair`: spikes → fill → filter on one file, written back as a valid C3D.

use crate::commands::info::read_c3d;
use crate::commands::repair_io::{self, method_name, RepairArgs};
use crate::output::{backup_path, write_atomic, write_backup};
use anyhow::{Context, Result};
use repair::FillOutcome;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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

/// What one repair did, in numbers.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Summary {
    pub file: String,
    pub output: String,
    pub markers: usize,
    pub model_outputs_left: usize,
    pub gaps: usize,
    pub filled: usize,
    /// Gaps filled per method (for `auto`, the method it chose).
    pub filled_by: BTreeMap<String, usize>,
    pub left: usize,
    /// Gaps left per reason.
    pub left_because: BTreeMap<String, usize>,
    pub spikes: usize,
    pub segments_filtered: usize,
    pub segments_too_short: usize,
    pub samples_changed: usize,
    /// Repaired samples clamped to the integer range of POINT:SCALE (integer files only).
    pub samples_clamped: usize,
    pub markers_changed: usize,
    /// Largest and mean expected error of the filled gaps, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm_max: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm_mean: Option<f64>,
    /// Every gap: where, what became of it, and its expected error in mm.
    pub gap_list: Vec<GapBrief>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backup: Option<String>,
    /// Why the file was left as it was (batch only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

/// One gap in a summary.
#[derive(Debug, Clone, Serialize)]
pub struct GapBrief {
    pub label: String,
    pub first: usize,
    pub last: usize,
    /// The method that filled it (`auto`: the one it chose), or why it was left.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub method: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Expected mean 3D error of the fill, mm (for `uncertain` gaps: of the fill withheld).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm: Option<f64>,
}

/// Repair `input` into `output`; the full report as JSON, and the summary.
pub fn repair_file(
    input: &Path,
    output: &Path,
    a: &RepairArgs,
    backup: bool,
    overwrite: bool,
) -> Result<(serde_json::Value, Summary)> {
    repair_read(read_c3d(input)?, input, output, a, backup, overwrite)
}

/// [`repair_file`] on a file already read from `input` (so callers that look at it first,
/// like `batch`, read and parse it once).
pub fn repair_read(
    mut c: c3d::C3d,
    input: &Path,
    output: &Path,
    a: &RepairArgs,
    backup: bool,
    overwrite: bool,
) -> Result<(serde_json::Value, Summary)> {
    if c.points().count() == 0 {
        anyhow::bail!("{}: the file has no points to repair", input.display());
    }
    let cfg = a.config(&c.point_units())?;
    let only = repair_io::select(&c, &a.markers)?;
    let points = repair_io::marker_indices(&c);
    let mut trial = repair_io::trial(&c, &points, a.zero_invalid)?;
    let report = repair::repair_trial(&mut trial, &cfg)
        .map_err(|e| anyhow::anyhow!("{}: {e}", input.display()))?;
    let labels = c.point_labels();
    let row_label = |row: usize| labels[points[row]].clone();
    let in_scope = |row: usize| only.as_ref().is_none_or(|o| o.contains(&points[row]));

    let mut s = Summary {
        file: input.display().to_string(),
        output: output.display().to_string(),
        markers: points.len(),
        model_outputs_left: c.points().count() - points.len(),
        ..Summary::default()
    };
    let mut gaps_json = Vec::new();
    let mm = repair_io::mm_per_unit(&c.point_units());
    let mut expected = Vec::new();
    for g in report.gaps.iter().filter(|g| in_scope(g.gap.marker)) {
        s.gaps += 1;
        let mut brief = GapBrief {
            label: row_label(g.gap.marker),
            first: g.gap.first,
            last: g.gap.last,
            method: None,
            reason: None,
            expected_error_mm: None,
        };
        match g.outcome {
            FillOutcome::Filled {
                method,
                expected_error,
                ..
            } => {
                s.filled += 1;
                *s.filled_by.entry(method_name(method)).or_default() += 1;
                brief.method = Some(method_name(method));
                brief.expected_error_mm = expected_error.map(|e| e * mm);
                expected.extend(brief.expected_error_mm);
            }
            FillOutcome::Skipped(reason) => {
                s.left += 1;
                *s.left_because.entry(reason.name().to_string()).or_default() += 1;
                brief.reason = Some(reason.name().to_string());
                if let repair::SkipReason::Uncertain { expected_error, .. } = reason {
                    brief.expected_error_mm = Some(expected_error * mm);
                }
            }
        }
        let mut v = serde_json::to_value(g)?;
        v["label"] = row_label(g.gap.marker).into();
        if let Some(e) = brief.expected_error_mm {
            v["expected_error_mm"] = e.into();
        }
        gaps_json.push(v);
        s.gap_list.push(brief);
    }
    if !expected.is_empty() {
        s.expected_error_mm_max = Some(expected.iter().copied().fold(0.0, f64::max));
        s.expected_error_mm_mean = Some(expected.iter().sum::<f64>() / expected.len() as f64);
    }
    let spikes: Vec<_> = report
        .spikes
        .iter()
        .filter(|sp| in_scope(sp.marker))
        .collect();
    s.spikes = spikes.len();
    let mut spikes_json = Vec::new();
    for sp in &spikes {
        let mut v = serde_json::to_value(sp)?;
        v["label"] = row_label(sp.marker).into();
        spikes_json.push(v);
    }
    for seg in report.segments.iter().filter(|x| in_scope(x.marker)) {
        if seg.filtered {
            s.segments_filtered += 1;
        } else {
            s.segments_too_short += 1;
        }
    }
    let wb = repair_io::write_back(&mut c, &trial, &points, &report.changes, only.as_deref());
    s.samples_changed = wb.changed;
    s.samples_clamped = wb.clamped;
    s.markers_changed = (0..points.len())
        .filter(|&r| in_scope(r) && report.changes[r].iter().any(|&x| x != 0))
        .count();
    let bytes = c
        .to_bytes()
        .with_context(|| format!("writing the repaired {}", input.display()))?;
    if backup {
        let b = backup_path(input);
        if write_backup(input, &b)? {
            s.backup = Some(b.display().to_string());
        }
    }
    write_atomic(output, &bytes, overwrite)?;
    let per_marker: Vec<_> = (0..points.len())
        .filter(|&r| in_scope(r))
        .map(|r| serde_json::json!({"label": row_label(r), "samples_changed": report.changed_per_marker[r]}))
        .collect();
    let full = serde_json::json!({
        "file": s.file,
        "output": s.output,
        "config": cfg,
        "summary": s,
        "gaps": gaps_json,
        "spikes": spikes_json,
        "spike_mode": report.spike_mode,
        "segments": report.segments.iter().filter(|x| in_scope(x.marker)).map(|x| {
            let mut v = serde_json::to_value(x).unwrap_or_default();
            v["label"] = row_label(x.marker).into();
            v
        }).collect::<Vec<_>>(),
        "markers": per_marker,
    });
    Ok((full, s))
}

pub fn run(a: Args) -> Result<i32> {
    let out = repair_io::output_path(&a.input, &a.output, a.in_place)?;
    if a.backup && !a.in_place {
        anyhow::bail!("--backup goes with --in-place");
    }
    if !a.in_place && !a.force && out.exists() {
        anyhow::bail!("{} exists (use --force to overwrite)", out.display());
    }
    let (full, s) = repair_file(&a.input, &out, &a.repair, a.backup, a.force || a.in_place)?;
    if let Some(r) = &a.report {
        write_atomic(r, serde_json::to_string_pretty(&full)?.as_bytes(), true)?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&s)?);
    } else {
        print_summary(&s);
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
    if let (Some(mean), Some(max)) = (s.expected_error_mm_mean, s.expected_error_mm_max) {
        println!("  expected fill error {mean:.2} mm on average, {max:.2} mm at most");
    }
    for g in s
        .gap_list
        .iter()
        .filter(|g| g.reason.as_deref() == Some("uncertain"))
    {
        println!(
            "  uncertain {} frames {}..{}: expected error {:.1} mm (left unfilled)",
            g.label,
            g.first,
            g.last,
            g.expected_error_mm.unwrap_or(f64::NAN)
        );
    }
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
