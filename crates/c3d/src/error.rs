//! Typed errors, split by cause: I/O, a malformed file (with section and byte offset), a limit
//! exceeded, a value the target format cannot hold, and a caller's misuse.

use std::fmt;

/// The part of a C3D file an error or warning refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Section {
    Header,
    Parameters,
    Data,
    Events,
}

impl fmt::Display for Section {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Section::Header => "header",
            Section::Parameters => "parameter section",
            Section::Data => "data section",
            Section::Events => "events",
        })
    }
}

/// Everything that can go wrong reading or writing a C3D file.
///
/// More kinds may come in later versions, so matches need a `_` arm.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or writing failed (the cause is in the message, not chained, so that it is
    /// printed once).
    #[error("I/O error: {0}")]
    Io(std::io::Error),
    /// The bytes do not follow the format; `offset` is from the start of the file.
    #[error("malformed {section} at byte {offset}: {what}")]
    Malformed {
        section: Section,
        offset: u64,
        what: String,
    },
    /// A value cannot be stored in the target format (e.g. a coordinate outside int16 range).
    #[error("cannot write: {0}")]
    Unrepresentable(String),
    /// The caller asked for something inconsistent with the file (wrong shapes, unknown names).
    #[error("invalid use: {0}")]
    Misuse(String),
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::Io(e)
    }
}

impl Error {
    pub(crate) fn malformed(section: Section, offset: usize, what: impl Into<String>) -> Self {
        Error::Malformed {
            section,
            offset: offset as u64,
            what: what.into(),
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// Something in a file that breaks the rules but could be read around.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Warning {
    pub section: Section,
    /// Byte offset from the start of the file, where one applies.
    pub offset: Option<u64>,
    pub message: String,
}

impl Warning {
    pub(crate) fn new(section: Section, offset: Option<usize>, message: impl Into<String>) -> Self {
        Warning {
            section,
            offset: offset.map(|o| o as u64),
            message: message.into(),
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.offset {
            Some(o) => write!(f, "{} at byte {}: {}", self.section, o, self.message),
            None => write!(f, "{}: {}", self.section, self.message),
        }
    }
}
