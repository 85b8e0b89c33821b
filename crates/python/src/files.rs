//! Path in, path out: `repair_file` and `convert_file`, the entry points to send to worker
//! processes (Dask, Ray, multiprocessing) instead of trials. Both call the library function
//! the `c3dfix repair` and `c3dfix convert` commands call ([`c3dfix::files`]), so the same
//! options write the same bytes, with the same checks and refusals; the GIL is released for
//! the whole call.

use crate::options::RepairKeywords;
use crate::{err, lib_err, to_python};
use c3dfix::files::{Conversion, Destination};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// A library error as `C3dError`, naming `input` when the message does not (option errors
/// say what is wrong, not with which call), and saying the keywords where the library's
/// kind names a setting or says how to ask for something.
fn file_err(input: &Path, e: c3dfix::Error) -> PyErr {
    use c3dfix::Error;
    let here = input.display();
    match e {
        Error::Options(m) => err(format!("{here}: {m}")),
        // The conflicts' own words ("backup goes with in-place") name the keywords already.
        Error::Conflict(c) => err(format!("{here}: {c}")),
        other => lib_err(other),
    }
}

/// repair_file(input, output=None, *, in_place=False, backup=False, force=False, report=None,
///             fill="auto", spikes=None, lowpass=None, max_gap=200, max_expected_error=20.0,
///             spike_mode="gap", spike_min_mm=5.0, spike_classic=False, markers=None,
///             zero_invalid=False, swaps="report") -> dict
///
/// `c3dfix repair INPUT -o OUTPUT` (or `--in-place`) from Python: reads the file, repairs it
/// and writes exactly the bytes the command writes with the same options; returns the report
/// (the one `--report` writes, also written to `report` when given). The write is atomic; an
/// existing output is replaced only with force (or in place, where backup keeps the original
/// as FILE.bak), a device or folder never; the report never replaces the input or the output.
/// Repair options as for `repair`. Raises C3dError naming the file.
#[pyfunction]
#[pyo3(signature = (input, output=None, *, in_place=false, backup=false, force=false, report=None, fill="auto", spikes=None, lowpass=None, max_gap=200, max_expected_error=Some(c3dfix::DEFAULT_MAX_EXPECTED_ERROR_MM), spike_mode="gap", spike_min_mm=5.0, spike_classic=false, markers=None, zero_invalid=false, swaps="report", reclaim="report", unlabelled=None))]
// As for `repair`: the text signature says the expression default's value.
#[pyo3(
    text_signature = "(input, output=None, *, in_place=False, backup=False, force=False, report=None, fill='auto', spikes=None, lowpass=None, max_gap=200, max_expected_error=20.0, spike_mode='gap', spike_min_mm=5.0, spike_classic=False, markers=None, zero_invalid=False, swaps='report', reclaim='report', unlabelled=None)"
)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn repair_file(
    py: Python<'_>,
    input: PathBuf,
    output: Option<PathBuf>,
    in_place: bool,
    backup: bool,
    force: bool,
    report: Option<PathBuf>,
    fill: &str,
    spikes: Option<&str>,
    lowpass: Option<&str>,
    max_gap: usize,
    max_expected_error: Option<f64>,
    spike_mode: &str,
    spike_min_mm: f64,
    spike_classic: bool,
    markers: Option<Vec<String>>,
    zero_invalid: bool,
    swaps: &str,
    reclaim: &str,
    unlabelled: Option<&str>,
) -> PyResult<PyObject> {
    let dest = Destination {
        output,
        in_place,
        backup,
        force,
    };
    let opts = RepairKeywords {
        fill,
        spikes,
        lowpass,
        max_gap,
        max_expected_error,
        spike_mode,
        spike_min_mm,
        spike_classic,
        markers,
        zero_invalid,
        swaps,
        reclaim,
        unlabelled,
    }
    .options()
    .map_err(|e| file_err(&input, e))?;
    let done = py
        .allow_threads(|| c3dfix::files::repair(&input, &dest, &opts, report.as_deref()))
        .map_err(|e| file_err(&input, e))?;
    to_python(py, &done.report())
}

/// convert_file(input, output=None, *, in_place=False, backup=False, force=False,
///              processor=None, format=None, scale=None) -> dict
///
/// `c3dfix convert INPUT -o OUTPUT` (or `--in-place`) from Python: rewrites the file in
/// another processor ("intel", "dec", "sgi") or number format ("int", "float"), each
/// defaulting to the file's own; scale is POINT:SCALE for integer output. Writes exactly the
/// bytes the command writes, atomically, with the same refusals as repair_file; in place, a
/// file that is already as asked is not rewritten (unchanged is True). Returns output,
/// processor, format, bytes, unchanged, warnings and, with a backup, backup. Raises C3dError
/// naming the file.
#[pyfunction]
#[pyo3(signature = (input, output=None, *, in_place=false, backup=false, force=false, processor=None, format=None, scale=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn convert_file(
    py: Python<'_>,
    input: PathBuf,
    output: Option<PathBuf>,
    in_place: bool,
    backup: bool,
    force: bool,
    processor: Option<&str>,
    format: Option<&str>,
    scale: Option<f64>,
) -> PyResult<PyObject> {
    let want = Conversion::parse(processor, format, scale).map_err(|e| file_err(&input, e))?;
    let dest = Destination {
        output,
        in_place,
        backup,
        force,
    };
    let done = py
        .allow_threads(|| c3dfix::files::convert(&input, &dest, &want))
        .map_err(|e| file_err(&input, e))?;
    to_python(py, &serde_json::to_value(&done).map_err(err)?)
}
