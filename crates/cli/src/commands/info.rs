//! `c3dfix info`: what a file holds, and what is wrong with it.

use crate::console::outln;
use anyhow::Result;
use c3dfix::info::{describe, Report};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The C3D (or BVH) file to describe.
    pub file: PathBuf,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Read a C3D file, naming the file in any error. A command runs for seconds and holds the
/// file for that long only, so the file is mapped rather than copied
/// ([`c3dfix::open_mapped`]).
pub fn read_c3d(path: &Path) -> Result<c3d::C3d> {
    Ok(c3dfix::open_mapped(path)?)
}

pub fn run(a: Args) -> Result<i32> {
    let is_bvh = a
        .file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("bvh"));
    if is_bvh {
        return crate::commands::bvh_info::run(&a.file, a.json);
    }
    let c = read_c3d(&a.file)?;
    let r = describe(&c, &a.file);
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&r)?)?;
    } else {
        print_text(&r)?;
    }
    Ok(0)
}

fn print_text(r: &Report) -> Result<()> {
    print_layout(r)?;
    print_markers(r)?;
    print_groups(r)?;
    print_plates(r)?;
    print_events(r)?;
    if r.warnings.is_empty() {
        outln!("  warnings     none")?;
    } else {
        outln!("  warnings")?;
        for w in &r.warnings {
            outln!("    - {w}")?;
        }
    }
    Ok(())
}

/// The file's format, frames, points, up and travel, analog channels and header.
fn print_layout(r: &Report) -> Result<()> {
    outln!("{}  ({} bytes)", r.file, r.bytes)?;
    outln!(
        "  format       {} processor, {} data",
        r.processor,
        r.format
    )?;
    outln!(
        "  frames       {} (first {}), {} Hz, {:.3} s",
        r.frames,
        r.first_frame,
        r.point_rate,
        r.duration_s
    )?;
    outln!(
        "  points       {} ({}, POINT:SCALE {})",
        r.points,
        r.point_units,
        r.point_scale
    )?;
    match (r.up, r.up_source) {
        (Some(up), Some(source)) => outln!("  up           {up} (from {source})")?,
        _ => outln!("  up           unknown (no force plates, no marker samples)")?,
    }
    if let Some(travel) = r.travel {
        outln!("  travel       {travel} (the pelvis stays while the feet swing back and forth under it)")?;
    }
    if r.analog_channels > 0 {
        outln!(
            "  analog       {} channels at {} Hz ({} samples per frame)",
            r.analog_channels,
            r.analog_rate,
            r.analog_samples_per_frame
        )?;
    } else {
        outln!("  analog       none")?;
    }
    outln!(
        "  header       parameters at block {}, data at block {}, max gap {}",
        r.header.parameter_block,
        r.header.data_start,
        r.header.max_gap
    )?;
    Ok(())
}

/// The markers with gaps, and per point its valid frames, gaps and longest gap (model
/// outputs under their own heading).
fn print_markers(r: &Report) -> Result<()> {
    // Counted as `gaps` counts them: markers only, model outputs apart.
    let markers: Vec<_> = r.markers.iter().filter(|m| !m.model_output).collect();
    let with_gaps = markers.iter().filter(|m| m.gaps > 0).count();
    let outputs = r.markers.len() - markers.len();
    if c3dfix::info::zeros_look_missing(r.origin_samples) {
        outln!(
            "  note         {} valid samples sit exactly at (0, 0, 0); if this writer stores missing points that way, use --zero-invalid with gaps, repair and batch",
            r.origin_samples
        )?;
    }
    if outputs > 0 {
        outln!(
            "  markers      {with_gaps} with gaps out of {} ({outputs} model outputs apart)",
            markers.len()
        )?;
    } else {
        outln!(
            "  markers      {with_gaps} with gaps out of {}",
            markers.len()
        )?;
    }
    if !r.markers.is_empty() {
        outln!(
            "    {:<24} {:>8} {:>6} {:>8}",
            "label",
            "valid",
            "gaps",
            "longest"
        )?;
        // Markers first, then the model outputs under their own heading.
        let (marks, outs): (Vec<_>, Vec<_>) = r.markers.iter().partition(|m| !m.model_output);
        for (i, m) in marks.iter().chain(&outs).enumerate() {
            if i == marks.len() {
                outln!("    model outputs")?;
            }
            outln!(
                "    {:<24} {:>8} {:>6} {:>8}",
                m.label,
                m.valid_frames,
                m.gaps,
                m.longest_gap
            )?;
        }
    }
    Ok(())
}

/// The parameter groups.
fn print_groups(r: &Report) -> Result<()> {
    outln!("  groups")?;
    for g in &r.groups {
        outln!(
            "    {:<16}{} {} parameters{}",
            g.name,
            if g.locked { " (locked)" } else { "" },
            g.parameters.len(),
            if g.description.is_empty() {
                String::new()
            } else {
                format!("  — {}", g.description)
            }
        )?;
    }
    Ok(())
}

/// The force plates with their channels, centre, peak push and contacts, and what was
/// wrong with them.
fn print_plates(r: &Report) -> Result<()> {
    if !r.force_platforms.is_empty() || !r.force_platform_warnings.is_empty() {
        outln!(
            "  plates       {} force platform{} (COP where |Fz| >= {} N)",
            r.force_platforms.len(),
            if r.force_platforms.len() == 1 {
                ""
            } else {
                "s"
            },
            c3dfix::platforms::DEFAULT_THRESHOLD_N
        )?;
        for p in &r.force_platforms {
            let channels: Vec<String> = p.channels.iter().map(|c| c.to_string()).collect();
            outln!(
                "    plate {}  type {}  channels {}  centre ({:.1}, {:.1}, {:.1}) {}  peak push {:.1} N  {} contact{}",
                p.index,
                p.kind,
                channels.join(","),
                p.centre[0],
                p.centre[1],
                p.centre[2],
                r.point_units,
                p.peak_force,
                p.contacts,
                if p.contacts == 1 { "" } else { "s" }
            )?;
        }
        for w in &r.force_platform_warnings {
            outln!("    - {w}")?;
        }
    }
    Ok(())
}

/// The header's events and the EVENT group's, each lab's own gait label with what it is
/// read as.
fn print_events(r: &Report) -> Result<()> {
    if !r.header_events.is_empty() || !r.events.is_empty() {
        outln!("  events")?;
        for e in &r.header_events {
            outln!("    header  {:<8} {:>9.3} s", e.label, e.time)?;
        }
        for e in &r.events {
            // A lab's own gait label (`LHS` in General) says what it is read as.
            match c3dfix::event_labels::read_as(&e.context, &e.label) {
                Some((side, kind)) => outln!(
                    "    {:<7} {:<16} {:>9.3} s  (read as {} {})",
                    e.context,
                    e.label,
                    e.time,
                    side.context(),
                    kind.label()
                )?,
                None => outln!("    {:<7} {:<16} {:>9.3} s", e.context, e.label, e.time)?,
            }
        }
    }
    Ok(())
}
