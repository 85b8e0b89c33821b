//! The gait-cycle parameters of an opened trial ([`gait::params`]): from the file's own
//! Foot Strike and Foot Off events or from detected ones ([`crate::events`]), lengths from
//! the toe markers on the file's time base (EVENT:TIMES share [`c3d::C3d::frame_time`]'s
//! origin, see `docs/events.md`).

use crate::error::{Error, Result};
use crate::events::{detect_events, EventOptions};
use gait::params::{GaitParameters, Parameter, TimedEvent, Toes};
use serde::Serialize;
use std::path::Path;

/// Where the events come from.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GaitOptions {
    /// Detect the events (with these options) instead of reading the file's.
    pub detect: Option<EventOptions>,
    /// Marker names given by a person, for the toes (and, with `detect`, ignored: its own
    /// names are used).
    pub markers: gait::MarkerNames,
    /// A treadmill's belt speed (m/s, constant), given by a person: on a treadmill trial the
    /// toes are carried into the belt's frame (moved forward by the belt's travel since the
    /// first frame), so the lengths and the walking speed are those of the walk over the
    /// belt. Without it a treadmill trial's Walking Speed, Stride Length and Step Length are
    /// left out: no corpus treadmill trial stores its belt speed (c3d-labs' rtosim,
    /// RBDS001runT35 and 20140515T133244_run have no such parameter), so none is read from
    /// the file. Ignored on a trial that is no treadmill.
    pub belt_speed_m_s: Option<f64>,
}

/// A trial's gait-cycle parameters and what they were computed from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GaitReport {
    /// Left's then Right's, each in Nexus' order ([`gait::params::NAMES`]).
    pub parameters: Vec<Parameter>,
    /// Per side, the cycle used and every value (lengths in metres).
    #[serde(skip)]
    pub detail: GaitParameters,
    /// "file" or "detected".
    pub events: &'static str,
    /// The toe markers lengths were measured on (left, right), when found.
    pub toes: Option<[String; 2]>,
    /// What could not be reported, in words.
    pub warnings: Vec<String>,
}

fn trial_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Trial {
        path: path.to_path_buf(),
        what: e.to_string(),
    }
}

/// What a treadmill trial's markers cannot give without the belt's speed.
const TREADMILL_LENGTHS: [&str; 3] = ["Walking Speed", "Stride Length", "Step Length"];

/// Said when the speed and lengths are left out of a treadmill trial's parameters.
pub const TREADMILL_WARNING: &str = "treadmill (the pelvis stays while the feet cycle): Walking Speed, Stride Length and Step Length need the belt's speed, which the file does not give, so they are left out";

/// The trial's time span (first and last frame's times).
fn span(c: &c3d::C3d) -> (f64, f64) {
    let n = c.frames();
    (c.frame_time(0), c.frame_time(n.saturating_sub(1)))
}

/// An error naming the first event outside the trial (half a frame of tolerance: a plate
/// event may fall after the last frame's time).
fn check_inside(c: &c3d::C3d, events: &[TimedEvent], path: &Path) -> Result<()> {
    let (a, b) = span(c);
    let rate = c.point_rate() as f64;
    let slack = if rate > 0.0 { 0.5 / rate } else { 0.0 };
    if let Some(e) = events
        .iter()
        .find(|e| e.time < a - slack || e.time > b + slack)
    {
        return Err(trial_error(
            path,
            format!(
                "the {} {} event at {:.4} s lies outside the trial ({a:.4}–{b:.4} s, frames {}–{}); \
                 its events belong to another trial or were cut",
                e.side.context(),
                e.kind.label(),
                e.time,
                c.frame_number(0),
                c.frame_number(c.frames().saturating_sub(1)),
            ),
        ));
    }
    Ok(())
}

/// The toe trajectories (mm) and the lab's vertical, or why lengths cannot be measured.
struct ToeData {
    left: Vec<[f64; 3]>,
    right: Vec<[f64; 3]>,
    vertical: gait::axes::Vertical,
    names: [String; 2],
}

