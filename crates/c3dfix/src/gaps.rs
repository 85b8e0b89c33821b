//! Every gap of every marker: what `c3dfix gaps` lists and the Python package's `gaps`
//! returns, found in one pass over the samples without decoding the trial into memory.

use crate::markers::marker_indices;
use crate::trial::validity;
use serde::Serialize;

/// One run of missing samples of one marker.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct GapInfo {
    pub label: String,
    /// First and last missing frame, numbered as the file numbers them (1-based, from its
    /// first frame).
    pub first_frame: usize,
    pub last_frame: usize,
    /// Frames missing.
    pub length: usize,
    /// The gap starts at the trial's first frame, or ends at its last: nothing on that side
    /// to fill from.
    pub at_start: bool,
    pub at_end: bool,
}

/// The gaps of the trial's markers (model outputs left out), marker by marker in file order.
/// A sample is missing by [`c3d::is_missing`]; `zero_invalid` also counts samples at
/// exactly (0, 0, 0) as missing.
pub fn gaps(c: &c3d::C3d, zero_invalid: bool) -> Vec<GapInfo> {
    let points = marker_indices(c);
    let v = validity(c, &points, zero_invalid);
    let labels = c.point_labels();
    let first = c.first_frame();
    let mut out = Vec::new();
    for (row, &i) in points.iter().enumerate() {
        for g in repair::find_gaps(&v.valid[row], row) {
            out.push(GapInfo {
                label: labels[i].clone(),
                first_frame: first + g.first,
                last_frame: first + g.last,
                length: g.len,
                at_start: g.at_start,
                at_end: g.at_end,
            });
        }
    }
    out
}
