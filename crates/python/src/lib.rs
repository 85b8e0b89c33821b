//! Python bindings of c3dfix: a thin layer over the `c3dfix` library, with data crossing as
//! numpy arrays. Long work (reading, repairing, evaluating) releases the GIL; every error
//! becomes `c3dfix.C3dError` (a `ValueError`) carrying the library's message, and nothing
//! panics across the boundary.

use numpy::ndarray::Array;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

mod cycles;
mod export;
mod files;
mod gait;
mod info_view;
mod label;
mod options;
mod pickling;
mod platforms;
mod plots;
mod report;
mod shared;
mod warnings;

pyo3::create_exception!(
    c3dfix,
    C3dError,
    PyValueError,
    "A file that cannot be read or written, or options that make no sense. The message names the file and, for malformed files, the section and byte offset."
);

fn err(e: impl std::fmt::Display) -> PyErr {
    C3dError::new_err(e.to_string())
}

/// A library error as `C3dError`, with this package's keywords where the library's kind
/// says how to ask for something (the library names no flag or keyword).
fn lib_err(e: c3dfix::Error) -> PyErr {
    use c3dfix::Error;
    match e {
        Error::Exists { path } => err(format!(
            "{} exists (pass force=True to overwrite)",
            path.display()
        )),
        Error::OwnInput { output, input } => err(format!(
            "the output {} is the input file {}: pass in_place=True (with backup=True to keep the original) to replace it",
            output.display(),
            input.display()
        )),
        Error::NoUp { path } => err(format!(
            "{}: neither force plates nor markers tell which way is up: pass the axes (e.g. axes=\"x,z,-y\")",
            path.display()
        )),
        other => err(other),
    }
}

