//! The parameter section: groups and parameters in file order.
//!
//! Every record keeps the bytes it was read from, plus the canonical encoding of what was
//! parsed. When writing, a record whose canonical encoding has not changed is written from its
//! original bytes, and an untouched section is written back whole — so vendor padding, odd
//! offsets and lossy-to-decode values survive a rewrite. Parsing is lenient: damaged records
//! are read as far as they make sense and reported as [`Warning`]s.
//!
//! `model` holds the types and their accessors, `parsing` reads them from a file's bytes,
//! `encoding` writes them back.

mod encoding;
mod model;
mod parsing;

pub use model::{Group, Parameter, Parameters, Record, Value};
pub(crate) use parsing::{parse, SectionBounds};
