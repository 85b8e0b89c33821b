//! `c3dfix info`: what a file holds, and what is wrong with it.

use crate::console::outln;
use anyhow::Result;
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The C3D (or BVH) file to describe.
    pub file: PathBuf,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct MarkerInfo {
    label: String,
    /// A model output (an angle, force, moment or power stored as a point), not a marker:
    /// `gaps` and `repair` leave these apart, and so does the count `info` prints.
    model_output: bool,
    valid_frames: usize,
    gaps: usize,
    longest_gap: usize,
}

/// A force plate as `info` lists it; `c3dfix forces` gives every sample.
#[derive(Serialize)]
struct PlateInfo {
    index: usize,
    #[serde(rename = "type")]
    kind: i32,
    channels: Vec<usize>,
    /// The centre of the corners, POINT:UNITS.
    centre: [f64; 3],
    /// Largest push over the trial (N), its unloaded level removed.
    peak_force: f64,
    /// Stretches where a foot pushes with at least the threshold.
    contacts: usize,
}

#[derive(Serialize)]
struct GroupInfo {
    id: u8,
    name: String,
    locked: bool,
    description: String,
    parameters: Vec<String>,
}

/// What `info` says about a C3D file.
#[derive(Serialize)]
pub struct Report<'a> {
    file: String,
    bytes: usize,
    processor: &'static str,
    format: &'static str,
    header: &'a c3d::Header,
    frames: usize,
    first_frame: usize,
    point_rate: f32,
    duration_s: f64,
    points: usize,
    point_units: String,
    point_scale: f32,
    /// The lab's up ("+z"), from the plates' corners or else the markers; null when neither
    /// tells.
    up: Option<c3dfix::Direction>,
    /// What `up` was read from: "plates" or "markers".
    up_source: Option<c3dfix::UpSource>,
    analog_channels: usize,
    analog_rate: f32,
    analog_samples_per_frame: usize,
    analog_labels: Vec<String>,
    markers: Vec<MarkerInfo>,
    /// Valid samples at exactly (0, 0, 0): some writers store missing points that way with a
    /// valid fourth word, which only `--zero-invalid` can tell.
    origin_samples: usize,
    groups: Vec<GroupInfo>,
    header_events: Vec<c3d::HeaderEvent>,
    events: Vec<c3d::Event>,
    force_platforms: Vec<PlateInfo>,
    /// Plates left out or parameters not used ("plate K: FORCE_PLATFORM:PARAM message").
    force_platform_warnings: Vec<String>,
    warnings: Vec<String>,
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