/// A JSON value as the Python object `json.loads` would make.
fn to_python(py: Python<'_>, v: &serde_json::Value) -> PyResult<PyObject> {
    let text = serde_json::to_string(v).map_err(err)?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// A C3D file in memory: points, analog data, parameters and events, written back losslessly.
#[pyclass(module = "c3dfix", name = "C3d")]
#[derive(Clone)]
struct PyC3d {
    inner: c3d::C3d,
    path: Option<PathBuf>,
}

impl PyC3d {
    fn name(&self) -> PathBuf {
        self.path.clone().unwrap_or_else(|| PathBuf::from("<c3d>"))
    }
}

#[pymethods]
impl PyC3d {
    /// Point coordinates, float64 (frames, points, 3) in POINT:UNITS; NaN where a sample is
    /// missing (the C3D manual's rule: a negative fourth word, -1.0 or 65535.0 in float
    /// files, or non-finite coordinates). Settable with an array of the same shape: a changed
    /// sample is written with residual 0 (computed, the manual's mark), a sample set to NaN
    /// is written as missing, an unchanged one keeps its bytes.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let p = self.inner.points();
        let (f, n) = (p.frames(), p.count());
        let mut v = Vec::with_capacity(f * n * 3);
        for k in 0..f * n {
            if p.is_valid_at(k) {
                v.extend(p.xyz[k].map(f64::from));
            } else {
                v.extend([f64::NAN; 3]);
            }
        }
        let a = Array::from_shape_vec((f, n, 3), v).map_err(err)?;
        Ok(a.into_pyarray(py))
    }

    #[setter]
    fn set_points(&mut self, value: PyReadonlyArray3<'_, f64>) -> PyResult<()> {
        let p = self.inner.points_mut();
        let (f, n) = (p.frames(), p.count());
        if value.shape() != [f, n, 3] {
            return Err(err(format!(
                "points must have shape ({f}, {n}, 3), got {:?}",
                value.shape()
            )));
        }
        let a = value.as_array();
        for fr in 0..f {
            for i in 0..n {
                let k = p.index(fr, i);
                let new = [a[[fr, i, 0]], a[[fr, i, 1]], a[[fr, i, 2]]];
                let was_valid = p.is_valid_at(k);
                // The library's one rule for samples set rather than measured (c3d::Mark).
                if new.iter().any(|c| c.is_nan()) {
                    if was_valid {
                        p.mark(k, c3d::Mark::Missing);
                    }
                    continue;
                }
                let new32 = new.map(|c| c as f32);
                if was_valid
                    && new32
                        .iter()
                        .zip(&p.xyz[k])
                        .all(|(a, b)| a.to_bits() == b.to_bits())
                {
                    continue;
                }
                p.mark(k, c3d::Mark::Computed(new32));
            }
        }
        Ok(())
    }

    /// Residuals, float64 (frames, points) in POINT:UNITS; -1 where a sample is missing, 0
    /// where it was computed (filled, filtered) rather than measured.
    #[getter]
    fn residuals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = self.inner.points();
        let (f, n) = (p.frames(), p.count());
        let v: Vec<f64> = (0..f * n)
            .map(|k| {
                if p.is_valid_at(k) {
                    p.residual[k] as f64
                } else {
                    -1.0
                }
            })
            .collect();
        Ok(Array::from_shape_vec((f, n), v)
            .map_err(err)?
            .into_pyarray(py))
    }

    /// Camera masks, uint8 (frames, points): bit n set when camera n+1 saw the point.
    #[getter]
    fn camera_masks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u8>>> {
        let p = self.inner.points();
        let v = p.camera_mask.clone();
        Ok(Array::from_shape_vec((p.frames(), p.count()), v)
            .map_err(err)?
            .into_pyarray(py))
    }

    /// Point labels (POINT:LABELS, LABELS2, …), one per point.
    #[getter]
    fn labels(&self) -> Vec<String> {
        self.inner.point_labels()
    }

    /// Frames per second of the point data.
    #[getter]
    fn point_rate(&self) -> f64 {
        self.inner.point_rate() as f64
    }

    /// POINT:UNITS ("mm", "m", …).
    #[getter]
    fn point_units(&self) -> String {
        self.inner.point_units()
    }

    /// Number of the first frame, as the file counts them.
    #[getter]
    fn first_frame(&self) -> usize {
        self.inner.first_frame()
    }

    /// Analog samples, float64 (samples, channels), scaled as the manual says:
    /// (raw - ANALOG:OFFSET) * ANALOG:SCALE * ANALOG:GEN_SCALE.
    #[getter]
    fn analog<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let a = self.inner.analog();
        let v: Vec<f64> = self
            .inner
            .analog_physical()
            .into_iter()
            .map(f64::from)
            .collect();
        Ok(Array::from_shape_vec((a.samples(), a.channels()), v)
            .map_err(err)?
            .into_pyarray(py))
    }

    /// Analog channel labels.
    #[getter]
    fn analog_labels(&self) -> Vec<String> {
        self.inner.analog_labels()
    }

    /// Analog samples per second (0 when there are no channels).
    #[getter]
    fn analog_rate(&self) -> f64 {
        if self.inner.analog().channels() > 0 {
            self.inner.analog_rate() as f64
        } else {
            0.0
        }
    }

    /// Every parameter: {group: {name: value}}. Numbers are numpy arrays shaped by the
    /// parameter's dimensions (Fortran order, as C3D stores them; a scalar has shape (1,));
    /// text is a str, or a list of str for a table of strings.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        let ps = &self.inner.parameters;
        for g in ps.groups() {
            let d = PyDict::new(py);
            for p in ps.parameters_of(g.id) {
                d.set_item(&p.name, parameter_value(py, p)?)?;
            }
            out.set_item(&g.name, d)?;
        }
        Ok(out)
    }

    /// Events of the EVENT group: dicts with label, context, time (s, on the group's base:
    /// frame 1 of the capture at 0 s), frame (the nearest, round(time x rate) + 1, as the
    /// file numbers frames) and description.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        let rate = self.inner.point_rate() as f64;
        for e in self.inner.events() {
            let d = PyDict::new(py);
            d.set_item("label", e.label)?;
            d.set_item("context", e.context)?;
            d.set_item("time", e.time)?;
            let frame = (rate > 0.0 && e.time.is_finite())
                .then(|| (e.time * rate).round().max(0.0) as usize + 1);
            d.set_item("frame", frame)?;
            d.set_item("description", e.description)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// Warnings the reader gave: rules of the format the file breaks but that were read
    /// around.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner
            .warnings()
            .iter()
            .map(|w| w.to_string())
            .collect()
    }

    /// Write the file to `path` atomically (a temporary file in the same folder, synced,
    /// renamed into place), replacing an existing file. Byte-identical to the file read
    /// when nothing changed; otherwise only changed samples and parameters get new bytes.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let opts = c3dfix::SaveOptions {
            force: true,
            backup: false,
        };
        py.allow_threads(|| c3dfix::save(&self.inner, &path, &opts))
            .map(|_| ())
            .map_err(err)
    }

    /// force_platforms(threshold=10.0, zero_baseline=True, lowpass=None) -> list[dict]
    ///
    /// Every force plate of the trial (FORCE_PLATFORM, plate types 1-4), at the analog rate,
    /// in the lab frame: `force` (N), `moment` about the centre of the working surface
    /// (N x POINT:UNITS), `cop` (POINT:UNITS) and `free_moment` (the torque about the COP,
    /// along the plate's normal), each (samples, 3) float64; `push` (samples,), how hard a
    /// foot presses the plate down (-Fz of the plate's frame, N; a pull is negative);
    /// `cop` and `free_moment` are NaN where the push < threshold N. Also `index`
    /// (1-based), `type`, `rate`, `channels` (1-based), `corners` (4, 3), `centre`, `origin`
    /// (as used), `origin_corrected`, `peak_force` (largest push), `contacts` (foot-strike to
    /// foot-off: samples, the file's frame numbers and times on its events' time base),
    /// `baseline` (the unloaded level subtracted: source, samples, frames, level in N; None
    /// when none), `filtered` and `units` {force, moment, position}. zero_baseline (on by
    /// default) subtracts each channel's mean over FORCE_PLATFORM:ZERO's frames, or over the
    /// plate's quietest low stretch; False keeps the raw values. lowpass is a zero-phase
    /// "butterworth:ORDER:CUTOFF_HZ" or "cheby2:ORDER:CUTOFF_HZ:ATTEN_DB" filter of the
    /// channels. A plate that cannot be computed is left out with a UserWarning naming the
    /// plate and the parameter.
    #[pyo3(signature = (threshold=c3dfix::platforms::DEFAULT_THRESHOLD_N, zero_baseline=true, lowpass=None))]
    fn force_platforms(
        &self,
        py: Python<'_>,
        threshold: f64,
        zero_baseline: bool,
        lowpass: Option<&str>,
    ) -> PyResult<PyObject> {
        let opts = options::force_options(threshold, zero_baseline, lowpass)?;
        platforms::force_platforms(py, &self.inner, &self.name().display().to_string(), &opts)
    }

    /// C3d(data, path=None): a trial read from the bytes of a C3D file (`path` names it in
    /// messages). Pickling and copying go through it (see pickling.rs).
    #[new]
    #[pyo3(signature = (data, path=None))]
    fn new(py: Python<'_>, data: &[u8], path: Option<PathBuf>) -> PyResult<Self> {
        pickling::from_bytes(py, data, path)
    }

    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, pyo3::types::PyTuple>)> {
        pickling::reduce(py, self)
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    /// Equal when both would write the same bytes.
    fn __eq__(&self, py: Python<'_>, other: PyRef<'_, Self>) -> PyResult<bool> {
        pickling::equal(py, self, &other)
    }

    fn __repr__(&self) -> String {
        let p = self.inner.points();
        format!(
            "<c3dfix.C3d {}: {} frames x {} points at {} Hz, {} analog channels>",
            self.name().display(),
            p.frames(),
            p.count(),
            self.inner.point_rate(),
            self.inner.analog().channels()
        )
    }
}

