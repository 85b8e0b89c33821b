//! `label`: `c3dfix label TRIAL --template LABELLED` from Python (issue 47 item 2), path in
//! and path out through the library function the command calls
//! ([`c3dfix::label_stage::label_file`]), so the same arguments write the same bytes.

use crate::{err, lib_err, to_python};
use c3dfix::files::Destination;
use c3dfix::label_stage::LabelSettings;
use pyo3::prelude::*;
use std::path::PathBuf;

/// label(input, template, output=None, *, in_place=False, backup=False, force=False,
///       unlabelled=None, zero_invalid=False) -> dict
///
/// Label the unlabelled trajectories of the trial at `input` from the labelled trial at
/// `template` (same marker set, ideally the same subject) and write an ordinary labelled
/// C3D to `output` (or in place), atomically; returns the report `c3dfix label --json`
/// prints (status, every fragment with its outcome and why it stays unlabelled, renamed
/// points, samples moved). Raises C3dError naming the file.
#[pyfunction]
#[pyo3(signature = (input, template, output=None, *, in_place=false, backup=false, force=false, unlabelled=None, zero_invalid=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn label(
    py: Python<'_>,
    input: PathBuf,
    template: PathBuf,
    output: Option<PathBuf>,
    in_place: bool,
    backup: bool,
    force: bool,
    unlabelled: Option<&str>,
    zero_invalid: bool,
) -> PyResult<PyObject> {
    let dest = Destination {
        output,
        in_place,
        backup,
        force,
    };
    let rule = match unlabelled {
        Some(p) => repair::Unlabelled::with_pattern(
            p.parse().map_err(|e| err(format!("unlabelled: {e}")))?,
        ),
        None => repair::Unlabelled::common(),
    };
    let settings = LabelSettings {
        unlabelled: rule,
        zero_invalid,
        ..LabelSettings::default()
    };
    let r = py
        .allow_threads(|| c3dfix::label_stage::label_file(&input, &template, &dest, &settings))
        .map_err(lib_err)?;
    to_python(py, &serde_json::to_value(&r).map_err(err)?)
}
