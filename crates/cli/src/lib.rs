//! The `c3dfix` command-line tool: its commands over the `c3dfix`, `show`, `c3d`, `repair`
//! and `bvh` crates.
//! A library as well as the binary, so that tests can reach the commands' own pieces (their
//! arguments, the flag phrasing); what the fuzz targets and Python drive (the repair of a
//! file, the report `info` prints, the pictures) is in those libraries.

pub mod commands;
pub mod console;
pub mod flags;
pub mod output;
pub mod plates;
pub mod ranges;
