//! What the functions that take a trial and write a file share (`info`, `view`, `plot`):
//! a trial given as read or as a path, the refusal to write over an input, the name a
//! picture is titled with, and the picture library's errors in this package's words. Its own
//! module so that those functions import it, not each other.

use pyo3::prelude::*;
use std::borrow::Cow;
use std::path::{Path, PathBuf};

use crate::{err, lib_err, PyC3d};

/// A trial given as a `C3d` already read, or as the path of a C3D file.
#[derive(FromPyObject)]
pub enum TrialArg<'py> {
    Read(PyRef<'py, PyC3d>),
    Path(PathBuf),
}

impl TrialArg<'_> {
    /// The trial and the path it is named by (`<c3d>` for a trial made from bytes alone).
    /// A path is read as `c3dfix info` and `c3dfix view` read it (mapped, for the length
    /// of the call).
    pub fn open(&self, py: Python<'_>) -> PyResult<(Cow<'_, c3d::C3d>, PathBuf)> {
        match self {
            TrialArg::Read(c) => Ok((Cow::Borrowed(&c.inner), c.name())),
            TrialArg::Path(p) => {
                let c = py.allow_threads(|| c3dfix::open_mapped(p)).map_err(err)?;
                Ok((Cow::Owned(c), p.clone()))
            }
        }
    }
}

/// Refuse an output that is one of the trials read (even with force=True: a page or a
/// picture written over a C3D file would lose it), as the command refuses it.
pub fn refuse_inputs(output: &Path, input: &Path, original: Option<&Path>) -> PyResult<()> {
    let inputs: Vec<&Path> = std::iter::once(input).chain(original).collect();
    c3dfix::save::refuse_input(output, &inputs, "output").map_err(lib_err)
}

/// A path's file name, as the command titles its pictures (the whole path when it has none).
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}

/// A picture library error as `C3dError`, the library's kinds in this package's words.
pub fn show_err(e: show::Error) -> PyErr {
    match e {
        show::Error::Library(e) => lib_err(e),
        e => err(e),
    }
}
