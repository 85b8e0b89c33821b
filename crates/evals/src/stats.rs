//! The order statistics of the evaluations' tables: the `signal` crate's, which the library
//! crates read too, under the names the evaluations use.
//!
//! Two readings, each kept where its figures were made with it: [`quantile`] interpolates
//! between order statistics (numpy's default; the event tables), [`rank`] takes the order
//! statistic at a fraction of the count (the upper median for 1/2; the fill and swap
//! tables, which print a sample that was measured).

pub use signal::order::{quantile, rank, sorted};

/// The upper median of `x` (see [`rank`]); None for no values.
pub fn median(x: impl IntoIterator<Item = f64>) -> Option<f64> {
    rank(&sorted(x), 1, 2)
}
