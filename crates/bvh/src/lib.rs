//! BVH skeleton files: parsing, writing, forward kinematics, rotations, interpolation and
//! keyframe reduction (see issue 5).
//!
//! The crate never prints; every input-dependent failure is a typed error.

pub mod error_metric;
pub mod fk;
pub mod interp;
pub mod keyframes;
pub mod parse;
pub mod rotation;
pub mod skeleton;
pub mod write;

pub use error_metric::Effectors;
pub use interp::Interp;
pub use keyframes::{KeyframeError, Reduction, Target};
pub use parse::{parse, ParseError, ParseErrorKind};
pub use skeleton::{Bvh, Channel, Joint, Motion, Skeleton};
pub use write::write;

/// Reading a file from disk: I/O or parse failure. The cause is part of the message (not
/// chained), so that it is printed once.
///
/// More kinds may come in later versions, so matches need a `_` arm.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("cannot read {path}: {error}")]
    Io {
        path: std::path::PathBuf,
        error: std::io::Error,
    },
    #[error("{path}: {error}")]
    Parse {
        path: std::path::PathBuf,
        error: ParseError,
    },
}

/// Read and parse a BVH file.
pub fn read(path: &std::path::Path) -> Result<Bvh, ReadError> {
    let bytes = std::fs::read(path).map_err(|error| ReadError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    // BVH is ASCII; tolerate stray non-UTF-8 bytes (e.g. Latin-1 joint names) rather than fail.
    let text = String::from_utf8_lossy(&bytes);
    parse(&text).map_err(|error| ReadError::Parse {
        path: path.to_path_buf(),
        error,
    })
}
