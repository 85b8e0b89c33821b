//! How many trials a run over many files does at once (`batch`, `convert`, `events`, `gait`
//! on folders): a count checked once, here, whichever front asks, and the one way such a run
//! spreads its trials over threads with its results in the trials' order — so what a run
//! reports never depends on which thread finished first.

use crate::error::{Error, Result, Setting};
use rayon::prelude::*;
use std::fmt;
use std::str::FromStr;

/// Most worker threads a run starts: enough to keep a disk busy with syncs while others
/// compute, far below what would exhaust the system's threads.
pub const MAX_JOBS: usize = 256;

/// Trials done at once: a count from 1 to [`MAX_JOBS`], or one per core (the default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Jobs(Option<usize>);

impl Jobs {
    /// One worker per core.
    pub const PER_CORE: Jobs = Jobs(None);

    /// `n` workers; refused outside 1 to [`MAX_JOBS`] before any memory or thread is sized
    /// from it.
    pub fn new(n: usize) -> Result<Jobs> {
        if (1..=MAX_JOBS).contains(&n) {
            Ok(Jobs(Some(n)))
        } else {
            Err(Self::out_of_range(n.to_string(), "must be"))
        }
    }

    /// The count asked for (None: one per core).
    pub fn get(self) -> Option<usize> {
        self.0
    }

    fn out_of_range(value: String, lead: &str) -> Error {
        Error::OutOfRange {
            setting: Setting::Jobs,
            value,
            limits: format!("{lead} from 1 to {MAX_JOBS}"),
        }
    }

    /// Threads for `items` jobs: never more than there are items; 0 lets the pool start one
    /// per core.
    fn threads(self, items: usize) -> usize {
        match self.0 {
            None => 0,
            Some(j) => j.min(items.max(1)),
        }
    }

    /// `work` on every item on these threads; the results come back in the items' order.
    pub fn each<I, T, W>(self, items: &[I], work: W) -> Result<Vec<T>>
    where
        I: Sync,
        T: Send,
        W: Fn(&I) -> T + Sync,
    {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads(items.len()))
            .build()
            .map_err(|e| Error::Output(format!("cannot start worker threads: {e}")))?;
        Ok(pool.install(|| items.par_iter().map(&work).collect()))
    }
}

impl FromStr for Jobs {
    type Err = Error;
    /// A whole number from 1 to [`MAX_JOBS`].
    fn from_str(s: &str) -> Result<Jobs> {
        match s.trim().parse::<usize>() {
            Ok(n) => Jobs::new(n),
            Err(_) => Err(Self::out_of_range(s.to_string(), "not a whole number")),
        }
    }
}

impl fmt::Display for Jobs {
    /// The count, or `per-core`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(n) => write!(f, "{n}"),
            None => f.write_str("per-core"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_checked_once_and_capped_by_the_items() {
        assert!("0".parse::<Jobs>().is_err());
        assert!("257".parse::<Jobs>().is_err());
        assert!("two".parse::<Jobs>().is_err());
        assert_eq!("256".parse::<Jobs>().ok().and_then(Jobs::get), Some(256));
        let e = Jobs::new(0).map(Jobs::get).unwrap_err();
        assert_eq!(e.to_string(), "jobs 0: must be from 1 to 256");
        assert_eq!(Jobs::PER_CORE.threads(10), 0);
        assert_eq!(Jobs(Some(2)).threads(10), 2);
        assert_eq!(Jobs(Some(256)).threads(3), 3);
        assert_eq!(Jobs(Some(4)).threads(0), 1);
    }

    #[test]
    fn results_keep_the_items_order() {
        let items: Vec<usize> = (0..100).collect();
        let out = Jobs(Some(4)).each(&items, |&i| i * 2);
        assert_eq!(out.ok(), Some((0..100).map(|i| i * 2).collect::<Vec<_>>()));
    }
}
