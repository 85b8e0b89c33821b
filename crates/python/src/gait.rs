//! `gait_parameters`: the gait-cycle parameters `c3dfix gait` reports, per side, as Vicon
//! Nexus names them.

use pyo3::prelude::*;

use crate::{err, to_python, PyC3d};

/// gait_parameters(c3d, detect=False, belt_speed=None) -> list[dict]
///
/// The gait-cycle parameters of the trial per side, as Vicon Nexus' "Generate Gait Cycle
/// Parameters" defines them and `c3dfix gait --json` lists them: dicts with context
/// ("Left"/"Right"), name (as Nexus names it in the ANALYSIS group: Cadence, Walking
/// Speed, Stride Time, Step Time, Opposite Foot Off, Opposite Foot Contact, Foot Off,
/// Single Support, Double Support, Stride Length, Step Length, then Step Width and Limp
/// Index), value and unit. From the file's own Foot Strike / Foot Off events, or with
/// detect=True from events detected as `c3dfix events` detects them. Lengths (and the
/// walking speed) come from the toe markers and are left out when those are missing; a side
/// without a complete cycle is left out. On a treadmill trial the lengths and the speed
/// need the belt's speed (m/s), belt_speed=, and are left out without it. Raises C3dError
/// when no side has a complete cycle.
#[pyfunction]
#[pyo3(signature = (c3d, detect=false, belt_speed=None))]
pub fn gait_parameters(
    py: Python<'_>,
    c3d: &PyC3d,
    detect: bool,
    belt_speed: Option<f64>,
) -> PyResult<PyObject> {
    let opts = c3dfix::GaitOptions {
        detect: detect.then(c3dfix::EventOptions::default),
        belt_speed_m_s: belt_speed,
        ..c3dfix::GaitOptions::default()
    };
    let name = c3d.name();
    let r = py
        .allow_threads(|| c3dfix::gait_parameters(&c3d.inner, &opts, &name))
        .map_err(err)?;
    to_python(py, &serde_json::to_value(&r.parameters).map_err(err)?)
}
