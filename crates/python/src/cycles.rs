//! `detect_events` and `cycles`: the library's gait events and time-normalised cycles, as
//! `c3dfix events --json` and `c3dfix cycles` give them, with the cycles as one numpy array.

use numpy::ndarray::Array;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::{err, lib_err, PyC3d};
use c3dfix::events::{EventOptions, EventSource};
use c3dfix::{session_from, CalibrationTruth, SessionReport};
use gait::session::SessionOptions;
use gait::{cycles::SAMPLES, Kind, MarkerNames, Side, Source};

/// Each warning as a Python `UserWarning` naming the file.
fn warn_all(py: Python<'_>, name: &str, warnings: &[String]) -> PyResult<()> {
    for w in warnings {
        crate::warnings::warn(py, name, w)?;
    }
    Ok(())
}

fn event_options(source: &str, markers: Option<Vec<String>>) -> PyResult<EventOptions> {
    let from: EventSource = source.parse().map_err(|_| {
        err(format!(
            "source={source:?}: expected plates, kinematics or auto"
        ))
    })?;
    Ok(EventOptions {
        from,
        markers: MarkerNames::parse(&markers.unwrap_or_default()).map_err(err)?,
        ..EventOptions::default()
    })
}

/// detect_events(c3d, source="auto", markers=None) -> list[dict]
///
/// Foot strikes and foot offs as `c3dfix events --json` finds them: dicts with context
/// ("Left"/"Right"), label ("Foot Strike"/"Foot Off"), time (s on the EVENT group's time
/// base), frame (the nearest, as the file numbers frames), source ("plate"/"kinematics") and
/// plate (for plate events). source is "plates", "kinematics" (the file's own events are
/// never read) or "auto" (plate events where a foot lands on a plate, kinematic elsewhere);
/// markers names markers the search does not find, as ["lheel=LHEEL", "pelvis=LPSI+RPSI"].
/// What could not be used is raised as a UserWarning; no walking or no foot markers raise
/// C3dError.
///
/// calibrate_from (files or folders of the same session, as `c3dfix events
/// --calibrate-from`): the kinematic events are shifted by the median lead or lag the
/// markers showed at those trials' plate contacts or own events (calibrate_truth "plates",
/// "events" or "auto": plates where a trial has contacts, else its events); the trial
/// itself never counts, and reference trials that give nothing are named in a UserWarning.
/// Each event then carries shift_ms: the offset added to it (None where none was: plate
/// events, and in "auto" a kind the trial's own plates calibrate).
#[pyfunction]
#[pyo3(signature = (c3d, source="auto", markers=None, calibrate_from=None, calibrate_truth="auto"))]
pub fn detect_events(
    py: Python<'_>,
    c3d: &PyC3d,
    source: &str,
    markers: Option<Vec<String>>,
    calibrate_from: Option<Vec<std::path::PathBuf>>,
    calibrate_truth: &str,
) -> PyResult<PyObject> {
    let mut opts = event_options(source, markers)?;
    let name = c3d.name();
    if let Some(refs) = &calibrate_from {
        if opts.from == EventSource::Plates {
            return Err(err(
                "calibrate_from shifts kinematic events: use source=\"kinematics\" or \"auto\"",
            ));
        }
        let truth: CalibrationTruth = calibrate_truth.parse().map_err(err)?;
        let lags = py
            .allow_threads(|| session_from(refs, &opts, truth))
            .map_err(err)?;
        let skipped: Vec<String> = lags
            .skipped
            .iter()
            .map(|why| format!("calibration: skipped {why}"))
            .collect();
        warn_all(py, &name.display().to_string(), &skipped)?;
        opts.session = Some(lags.for_trial(&name, &SessionOptions::default()));
    }
    let d = py
        .allow_threads(|| c3dfix::detect_events(&c3d.inner, &opts, &name))
        .map_err(err)?;
    warn_all(py, &name.display().to_string(), &d.warnings)?;
    let out = PyList::empty(py);
    for e in &d.events {
        let dict = PyDict::new(py);
        dict.set_item("context", e.side.context())?;
        dict.set_item("label", e.kind.label())?;
        dict.set_item("time", e.time)?;
        dict.set_item("frame", e.frame)?;
        dict.set_item("source", e.source.name())?;
        dict.set_item("plate", e.plate)?;
        if let Some(r) = &d.session_calibration {
            dict.set_item("shift_ms", shift_ms(r, e))?;
        }
        out.append(dict)?;
    }
    Ok(out.into_any().unbind())
}

