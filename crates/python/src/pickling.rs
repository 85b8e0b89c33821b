//! A trial that pickles and copies, so that multiprocessing, joblib, Dask and Ray can move it
//! between processes. A trial travels as the bytes it would write ([`c3d::C3d::encoded`]: the
//! file read, with every edit patched in) and the path it was read from, and is rebuilt by
//! reading those bytes; so the copy writes exactly what the original would.

use crate::{err, PyC3d};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};
use std::path::PathBuf;

/// A trial read from the bytes of a C3D file; `path` names it in messages and `repr`.
pub(crate) fn from_bytes(py: Python<'_>, data: &[u8], path: Option<PathBuf>) -> PyResult<PyC3d> {
    let inner = py.allow_threads(|| c3d::read(data.to_vec())).map_err(|e| {
        let name = path.clone().unwrap_or_else(|| PathBuf::from("<c3d>"));
        err(format!("{}: {e}", name.display()))
    })?;
    Ok(PyC3d { inner, path })
}

/// The bytes `c` would write.
pub(crate) fn encoded(py: Python<'_>, c: &PyC3d) -> PyResult<Vec<u8>> {
    py.allow_threads(|| c.inner.encoded().map(|b| b.into_owned()))
        .map_err(|e| err(format!("{}: {e}", c.name().display())))
}

/// `__reduce__`: the class and the arguments that rebuild the trial, `C3d(bytes, path)`.
pub(crate) fn reduce<'py>(
    py: Python<'py>,
    c: &PyC3d,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
    let bytes = PyBytes::new(py, &encoded(py, c)?);
    let path = c.path.as_ref().map(|p| p.display().to_string());
    let args = PyTuple::new(py, [bytes.into_any(), path.into_pyobject(py)?.into_any()])?;
    Ok((py.get_type::<PyC3d>().into_any(), args))
}

/// `__eq__`: two trials are equal when they would write the same bytes (where they were read
/// from does not count).
pub(crate) fn equal(py: Python<'_>, a: &PyC3d, b: &PyC3d) -> PyResult<bool> {
    Ok(encoded(py, a)? == encoded(py, b)?)
}
