//! The repair keywords of `repair` and `repair_file`, read into the library's typed
//! [`c3dfix::RepairOptions`] by the library's own `FromStr`, so Python accepts and refuses
//! the names the command line does. The keywords' defaults in the pyo3 signatures and the
//! stub are checked against [`c3dfix::RepairOptions::default`] by a test
//! (`test_repair_defaults_agree_everywhere`), which reads them from [`repair_defaults`].
//! The force plate keywords (threshold, zero_baseline, lowpass) are read once here too, by
//! [`force_options`], for every function that takes them.

use crate::{err, to_python};
use c3dfix::RepairOptions;
use pyo3::prelude::*;

/// The force plate keywords as given to a Python function, as the library's options; a
/// misspelt lowpass spec is the library's error, raised as C3dError.
pub(crate) fn force_options(
    threshold: f64,
    zero_baseline: bool,
    lowpass: Option<&str>,
) -> PyResult<c3dfix::ForceOptions> {
    Ok(c3dfix::ForceOptions {
        threshold,
        zero_baseline,
        lowpass: lowpass.map(str::parse).transpose().map_err(err)?,
    })
}

/// The repair keywords as given to a Python function.
pub(crate) struct RepairKeywords<'a> {
    pub fill: &'a str,
    pub spikes: Option<&'a str>,
    pub lowpass: Option<&'a str>,
    pub max_gap: usize,
    pub max_expected_error: Option<f64>,
    pub spike_mode: &'a str,
    pub spike_min_mm: f64,
    pub spike_classic: bool,
    pub markers: Option<Vec<String>>,
    pub zero_invalid: bool,
    pub swaps: &'a str,
    pub reclaim: &'a str,
    pub unlabelled: Option<&'a str>,
}

impl RepairKeywords<'_> {
    /// The library's options; a misspelt name or spec is the library's error.
    pub fn options(self) -> c3dfix::Result<RepairOptions> {
        Ok(RepairOptions {
            fill: self.fill.parse()?,
            max_gap: self.max_gap,
            max_expected_error_mm: self.max_expected_error,
            spikes: self.spikes.map(str::parse).transpose()?,
            spike_mode: self.spike_mode.parse()?,
            spike_min_mm: self.spike_min_mm,
            spike_classic: self.spike_classic,
            lowpass: self.lowpass.map(str::parse).transpose()?,
            markers: self.markers,
            zero_invalid: self.zero_invalid,
            swaps: self.swaps.parse()?,
            reclaim: self.reclaim.parse()?,
            unlabelled: self.unlabelled.map(str::parse).transpose()?,
        })
    }
}

/// _repair_defaults() -> dict
///
/// The library's default repair options, keyed by the Python keywords, with names and specs
/// as strings: what the defaults of repair and repair_file must be.
#[pyfunction]
pub(crate) fn _repair_defaults(py: Python<'_>) -> PyResult<PyObject> {
    let d = RepairOptions::default();
    let v = serde_json::json!({
        "fill": d.fill.to_string(),
        "spikes": d.spikes.map(|s| s.to_string()),
        "lowpass": d.lowpass.map(|f| f.to_string()),
        "max_gap": d.max_gap,
        "max_expected_error": d.max_expected_error_mm,
        "spike_mode": d.spike_mode.to_string(),
        "spike_min_mm": d.spike_min_mm,
        "spike_classic": d.spike_classic,
        "markers": d.markers,
        "zero_invalid": d.zero_invalid,
        "swaps": d.swaps.to_string(),
        "reclaim": d.reclaim.to_string(),
        "unlabelled": d.unlabelled.map(|g| g.to_string()),
    });
    to_python(py, &v).map_err(|e| err(format!("repair defaults: {e}")))
}
