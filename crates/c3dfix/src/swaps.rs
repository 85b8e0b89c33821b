//! Marker label swaps and label jumps of a C3D trial (issue 34): what `c3dfix swaps` lists
//! and the Python package's `swaps` returns. The finding is the repair crate's
//! ([`repair::swaps`]), on the trial's markers in mm; this module names the markers by
//! label and the frames by the file's own numbers ([`c3d::C3d::frame_number`]).

use crate::error::{Error, Result};
use crate::markers::mm_per_unit;
use crate::trial::to_trial;
use repair::swaps::{find_swaps_learned, Evidence, FindKind, LearnedLinks, SwapOptions};
use serde::Serialize;
use std::path::Path;

/// One swap or jump, as a person reads it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SwapFind {
    pub kind: FindKind,
    /// Two labels (a swap) or one (a jump). A label the file gives to more than one point
    /// is followed by `#` and the point's number (1-based), so each name is one marker.
    pub markers: Vec<String>,
    /// First and last frame of the episode in the file's numbering.
    pub first_frame: usize,
    pub last_frame: usize,
    pub confidence: f64,
    /// Strong enough to be undone by `repair --swaps fix`; the others are only reported.
    pub settled: bool,
    pub evidence: Evidence,
    /// The points (0-based indices) the markers are, in the order of `markers`.
    #[serde(skip)]
    pub points: Vec<usize>,
    /// 0-based first and last frame (indices into the trial's frames).
    #[serde(skip)]
    pub first_index: usize,
    #[serde(skip)]
    pub last_index: usize,
}

/// What [`swaps`] found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Swaps {
    pub frames: usize,
    pub markers: usize,
    pub swaps: Vec<SwapFind>,
    /// Things about the file a reader of the finds should know (labels given twice).
    pub warnings: Vec<String>,
}

/// Swaps and jumps among the labelled markers of `c` (model outputs and unlabelled points,
/// [`repair::Unlabelled::common`], left out). `path` only names the
/// file in errors. Too little to judge is an error that says so: fewer than 2 markers,
/// fewer than 3 frames, every sample missing. Coordinates that are not finite count as
/// missing, as [`c3d::is_missing`] says.
pub fn swaps(c: &c3d::C3d, path: &Path, opts: &SwapOptions) -> Result<Swaps> {
    Ok(swaps_with(c, path, opts, None)?.0)
}

/// [`swaps`] on the trial a repair built of the file's markers: `points` are
/// [`crate::markers::marker_indices`] of `c` and the trial's rows are those points (it comes back as it
/// was); `None` finds both. A repair passes the ones it has: telling markers from model
/// outputs decodes frames of the file to find a model's segment axes, and done twice more
/// per repair it was 0.02–0.04 s over the corpus.
pub(crate) fn swaps_with(
    c: &c3d::C3d,
    path: &Path,
    opts: &SwapOptions,
    repairing: Option<(&[usize], &mut repair::Trial)>,
) -> Result<(Swaps, Option<LearnedLinks>)> {
    let trial_err = |what: String| Error::Trial {
        path: path.to_path_buf(),
        what,
    };
    let (points, trial) = match repairing {
        Some((points, trial)) => (points.to_vec(), Some(trial)),
        // Labelled markers only, as the repair's swap stage: a capture system's unlabelled
        // points (`*53`) are no markers whose labels could swap (docs/swaps.md).
        None => (
            crate::markers::split_unlabelled(c, &repair::Unlabelled::common()).labelled,
            None,
        ),
    };
    if points.len() < 2 {
        return Err(trial_err(format!(
            "finding swaps needs at least 2 markers; the file has {}",
            points.len()
        )));
    }
    if c.frames() < 3 {
        return Err(trial_err(format!(
            "finding swaps needs at least 3 frames; the file has {}",
            c.frames()
        )));
    }
    let labels = c.point_labels();
    let mut warnings = Vec::new();
    let names: Vec<String> = points
        .iter()
        .map(|&i| {
            let l = labels[i].trim();
            let twins: Vec<usize> = points
                .iter()
                .copied()
                .filter(|&j| labels[j].trim() == l)
                .collect();
            if twins.len() > 1 {
                format!("{l}#{}", i + 1)
            } else {
                l.to_string()
            }
        })
        .collect();
    let mut seen: Vec<&str> = Vec::new();
    for &i in &points {
        let l = labels[i].trim();
        let twins: Vec<String> = points
            .iter()
            .filter(|&&j| labels[j].trim() == l)
            .map(|j| (j + 1).to_string())
            .collect();
        if twins.len() > 1 && !seen.contains(&l) {
            seen.push(l);
            warnings.push(format!(
                "label {l:?} names points {}: finds call them {l}#N (N the point's number)",
                twins.join(", ")
            ));
        }
    }
    let (finds, learned) = match trial {
        Some(t) => find_on_trial(c, path, opts, &points, t)?,
        None => find_on_trial(c, path, opts, &points, &mut to_trial(c, &points, false)?)?,
    };
    let swaps = finds
        .into_iter()
        .map(|x| SwapFind {
            kind: x.kind,
            markers: x.markers.iter().map(|&m| names[m].clone()).collect(),
            first_frame: c.frame_number(x.first),
            last_frame: c.frame_number(x.last),
            confidence: x.confidence,
            settled: x.settled,
            evidence: x.evidence,
            points: x.markers.iter().map(|&m| points[m]).collect(),
            first_index: x.first,
            last_index: x.last,
        })
        .collect();
    let found = Swaps {
        frames: c.frames(),
        markers: points.len(),
        swaps,
        warnings,
    };
    Ok((found, learned))
}

