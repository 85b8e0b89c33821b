//! `c3dfix diff`: compare two C3D files. Exit 0 when equal, 1 when different, 2 on error.

use crate::commands::info::read_c3d;
use crate::console::outln;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    pub a: PathBuf,
    pub b: PathBuf,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
    /// Coordinates closer than this (in POINT:UNITS; a finite number, 0 or more) count as equal.
    #[arg(long, default_value_t = 0.0, value_parser = crate::ranges::non_negative)]
    pub tolerance: f64,
    /// Compare the data only (points, validity, residuals, analog values, labels, every
    /// parameter that carries meaning), not the layout a conversion may move (processor,
    /// number format, POINT:SCALE, DATA_START, block counts, ANALOG's encoding words, record
    /// order): a round trip through `convert` says "same data" here.
    #[arg(long)]
    pub data: bool,
}

pub fn run(a: Args) -> Result<i32> {
    if a.tolerance.is_nan() || a.tolerance < 0.0 {
        anyhow::bail!("--tolerance must be 0 or more");
    }
    let x = read_c3d(&a.a)?;
    let y = read_c3d(&a.b)?;
    let opts = c3d::diff::DiffOptions {
        tolerance: a.tolerance,
        data: a.data,
    };
    let d = c3d::diff::diff_with(&x, &y, &opts);
    if a.json {
        let v = serde_json::json!({
            "a": a.a.display().to_string(),
            "b": a.b.display().to_string(),
            "equal": d.is_empty(),
            "data_only": a.data,
            "diff": d,
        });
        outln!("{}", serde_json::to_string_pretty(&v)?)?;
    } else if d.is_empty() && a.data {
        outln!("same data")?;
    } else if d.is_empty() {
        outln!("no differences")?;
    } else {
        print_text(&d)?;
    }
    Ok(if d.is_empty() { 0 } else { 1 })
}

fn print_text(d: &c3d::diff::Diff) -> Result<()> {
    for f in d.format.iter().chain(&d.header) {
        outln!("header     {:<24} {} -> {}", f.field, f.a, f.b)?;
    }
    for p in &d.parameters {
        match (&p.a, &p.b) {
            (Some(x), Some(y)) => outln!("parameter  {:<24} {}: {} -> {}", p.name, p.change, x, y)?,
            _ => outln!("parameter  {:<24} {}", p.name, p.change)?,
        }
    }
    if d.parameters_reordered {
        outln!("parameter  records are in a different order")?;
    }
    let pd = &d.points;
    if let Some((x, y)) = pd.frames {
        outln!("points     frames {x} -> {y}")?;
    }
    for l in &pd.only_in_a {
        outln!("points     {l}: only in the first file")?;
    }
    for l in &pd.only_in_b {
        outln!("points     {l}: only in the second file")?;
    }
    for m in &pd.markers {
        outln!(
            "points     {:<24} {} frames changed ({}–{}), max displacement {:.3}, +{} valid, -{} valid, {} flag-only",
            m.label,
            m.frames_changed,
            m.first_frame.unwrap_or(0),
            m.last_frame.unwrap_or(0),
            m.max_displacement,
            m.became_valid,
            m.became_invalid,
            m.flags_changed
        )?;
    }
    let ad = &d.analog;
    if let Some((x, y)) = ad.samples {
        outln!("analog     samples {x} -> {y}")?;
    }
    for l in &ad.only_in_a {
        outln!("analog     {l}: only in the first file")?;
    }
    for l in &ad.only_in_b {
        outln!("analog     {l}: only in the second file")?;
    }
    for c in &ad.channels {
        outln!(
            "analog     {:<24} {} samples changed, max difference {}",
            c.label,
            c.samples_changed,
            number(c.max_difference)
        )?;
    }
    Ok(())
}

/// A difference as people read it: six decimals, or scientific notation when that would
/// print a difference as 0.000000.
fn number(x: f64) -> String {
    if x != 0.0 && x.abs() < 5e-7 {
        format!("{x:.3e}")
    } else {
        format!("{x:.6}")
    }
}