fn toes(
    c: &c3d::C3d,
    names: &gait::MarkerNames,
    path: &Path,
) -> std::result::Result<ToeData, String> {
    // The file is named once, by the report: only what is wrong here.
    let what = |e: Error| match e {
        Error::Trial { what, .. } => what,
        Error::Markers { source, .. } => source.to_string(),
        e => e.to_string(),
    };
    let mut choice = crate::events::choose_markers(c, names, path).map_err(what)?;
    let feet = crate::events::feet(c, &mut choice, path).map_err(what)?;
    let vertical = gait::axes::vertical(&feet.pelvis, &[&feet.left_toe, &feet.right_toe])
        .ok_or("no frame has both the pelvis and a toe marker, so the vertical is unknown")?;
    let labels = c.point_labels();
    let name = |r: &[usize]| {
        r.iter()
            .map(|&i| labels.get(i).cloned().unwrap_or_default())
            .collect::<Vec<_>>()
            .join("+")
    };
    Ok(ToeData {
        names: [name(&choice.left_toe), name(&choice.right_toe)],
        left: feet.left_toe,
        right: feet.right_toe,
        vertical,
    })
}

/// The gait-cycle parameters of `c` (`path` names it in messages), as Nexus' "Generate
/// Gait Cycle Parameters" defines them (see [`gait::params`]).
///
/// Errors: no Foot Strike / Foot Off events (from the file, or none detected), an event
/// outside the trial, no side with a complete cycle. Lengths the toe markers cannot give
/// (none found, missing at an event) are left out and said in the warnings, with every
/// other value kept.
pub fn gait_parameters(c: &c3d::C3d, opts: &GaitOptions, path: &Path) -> Result<GaitReport> {
    let (events, source, mut warnings) = match &opts.detect {
        Some(o) => {
            let d = detect_events(c, o, path)?;
            let ev = d
                .events
                .iter()
                .map(|e| TimedEvent {
                    side: e.side,
                    kind: e.kind,
                    time: e.time,
                })
                .collect();
            (ev, "detected", d.warnings)
        }
        None => (crate::event_labels::file_gait_events(c), "file", Vec::new()),
    };
    if events.is_empty() {
        return Err(match source {
            "file" => Error::NoFileEvents {
                path: path.to_path_buf(),
            },
            _ => trial_error(path, "no Foot Strike or Foot Off events were detected"),
        });
    }
    check_inside(c, &events, path)?;
    let names = opts.detect.as_ref().map_or(&opts.markers, |d| &d.markers);
    let toe_data = match toes(c, names, path) {
        Ok(t) => Some(t),
        Err(e) => {
            warnings.push(format!("no lengths (and no walking speed): {e}"));
            None
        }
    };
    let rate = c.point_rate() as f64;
    let treadmill = toe_data
        .as_ref()
        .and_then(|_| crate::events::treadmill_direction(c, path));
    let belt = match (treadmill, opts.belt_speed_m_s) {
        (Some(dir), Some(v)) => {
            if !(v.is_finite() && v > 0.0) {
                return Err(trial_error(
                    path,
                    format!("belt speed {v} m/s: expected a positive number of metres per second"),
                ));
            }
            Some((dir, v))
        }
        _ => None,
    };
    let belt_frame = |t: &[[f64; 3]], (dir, v): ([f64; 3], f64)| -> Vec<[f64; 3]> {
        t.iter()
            .enumerate()
            .map(|(i, p)| {
                let travel = v * 1000.0 * i as f64 / rate;
                [0, 1, 2].map(|k| p[k] + travel * dir[k])
            })
            .collect()
    };
    let on_belt = toe_data
        .as_ref()
        .zip(belt)
        .map(|(t, b)| (belt_frame(&t.left, b), belt_frame(&t.right, b)));
    let toes_in = toe_data.as_ref().map(|t| {
        let (left, right) = match &on_belt {
            Some((l, r)) => (l.as_slice(), r.as_slice()),
            None => (t.left.as_slice(), t.right.as_slice()),
        };
        Toes {
            left,
            right,
            start: c.frame_time(0),
            rate,
            vertical: t.vertical,
        }
    });
    let detail =
        gait::gait_parameters(&events, toes_in.as_ref()).map_err(|e| trial_error(path, e))?;
    warnings.extend(detail.warnings.iter().cloned());
    let mut parameters = detail.parameters();
    if treadmill.is_some() && belt.is_none() {
        // The feet travel with the belt, not over the floor: the lengths and the speed the
        // markers give are the pelvis' drift, not the walk's.
        parameters.retain(|p| !TREADMILL_LENGTHS.contains(&p.name));
        warnings.push(TREADMILL_WARNING.to_string());
    }
    Ok(GaitReport {
        parameters,
        detail,
        events: source,
        toes: toe_data.map(|t| t.names),
        warnings,
    })
}
