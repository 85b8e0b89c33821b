//! Fill accuracy on artificial gaps: knock out gaps of given lengths where the truth is
//! known, fill them with each method, and report 3D errors. The harder mode knocks out
//! 2–3 neighbouring markers over overlapping frames together, as occlusions often do.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{RepairError, Result};
use crate::fill::{
    features, fill_gaps, max_steps, step_ratio, Data, Diag, FillMethod, FillOptions, FillOutcome,
    Span, Target, Vetting, FEATURES,
};
use crate::gaps::Gap;
use crate::rng::SplitMix64;
use crate::Trial;

/// Valid samples required on each side of an artificial gap.
const MARGIN: usize = 4;
/// Random placements tried per artificial gap before giving up on it.
const TRIES: usize = 200;
/// Other markers a stretch keeps its distance to, within [`RIGID_TOL`] of it, that make it
/// a computed point (see [`computed`]): three fix a point in space.
const RIGID_PARTNERS: usize = 3;
/// Largest range of a distance over a stretch, relative to the distance, that counts as
/// constant: 10⁻⁵, 3 µm at 300 mm. A point computed from others and stored as 32-bit
/// floats keeps its distances to 10⁻⁶ of them; two recorded markers, even on one rigid
/// cluster, move against each other by camera noise (0.02 mm and more over five frames,
/// 10⁻⁴ of 200 mm).
const RIGID_TOL: f64 = 1e-5;

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
    /// Knock the gaps out at a trial's start or end instead of inside it. A real gap there
    /// has recorded samples on one side only, so the polynomial methods cannot fill it and
    /// `auto` leans on its donors: its expected errors must be judged on such gaps apart.
    /// Each gap is made by cutting the trial (to at least half its frames) where the gap
    /// begins or ends, so that any recorded stretch may serve, not only the trial's first
    /// and last frames; the 2–3 markers of a group lose the same frames.
    pub at_trial_ends: bool,
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
            at_trial_ends: false,
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

/// One artificial gap filled by one method: its real errors, the error the fill expected
/// of itself, and its largest step relative to the marker's largest recorded step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GapScore {
    pub method: FillMethod,
    pub gap_len: usize,
    pub marker: usize,
    pub first: usize,
    /// Mean and largest 3D error over the gap's frames.
    pub mean: f64,
    pub max: f64,
    /// The fill's own expected error (`auto`; `None` for unchecked single methods).
    pub expected: Option<f64>,
    /// Largest step of the fill (joins to the anchors included) divided by the marker's
    /// largest recorded step.
    pub step_ratio: f64,
    /// What `expected` was made from (`auto` and checked single methods; see [`Diag`]).
    #[serde(flatten)]
    pub evidence: Option<Diag>,
    /// The method whose fill was used (for `auto`, the choice or the blend's first
    /// method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chosen: Option<FillMethod>,
}

/// All scores, method-major within each gap length.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    pub group: usize,
    pub seed: u64,
    pub scores: Vec<MethodScore>,
    /// Every filled artificial gap (not serialized: one record per gap and method).
    #[serde(skip)]
    pub gaps: Vec<GapScore>,
}

