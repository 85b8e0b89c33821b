//! The markers as the events read them: labels with model outputs blanked, and trajectories
//! in millimetres (NaN where missing). Shared by the events ([`crate::events`]) and the
//! stand-in markers ([`crate::events_stand_in`]).

use crate::error::{Error, Result};
use std::path::Path;

/// A trial that could not be read as markers, for `path`.
pub(crate) fn trial_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Trial {
        path: path.to_path_buf(),
        what: e.to_string(),
    }
}

/// The point labels of `c` with model outputs blanked, so that a role is never given to an
/// angle or a moment that happens to share a marker's name.
pub(crate) fn marker_labels(c: &c3d::C3d) -> Vec<String> {
    let outputs = c.model_output_labels();
    c.point_labels()
        .into_iter()
        .map(|l| {
            if outputs.contains(&l) {
                String::new()
            } else {
                l
            }
        })
        .collect()
}

/// Each point's trajectory in millimetres, NaN where missing.
pub(crate) fn tracks(c: &c3d::C3d, points: &[usize], path: &Path) -> Result<Vec<Vec<[f64; 3]>>> {
    let mut sorted = points.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let trial = crate::trial::to_trial(c, &sorted, false).map_err(|e| trial_error(path, e))?;
    let mm = c3d::mm_per_unit(&c.point_units());
    let frames = c.frames();
    Ok(points
        .iter()
        .map(|p| {
            let Ok(row) = sorted.binary_search(p) else {
                return vec![[f64::NAN; 3]; frames];
            };
            (0..frames)
                .map(|f| {
                    let v = trial.xyz[row][f];
                    if trial.valid[row][f] && v.iter().all(|x| x.is_finite()) {
                        [v[0] * mm, v[1] * mm, v[2] * mm]
                    } else {
                        [f64::NAN; 3]
                    }
                })
                .collect()
        })
        .collect())
}
