//! Measuring fill accuracy on real trials: known samples are knocked out, refilled by each
//! method, and the 3D error reported per method and gap length, per file and pooled. Errors
//! are reported in millimetres whatever POINT:UNITS a file uses, so files in metres and
//! millimetres pool correctly.

use crate::error::{Error, Result, Setting};
use crate::markers::{marker_indices, mm_per_unit};
use crate::trial::{open, to_trial};
use repair::{EvalConfig, FillMethod};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

pub use repair::evaluate::{MAX_GAPS_PER_LENGTH, MAX_GAP_LENGTH};

/// What to measure.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaluateOptions {
    /// Lengths of the artificial gaps, in frames.
    pub gap_lengths: Vec<usize>,
    /// Markers that lose data (labels); `None` for every marker.
    pub markers: Option<Vec<String>>,
    /// Methods to compare; `None` for all ([`FillMethod::ALL`]).
    pub methods: Option<Vec<FillMethod>>,
    /// Artificial gaps (or groups of gaps) per length.
    pub gaps_per_length: usize,
    /// 1, or 2–3 markers (a marker and its nearest neighbours) losing frames together.
    pub group: usize,
    /// Seed of the gap placement.
    pub seed: u64,
}

impl Default for EvaluateOptions {
    fn default() -> Self {
        EvaluateOptions {
            gap_lengths: vec![5, 10, 20, 40, 80],
            markers: None,
            methods: None,
            gaps_per_length: 40,
            group: 1,
            seed: 1,
        }
    }
}

/// One file's evaluation, its errors in mm (`units`) whatever the file's own unit
/// (`file_units`). Each artificial gap's `first` frame is the file's own frame number
/// ([`c3d::C3d::frame_number`]), as in every other output.
#[derive(Debug, Clone, Serialize)]
pub struct FileEvaluation {
    pub file: String,
    pub units: String,
    pub file_units: String,
    pub evaluation: repair::Evaluation,
}

/// Sample-weighted errors over all files for one method and gap length, in mm.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Pooled {
    pub gap_len: usize,
    pub method: String,
    pub mean: f64,
    pub max: f64,
    pub samples: usize,
}

/// Everything [`evaluate`] measured.
#[derive(Debug, Clone, Serialize)]
pub struct Evaluation {
    pub files: Vec<FileEvaluation>,
    pub pooled: Vec<Pooled>,
}

impl EvaluateOptions {
    /// The methods to compare.
    pub fn fill_methods(&self) -> Vec<FillMethod> {
        self.methods
            .clone()
            .unwrap_or_else(|| FillMethod::ALL.to_vec())
    }

    fn check(&self) -> Result<()> {
        let out_of_range = |setting, value: String, limits: String| Error::OutOfRange {
            setting,
            value,
            limits,
        };
        if !(1..=3).contains(&self.group) {
            return Err(out_of_range(
                Setting::Group,
                self.group.to_string(),
                "must be 1, 2 or 3".into(),
            ));
        }
        let lengths = 1..=MAX_GAP_LENGTH;
        if let Some(bad) = self.gap_lengths.iter().find(|l| !lengths.contains(l)) {
            return Err(out_of_range(
                Setting::GapLengths,
                bad.to_string(),
                format!("must be frame counts from 1 to {MAX_GAP_LENGTH}"),
            ));
        }
        if self.gap_lengths.is_empty() {
            return Err(out_of_range(
                Setting::GapLengths,
                "(none)".into(),
                format!("must be frame counts from 1 to {MAX_GAP_LENGTH}"),
            ));
        }
        if !(1..=MAX_GAPS_PER_LENGTH).contains(&self.gaps_per_length) {
            return Err(out_of_range(
                Setting::GapsPerLength,
                self.gaps_per_length.to_string(),
                format!("must be from 1 to {MAX_GAPS_PER_LENGTH}"),
            ));
        }
        Ok(())
    }
}