/// One parameter's value for Python.
fn parameter_value(py: Python<'_>, p: &c3d::Parameter) -> PyResult<PyObject> {
    // C3D dimensions run fastest first (Fortran order); numpy gets the same shape with
    // order='F'.
    let shape: Vec<usize> = if p.dims.is_empty() {
        vec![1]
    } else {
        p.dims.iter().map(|&d| d as usize).collect()
    };
    let numbers = |v: Vec<f64>| -> PyResult<PyObject> {
        let flat = PyArray1::from_vec(py, v);
        let kw = PyDict::new(py);
        kw.set_item("order", "F")?;
        Ok(flat
            .call_method("reshape", (shape.clone(),), Some(&kw))?
            .unbind())
    };
    Ok(match &p.value {
        c3d::Value::Char(_) => {
            let s = p.as_strings();
            if p.dims.len() <= 1 {
                s.into_iter()
                    .next()
                    .unwrap_or_default()
                    .into_pyobject(py)?
                    .into_any()
                    .unbind()
            } else {
                s.into_pyobject(py)?.into_any().unbind()
            }
        }
        c3d::Value::Float(v) => numbers(v.iter().map(|&x| x as f64).collect())?,
        c3d::Value::Int(v) => numbers(v.iter().map(|&x| x as f64).collect())?,
        c3d::Value::Byte(v) => numbers(v.iter().map(|&x| x as f64).collect())?,
    })
}

/// read(path) -> C3d
///
/// Read a C3D file (any processor format, integer or float). Raises C3dError naming the
/// file, the section and the byte offset when the file cannot be read.
#[pyfunction]
fn read(py: Python<'_>, path: PathBuf) -> PyResult<PyC3d> {
    let inner = py.allow_threads(|| c3dfix::open(&path)).map_err(err)?;
    Ok(PyC3d {
        inner,
        path: Some(path),
    })
}

