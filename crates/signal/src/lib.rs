//! Sampled signals' shared maths: filters and order statistics, one implementation of each
//! for every crate that needs them (repair's low-pass stage and the plates' filter, gait's
//! zero-lag smoothing, the evaluations' tables).
//!
//! It knows nothing of trials, markers or C3D: plain slices of `f64` in, numbers out.

pub mod error;
pub mod filter;
pub mod order;

pub use error::FilterError;
pub use filter::{Iir, Pass, Section};
