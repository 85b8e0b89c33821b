//! The `c3dfix` command-line tool: its commands over the `c3dfix`, `show`, `c3d`, `repair`
//! and `bvh` crates.
//! A library as well as the binary, so that fuzz targets and tests drive the very code the
//! binary runs (the repair of a file in memory, the description `info` prints).

pub mod commands;
pub mod console;
pub mod flags;
pub mod output;
pub mod plates;
pub mod ranges;