/// Evaluate every file; `each` sees each file's result as soon as it is measured (the
/// command prints its table then).
pub fn evaluate(
    files: &[PathBuf],
    opts: &EvaluateOptions,
    mut each: impl FnMut(&FileEvaluation),
) -> Result<Evaluation> {
    opts.check()?;
    let methods = opts.fill_methods();
    let mut out = Vec::new();
    let mut pooled: BTreeMap<(usize, String), (f64, usize, f64)> = BTreeMap::new();
    for f in files {
        let c = open(f)?;
        let points = marker_indices(&c);
        if points.len() < 4 {
            return Err(Error::Trial {
                path: f.clone(),
                what: format!("needs at least 4 markers to evaluate, has {}", points.len()),
            });
        }
        // Errors in mm whatever the file's units, so that files pool and tables compare.
        let units = c.point_units();
        let scale = mm_per_unit(&units);
        // A sample at exactly (0, 0, 0) is no truth for an artificial gap, whatever its
        // fourth word says: no marker sits on the lab's origin to the last bit, and the
        // writers that store such samples mean a lost one (ART-Human puts every point of a
        // frame where the body was lost there). Scored against it, a fill would be off by
        // the marker's distance from the origin.
        let mut t = to_trial(&c, &points, true)?;
        // Nor is a sample c3dfix filled (the file's record, crate::rerun): its error would
        // be a fill's against a fill.
        for &(p, a, b) in &crate::rerun::Record::read(&c).filled {
            if let Some(r) = points.iter().position(|&i| i == p) {
                t.valid[r][a..=b].fill(false);
            }
        }
        if scale != 1.0 {
            for p in t.xyz.iter_mut().flatten() {
                *p = p.map(|x| x * scale);
            }
        }
        let rows = match &opts.markers {
            None => None,
            Some(names) => {
                let mut rows = Vec::new();
                for n in names {
                    let Some(i) = c.point_index(n.trim()) else {
                        return Err(Error::Trial {
                            path: f.clone(),
                            what: format!(
                                "no marker {n:?}; the file has: {}",
                                c.point_labels().join(", ")
                            ),
                        });
                    };
                    match points.iter().position(|&p| p == i) {
                        Some(r) => rows.push(r),
                        None => {
                            return Err(Error::Trial {
                                path: f.clone(),
                                what: format!("{n} is a model output, not a marker"),
                            })
                        }
                    }
                }
                Some(rows)
            }
        };
        let cfg = EvalConfig {
            markers: rows,
            gap_lengths: opts.gap_lengths.clone(),
            gaps_per_length: opts.gaps_per_length,
            methods: methods.clone(),
            group: opts.group,
            seed: opts.seed,
            ..EvalConfig::default()
        };
        // In the process's own pool, so that a forked process evaluates too (see forkpool).
        let mut ev =
            forkpool::install(|| repair::evaluate(&t, &cfg)).map_err(|source| Error::Repair {
                path: f.clone(),
                source,
            })?;
        for g in &mut ev.gaps {
            g.first = c.frame_number(g.first);
        }
        for s in &ev.scores {
            let e = pooled
                .entry((s.gap_len, s.method.to_string()))
                .or_insert((0.0, 0, 0.0));
            e.0 += s.mean * s.samples as f64;
            e.1 += s.samples;
            e.2 = e.2.max(s.max);
        }
        let fe = FileEvaluation {
            file: f.display().to_string(),
            units: "mm".into(),
            file_units: units,
            evaluation: ev,
        };
        each(&fe);
        out.push(fe);
    }
    let pooled = pooled
        .into_iter()
        .map(|((gap_len, method), (sum, n, max))| Pooled {
            gap_len,
            method,
            mean: if n > 0 { sum / n as f64 } else { f64::NAN },
            max,
            samples: n,
        })
        .collect();
    Ok(Evaluation { files: out, pooled })
}
