//! The package's `UserWarning`s, each naming its file. A plate's ORIGIN warning (the
//! FORCE_PLATFORM:ORIGIN the maths read otherwise than stored) is about the file, not the
//! call: every function that reads the plates (`force_platforms`, `export_opensim`,
//! `detect_events`, `cycles`) finds it again, so it is said once per file and process, the
//! first time; every other warning is said on each call, as it concerns that call's result.

use pyo3::prelude::*;
use std::collections::HashSet;
use std::sync::Mutex;

use crate::err;

/// The ORIGIN warnings said so far ("FILE: message").
static SAID: Mutex<Option<HashSet<String>>> = Mutex::new(None);

/// Whether `text` is a plate's ORIGIN warning.
fn about_the_file(text: &str) -> bool {
    text.contains("FORCE_PLATFORM:ORIGIN")
}

/// `text` about file `name` as a `UserWarning`, unless it is an ORIGIN warning already said.
pub fn warn(py: Python<'_>, name: &str, text: &str) -> PyResult<()> {
    let full = format!("{name}: {text}");
    if about_the_file(text) {
        let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
        if !said.get_or_insert_with(HashSet::new).insert(full.clone()) {
            return Ok(());
        }
    }
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    let msg = std::ffi::CString::new(full).map_err(err)?;
    PyErr::warn(py, &category, &msg, 1)
}