/// The session offset added to one detected event, as the report says it was used.
fn shift_ms(r: &SessionReport, e: &c3dfix::events::TrialEvent) -> Option<f64> {
    if e.source != Source::Kinematics {
        return None;
    }
    let kind = match e.kind {
        Kind::FootStrike => &r.strike,
        Kind::FootOff => &r.off,
    };
    if !kind.used {
        return None;
    }
    match e.side {
        Side::Left => kind.left_ms,
        Side::Right => kind.right_ms,
    }
}

/// cycles(c3d, side="both", markers=None, analog=None, forces=False, detect=False,
///        source="auto") -> dict
///
/// Gait cycles (each foot strike to the next of the same foot) with the chosen signals
/// time-normalised to 0-100 % in 101 samples, as `c3dfix cycles` writes them: linear
/// interpolation at 101 evenly spaced times from the strike to the next, both included
/// (Kinetics Toolkit's cycles.time_normalize, which keeps the first 100); NaN where the
/// signal is missing, never invented.
///
/// markers: labels (x, y, z in mm; model outputs such as angles in their own units);
/// analog: channel labels (physical units, at their own rate); forces: each plate's force
/// (lab frame, N). With none of them, every marker. Cycles come from the file's EVENT group,
/// or with detect=True from detected events (source as in detect_events).
///
/// Returns a dict: data, float64 (cycles, 101, columns); columns and units (lists); percent
/// (0..100); and per cycle side ("Left"/"Right"), number (from 1 per side), start_time,
/// end_time (s on the file's time base) and start_frame, end_frame (the file's numbering);
/// events ("file" or "detected"). Cycles reaching outside the trial are left out with a
/// UserWarning; no complete cycle raises C3dError.
#[pyfunction]
#[pyo3(signature = (c3d, side="both", markers=None, analog=None, forces=false, detect=false, source="auto"))]
#[allow(clippy::too_many_arguments)]
pub fn cycles(
    py: Python<'_>,
    c3d: &PyC3d,
    side: &str,
    markers: Option<Vec<String>>,
    analog: Option<Vec<String>>,
    forces: bool,
    detect: bool,
    source: &str,
) -> PyResult<PyObject> {
    let sides = side.parse::<c3dfix::Feet>().map_err(lib_err)?.sides();
    let opts = c3dfix::CycleOptions {
        sides,
        markers: markers.unwrap_or_default(),
        analog: analog.unwrap_or_default(),
        forces,
        detect: detect.then(|| event_options(source, None)).transpose()?,
        ..c3dfix::CycleOptions::default()
    };
    let name = c3d.name();
    let cy = py
        .allow_threads(|| c3dfix::cycles(&c3d.inner, &opts, &name))
        .map_err(err)?;
    warn_all(py, &name.display().to_string(), &cy.warnings)?;
    let width = cy.columns.len();
    let flat: Vec<f64> = cy.data.iter().flatten().copied().collect();
    let data = Array::from_shape_vec((cy.cycles.len(), SAMPLES, width), flat).map_err(err)?;
    let out = PyDict::new(py);
    out.set_item("data", data.into_pyarray(py))?;
    out.set_item(
        "columns",
        cy.columns
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "units",
        cy.columns
            .iter()
            .map(|c| c.unit.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "percent",
        (0..SAMPLES)
            .map(|k| k as f64)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    out.set_item(
        "side",
        cy.cycles
            .iter()
            .map(|c| c.side.context())
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "number",
        cy.cycles.iter().map(|c| c.number).collect::<Vec<_>>(),
    )?;
    let times = |f: fn(&c3dfix::CycleInfo) -> f64| {
        cy.cycles
            .iter()
            .map(f)
            .collect::<Vec<f64>>()
            .into_pyarray(py)
    };
    out.set_item("start_time", times(|c| c.start_time))?;
    out.set_item("end_time", times(|c| c.end_time))?;
    out.set_item(
        "start_frame",
        cy.cycles.iter().map(|c| c.start_frame).collect::<Vec<_>>(),
    )?;
    out.set_item(
        "end_frame",
        cy.cycles.iter().map(|c| c.end_frame).collect::<Vec<_>>(),
    )?;
    out.set_item("events", cy.events)?;
    Ok(out.into_any().unbind())
}
