//! The library's one error type: each variant says what went wrong and names the file.

use std::path::PathBuf;

/// Everything opening, repairing, evaluating or saving a trial can fail with. Messages name
/// the file (and, for malformed files, the section and byte offset, from [`c3d::Error`]), so
/// they can be shown to a person as they are.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read as C3D, or a trial could not be encoded for writing.
    #[error("{}: {source}", path.display())]
    C3d {
        path: PathBuf,
        #[source]
        source: c3d::Error,
    },
    /// A destination cannot be written (the message names it and says why: its folder is
    /// missing, it is a device, it exists and replacing it was not asked for, …).
    #[error("{0}")]
    Output(String),
    /// Options that make no sense (an unknown method, a malformed filter spec, a marker the
    /// file does not have, a value out of range).
    #[error("{0}")]
    Options(String),
    /// The trial cannot be processed as asked (no points, too few markers).
    #[error("{}: {what}", path.display())]
    Trial { path: PathBuf, what: String },
    /// A parameter names a unit the output cannot convert (an export to metres from a
    /// POINT:UNITS no table knows).
    #[error("{}: {parameter} {source}", path.display())]
    Unit {
        path: PathBuf,
        /// The parameter that holds the unit, e.g. "POINT:UNITS".
        parameter: String,
        #[source]
        source: c3d::UnknownUnit,
    },
    /// The repair library refused the data or configuration.
    #[error("{}: {source}", path.display())]
    Repair {
        path: PathBuf,
        #[source]
        source: repair::RepairError,
    },
}

impl Error {
    pub(crate) fn options(what: impl Into<String>) -> Self {
        Error::Options(what.into())
    }
}

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;
