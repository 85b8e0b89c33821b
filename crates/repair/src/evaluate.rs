//! Fill accuracy on artificial gaps: knock out gaps of given lengths where the truth is
//! known, fill them with each method, and report 3D errors. The harder mode knocks out
//! 2–3 neighbouring markers over overlapping frames together, as occlusions often do.

use rayon::prelude::*;
use serde::Serialize;

use crate::error::{RepairError, Result};
use crate::fill::{fill_gap, Data, FillMethod, FillOptions, FillOutcome};
use crate::gaps::Gap;
use crate::rng::SplitMix64;
use crate::Trial;

/// Valid samples required on each side of an artificial gap.
const MARGIN: usize = 4;
/// Random placements tried per artificial gap before giving up on it.
const TRIES: usize = 200;

/// What to evaluate.
/// Longest artificial gap, in frames (over an hour at 200 Hz): longer ones could not be
/// placed in any trial, and the bound keeps placement arithmetic from overflowing.
pub const MAX_GAP_LENGTH: usize = 1_000_000;

/// Most artificial gaps per length: each is filled by every method, so this bounds the work.
pub const MAX_GAPS_PER_LENGTH: usize = 10_000;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvalConfig {
    /// Markers that lose data (`None`: all).
    pub markers: Option<Vec<usize>>,
    /// Lengths of the artificial gaps, 1 to [`MAX_GAP_LENGTH`] frames.
    pub gap_lengths: Vec<usize>,
    /// Artificial gaps (or groups) per length, 0 to [`MAX_GAPS_PER_LENGTH`].
    pub gaps_per_length: usize,
    pub methods: Vec<FillMethod>,
    /// Markers losing overlapping frames together: 1, or 2–3 (the chosen marker and its
    /// nearest neighbours by mean distance).
    pub group: usize,
    pub seed: u64,
    /// Other fill settings (`method` and `max_gap` are overridden).
    pub fill: FillOptions,
}

impl Default for EvalConfig {
    fn default() -> Self {
        EvalConfig {
            markers: None,
            gap_lengths: vec![5, 10, 20, 40, 80],
            gaps_per_length: 20,
            methods: FillMethod::ALL.to_vec(),
            group: 1,
            seed: 1,
            fill: FillOptions::default(),
        }
    }
}

/// Errors of one method at one gap length, in the data's units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MethodScore {
    pub method: FillMethod,
    pub gap_len: usize,
    /// Artificial gaps placed (per marker).
    pub gaps: usize,
    /// Of those, gaps the method could not fill (excluded from the errors).
    pub failed: usize,
    pub samples: usize,
    pub mean: f64,
    pub median: f64,
    pub max: f64,
}

/// All scores, method-major within each gap length.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    pub group: usize,
    pub seed: u64,
    pub scores: Vec<MethodScore>,
}

impl Evaluation {
    pub fn score(&self, method: FillMethod, gap_len: usize) -> Option<&MethodScore> {
        self.scores
            .iter()
            .find(|s| s.method == method && s.gap_len == gap_len)
    }
}

/// Runs the evaluation. Only markers' valid samples serve as truth; placements need
/// `MARGIN` valid samples around each artificial gap.
pub fn evaluate(trial: &Trial, cfg: &EvalConfig) -> Result<Evaluation> {
    trial.check()?;
    if !(1..=3).contains(&cfg.group) {
        return Err(RepairError::Option(
            "evaluation group must be 1, 2 or 3".into(),
        ));
    }
    cfg.fill.validate()?;
    if let Some(len) = cfg
        .gap_lengths
        .iter()
        .find(|l| !(1..=MAX_GAP_LENGTH).contains(*l))
    {
        return Err(RepairError::Option(format!(
            "evaluation gap length {len} must be from 1 to {MAX_GAP_LENGTH} frames"
        )));
    }
    if cfg.gaps_per_length > MAX_GAPS_PER_LENGTH {
        return Err(RepairError::Option(format!(
            "{} gaps per length: at most {MAX_GAPS_PER_LENGTH}",
            cfg.gaps_per_length
        )));
    }
    let markers: Vec<usize> = match &cfg.markers {
        Some(v) => v.iter().copied().filter(|&m| m < trial.markers()).collect(),
        None => (0..trial.markers()).collect(),
    };
    let neighbours: Vec<Vec<usize>> = (0..trial.markers())
        .map(|m| nearest(trial, m, cfg.group - 1))
        .collect();
    let mut scores = Vec::new();
    for &len in &cfg.gap_lengths {
        let mut rng = SplitMix64::new(cfg.seed ^ (len as u64).wrapping_mul(0x9E37_79B9));
        let groups: Vec<Vec<(usize, usize)>> = (0..cfg.gaps_per_length)
            .filter_map(|_| place(trial, &markers, &neighbours, len, &mut rng))
            .collect();
        // errors[method] = per-sample errors, failures[method] = gaps left.
        let per_group: Vec<Vec<(Vec<f64>, usize)>> = groups
            .par_iter()
            .map(|g| run_group(trial, g, len, cfg))
            .collect();
        for (i, &method) in cfg.methods.iter().enumerate() {
            let mut e: Vec<f64> = Vec::new();
            let mut failed = 0;
            for pg in &per_group {
                e.extend_from_slice(&pg[i].0);
                failed += pg[i].1;
            }
            scores.push(summarize(
                method,
                len,
                groups.iter().map(Vec::len).sum(),
                failed,
                e,
            ));
        }
    }
    Ok(Evaluation {
        group: cfg.group,
        seed: cfg.seed,
        scores,
    })
}

