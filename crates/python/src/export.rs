//! `export_trc`, `export_mot`, `export_opensim` and `lab_up`: the library's writers and the
//! lab's up, as `c3dfix export` and `c3dfix info` use them.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

use crate::{err, lib_err, PyC3d};
use c3dfix::export::{self, ExportDestination, ExportFormat, ExportOptions, Points};
use c3dfix::Axes;

/// The points a marker table holds, from the keyword arguments (`None`: the format's
/// default, [`export::ExportFormat::default_points`]).
fn selection(markers: Option<Vec<String>>, all_points: bool) -> PyResult<Option<Points>> {
    match (markers, all_points) {
        (Some(_), true) => Err(err("give markers or all_points, not both")),
        (Some(m), false) => Ok(Some(Points::Named(m))),
        (None, true) => Ok(Some(Points::All)),
        (None, false) => Ok(None),
    }
}

/// One file of `format` written by the library's export job.
fn export_file(py: Python<'_>, c3d: &PyC3d, path: PathBuf, opts: ExportOptions) -> PyResult<()> {
    let name = c3d.name();
    py.allow_threads(|| {
        export::export(
            &c3d.inner,
            &name,
            &ExportDestination::File(path),
            &opts,
            &mut |_| {},
        )
        .map(|_| ())
    })
    .map_err(lib_err)
}

fn axes(spec: Option<&str>) -> PyResult<Option<Axes>> {
    spec.map(Axes::parse).transpose().map_err(err)
}

/// export_trc(c3d, path, markers=None, all_points=False, axes=None, force=False) -> None
///
/// Write the trial's markers as TRC (what `c3dfix export --format trc` writes), atomically:
/// Frame# the file's frame numbers, Time on its time base, NaN for missing samples, model
/// outputs left out unless all_points or named in markers; axes a rotation such as "x,z,-y".
#[pyfunction]
#[pyo3(signature = (c3d, path, markers=None, all_points=false, axes=None, force=false))]
pub fn export_trc(
    py: Python<'_>,
    c3d: &PyC3d,
    path: PathBuf,
    markers: Option<Vec<String>>,
    all_points: bool,
    axes: Option<&str>,
    force: bool,
) -> PyResult<()> {
    let opts = ExportOptions {
        format: ExportFormat::Trc,
        points: selection(markers, all_points)?,
        axes: self::axes(axes)?,
        forces: c3dfix::ForceOptions::default(),
        force,
    };
    export_file(py, c3d, path, opts)
}

/// export_mot(c3d, path, axes=None, threshold=10.0, zero_baseline=True, lowpass=None,
///            force=False) -> None
///
/// Write the force plates' ground reaction as OpenSim's MOT (`c3dfix export --format mot`),
/// atomically: per plate force (N), point (m) and free torque (N·m) per analog sample, on
/// the file's time base; the plate options as for C3d.force_platforms.
#[pyfunction]
#[pyo3(signature = (c3d, path, axes=None, threshold=c3dfix::platforms::DEFAULT_THRESHOLD_N, zero_baseline=true, lowpass=None, force=false))]
#[allow(clippy::too_many_arguments)]
pub fn export_mot(
    py: Python<'_>,
    c3d: &PyC3d,
    path: PathBuf,
    axes: Option<&str>,
    threshold: f64,
    zero_baseline: bool,
    lowpass: Option<&str>,
    force: bool,
) -> PyResult<()> {
    let opts = ExportOptions {
        format: ExportFormat::Mot,
        points: None,
        axes: self::axes(axes)?,
        forces: crate::options::force_options(threshold, zero_baseline, lowpass)?,
        force,
    };
    export_file(py, c3d, path, opts)
}

/// export_opensim(c3d, out_dir, markers=None, all_points=False, axes=None, threshold=10.0,
///                zero_baseline=True, lowpass=None, force=False) -> dict
///
/// Write NAME.trc and (with force plates) NAME.mot into out_dir on one time base, turned to
/// OpenSim's frame (`c3dfix export --format opensim`): the lab's up as Y, the direction of
/// travel as X when there is one, or the rotation axes. Returns {trc, mot (None without
/// plates), axes, up, up_source, forward}.
#[pyfunction]
#[pyo3(signature = (c3d, out_dir, markers=None, all_points=false, axes=None, threshold=c3dfix::platforms::DEFAULT_THRESHOLD_N, zero_baseline=true, lowpass=None, force=false))]
#[allow(clippy::too_many_arguments)]
pub fn export_opensim(
    py: Python<'_>,
    c3d: &PyC3d,
    out_dir: PathBuf,
    markers: Option<Vec<String>>,
    all_points: bool,
    axes: Option<&str>,
    threshold: f64,
    zero_baseline: bool,
    lowpass: Option<&str>,
    force: bool,
) -> PyResult<PyObject> {
    let opts = ExportOptions {
        format: ExportFormat::Opensim,
        points: selection(markers, all_points)?,
        axes: self::axes(axes)?,
        forces: crate::options::force_options(threshold, zero_baseline, lowpass)?,
        force,
    };
    let name = c3d.name();
    let dest = ExportDestination::Folder(out_dir);
    let exported = py
        .allow_threads(|| export::export(&c3d.inner, &name, &dest, &opts, &mut |_| {}))
        .map_err(lib_err)?;
    let Some(done) = exported.opensim else {
        return Err(err("the OpenSim export wrote no pair"));
    };
    for w in &done.warnings {
        crate::warnings::warn(py, &name.display().to_string(), &w.to_string())?;
    }
    let d = PyDict::new(py);
    d.set_item("trc", done.trc)?;
    d.set_item("mot", done.mot)?;
    d.set_item("axes", done.axes.to_string())?;
    d.set_item("up", done.up.map(|u| u.up.to_string()))?;
    d.set_item(
        "up_source",
        done.up.map(|u| match u.source {
            c3dfix::UpSource::Plates => "plates",
            c3dfix::UpSource::Markers => "markers",
        }),
    )?;
    d.set_item("forward", done.forward.map(|f| f.to_string()))?;
    Ok(d.into_any().unbind())
}

/// lab_up(c3d) -> tuple[str, str] | None
///
/// The lab's up as `c3dfix info` reports it: ("+z", "plates") from the force plates'
/// corners, else from the markers (model outputs left out); None when neither tells.
#[pyfunction]
pub fn lab_up(c3d: &PyC3d) -> Option<(String, &'static str)> {
    c3dfix::axes::up(&c3d.inner).map(|u| {
        (
            u.up.to_string(),
            match u.source {
                c3dfix::UpSource::Plates => "plates",
                c3dfix::UpSource::Markers => "markers",
            },
        )
    })
}
