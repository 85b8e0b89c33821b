//! `C3d.force_platforms()`: each plate as a dict of numpy arrays with its units, as ezc3d
//! users expect, from the library's `force_platforms`.

use numpy::ndarray::Array;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::err;

/// `(n, 3)` float64 from a list of vectors.
fn array3<'py>(py: Python<'py>, v: &[[f64; 3]]) -> PyResult<PyObject> {
    let flat: Vec<f64> = v.iter().flatten().copied().collect();
    Ok(Array::from_shape_vec((v.len(), 3), flat)
        .map_err(err)?
        .into_pyarray(py)
        .into_any()
        .unbind())
}

/// The plates of `c`; plate warnings become Python `UserWarning`s naming the file (an
/// ORIGIN warning once per file: [`crate::warnings`]).
pub fn force_platforms(
    py: Python<'_>,
    c: &c3d::C3d,
    name: &str,
    opts: &c3dfix::ForceOptions,
) -> PyResult<PyObject> {
    let fp = py
        .allow_threads(|| c3dfix::force_platforms(c, opts))
        .map_err(err)?;
    for w in &fp.warnings {
        crate::warnings::warn(py, name, &w.to_string())?;
    }
    let out = PyList::empty(py);
    for p in &fp.platforms {
        let d = PyDict::new(py);
        d.set_item("index", p.index)?;
        d.set_item("type", p.kind)?;
        d.set_item("rate", p.rate)?;
        d.set_item("channels", p.channels.clone())?;
        d.set_item("corners", array3(py, &p.corners)?)?;
        d.set_item("centre", p.centre.to_vec().into_pyarray(py))?;
        d.set_item("origin", p.origin.to_vec().into_pyarray(py))?;
        d.set_item("origin_corrected", p.origin_corrected)?;
        d.set_item("force", array3(py, &p.force)?)?;
        d.set_item("moment", array3(py, &p.moment)?)?;
        d.set_item("cop", array3(py, &p.cop)?)?;
        d.set_item("free_moment", array3(py, &p.free_moment)?)?;
        d.set_item("peak_force", p.peak_force)?;
        d.set_item("push", p.push.clone().into_pyarray(py))?;
        match &p.baseline {
            Some(b) => {
                let bd = PyDict::new(py);
                bd.set_item("source", b.source.name())?;
                bd.set_item("first_sample", b.first_sample)?;
                bd.set_item("last_sample", b.last_sample)?;
                bd.set_item("first_frame", b.first_frame)?;
                bd.set_item("last_frame", b.last_frame)?;
                bd.set_item("level", b.level)?;
                d.set_item("baseline", bd)?;
            }
            None => d.set_item("baseline", py.None())?,
        }
        d.set_item("filtered", p.filtered.clone())?;
        let contacts = PyList::empty(py);
        for k in &p.contacts {
            let kd = PyDict::new(py);
            kd.set_item("first_sample", k.first_sample)?;
            kd.set_item("last_sample", k.last_sample)?;
            kd.set_item("first_frame", k.first_frame)?;
            kd.set_item("last_frame", k.last_frame)?;
            kd.set_item("first_time", k.first_time)?;
            kd.set_item("last_time", k.last_time)?;
            kd.set_item("peak", k.peak)?;
            contacts.append(kd)?;
        }
        d.set_item("contacts", contacts)?;
        let units = PyDict::new(py);
        units.set_item("force", &p.units.force)?;
        units.set_item("moment", &p.units.moment)?;
        units.set_item("position", &p.units.position)?;
        d.set_item("units", units)?;
        out.append(d)?;
    }
    Ok(out.into_any().unbind())
}
