//! `plot` and `plot_forces`: the pictures `c3dfix plot` draws, from the same library
//! functions (`show::plot`), so a trial gives the same SVG or PNG bytes from Python as from
//! the command.

use pyo3::prelude::*;
use std::path::PathBuf;

use crate::lib_err;
use crate::shared::{file_name, refuse_inputs, show_err, TrialArg};

/// plot(c3d, path, markers, against=None, analog=None, detect_events=False, force=False)
///
/// Draw the markers' x, y and z against time (what `c3dfix plot --marker` draws, byte for
/// byte) as SVG or PNG by path's extension, atomically: one column per marker (at most 6;
/// a "Subject:" prefix and case are ignored), the analog channel (label or 1-based number)
/// in physical units below, the file's events (and the detector's with detect_events). c3d
/// and against (the original it was repaired from: its gaps shaded, the fills, spikes and
/// filtered samples marked) are C3d objects or paths of C3D files.
#[pyfunction]
#[pyo3(signature = (c3d, path, markers, against=None, analog=None, detect_events=false, force=false))]
#[allow(clippy::too_many_arguments)]
pub fn plot(
    py: Python<'_>,
    c3d: TrialArg<'_>,
    path: PathBuf,
    markers: Vec<String>,
    against: Option<TrialArg<'_>>,
    analog: Option<String>,
    detect_events: bool,
    force: bool,
) -> PyResult<()> {
    let format = show::plot::Format::from_path(&path).map_err(show_err)?;
    let (c, cpath) = c3d.open(py)?;
    let original = against.as_ref().map(|a| a.open(py)).transpose()?;
    refuse_inputs(&path, &cpath, original.as_ref().map(|(_, p)| p.as_path()))?;
    let (c, name): (&c3d::C3d, String) = (&c, file_name(&cpath));
    let original = original.as_ref().map(|(o, p)| (&**o, file_name(p)));
    py.allow_threads(|| {
        let bytes = show::plot::markers_picture(
            (c, &cpath, &name),
            original.as_ref().map(|(o, n)| (*o, n.as_str())),
            &markers,
            analog.as_deref(),
            detect_events,
            format,
        )
        .map_err(show_err)?;
        c3dfix::save::write_atomic(&path, &bytes, force).map_err(lib_err)
    })
}

/// plot_forces(c3d, path, threshold=10.0, zero_baseline=True, lowpass=None,
///             detect_events=False, force=False) -> list[str]
///
/// Draw the force plates (what `c3dfix plot --forces` draws, byte for byte) as SVG or PNG by
/// path's extension, atomically: each plate's vertical ground reaction against time with the
/// file's events, and the centres of pressure over the plates' outlines seen from above.
/// The plate options as for C3d.force_platforms. Returns the plates' warnings (what the
/// command prints on standard error).
#[pyfunction]
#[pyo3(signature = (c3d, path, threshold=c3dfix::platforms::DEFAULT_THRESHOLD_N, zero_baseline=true, lowpass=None, detect_events=false, force=false))]
#[allow(clippy::too_many_arguments)]
pub fn plot_forces(
    py: Python<'_>,
    c3d: TrialArg<'_>,
    path: PathBuf,
    threshold: f64,
    zero_baseline: bool,
    lowpass: Option<&str>,
    detect_events: bool,
    force: bool,
) -> PyResult<Vec<String>> {
    let format = show::plot::Format::from_path(&path).map_err(show_err)?;
    let opts = crate::options::force_options(threshold, zero_baseline, lowpass)?;
    let (c, cpath) = c3d.open(py)?;
    refuse_inputs(&path, &cpath, None)?;
    let (c, name): (&c3d::C3d, String) = (&c, file_name(&cpath));
    let mut warnings = Vec::new();
    py.allow_threads(|| {
        let bytes = show::plot::forces_picture(
            (c, &cpath, &name),
            &opts,
            detect_events,
            format,
            &mut |w| warnings.push(w),
        )
        .map_err(show_err)?;
        c3dfix::save::write_atomic(&path, &bytes, force).map_err(lib_err)
    })?;
    Ok(warnings)
}
