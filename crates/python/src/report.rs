//! `report`: the session report `c3dfix report --json` prints and the page it writes, from
//! the same library functions (`c3dfix::report`, `show::report`).

use pyo3::prelude::*;
use std::path::PathBuf;

use crate::{err, lib_err};

/// report(paths, out=None, repaired=None, views=False, force=False) -> dict
///
/// One row per trial of the files and folders in paths (folders walked for *.c3d), with
/// their repaired copies in the folder repaired (matched by path below the given folder,
/// else by file name), and the session's summary: the dict `c3dfix report --json` prints
/// (keys summary and trials). out: also write the self-contained page there (atomically; an
/// existing file only with force=True); views: with out, write each trial's view page into
/// NAME_views/ beside it and link it from its row. A trial that cannot be read is a row with
/// its error.
#[pyfunction]
#[pyo3(signature = (paths, out=None, repaired=None, views=false, force=false))]
pub fn report(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    out: Option<PathBuf>,
    repaired: Option<PathBuf>,
    views: bool,
    force: bool,
) -> PyResult<PyObject> {
    if views && out.is_none() {
        return Err(err("views are written beside the page: give out"));
    }
    let opts = c3dfix::report::ReportOptions {
        paths,
        repaired,
        views,
    };
    let text = py.allow_threads(|| -> PyResult<String> {
        let mut rep = c3dfix::report::report(&opts).map_err(lib_err)?;
        if let Some(out) = &out {
            show::report::write(&mut rep, out, force).map_err(crate::shared::show_err)?;
        }
        serde_json::to_string(&rep).map_err(err)
    })?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}
