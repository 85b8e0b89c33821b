//! Trials shown to a person: the viewer page ([`view`], one self-contained HTML file that
//! plays a C3D trial or a BVH skeleton in 3D) and the plots ([`plot`], SVG or PNG pictures of
//! markers, analog channels, force plates and keyframe errors), with the events both mark
//! ([`marks`]).
//!
//! A library rather than part of the command, so that the Python package writes the very
//! bytes `c3dfix view` and `c3dfix plot` write. Nothing here reads arguments or prints; errors
//! are [`Error`]s that name the file.

mod error;
pub mod marks;
pub mod plot;
pub mod report;
pub mod view;

pub use error::{Error, Result};
