//! What a trial holds and what is wrong with it, as one report: `c3dfix info` prints it as
//! text or JSON, and the Python package returns it, so both say the same of a file.

use serde::Serialize;
use std::path::Path;

/// One point as `info` lists it: its valid frames and its gaps.
#[derive(Serialize)]
pub struct MarkerInfo {
    pub label: String,
    /// A model output (an angle, force, moment or power stored as a point), not a marker:
    /// `gaps` and `repair` leave these apart, and so does the count `info` prints.
    pub model_output: bool,
    pub valid_frames: usize,
    pub gaps: usize,
    pub longest_gap: usize,
}

/// A force plate as `info` lists it; `c3dfix forces` gives every sample.
#[derive(Serialize)]
pub struct PlateInfo {
    pub index: usize,
    #[serde(rename = "type")]
    pub kind: i32,
    pub channels: Vec<usize>,
    /// The centre of the corners, POINT:UNITS.
    pub centre: [f64; 3],
    /// Largest push over the trial (N), its unloaded level removed.
    pub peak_force: f64,
    /// Stretches where a foot pushes with at least the threshold.
    pub contacts: usize,
}

/// A parameter group as `info` lists it: its parameters by name.
#[derive(Serialize)]
pub struct GroupInfo {
    pub id: u8,
    pub name: String,
    pub locked: bool,
    pub description: String,
    pub parameters: Vec<String>,
}

/// From this many valid samples at the exact origin on, a trial's zeros look like a writer's
/// stand-in for "missing" rather than data: a real marker lands on (0, 0, 0) to the last bit
/// rarely, some writers store every lost point there. `info` and `repair` then say how to
/// read such samples as missing.
pub const ORIGIN_SUSPECT_SAMPLES: usize = 10;

/// Whether `samples` valid samples at the exact origin look like a writer's missing points
/// ([`ORIGIN_SUSPECT_SAMPLES`]).
pub fn zeros_look_missing(samples: usize) -> bool {
    samples >= ORIGIN_SUSPECT_SAMPLES
}

/// What `info` says about a C3D file (`c3dfix info --json` prints it as it is).
#[derive(Serialize)]
pub struct Report<'a> {
    pub file: String,
    pub bytes: usize,
    pub processor: &'static str,
    pub format: &'static str,
    pub header: &'a c3d::Header,
    pub frames: usize,
    pub first_frame: usize,
    pub point_rate: f32,
    pub duration_s: f64,
    pub points: usize,
    pub point_units: String,
    pub point_scale: f32,
    /// The lab's up ("+z"), from the plates' corners or else the markers; null when neither
    /// tells.
    pub up: Option<crate::Direction>,
    /// What `up` was read from: "plates" or "markers".
    pub up_source: Option<crate::UpSource>,
    /// "treadmill" where the pelvis stays while the feet cycle under it
    /// ([`crate::events::is_treadmill`]); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub travel: Option<&'static str>,
    pub analog_channels: usize,
    pub analog_rate: f32,
    pub analog_samples_per_frame: usize,
    pub analog_labels: Vec<String>,
    pub markers: Vec<MarkerInfo>,
    /// Valid samples at exactly (0, 0, 0): some writers store missing points that way with a
    /// valid fourth word, which only reading with `zero_invalid` ([`crate::RepairOptions::zero_invalid`]) can tell.
    pub origin_samples: usize,
    pub groups: Vec<GroupInfo>,
    pub header_events: Vec<c3d::HeaderEvent>,
    pub events: Vec<c3d::Event>,
    pub force_platforms: Vec<PlateInfo>,
    /// Plates left out or parameters not used ("plate K: FORCE_PLATFORM:PARAM message").
    pub force_platform_warnings: Vec<String>,
    /// The reader's warnings, then each plate whose FORCE_PLATFORM:ORIGIN the maths read
    /// otherwise than stored: a fault of the file, said once here (every command that reads
    /// the plates meets it again), not among the plates' warnings.
    pub warnings: Vec<String>,
}

/// Everything `info` reports about `c`, read from `file`.
pub fn describe<'a>(c: &'a c3d::C3d, file: &Path) -> Report<'a> {
    let labels = c.point_labels();
    let all: Vec<usize> = (0..c.point_count()).collect();
    // One pass over the samples, one chunk in memory at a time.
    let v = crate::trial::validity(c, &all, false);
    let outputs = crate::markers::model_outputs(c);
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
    let (force_platforms, mut force_platform_warnings) = plates(c);
    let mut warnings: Vec<String> = c.warnings().iter().map(|w| w.to_string()).collect();
    let (origin, others): (Vec<String>, Vec<String>) = force_platform_warnings
        .drain(..)
        .partition(|w| w.contains(": FORCE_PLATFORM:ORIGIN "));
    force_platform_warnings = others;
    warnings.extend(origin);
    let up = crate::axes::up(c);
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
        travel: crate::events::is_treadmill(c, file).then_some("treadmill"),
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
        warnings,
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
                crate::PlateWarning {
                    plate: p.plate,
                    parameter: p.parameter,
                    message: p.message,
                }
                .to_string()
            })
            .collect();
        return (Vec::new(), warnings);
    }
    match crate::force_platforms(c, &crate::ForceOptions::default()) {
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