/// gaps(path, zero_invalid=False) -> list[dict]
///
/// Every gap of every marker of a C3D file, as `c3dfix gaps --json` lists them: label,
/// first_frame and last_frame (numbered as the file numbers its frames), length, at_start,
/// at_end. The file is scanned once without being decoded into memory, so this is the way to
/// survey a large archive. zero_invalid also counts samples at exactly (0, 0, 0) as missing.
#[pyfunction]
#[pyo3(signature = (path, zero_invalid=false))]
fn gaps(py: Python<'_>, path: PathBuf, zero_invalid: bool) -> PyResult<PyObject> {
    // The file is mapped only for the length of this call (see c3dfix::open_mapped).
    let found = py
        .allow_threads(|| c3dfix::open_mapped(&path).map(|c| c3dfix::gaps(&c, zero_invalid)))
        .map_err(err)?;
    to_python(py, &serde_json::to_value(&found).map_err(err)?)
}

/// repair(c3d, fill="auto", spikes=None, lowpass=None, max_gap=200,
///        max_expected_error=20.0, spike_mode="gap", spike_min_mm=5.0, spike_classic=False,
///        markers=None, zero_invalid=False, swaps="report") -> (C3d, dict)
///
/// The `c3dfix repair` pipeline (swaps -> spikes -> fill -> filter) on a copy of `c3d`; returns the
/// repaired copy and the report `c3dfix repair --report` writes. Options as on the command
/// line: fill is a method name (as `c3dfix repair --help` lists them: auto, linear, …,
/// gloersen, none), spikes "hampel[:K[:NSIGMA]]", lowpass "butterworth:ORDER:CUTOFF_HZ" or
/// "cheby2:ORDER:CUTOFF_HZ:ATTEN_DB", markers a list of labels to repair; gaps whose expected
/// fill error is above max_expected_error mm are left (reason "uncertain"), None fills all;
/// swaps is "fix" (settled label swaps exchanged back, jumps refilled), "report" (listed in
/// the report's "swaps", nothing changed) or "off"; reclaim is "on" (unlabelled samples that
/// are a marker's moved into it as recorded), "report" (listed in the report's "reclaim",
/// nothing changed) or "off"; unlabelled a label glob that also marks points unlabelled
/// (beside `*51`, `Unlabeled 3`, empty labels): such points are not repaired.
#[pyfunction]
#[pyo3(signature = (c3d, fill="auto", spikes=None, lowpass=None, max_gap=200, max_expected_error=Some(c3dfix::DEFAULT_MAX_EXPECTED_ERROR_MM), spike_mode="gap", spike_min_mm=5.0, spike_classic=false, markers=None, zero_invalid=false, swaps="report", reclaim="report", unlabelled=None))]
// The default of max_expected_error is an expression, which pyo3 would show as `...`; the
// text signature says its value (test_repair_defaults_agree_everywhere checks it).
#[pyo3(
    text_signature = "(c3d, fill='auto', spikes=None, lowpass=None, max_gap=200, max_expected_error=20.0, spike_mode='gap', spike_min_mm=5.0, spike_classic=False, markers=None, zero_invalid=False, swaps='report', reclaim='report', unlabelled=None)"
)]
#[allow(clippy::too_many_arguments)]
fn repair(
    py: Python<'_>,
    c3d: &PyC3d,
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
) -> PyResult<(PyC3d, PyObject)> {
    let opts = options::RepairKeywords {
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
    .map_err(err)?;
    let mut out = c3d.clone();
    let name = c3d.name();
    let done = py
        .allow_threads(|| c3dfix::repair(&mut out.inner, &opts, &name))
        .map_err(err)?;
    let report = to_python(py, &done.report())?;
    Ok((out, report))
}

/// swaps(c3d) -> dict
///
/// Marker label swaps and label jumps, as `c3dfix swaps --json` lists them: "swaps" is a list
/// of finds, each with kind ("swap" or "jump"), markers (two labels or one), first_frame and
/// last_frame (numbered as the file numbers its frames), confidence, settled (what
/// repair(..., swaps="fix") would undo) and evidence; also frames, markers and warnings.
/// Too little to judge (fewer than 2 markers or 3 frames, every sample missing) raises
/// C3dError.
#[pyfunction]
fn swaps(py: Python<'_>, c3d: &PyC3d) -> PyResult<PyObject> {
    let name = c3d.name();
    let opts = ::repair::swaps::SwapOptions::default();
    let found = py
        .allow_threads(|| c3dfix::swaps(&c3d.inner, &name, &opts))
        .map_err(err)?;
    to_python(py, &serde_json::to_value(&found).map_err(err)?)
}

/// reclaim(c3d, unlabelled=None, zero_invalid=False) -> dict
///
/// The unlabelled samples that are a labelled marker's, as `c3dfix reclaim --json` lists
/// them: "settled" (what repair(..., reclaim="on") moves: marker, source, first_frame,
/// last_frame, samples, fit) and "unsettled" (with why), markers, unlabelled and pieces.
/// Changes nothing.
#[pyfunction]
#[pyo3(signature = (c3d, unlabelled=None, zero_invalid=false))]
fn reclaim(
    py: Python<'_>,
    c3d: &PyC3d,
    unlabelled: Option<&str>,
    zero_invalid: bool,
) -> PyResult<PyObject> {
    let name = c3d.name();
    let rule = match unlabelled {
        Some(p) => ::repair::Unlabelled::with_pattern(p.parse().map_err(err)?),
        None => ::repair::Unlabelled::common(),
    };
    let found = py
        .allow_threads(|| c3dfix::reclaim(&c3d.inner, &name, &rule, zero_invalid))
        .map_err(err)?;
    to_python(py, &serde_json::to_value(&found).map_err(err)?)
}

/// evaluate(files, gap_lengths=(5, 10, 20, 40, 80), markers=None, methods=None,
///          gaps_per_length=40, group=1, seed=1) -> dict
///
/// Fill accuracy as `c3dfix evaluate --json` measures it: known samples knocked out,
/// refilled by each method; errors per file (in its units) and pooled (in mm).
#[pyfunction]
#[pyo3(signature = (files, gap_lengths=vec![5, 10, 20, 40, 80], markers=None, methods=None, gaps_per_length=40, group=1, seed=1))]
#[allow(clippy::too_many_arguments)]
fn evaluate(
    py: Python<'_>,
    files: Vec<PathBuf>,
    gap_lengths: Vec<usize>,
    markers: Option<Vec<String>>,
    methods: Option<Vec<String>>,
    gaps_per_length: usize,
    group: usize,
    seed: u64,
) -> PyResult<PyObject> {
    // A misspelt method is the library's error, as on the command line.
    let methods = methods
        .map(|names| {
            names
                .iter()
                .map(|n| n.parse().map_err(c3dfix::Error::from))
                .collect::<c3dfix::Result<Vec<c3dfix::FillMethod>>>()
        })
        .transpose()
        .map_err(err)?;
    let opts = c3dfix::EvaluateOptions {
        gap_lengths,
        markers,
        methods,
        gaps_per_length,
        group,
        seed,
    };
    let ev = py
        .allow_threads(|| c3dfix::evaluate(&files, &opts, |_| {}))
        .map_err(err)?;
    to_python(py, &serde_json::to_value(&ev).map_err(err)?)
}

#[pymodule]
fn _c3dfix(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyC3d>()?;
    m.add("C3dError", m.py().get_type::<C3dError>())?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(gaps, m)?)?;
    m.add_function(wrap_pyfunction!(self::repair, m)?)?;
    m.add_function(wrap_pyfunction!(swaps, m)?)?;
    m.add_function(wrap_pyfunction!(reclaim, m)?)?;
    m.add_function(wrap_pyfunction!(label::label, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(files::repair_file, m)?)?;
    m.add_function(wrap_pyfunction!(options::_repair_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(files::convert_file, m)?)?;
    m.add_function(wrap_pyfunction!(export::export_trc, m)?)?;
    m.add_function(wrap_pyfunction!(export::export_mot, m)?)?;
    m.add_function(wrap_pyfunction!(export::export_opensim, m)?)?;
    m.add_function(wrap_pyfunction!(export::lab_up, m)?)?;
    m.add_function(wrap_pyfunction!(gait::gait_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(cycles::detect_events, m)?)?;
    m.add_function(wrap_pyfunction!(cycles::cycles, m)?)?;
    m.add_function(wrap_pyfunction!(info_view::info, m)?)?;
    m.add_function(wrap_pyfunction!(info_view::view, m)?)?;
    m.add_function(wrap_pyfunction!(plots::plot, m)?)?;
    m.add_function(wrap_pyfunction!(plots::plot_forces, m)?)?;
    m.add_function(wrap_pyfunction!(report::report, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