/// Everything `info` reports about `c`, read from `file`.
pub fn describe<'a>(c: &'a c3d::C3d, file: &Path) -> Report<'a> {
    let labels = c.point_labels();
    let all: Vec<usize> = (0..c.point_count()).collect();
    // One pass over the samples, one chunk in memory at a time.
    let v = c3dfix::trial::validity(c, &all, false);
    let outputs = c3dfix::markers::model_outputs(c);
    let markers = v
        .valid
        .iter()
        .zip(&labels)
        .map(|(valid, label)| {
            let gaps = repair::find_gaps(valid, 0);
            MarkerInfo {
                label: label.clone(),
                model_output: outputs.contains(label),
                valid_frames: valid.iter().filter(|&&ok| ok).count(),
                gaps: gaps.len(),
                longest_gap: gaps.iter().map(|g| g.len).max().unwrap_or(0),
            }
        })
        .collect();
    let groups = c
        .parameters
        .groups()
        .map(|g| GroupInfo {
            id: g.id,
            name: g.name.clone(),
            locked: g.locked,
            description: g.description.clone(),
            parameters: c
                .parameters
                .parameters_of(g.id)
                .map(|p| p.name.clone())
                .collect(),
        })
        .collect();
    let origin_samples = v.at_origin;
    let frames = c.frames();
    let rate = c.point_rate();
    let (force_platforms, force_platform_warnings) = plates(c);
    let up = c3dfix::axes::up(c);
    Report {
        file: file.display().to_string(),
        bytes: c.source_bytes().map_or(0, |b| b.len()),
        processor: c.processor().name(),
        format: c.format().name(),
        header: &c.header,
        frames,
        first_frame: c.first_frame(),
        point_rate: rate,
        duration_s: if rate > 0.0 {
            frames as f64 / rate as f64
        } else {
            0.0
        },
        points: c.point_count(),
        point_units: c.point_units(),
        point_scale: c
            .parameters
            .get_f32("POINT", "SCALE")
            .unwrap_or(c.header.scale),
        up: up.map(|u| u.up),
        up_source: up.map(|u| u.source),
        analog_channels: c.analog_channels(),
        analog_rate: if c.analog_channels() > 0 {
            c.analog_rate()
        } else {
            0.0
        },
        analog_samples_per_frame: c.layout().analog_samples_per_frame,
        analog_labels: c.analog_labels(),
        markers,
        origin_samples,
        groups,
        header_events: {
            let mut h = c.header_events();
            h.sort_by(|a, b| a.time.total_cmp(&b.time));
            h
        },
        events: in_time_order(c.events()),
        force_platforms,
        force_platform_warnings,
        warnings: c.warnings().iter().map(|w| w.to_string()).collect(),
    }
}

/// Events as a lab reads them: in time order (files list them in the order they were
/// marked, often all of one side first). The sort is stable, so simultaneous events keep
/// the file's order.
fn in_time_order(mut events: Vec<c3d::Event>) -> Vec<c3d::Event> {
    events.sort_by(|a, b| a.time.total_cmp(&b.time));
    events
}

/// The plates of `c` and their warnings. FORCE_PLATFORM is read first, so a file without
/// plates never has its analog data decoded: `info` stays as fast as it was.
fn plates(c: &c3d::C3d) -> (Vec<PlateInfo>, Vec<String>) {
    let params = c.platform_params();
    if params.plates.is_empty() {
        let warnings = params
            .problems
            .into_iter()
            .map(|p| {
                c3dfix::PlateWarning {
                    plate: p.plate,
                    parameter: p.parameter,
                    message: p.message,
                }
                .to_string()
            })
            .collect();
        return (Vec::new(), warnings);
    }
    match crate::plates::compute(c) {
        Ok(fp) => (
            fp.platforms
                .iter()
                .map(|p| PlateInfo {
                    index: p.index,
                    kind: p.kind,
                    channels: p.channels.clone(),
                    centre: p.centre,
                    peak_force: p.peak_force,
                    contacts: p.contacts.len(),
                })
                .collect(),
            fp.warnings.iter().map(|w| w.to_string()).collect(),
        ),
        Err(e) => (Vec::new(), vec![e.to_string()]),
    }
}

/// From this many valid samples at the exact origin on, `info` names `--zero-invalid`: a real
/// marker lands on (0, 0, 0) to the last bit rarely, a writer's stand-in for "missing" often.
pub(crate) const ORIGIN_NOTE: usize = 10;

fn print_text(r: &Report) -> Result<()> {
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
    // Counted as `gaps` counts them: markers only, model outputs apart.
    let markers: Vec<_> = r.markers.iter().filter(|m| !m.model_output).collect();
    let with_gaps = markers.iter().filter(|m| m.gaps > 0).count();
    let outputs = r.markers.len() - markers.len();
    if r.origin_samples >= ORIGIN_NOTE {
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
    if !r.header_events.is_empty() || !r.events.is_empty() {
        outln!("  events")?;
        for e in &r.header_events {
            outln!("    header  {:<8} {:>9.3} s", e.label, e.time)?;
        }
        for e in &r.events {
            outln!("    {:<7} {:<16} {:>9.3} s", e.context, e.label, e.time)?;
        }
    }
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
