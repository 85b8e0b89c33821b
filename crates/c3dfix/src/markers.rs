//! Which points of a trial are markers, and how labels name them: one notion of a marker for
//! every command and binding.

use crate::error::{Error, Result};

/// Labels of points that are model outputs, not markers ([`c3d::C3d::model_output_labels`]).
/// They are never repaired nor used as donors.
pub fn model_outputs(c: &c3d::C3d) -> Vec<String> {
    c.model_output_labels()
}

/// The markers of a trial: indices of the points that are not model outputs.
pub fn marker_indices(c: &c3d::C3d) -> Vec<usize> {
    let outputs = model_outputs(c);
    c.point_labels()
        .iter()
        .enumerate()
        .filter(|(_, l)| !outputs.contains(l))
        .map(|(i, _)| i)
        .collect()
}

/// Point indices of the given labels (surrounding blanks ignored, empty names skipped); an
/// unknown label is an error that lists the labels the trial has.
pub fn select(c: &c3d::C3d, names: &[String]) -> Result<Vec<usize>> {
    let mut out = Vec::new();
    for n in names.iter().map(|n| n.trim()).filter(|n| !n.is_empty()) {
        match c.point_index(n) {
            Some(i) => out.push(i),
            None => {
                return Err(Error::options(format!(
                    "no marker {n:?}; the file has: {}",
                    c.point_labels().join(", ")
                )))
            }
        }
    }
    Ok(out)
}

/// The markers of a trial split by [`repair::Unlabelled`]'s one rule: `labelled` are the
/// markers every repair stage speaks of, `unlabelled` the points a capture system could not
/// name (`*51`, `Unlabeled 3`, an empty label, or the user's pattern), candidates for the
/// markers' gaps and otherwise left as recorded. Both in the file's order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Split {
    pub labelled: Vec<usize>,
    pub unlabelled: Vec<usize>,
}

/// [`marker_indices`] of `c` split into labelled markers and unlabelled points by `rule`.
pub fn split_unlabelled(c: &c3d::C3d, rule: &repair::Unlabelled) -> Split {
    let labels = c.point_labels();
    let (unlabelled, labelled) = marker_indices(c)
        .into_iter()
        .partition(|&i| rule.is_unlabelled(&labels[i]));
    Split {
        labelled,
        unlabelled,
    }
}

pub use c3d::mm_per_unit;