impl GapScore {
    /// The features `auto`'s expected error is made from (`None` without its evidence), as
    /// the evaluation that fits the model needs them.
    pub fn calibration_features(&self) -> Option<[f64; FEATURES]> {
        self.evidence.as_ref().map(features)
    }
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
    let mut gaps = Vec::new();
    for &len in &cfg.gap_lengths {
        let mut rng = SplitMix64::new(cfg.seed ^ (len as u64).wrapping_mul(0x9E37_79B9));
        let groups: Vec<Placed> = (0..cfg.gaps_per_length)
            .filter_map(|_| {
                if cfg.at_trial_ends {
                    place_at_end(trial, &markers, &neighbours, len, &mut rng)
                } else {
                    place(trial, &markers, &neighbours, len, &mut rng)
                        .map(|g| (g, 0..trial.frames()))
                }
            })
            .collect();
        // errors[method] = per-sample errors, failures[method] = gaps left.
        let per_group: Vec<Vec<MethodRun>> = groups
            .par_iter()
            .map(|g| run_group(trial, g, len, cfg))
            .collect();
        for (i, &method) in cfg.methods.iter().enumerate() {
            let mut e: Vec<f64> = Vec::new();
            let mut failed = 0;
            for pg in &per_group {
                e.extend_from_slice(&pg[i].0);
                failed += pg[i].1;
                gaps.extend_from_slice(&pg[i].2);
            }
            scores.push(summarize(
                method,
                len,
                groups.iter().map(|g| g.0.len()).sum(),
                failed,
                e,
            ));
        }
    }
    Ok(Evaluation {
        group: cfg.group,
        seed: cfg.seed,
        scores,
        gaps,
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
    let median = signal::order::sorted_median(&e).unwrap_or(f64::NAN);
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
            && !computed(trial, m, a, len)
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

/// One artificial gap group at a trial's start or end (see [`EvalConfig::at_trial_ends`]):
/// the group, and the frames the trial is cut to so that the gap touches its first or last
/// frame. The part kept holds at least half the trial; the gap needs `MARGIN` recorded
/// samples on its inner side only.
fn place_at_end(
    trial: &Trial,
    markers: &[usize],
    neighbours: &[Vec<usize>],
    len: usize,
    rng: &mut SplitMix64,
) -> Option<Placed> {
    let n = trial.frames();
    if markers.is_empty() || n < 2 * (len + MARGIN) + 2 {
        return None;
    }
    for _ in 0..TRIES {
        let m = markers[rng.range(0, markers.len())];
        // The trial starts with the gap (cut at `a`) or ends with it (cut at `a + len`).
        let at_start = rng.range(0, 2) == 0;
        let (a, keep) = if at_start {
            let a = rng.range(0, n / 2);
            (a, a..n)
        } else {
            let end = rng.range(n - n / 2, n + 1);
            (end - len, 0..end)
        };
        let recorded = if at_start {
            a..a + len + MARGIN
        } else {
            a - MARGIN..a + len
        };
        let clean = |j: usize| {
            trial.valid[j][recorded.clone()].iter().all(|&v| v) && !computed(trial, j, a, len)
        };
        if !clean(m) || !neighbours[m].iter().all(|&j| clean(j)) {
            continue;
        }
        let g = std::iter::once(m)
            .chain(neighbours[m].iter().copied())
            .map(|j| (j, a))
            .collect();
        return Some((g, keep));
    }
    None
}

/// Whether marker `m` over frames `a..a + len` is a point computed from other markers
/// rather than a recording: it keeps its distance to three or more of them constant (to
/// 10⁻⁵ of it; `RIGID_PARTNERS`, `RIGID_TOL`). Plug-in Gait's virtual markers (segment
/// origins and axes, joint centres) and the capture software's rigid-body fills are such
/// points; no camera saw them, and the donor methods rebuild them from the same markers
/// exactly (to 0.001 mm), so a gap knocked there measures nothing a lab's real gap has.
/// Before this rule, 1 208 of the corpus evaluation's 27 680 gaps (`fill_eval`) lay in such
/// stretches, most in ART's body points (whose fills were off by up to 75 mm: the donors
/// chosen were not the partners), and 322 of the 686 fills within 0.001 mm of the truth.
/// Such stretches get no artificial gap.
pub fn computed(trial: &Trial, m: usize, a: usize, len: usize) -> bool {
    let frames = a..a + len;
    let mut partners = 0;
    for j in (0..trial.markers()).filter(|&j| j != m) {
        if !trial.valid[j][frames.clone()].iter().all(|&v| v) {
            continue;
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for f in frames.clone() {
            let d = crate::fill::dist(trial.xyz[m][f], trial.xyz[j][f]);
            lo = lo.min(d);
            hi = hi.max(d);
            if hi - lo > RIGID_TOL * hi {
                break;
            }
        }
        if hi > 0.0 && hi - lo <= RIGID_TOL * hi {
            partners += 1;
            if partners >= RIGID_PARTNERS {
                return true;
            }
        }
    }
    false
}

/// One method on one group: per-sample errors, gaps it could not fill, per-gap records.
type MethodRun = (Vec<f64>, usize, Vec<GapScore>);

/// An artificial gap group, `(marker, first frame)` per marker, and the frames of the trial
/// it is filled in (the whole trial, or the part that starts or ends with the gap).
type Placed = (Vec<(usize, usize)>, std::ops::Range<usize>);

/// Errors of every method on one group of artificial gaps. Records give the gaps' frames in
/// the whole trial.
fn run_group(trial: &Trial, placed: &Placed, len: usize, cfg: &EvalConfig) -> Vec<MethodRun> {
    let (whole, keep) = placed;
    let cut = Trial {
        rate_hz: trial.rate_hz,
        xyz: trial.xyz.iter().map(|v| v[keep.clone()].to_vec()).collect(),
        valid: trial
            .valid
            .iter()
            .map(|v| v[keep.clone()].to_vec())
            .collect(),
    };
    let trial = &cut;
    let n = trial.frames();
    let g: Vec<(usize, usize)> = whole.iter().map(|&(m, a)| (m, a - keep.start)).collect();
    let mut valid = trial.valid.clone();
    for &(m, a) in &g {
        valid[m][a..a + len].iter_mut().for_each(|v| *v = false);
    }
    let steps = max_steps(&trial.xyz, &valid);
    let data = Data::new(&trial.xyz, &valid, &steps);
    cfg.methods
        .iter()
        .map(|&method| {
            let opts = FillOptions {
                method,
                max_gap: None,
                max_expected_error: None,
                ..cfg.fill.clone()
            };
            let mut e = Vec::new();
            let mut failed = 0;
            let mut recs = Vec::new();
            let gaps: Vec<Gap> = g
                .iter()
                .map(|&(m, a)| Gap {
                    marker: m,
                    first: a,
                    last: a + len - 1,
                    len,
                    at_start: a == 0,
                    at_end: a + len == n,
                })
                .collect();
            // The group filled together, as the pipeline fills a trial's gaps (into a copy:
            // the trial holds the truth).
            let mut xyz = trial.xyz.clone();
            let filled = fill_gaps(&mut xyz, &valid, &steps, &gaps, &opts, Vetting::AsMade);
            for ((&(m, a), gap), got) in g.iter().zip(&gaps).zip(filled) {
                match got {
                    (
                        Some(v),
                        FillOutcome::Filled {
                            expected_error,
                            method: chosen,
                            ..
                        },
                        diag,
                    ) => {
                        let errs: Vec<f64> = v
                            .iter()
                            .enumerate()
                            .map(|(i, p)| crate::fill::dist(*p, trial.xyz[m][a + i]))
                            .collect();
                        let t = Target {
                            m,
                            data,
                            hole: None,
                        };
                        recs.push(GapScore {
                            method,
                            gap_len: len,
                            marker: m,
                            first: a + keep.start,
                            mean: errs.iter().sum::<f64>() / errs.len().max(1) as f64,
                            max: errs.iter().copied().fold(0.0, f64::max),
                            expected: expected_error,
                            step_ratio: step_ratio(&t, Span::of(gap, data.frames), &v),
                            evidence: diag,
                            chosen: Some(chosen),
                        });
                        e.extend(errs);
                    }
                    _ => failed += 1,
                }
            }
            (e, failed, recs)
        })
        .collect()
}

/// How well expected errors match real ones over a set of filled gaps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Calibration {
    /// Gaps with an expected error.
    pub gaps: usize,
    /// Spearman rank correlation of expected and real mean error.
    pub spearman: f64,
    /// Share of gaps whose real error is within a factor 2 of the expected one.
    pub within_2x: f64,
    /// Share of gaps whose real error is above twice the expected one.
    pub over_confident: f64,
    /// Share of gaps whose real error is below half the expected one.
    pub under_confident: f64,
    /// Median of real / expected.
    pub median_ratio: f64,
}

/// Calibration of the gaps that carry an expected error. Real and expected errors below
/// `floor` (data units: the noise level, where a ratio means nothing) count as `floor`.
pub fn calibration(gaps: &[GapScore], floor: f64) -> Calibration {
    let pairs: Vec<(f64, f64)> = gaps
        .iter()
        .filter_map(|g| g.expected.map(|e| (e.max(floor), g.mean.max(floor))))
        .collect();
    let n = pairs.len();
    let share = |f: &dyn Fn(f64, f64) -> bool| {
        pairs.iter().filter(|&&(e, r)| f(e, r)).count() as f64 / n.max(1) as f64
    };
    let mut ratios: Vec<f64> = pairs.iter().map(|&(e, r)| r / e).collect();
    ratios.sort_by(f64::total_cmp);
    Calibration {
        gaps: n,
        spearman: spearman(&pairs),
        within_2x: share(&|e, r| r <= 2.0 * e && r >= 0.5 * e),
        over_confident: share(&|e, r| r > 2.0 * e),
        under_confident: share(&|e, r| r < 0.5 * e),
        median_ratio: signal::order::rank(&ratios, 1, 2).unwrap_or(f64::NAN),
    }
}

fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0;
        for &k in &idx[i..=j] {
            r[k] = avg;
        }
        i = j + 1;
    }
    r
}

fn spearman(pairs: &[(f64, f64)]) -> f64 {
    let n = pairs.len();
    if n < 2 {
        return f64::NAN;
    }
    let a = ranks(&pairs.iter().map(|p| p.0).collect::<Vec<_>>());
    let b = ranks(&pairs.iter().map(|p| p.1).collect::<Vec<_>>());
    let mean = (n - 1) as f64 / 2.0;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (x, y) = (a[i] - mean, b[i] - mean);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    sab / (saa * sbb).sqrt()
}
