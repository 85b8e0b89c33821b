//! Gaps: maximal runs of invalid samples of one marker, and building validity masks.

use serde::Serialize;

/// One run of invalid samples of one marker (frames are 0-based and inclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Gap {
    pub marker: usize,
    pub first: usize,
    pub last: usize,
    pub len: usize,
    /// The gap starts at frame 0: there is no valid sample before it.
    pub at_start: bool,
    /// The gap ends at the last frame: there is no valid sample after it.
    pub at_end: bool,
}

impl Gap {
    /// Whether the gap has valid data on one side only (or none), so polynomial methods
    /// would have to extrapolate.
    pub fn touches_edge(&self) -> bool {
        self.at_start || self.at_end
    }
}

/// All gaps of one marker's validity mask, in frame order.
pub fn find_gaps(valid: &[bool], marker: usize) -> Vec<Gap> {
    let n = valid.len();
    let mut out = Vec::new();
    let mut f = 0;
    while f < n {
        if valid[f] {
            f += 1;
            continue;
        }
        let first = f;
        while f < n && !valid[f] {
            f += 1;
        }
        let last = f - 1;
        out.push(Gap {
            marker,
            first,
            last,
            len: last - first + 1,
            at_start: first == 0,
            at_end: last + 1 == n,
        });
    }
    out
}

/// Maximal runs of valid samples, as inclusive `(first, last)` frame pairs.
pub fn valid_segments(valid: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut f = 0;
    while f < valid.len() {
        if !valid[f] {
            f += 1;
            continue;
        }
        let first = f;
        while f < valid.len() && valid[f] {
            f += 1;
        }
        out.push((first, f - 1));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_interior_and_edge_gaps() {
        let v = [false, false, true, true, false, true, false];
        let g = find_gaps(&v, 4);
        assert_eq!(g.len(), 3);
        assert_eq!(
            (g[0].first, g[0].last, g[0].len, g[0].at_start, g[0].at_end),
            (0, 1, 2, true, false)
        );
        assert_eq!(
            (g[1].first, g[1].last, g[1].at_start, g[1].at_end),
            (4, 4, false, false)
        );
        assert_eq!(
            (g[2].first, g[2].last, g[2].at_start, g[2].at_end),
            (6, 6, false, true)
        );
        assert!(g.iter().all(|g| g.marker == 4));
        assert_eq!(valid_segments(&v), vec![(2, 3), (5, 5)]);
        assert!(find_gaps(&[true; 5], 0).is_empty());
        assert_eq!(find_gaps(&[false; 3], 0)[0].len, 3);
    }
}