/// The finds among `points` of `c`, with the links learned to find them (for the repair's
/// reclaim stage, which would learn the same), whose trajectories `trial` holds in the file's units
/// (as [`to_trial`] gives them, with any validity): a repair passes its own trial, so that a
/// long trial is held once. The samples the finding leaves out (at the origin, residual 0,
/// see [`drop_processed`]; c3dfix's own fills, see [`drop_own_fills`]) are left out for the
/// finding only: `trial` comes back as it was.
pub(crate) fn find_on_trial(
    c: &c3d::C3d,
    path: &Path,
    opts: &SwapOptions,
    points: &[usize],
    trial: &mut repair::Trial,
) -> Result<(Vec<repair::swaps::Find>, Option<LearnedLinks>)> {
    let trial_err = |what: String| Error::Trial {
        path: path.to_path_buf(),
        what,
    };
    let kept = trial.valid.clone();
    // A sample at exactly (0, 0, 0) is some writers' lost sample, never evidence of where a
    // marker is.
    for (xs, vs) in trial.xyz.iter().zip(trial.valid.iter_mut()) {
        for (p, v) in xs.iter().zip(vs.iter_mut()) {
            *v &= *p != [0.0; 3];
        }
    }
    drop_processed(c, points, trial);
    drop_own_fills(c, points, trial);
    let found = if !trial.valid.iter().flatten().any(|&v| v) {
        Err(trial_err(
            "every marker sample is missing: there is nothing to check".into(),
        ))
    } else {
        let mm = mm_per_unit(&c.point_units());
        // In the process's own pool, so that a forked process finds too (see forkpool).
        let run = |t: &repair::Trial| {
            forkpool::install(|| find_swaps_learned(t, opts)).map_err(|source| Error::Repair {
                path: path.to_path_buf(),
                source,
            })
        };
        if mm == 1.0 {
            run(trial)
        } else {
            // Other units: a copy in mm (the finding's thresholds are in mm).
            let mut t = trial.clone();
            for row in &mut t.xyz {
                for p in row.iter_mut() {
                    *p = p.map(|v| v * mm);
                }
            }
            run(&t)
        }
    };
    trial.valid = kept;
    found
}

/// c3dfix's own fills are no data (the rule every later run follows, see [`crate::rerun`]):
/// a fill is where the fill put the marker, within its expected error, not where a camera
/// saw a label, so it is no evidence of which point the label sat on. Read as data, a fill
/// a few millimetres off its donors' distances was a "jump" on a repaired file that the
/// original did not show (pyCGM's `*154`, filled over frames 695–711 at the trial's start
/// with an expected error of 11 mm, then called a settled jump over 695–712): finding on a
/// repaired file sees the trial as recorded, as the repair's other stages do. The trial
/// comes back as it was (the caller restores `valid`).
fn drop_own_fills(c: &c3d::C3d, points: &[usize], trial: &mut repair::Trial) {
    let record = crate::rerun::Record::read(c);
    for &(p, first, last) in &record.filled {
        let Some(row) = points.iter().position(|&q| q == p) else {
            continue;
        };
        if let Some(valid) = trial.valid.get_mut(row) {
            let end = (last + 1).min(valid.len());
            if first < end {
                valid[first..end].fill(false);
            }
        }
    }
}

/// The residuals as evidence: a sample of residual 0 is one the capture software computed
/// (the C3D manual's mark for a processed point: its own gap fills), not a camera's
/// measurement, so it says nothing about which point a label sat on. In a file whose markers
/// have measured samples (residual above 0) those samples are left out of the finding (an
/// undo still exchanges them with their span). A file that stores every sample with
/// residual 0, as many writers do, says nothing by it, and nothing is left out.
fn drop_processed(c: &c3d::C3d, points: &[usize], trial: &mut repair::Trial) {
    // First whether anything was measured, so that a file of residual-0 samples throughout
    // costs one scan and no list of them.
    let measured = c
        .map_point_chunks(vec![(); c.point_chunks()], |(), view| {
            (0..view.frames).any(|f| points.iter().any(|&i| view.sample(f, i).1 > 0.0))
        })
        .into_iter()
        .any(|m| m);
    if !measured {
        return;
    }
    let processed: Vec<Vec<(usize, usize)>> =
        c.map_point_chunks(vec![(); c.point_chunks()], |(), view| {
            let mut out = Vec::new();
            for f in 0..view.frames {
                for (row, &i) in points.iter().enumerate() {
                    if view.sample(f, i).1 == 0.0 {
                        out.push((view.first_frame + f, row));
                    }
                }
            }
            out
        });
    for (f, row) in processed.into_iter().flatten() {
        trial.valid[row][f] = false;
    }
}
