//! Markers alone with a session calibration: the lead or lag of a trial's kinematic events
//! learned from OTHER trials of the same session or lab, where their feet land cleanly on a
//! plate or where the lab has marked its own events ([`gait::session`]).
//!
//! The kinematic methods' error is mostly a constant per lab (marker placement; docs/events.md,
//! "Where the held-out errors come from"), which no constant chosen on other labs removes.
//! A session usually has trials with plate contacts beside trials without: those tell the
//! lab's offset for these.

use crate::error::{Error, Result, Setting};
use crate::events::{self, EventOptions};
pub use crate::session_calibration::{KindReport, SessionCalibration, SessionReport};
use gait::session::{Lag, SessionOptions};
use gait::{Event, Source};
use std::path::{Path, PathBuf};

/// Which known events of a reference trial teach the offset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CalibrationTruth {
    /// Plate contacts where one foot alone loads a plate ([`events::plate_events`]).
    Plates,
    /// The file's own Foot Strike / Foot Off events (EVENT group, Left/Right).
    Events,
    /// A trial's plate contacts where it has any, else its own events: the plates are a
    /// physical measurement; a lab's events may have been set by hand.
    #[default]
    PlatesElseEvents,
}

impl std::str::FromStr for CalibrationTruth {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "plates" | "plate" => Ok(CalibrationTruth::Plates),
            "events" | "lab" => Ok(CalibrationTruth::Events),
            "auto" | "plates-else-events" => Ok(CalibrationTruth::PlatesElseEvents),
            _ => Err(Error::OutOfRange {
                setting: Setting::EventSource,
                value: s.to_string(),
                limits: "expected plates, events or auto".into(),
            }),
        }
    }
}

/// One reference trial's lags (truth − kinematic, seconds).
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceTrial {
    pub path: PathBuf,
    /// "plates" or "events": what its lags were measured against.
    pub truth: &'static str,
    pub lags: Vec<Lag>,
}

/// The lags of a session's reference trials, and the files that gave none (with why).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SessionLags {
    pub trials: Vec<ReferenceTrial>,
    pub skipped: Vec<String>,
}

/// The file's own Foot Strike / Foot Off events of the left and right feet, as fractional
/// frame indices (from `frame_time(0)` at POINT:RATE).
pub fn lab_events(c: &c3d::C3d) -> Vec<Event> {
    let rate = c.point_rate() as f64;
    if !(rate.is_finite() && rate > 0.0) {
        return Vec::new();
    }
    let t0 = c.frame_time(0);
    crate::event_labels::file_gait_events(c)
        .into_iter()
        .filter_map(|e| {
            let index = (e.time - t0) * rate;
            index.is_finite().then_some(Event {
                side: e.side,
                kind: e.kind,
                index,
                source: Source::Plate,
                plate: None,
            })
        })
        .collect()
}

/// One reference trial's lags: its kinematic events (as `opts` detects them, uncalibrated)
/// against its plate contacts or its own events, as `truth` says.
pub fn reference_lags(
    c: &c3d::C3d,
    path: &Path,
    opts: &EventOptions,
    truth: CalibrationTruth,
    window_s: f64,
) -> Result<ReferenceTrial> {
    let mut choice = events::choose_markers(c, &opts.markers, path)?;
    let feet = events::feet(c, &mut choice, path)?;
    let rate = c.point_rate() as f64;
    let kin = gait::kinematic_events(&feet, rate, &opts.kinematic).map_err(|e| Error::Trial {
        path: path.to_path_buf(),
        what: e.to_string(),
    })?;
    let plates = || -> Result<Vec<Event>> {
        if c.platform_params().plates.is_empty() {
            Ok(Vec::new())
        } else {
            events::plate_events(c, &feet, &opts.plate)
        }
    };
    let (name, known) = match truth {
        CalibrationTruth::Plates => ("plates", plates()?),
        CalibrationTruth::Events => ("events", lab_events(c)),
        CalibrationTruth::PlatesElseEvents => {
            let p = plates()?;
            if p.is_empty() {
                ("events", lab_events(c))
            } else {
                ("plates", p)
            }
        }
    };
    Ok(ReferenceTrial {
        path: path.to_path_buf(),
        truth: name,
        lags: gait::session::trial_lags(&known, &kin, rate, window_s),
    })
}

/// The lags of each of `paths` (a file that cannot be read, or whose markers give no
/// events, is listed in [`SessionLags::skipped`] with the reason; it is no error, since a
/// session's folder also holds static and calibration trials).
pub fn session_lags(
    paths: &[PathBuf],
    opts: &EventOptions,
    truth: CalibrationTruth,
    window_s: f64,
) -> SessionLags {
    let mut out = SessionLags::default();
    for p in paths {
        let r = crate::open(p).and_then(|c| reference_lags(&c, p, opts, truth, window_s));
        match r {
            Ok(t) if t.lags.is_empty() => out.skipped.push(format!(
                "{}: no {} within {} ms of a kinematic event of its foot and kind",
                p.display(),
                if t.truth == "plates" {
                    "plate contact"
                } else {
                    "Foot Strike or Foot Off event of its own"
                },
                window_s * 1000.0
            )),
            Ok(t) => out.trials.push(t),
            Err(e) => out.skipped.push(e.to_string()),
        }
    }
    out
}

/// The lags of the trials named (files, or folders walked as `batch` walks them): what the
/// command line's `--calibrate-from` and Python's `calibrate_from=` read, so both fronts take
/// the same trials. A name that is neither a file nor a folder, or a folder without a C3D
/// file, is an error (a typo must not leave a trial silently uncalibrated); a trial that
/// gives no lag is skipped with why.
pub fn session_from(
    named: &[PathBuf],
    opts: &EventOptions,
    truth: CalibrationTruth,
) -> Result<SessionLags> {
    let mut refs = Vec::new();
    for p in named {
        let found = crate::targets::plan(
            std::slice::from_ref(p),
            crate::targets::Destination::InPlace,
            None,
        )?;
        if found.targets.is_empty() {
            return Err(Error::Trial {
                path: p.clone(),
                what: "no C3D files in this folder".into(),
            });
        }
        refs.extend(found.targets.into_iter().map(|t| t.input));
    }
    Ok(session_lags(&refs, opts, truth, gait::session::WINDOW_S))
}

/// Whether two paths name one file (a trial never calibrates itself).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

impl SessionLags {
    /// The offsets learned from every reference trial but `trial` itself.
    pub fn for_trial(&self, trial: &Path, opts: &SessionOptions) -> SessionCalibration {
        let used: Vec<&ReferenceTrial> = self
            .trials
            .iter()
            .filter(|t| !same_file(&t.path, trial))
            .collect();
        let lags: Vec<Lag> = used.iter().flat_map(|t| t.lags.iter().copied()).collect();
        SessionCalibration {
            offsets: gait::session_offsets(&lags, opts),
            trials: used.len(),
            min_contacts: opts.min_contacts,
        }
    }
}