fn summarize(
    method: FillMethod,
    len: usize,
    gaps: usize,
    failed: usize,
    mut e: Vec<f64>,
) -> MethodScore {
    e.sort_by(f64::total_cmp);
    let n = e.len();
    let mean = if n > 0 {
        e.iter().sum::<f64>() / n as f64
    } else {
        f64::NAN
    };
    let median = match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => e[n / 2],
        _ => (e[n / 2 - 1] + e[n / 2]) / 2.0,
    };
    MethodScore {
        method,
        gap_len: len,
        gaps,
        failed,
        samples: n,
        mean,
        median,
        max: e.last().copied().unwrap_or(f64::NAN),
    }
}

/// The `k` markers nearest `m` by mean distance over frames where both are valid.
fn nearest(trial: &Trial, m: usize, k: usize) -> Vec<usize> {
    if k == 0 {
        return Vec::new();
    }
    let step = (trial.frames() / 500).max(1);
    let mut d: Vec<(f64, usize)> = (0..trial.markers())
        .filter(|&j| j != m)
        .filter_map(|j| {
            let (mut s, mut n) = (0.0, 0usize);
            for f in (0..trial.frames()).step_by(step) {
                if trial.valid[m][f] && trial.valid[j][f] {
                    let (p, q) = (trial.xyz[m][f], trial.xyz[j][f]);
                    s += ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2))
                        .sqrt();
                    n += 1;
                }
            }
            (n > 0).then(|| (s / n as f64, j))
        })
        .collect();
    d.sort_by(|a, b| a.0.total_cmp(&b.0));
    d.into_iter().take(k).map(|x| x.1).collect()
}

/// One artificial gap group: `(marker, first frame)` per marker, all of length `len`.
fn place(
    trial: &Trial,
    markers: &[usize],
    neighbours: &[Vec<usize>],
    len: usize,
    rng: &mut SplitMix64,
) -> Option<Vec<(usize, usize)>> {
    let n = trial.frames();
    if markers.is_empty() || n < len + 2 * MARGIN + 2 {
        return None;
    }
    let clean = |m: usize, a: usize| {
        a >= MARGIN
            && a + len + MARGIN <= n
            && trial.valid[m][a - MARGIN..a + len + MARGIN]
                .iter()
                .all(|&v| v)
    };
    for _ in 0..TRIES {
        let m = markers[rng.range(0, markers.len())];
        let a = rng.range(MARGIN, n - len - MARGIN + 1);
        if !clean(m, a) {
            continue;
        }
        let mut g = vec![(m, a)];
        for &j in &neighbours[m] {
            let half = len / 2;
            let shift = rng.range(0, 2 * half + 1) as isize - half as isize;
            let aj = a as isize + shift;
            if aj >= 0 && clean(j, aj as usize) {
                g.push((j, aj as usize));
            }
        }
        if g.len() == 1 + neighbours[m].len() {
            return Some(g);
        }
    }
    None
}

/// Errors of every method on one group of artificial gaps.
fn run_group(
    trial: &Trial,
    g: &[(usize, usize)],
    len: usize,
    cfg: &EvalConfig,
) -> Vec<(Vec<f64>, usize)> {
    let mut valid = trial.valid.clone();
    for &(m, a) in g {
        valid[m][a..a + len].iter_mut().for_each(|v| *v = false);
    }
    let data = Data::new(&trial.xyz, &valid);
    cfg.methods
        .iter()
        .map(|&method| {
            let opts = FillOptions {
                method,
                max_gap: None,
                ..cfg.fill.clone()
            };
            let mut e = Vec::new();
            let mut failed = 0;
            for &(m, a) in g {
                let gap = Gap {
                    marker: m,
                    first: a,
                    last: a + len - 1,
                    len,
                    at_start: false,
                    at_end: false,
                };
                match fill_gap(data, &gap, &opts) {
                    (Some(v), FillOutcome::Filled { .. }) => {
                        for (i, p) in v.iter().enumerate() {
                            let q = trial.xyz[m][a + i];
                            e.push(
                                ((p[0] - q[0]).powi(2)
                                    + (p[1] - q[1]).powi(2)
                                    + (p[2] - q[2]).powi(2))
                                .sqrt(),
                            );
                        }
                    }
                    _ => failed += 1,
                }
            }
            (e, failed)
        })
        .collect()
}
