//! Gap fill methods. Each method fills one span of one marker from data that is only read,
//! so markers can be filled in parallel and a method can be tried on artificial gaps
//! (see `FillMethod::Auto`) without copying the trial.

mod anchor;
mod auto;
mod gloersen;
mod kalman;
mod linear;
mod pattern;
mod pca;
mod plan;
mod poly;
mod rigid;
mod skeleton;
mod spline;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{RepairError, Result};
use crate::gaps::Gap;

pub(crate) use auto::features;
pub use auto::{calibrated, log_ratio, Diag, FEATURES};
pub(crate) use plan::Plan;

/// How gaps are filled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FillMethod {
    /// Leave every gap (still reported).
    None,
    Linear,
    /// Quadratic through the 3 valid samples nearest the gap, split across both sides.
    Lagrange2,
    /// Quintic through the 6 valid samples nearest the gap, split across both sides.
    Lagrange5,
    /// Not-a-knot cubic spline through up to `spline_context` valid samples per side.
    Spline,
    /// Rigid-body fill from donor markers that keep their distances to the target.
    Rigid,
    /// The best-correlated donor's shape added to the straight line across the gap.
    Pattern,
    /// Distance-weighted PCA reconstruction (Gløersen & Federolf 2016).
    Pca,
    /// The marker and its PCA neighbours' component scores Kalman-smoothed through the gap
    /// (Burke & Lasenby 2016).
    Kalman,
    /// Per gap, the best method (or blend of up to three) judged on artificial gaps.
    Auto,
    /// Gløersen & Federolf's PCA exactly as published: the whole trial, every marker, their
    /// distance weighting and reconstruction, no tie to the anchors (see `gloersen`).
    Gloersen,
    /// The one valid sample next to a gap at the trial's edge, held: `auto`'s last resort
    /// there when every donor fill moves the marker implausibly fast.
    Hold,
}

impl FillMethod {
    /// Every method that fills, for evaluations.
    pub const ALL: [FillMethod; 9] = [
        FillMethod::Linear,
        FillMethod::Lagrange2,
        FillMethod::Lagrange5,
        FillMethod::Spline,
        FillMethod::Rigid,
        FillMethod::Pattern,
        FillMethod::Pca,
        FillMethod::Kalman,
        FillMethod::Auto,
    ];

    /// Whether the method only uses the target's own samples (and so extrapolates a
    /// polynomial at the trial's ends).
    pub fn is_polynomial(self) -> bool {
        matches!(
            self,
            FillMethod::Linear | FillMethod::Lagrange2 | FillMethod::Lagrange5 | FillMethod::Spline
        )
    }

    /// Parses the snake_case name used in reports (`"lagrange5"`, `"pca"`, ...).
    pub fn from_name(s: &str) -> Option<FillMethod> {
        Some(match s {
            "none" => FillMethod::None,
            "linear" => FillMethod::Linear,
            "lagrange2" => FillMethod::Lagrange2,
            "lagrange5" => FillMethod::Lagrange5,
            "spline" => FillMethod::Spline,
            "rigid" => FillMethod::Rigid,
            "pattern" => FillMethod::Pattern,
            "pca" => FillMethod::Pca,
            "kalman" => FillMethod::Kalman,
            "auto" => FillMethod::Auto,
            "hold" => FillMethod::Hold,
            "gloersen" => FillMethod::Gloersen,
            _ => return None,
        })
    }
}

/// Fill settings. Defaults: `auto`, gaps up to 200 frames, 10 spline samples per side,
/// 3 rigid donors, 8 PCA neighbours, 99.9 % PCA variance, PCA window ±max(250, 5×gap),
/// 8 artificial gaps per `auto` choice.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FillOptions {
    pub method: FillMethod,
    /// Longer gaps are left and reported; `None` fills any length.
    pub max_gap: Option<usize>,
    /// Valid samples per side the spline is fitted through. 6 instead of 10 was chosen in
    /// 17 of 26 folds of `fill_eval --nested` with every cell within 1 % of 10's (a tie:
    /// `auto` seldom leans on the spline where the two differ); 10 stays, as it is also the
    /// single `spline` method's, which that choice did not measure.
    pub spline_context: usize,
    /// Donor markers per rigid fill (at least 3). 3 instead of 4 was chosen in 26 of 26
    /// folds of `fill_eval --nested` (`auto`'s held-apart cells 6 % better to 4 % worse,
    /// tuned ones up to 15 % better at 80 frames on full body): the three donors that move
    /// most rigidly with the target carry it better than a fourth that averages noise in
    /// but moves less with it.
    pub rigid_donors: usize,
    /// Nearest markers the PCA model uses besides the target (at least 2). 12 instead of
    /// 8 was chosen in 0 of 26 folds of `fill_eval --nested` (`auto`'s held-apart cells at
    /// 40 and 80 frames 5 % better to 10 % worse, seven of eight worse).
    pub pca_neighbours: usize,
    /// Fraction of the (weighted) variance the kept principal components explain. 0.99
    /// instead of 0.999 was chosen in 0 of 26 folds (cells 7 % better to 22 % worse).
    pub pca_variance: f64,
    /// Minimum half-width of the PCA training window in frames (the window is
    /// ±max(pca_window, 5 × gap length) around the gap). ±500 instead of ±250 was chosen
    /// in 0 of 26 folds (cells 4 % better to 6 % worse).
    pub pca_window: usize,
    /// Artificial gaps `auto` scores candidates on per gap (half as many for gaps shorter
    /// than `auto`'s LONG, 5 frames: every gap the evaluation measures gets all of them).
    /// 8 instead of 6 was chosen in 26 of 26 folds of `fill_eval --nested` (held-apart
    /// cells 5.5 % better to 3.5 % worse, tuned ones 4.7 % better to 5.2 % worse), 4
    /// instead of 6 in 0 of 26 (cells 8 % better to 12 % worse, 31 of 40 worse); 10 chose
    /// no better on the gait trials of an earlier evaluation, at 1.25× the cost.
    pub auto_trials: usize,
    /// Gaps whose expected error (in the data's units) is above this are left unfilled
    /// and reported as `uncertain`; `None` fills every gap a method can fill.
    pub max_expected_error: Option<f64>,
    /// How the file will store the fills: every fill is held to the step rule (see
    /// [`STEP_FACTOR`]) as stored, since rounding can take a fill checked at the limit above
    /// it. A property of the file, not a setting, so it is not reported.
    #[serde(skip)]
    pub storage: Storage,
    /// Millimetres per unit of the data (the published PCA's distance weighting is in mm).
    #[serde(skip)]
    pub mm_per_unit: f64,
}

/// How coordinates are stored: exactly (in memory), as 32-bit floats, or as integers times
/// a scale (an integer C3D file's POINT:SCALE, in the data's units).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Storage {
    #[default]
    Exact,
    Float32,
    Integer {
        scale: f32,
    },
}

impl Storage {
    /// `p` as stored and read back: rounded to the nearest 32-bit float, then for integer
    /// storage to the nearest multiple of the scale (as the C3D writer rounds x / scale).
    pub fn stored(self, p: [f64; 3]) -> [f64; 3] {
        match self {
            Storage::Exact => p,
            Storage::Float32 => p.map(|x| f64::from(x as f32)),
            Storage::Integer { scale } if scale > 0.0 => {
                p.map(|x| f64::from((x as f32 / scale).round() * scale))
            }
            Storage::Integer { .. } => p.map(|x| f64::from(x as f32)),
        }
    }
}

impl Default for FillOptions {
    fn default() -> Self {
        FillOptions {
            method: FillMethod::Auto,
            max_gap: Some(200),
            spline_context: 10,
            rigid_donors: 3,
            pca_neighbours: 8,
            pca_variance: 0.999,
            pca_window: 250,
            auto_trials: 8,
            max_expected_error: None,
            storage: Storage::Exact,
            mm_per_unit: 1.0,
        }
    }
}

impl FillOptions {
    /// Rejects settings no fill could work with.
    pub fn validate(&self) -> Result<()> {
        let bad = |s: &str| Err(RepairError::Option(s.to_string()));
        if self.max_gap == Some(0) {
            return bad("max_gap must be at least 1 frame");
        }
        if self.spline_context < 1 {
            return bad("spline_context must be at least 1");
        }
        if self.rigid_donors < 3 {
            return bad("rigid_donors must be at least 3");
        }
        if self.pca_neighbours < 2 {
            return bad("pca_neighbours must be at least 2");
        }
        if !(self.pca_variance > 0.0 && self.pca_variance <= 1.0) {
            return bad("pca_variance must be in (0, 1]");
        }
        if self.auto_trials < 1 {
            return bad("auto_trials must be at least 1");
        }
        if self
            .max_expected_error
            .is_some_and(|e| !(e > 0.0 && e.is_finite()))
        {
            return bad("max_expected_error must be a positive number");
        }
        Ok(())
    }
}

impl FillOutcome {
    /// This outcome with `expected` as its expected error (when it is a fill).
    fn with_expected_error(self, expected: Option<f64>) -> FillOutcome {
        match self {
            FillOutcome::Filled {
                method,
                blended_with,
                weight,
                blended_with_2,
                weight_2,
                blended_with_3,
                weight_3,
                skeleton,
                ..
            } => FillOutcome::Filled {
                method,
                blended_with,
                weight,
                blended_with_2,
                weight_2,
                blended_with_3,
                weight_3,
                expected_error: expected,
                skeleton,
            },
            o => o,
        }
    }
}

/// Why a gap was left unfilled.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum SkipReason {
    /// The method is `none`.
    MethodNone,
    /// Longer than `max_gap` frames.
    TooLong { max_gap: usize },
    /// Touches the trial's start or end and the method would extrapolate a polynomial.
    TouchesEdge,
    /// Not enough donor markers valid through the gap.
    NoDonors,
    /// Not enough valid samples around the gap to fit or to train on.
    NoContext,
    /// A linear system was singular.
    Degenerate,
    /// Every candidate fill has a step between consecutive frames above [`STEP_FACTOR`]
    /// times the marker's largest recorded step (`step_ratio`: the smallest such ratio).
    Implausible { step_ratio: f64 },
    /// The fill's expected error is above `max_expected_error` (both in the data's units).
    Uncertain {
        expected_error: f64,
        max_expected_error: f64,
    },
}

impl SkipReason {
    /// The reason's name as reports spell it (`no_donors`, `too_long`, …).
    pub fn name(self) -> &'static str {
        match self {
            SkipReason::MethodNone => "method_none",
            SkipReason::TooLong { .. } => "too_long",
            SkipReason::TouchesEdge => "touches_edge",
            SkipReason::NoDonors => "no_donors",
            SkipReason::NoContext => "no_context",
            SkipReason::Degenerate => "degenerate",
            SkipReason::Implausible { .. } => "implausible",
            SkipReason::Uncertain { .. } => "uncertain",
        }
    }
}

/// What happened to one gap.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum FillOutcome {
    Filled {
        method: FillMethod,
        /// `auto` only: the second method blended in, with `weight` its share.
        #[serde(skip_serializing_if = "Option::is_none")]
        blended_with: Option<FillMethod>,
        #[serde(skip_serializing_if = "Option::is_none")]
        weight: Option<f64>,
        /// `auto` only: a third method blended in, with `weight_2` its share.
        #[serde(skip_serializing_if = "Option::is_none")]
        blended_with_2: Option<FillMethod>,
        #[serde(skip_serializing_if = "Option::is_none")]
        weight_2: Option<f64>,
        /// `auto` only: a fourth method blended in, with `weight_3` its share. `method`,
        /// with any further methods of smaller share, has what the listed weights leave.
        #[serde(skip_serializing_if = "Option::is_none")]
        blended_with_3: Option<FillMethod>,
        #[serde(skip_serializing_if = "Option::is_none")]
        weight_3: Option<f64>,
        /// Expected mean 3D error of the fill (data units), from the same fill's errors on
        /// artificial gaps nearby, calibrated on real trials (see `auto`).
        #[serde(skip_serializing_if = "Option::is_none")]
        expected_error: Option<f64>,
        /// The fill was held to the skeleton: each distance to a neighbouring marker
        /// within the interval it spans in the recorded data (long gaps, when that scored
        /// better on the artificial gaps).
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        skeleton: bool,
    },
    Skipped(SkipReason),
}

/// The trial's data as the fill methods read it.
#[derive(Clone, Copy)]
pub(crate) struct Data<'a> {
    pub xyz: &'a [Vec<[f64; 3]>],
    pub valid: &'a [Vec<bool>],
    pub frames: usize,
    /// Per marker, its largest step between consecutive valid frames ([`max_steps`]):
    /// no fill may move the marker faster than its own recorded data does.
    pub max_step: &'a [f64],
    /// One marker's validity read from here instead of `valid` (see [`fill_gaps`]: the
    /// target as recorded, among neighbours whose first-pass fills count as samples).
    own: Option<(usize, &'a [bool])>,
    /// The published PCA's whole-trial models of this data, shared by the pass's gaps.
    gloersen: Option<&'a gloersen::Cache>,
}

/// Per marker, the largest distance between two consecutive valid samples (0 without any
/// such pair). Fills are held to [`STEP_FACTOR`] times this.
pub(crate) fn max_steps(xyz: &[Vec<[f64; 3]>], valid: &[Vec<bool>]) -> Vec<f64> {
    xyz.iter()
        .zip(valid)
        .map(|(x, v)| {
            let mut m = 0.0f64;
            for f in 1..x.len().min(v.len()) {
                if v[f] && v[f - 1] {
                    m = m.max(dist(x[f], x[f - 1]));
                }
            }
            m
        })
        .collect()
}

/// A fill step between consecutive frames above this many times the marker's largest
/// recorded step makes the fill implausible (issue 10).
pub const STEP_FACTOR: f64 = 1.5;

pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The largest step of `fill` (frames `span.first..`) including the joins to the anchors,
/// as a multiple of the marker's largest recorded step (0 when it has none recorded).
pub(crate) fn step_ratio(t: &Target, span: Span, fill: &[[f64; 3]]) -> f64 {
    let limit = t.data.max_step[t.m];
    if limit <= 0.0 || fill.is_empty() {
        return 0.0;
    }
    let mut worst = 0.0f64;
    for w in fill.windows(2) {
        worst = worst.max(dist(w[0], w[1]));
    }
    if let Some(b) = span.before.filter(|&f| t.ok(f)) {
        worst = worst.max(dist(t.at(b), fill[0]));
    }
    if let Some(a) = span.after.filter(|&f| t.ok(f)) {
        worst = worst.max(dist(fill[fill.len() - 1], t.at(a)));
    }
    worst / limit
}

impl<'a> Data<'a> {
    pub fn new(xyz: &'a [Vec<[f64; 3]>], valid: &'a [Vec<bool>], max_step: &'a [f64]) -> Self {
        let frames = xyz.first().map_or(0, Vec::len);
        Data {
            xyz,
            valid,
            frames,
            max_step,
            own: None,
            gloersen: None,
        }
    }

    /// The same data with the published PCA's models kept in `cache` (which must not
    /// outlive this data: the models are of it).
    fn with_gloersen(self, cache: &'a gloersen::Cache) -> Self {
        Data {
            gloersen: Some(cache),
            ..self
        }
    }

    /// The same data with marker `m`'s validity taken from `own`.
    fn with_own(self, m: usize, own: &'a [bool]) -> Self {
        Data {
            own: Some((m, own)),
            ..self
        }
    }

    #[inline]
    fn row(&self, m: usize) -> &'a [bool] {
        match self.own {
            Some((o, v)) if o == m => v,
            _ => &self.valid[m],
        }
    }

    #[inline]
    pub fn ok(&self, m: usize, f: usize) -> bool {
        self.row(m)[f]
    }

    #[inline]
    pub fn at(&self, m: usize, f: usize) -> [f64; 3] {
        self.xyz[m][f]
    }

    /// Whether marker `m` is valid on every frame of `lo..=hi`.
    pub fn ok_through(&self, m: usize, lo: usize, hi: usize) -> bool {
        self.row(m)[lo..=hi].iter().all(|&v| v)
    }
}

/// The marker being filled, possibly with an extra artificial hole (frames treated as
/// invalid) used when `auto` scores methods on data whose truth is known.
#[derive(Clone, Copy)]
pub(crate) struct Target<'a> {
    pub m: usize,
    pub data: Data<'a>,
    pub hole: Option<(usize, usize)>,
}

impl Target<'_> {
    #[inline]
    pub fn ok(&self, f: usize) -> bool {
        self.data.ok(self.m, f) && !self.hole.is_some_and(|(a, b)| f >= a && f <= b)
    }

    #[inline]
    pub fn at(&self, f: usize) -> [f64; 3] {
        self.data.at(self.m, f)
    }

    /// Up to `k` valid frames before `first`, nearest first.
    pub fn before(&self, first: usize, k: usize) -> Vec<usize> {
        (0..first).rev().filter(|&f| self.ok(f)).take(k).collect()
    }

    /// Up to `k` valid frames after `last`, nearest first.
    pub fn after(&self, last: usize, k: usize) -> Vec<usize> {
        (last + 1..self.data.frames)
            .filter(|&f| self.ok(f))
            .take(k)
            .collect()
    }
}

/// The frames to fill, inclusive, and the anchors just outside (valid target samples).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Span {
    pub first: usize,
    pub last: usize,
    pub before: Option<usize>,
    pub after: Option<usize>,
}

impl Span {
    pub fn new(first: usize, last: usize, frames: usize) -> Span {
        Span {
            first,
            last,
            before: first.checked_sub(1),
            after: (last + 1 < frames).then_some(last + 1),
        }
    }

    pub fn of(gap: &Gap, frames: usize) -> Span {
        Span::new(gap.first, gap.last, frames)
    }

    pub fn len(&self) -> usize {
        self.last - self.first + 1
    }

    /// First and last frame including the anchors that exist.
    pub fn outer(&self) -> (usize, usize) {
        (
            self.before.unwrap_or(self.first),
            self.after.unwrap_or(self.last),
        )
    }
}

type Fill = std::result::Result<Vec<[f64; 3]>, SkipReason>;

/// Fills `span` of the target with one concrete method (not `auto`/`none`).
pub(crate) fn fill_with(
    method: FillMethod,
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
) -> Fill {
    match method {
        FillMethod::None => Err(SkipReason::MethodNone),
        FillMethod::Linear => linear::fill(t, span),
        FillMethod::Lagrange2 => poly::lagrange(t, span, 3),
        FillMethod::Lagrange5 => poly::lagrange(t, span, 6),
        FillMethod::Spline => spline::fill(t, span, opts.spline_context),
        FillMethod::Rigid | FillMethod::Pattern | FillMethod::Pca | FillMethod::Kalman => {
            fill_raw(method, t, span, plan, opts, 1).map(|r| r.anchored(span))
        }
        FillMethod::Auto => auto::fill(t, span, plan, opts, auto::candidates(span)).map(|(v, _)| v),
        FillMethod::Hold => linear::hold(t, span),
        FillMethod::Gloersen => gloersen::fill(t, span, plan, opts.mm_per_unit),
    }
}

/// A donor method's raw prediction of `span` with residuals at up to `per_side` valid
/// frames on each side (see [`anchor::Raw`]); `NoDonors` for methods that use no donors.
pub(crate) fn fill_raw(
    method: FillMethod,
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
    per_side: usize,
) -> std::result::Result<anchor::Raw, SkipReason> {
    match method {
        FillMethod::Rigid => rigid::raw(t, span, plan, per_side),
        FillMethod::Pattern => pattern::raw(t, span, plan, per_side),
        FillMethod::Pca => pca::raw(t, span, plan, opts, per_side),
        FillMethod::Kalman => kalman::raw(t, span, plan, opts, per_side),
        _ => Err(SkipReason::NoDonors),
    }
}

impl FillMethod {
    /// Whether the method predicts from donor markers (and so has a [`fill_raw`]).
    pub(crate) fn is_donor(self) -> bool {
        matches!(
            self,
            FillMethod::Rigid | FillMethod::Pattern | FillMethod::Pca | FillMethod::Kalman
        )
    }
}

/// One gap's fill: the samples for `gap.first..=gap.last` (none when skipped), the
/// outcome, and for `auto` the evidence behind its expected error (for calibration).
pub(crate) type GapFill = (Option<Vec<[f64; 3]>>, FillOutcome, Option<auto::Diag>);

/// Fills one gap of marker `gap.marker` with the configured method, applying `max_gap` and
/// the edge rule. With `checked` false a single method's fill is returned as the method
/// makes it, without the plausibility check or an expected error (evaluations of the
/// methods themselves); `auto` is always checked.
pub(crate) fn fill_gap_diag(data: Data, gap: &Gap, opts: &FillOptions, checked: bool) -> GapFill {
    if let Some(r) = refused(gap, opts) {
        return (None, FillOutcome::Skipped(r), None);
    }
    let t = Target {
        m: gap.marker,
        data,
        hole: None,
    };
    let span = Span::of(gap, data.frames);
    let plan = if opts.method.is_polynomial() {
        Plan::empty(span)
    } else {
        Plan::build(&t, span, opts)
    };
    fill_planned(&t, span, &plan, opts, checked)
}

/// Why the configured method leaves `gap` whatever the data (`None`: it may fill it).
fn refused(gap: &Gap, opts: &FillOptions) -> Option<SkipReason> {
    if opts.method == FillMethod::None {
        return Some(SkipReason::MethodNone);
    }
    if let Some(max) = opts.max_gap {
        if gap.len > max {
            return Some(SkipReason::TooLong { max_gap: max });
        }
    }
    if gap.touches_edge() && opts.method.is_polynomial() {
        return Some(SkipReason::TouchesEdge);
    }
    if gap.at_start && gap.at_end {
        return Some(SkipReason::NoContext);
    }
    None
}

/// The configured method's fill of `span` with donors from `plan`.
fn fill_planned(t: &Target, span: Span, plan: &Plan, opts: &FillOptions, checked: bool) -> GapFill {
    let skip = |r| (None, FillOutcome::Skipped(r), None);
    let single = [opts.method];
    let cands = if opts.method == FillMethod::Auto {
        auto::candidates(span)
    } else {
        &single
    };
    let checked = checked || opts.method == FillMethod::Auto;
    match auto::fill_checked(t, span, plan, opts, cands, checked) {
        Ok((v, choice)) => match (choice.expected_error, opts.max_expected_error) {
            (Some(e), Some(max)) if e > max => skip(SkipReason::Uncertain {
                expected_error: e,
                max_expected_error: max,
            }),
            // Checked fills are held to the step rule as the file will store them; single
            // methods in evaluations are measured as the method made them.
            _ if checked => match auto::steps::as_stored(t, span, v, opts.storage) {
                Ok(v) => (Some(v), choice.outcome(), choice.diag),
                Err(r) => skip(SkipReason::Implausible { step_ratio: r }),
            },
            _ => (Some(v), choice.outcome(), choice.diag),
        },
        Err(r) => skip(r),
    }
}

/// A gap is filled again when one of its this many nearest PCA neighbours is a marker
/// filled near it. On the corpus evaluation 2 kept the gains of refilling whenever any donor
/// was filled (2–3 markers missing together, every rate within 2 %; 1 lost up to 30 % of
/// them), and on the pipeline bench (independent random gaps) it refills a sixth of the
/// gaps instead of most: the nearest markers carry most of the weight, and many far donors
/// are filled somewhere near a gap.
const REFILL_NEAREST: usize = 2;

/// Fills `gaps` (of any markers; each gap one of its marker's) in two passes, each pass's
/// fills read from the data as the pass found it, and writes every fill into `xyz` (the
/// samples are also returned; `valid` is left to the caller, who knows what it means).
/// Occlusions often hide several neighbouring markers over overlapping frames, and each
/// then loses its nearest donors to the others for the whole gap, though they are missing
/// only part of it. So after the first pass every gap is planned again with the other
/// markers' first-pass fills counted as samples (the target's own samples stay as
/// recorded, so `auto` still scores on recorded truth only), and filled again when one of
/// its nearest donors now is a marker filled near it. On the corpus evaluation
/// (`fill_eval`) this took 10–25 % off `auto`'s errors on 2–3 neighbouring markers missing
/// together. The first pass's fills are written into `xyz` rather than into a copy, so the
/// second pass costs no second copy of the trial.
pub(crate) fn fill_gaps(
    xyz: &mut [Vec<[f64; 3]>],
    valid: &[Vec<bool>],
    max_step: &[f64],
    gaps: &[Gap],
    opts: &FillOptions,
    checked: bool,
) -> Vec<GapFill> {
    let write = |xyz: &mut [Vec<[f64; 3]>], fills: &[GapFill]| {
        for (g, r) in gaps.iter().zip(fills) {
            if let Some(v) = &r.0 {
                xyz[g.marker][g.first..=g.last].copy_from_slice(v);
            }
        }
    };
    // Each pass's data has its own published-PCA models (see `gloersen::Cache`).
    let (cache1, cache2) = (gloersen::Cache::default(), gloersen::Cache::default());
    let data = Data::new(xyz, valid, max_step).with_gloersen(&cache1);
    let first: Vec<GapFill> = gaps
        .par_iter()
        .map(|g| {
            let _time = crate::profile::gap(g.len);
            fill_gap_diag(data, g, opts, checked)
        })
        .collect();
    write(xyz, &first);
    if !(opts.method.is_donor() || opts.method == FillMethod::Auto) {
        return first;
    }
    // Per marker, the frames the first pass filled and the fills' scores on their artificial
    // gaps (the raw evidence, not the calibrated estimate, which is fitted with it).
    let mut filled: Vec<Vec<(usize, usize, Option<f64>)>> = vec![Vec::new(); xyz.len()];
    for (g, r) in gaps.iter().zip(&first) {
        if r.0.is_some() {
            filled[g.marker].push((g.first, g.last, r.2.map(|d| d.scored)));
        }
    }
    if filled.iter().all(Vec::is_empty) {
        return first;
    }
    // Whether one of the gap's nearest donors now is a marker filled near it and recorded
    // on some frame of the gap (a neighbour missing all through the gap adds only its fill,
    // made without the target: on the corpus evaluation, refilling for it changed no cell
    // by more than 1.5 %, and it is a sixth of the refills on the pipeline bench).
    let near_filled = |plan: &Plan, span: Span| {
        let (lo, hi) = span.outer();
        plan.pca.iter().take(REFILL_NEAREST).any(|&(j, _)| {
            filled[j].iter().any(|&(a, b, _)| a <= hi && b >= lo)
                && valid[j][span.first..=span.last].contains(&true)
        })
    };
    let mut valid2 = valid.to_vec();
    for (m, ranges) in filled.iter().enumerate() {
        for &(a, b, _) in ranges {
            valid2[m][a..=b].fill(true);
        }
    }
    let second = Data::new(xyz, &valid2, max_step).with_gloersen(&cache2);
    let out: Vec<GapFill> = gaps
        .par_iter()
        .zip(first)
        .map(|(g, r)| {
            // A gap too uncertain to fill stays so: its estimate is the first pass's.
            let uncertain = matches!(r.1, FillOutcome::Skipped(SkipReason::Uncertain { .. }));
            if uncertain || refused(g, opts).is_some() {
                return r;
            }
            let _time = crate::profile::gap(g.len);
            let t = Target {
                m: g.marker,
                data: second.with_own(g.marker, &valid[g.marker]),
                hole: None,
            };
            let span = Span::of(g, second.frames);
            let plan = Plan::build(&t, span, opts);
            if !near_filled(&plan, span) {
                return r;
            }
            match (fill_planned(&t, span, &plan, opts, checked), r) {
                // The expected error is the first pass's evidence, marked as refilled (the
                // calibration learns how much better a refill does than that evidence
                // says): the second pass's own artificial gaps are scored with recorded
                // donors where the real gap has filled ones, so its own estimate is
                // over-confident (on the corpus evaluation, 10 % of gaps above twice
                // their estimate instead of 5 %).
                // A refill whose estimate is above `max_expected_error` (it leans on fills
                // less sure than the recorded donors of the first pass) gives way to the
                // first pass's fill, which its estimate vouched for.
                // A gap the first pass could not fill keeps the second pass's own.
                ((Some(v), again, own), (v1, first, diag)) => match (&first, diag) {
                    (FillOutcome::Filled { .. }, Some(d1)) => {
                        let (donor_err, share) = filled_donors(&plan, g, &filled, valid);
                        let d = auto::Diag {
                            refilled: true,
                            donor_err: donor_err.map(|e| e / d1.scored.max(1e-12)),
                            share,
                            rescored: own.map(|o| o.scored / d1.scored.max(1e-12)),
                            respread: own.map(|o| o.spread / d1.spread.max(1e-12)),
                            // The fill written is the second pass's.
                            slowed: own.map_or(d1.slowed, |o| o.slowed),
                            ..d1
                        };
                        let e = auto::calibrated(&d);
                        if opts.max_expected_error.is_some_and(|max| e > max) {
                            (v1, first, Some(d1))
                        } else {
                            (Some(v), again.with_expected_error(Some(e)), Some(d))
                        }
                    }
                    (FillOutcome::Filled { expected_error, .. }, None) => {
                        (Some(v), again.with_expected_error(*expected_error), None)
                    }
                    _ => (Some(v), again, own),
                },
                (_, r) => r,
            }
        })
        .collect();
    write(xyz, &out);
    out
}

/// What a refilled gap leans on: the largest first-pass score (mean error on artificial
/// gaps) among the fills of its nearest donors that overlap it, and the largest share of
/// its frames where one of those donors is not recorded (so is a fill).
fn filled_donors(
    plan: &Plan,
    g: &Gap,
    filled: &[Vec<(usize, usize, Option<f64>)>],
    valid: &[Vec<bool>],
) -> (Option<f64>, Option<f64>) {
    let (mut err, mut share) = (None::<f64>, None::<f64>);
    let n = (g.last - g.first + 1) as f64;
    for &(j, _) in plan.pca.iter().take(REFILL_NEAREST) {
        for &(a, b, e) in &filled[j] {
            if let (true, Some(e)) = (a <= g.last && b >= g.first, e) {
                err = Some(err.map_or(e, |x| x.max(e)));
            }
        }
        let missing = valid[j][g.first..=g.last].iter().filter(|v| !**v).count() as f64 / n;
        share = Some(share.map_or(missing, |x| x.max(missing)));
    }
    (err, share)
}

#[cfg(test)]
pub(crate) mod test_util {
    use super::*;

    /// A one-marker-or-more trial with marker 0's frames `first..=last` invalid.
    pub fn with_gap(
        mut xyz: Vec<Vec<[f64; 3]>>,
        first: usize,
        last: usize,
    ) -> (Vec<Vec<[f64; 3]>>, Vec<Vec<bool>>) {
        let n = xyz[0].len();
        let mut valid = vec![vec![true; n]; xyz.len()];
        for f in first..=last {
            valid[0][f] = false;
            xyz[0][f] = [f64::NAN; 3];
        }
        (xyz, valid)
    }

    /// Fills marker 0's gap `first..=last` with `method` and returns the fill.
    pub fn fill(
        xyz: &[Vec<[f64; 3]>],
        valid: &[Vec<bool>],
        first: usize,
        last: usize,
        method: FillMethod,
    ) -> Fill {
        let steps = max_steps(xyz, valid);
        let data = Data::new(xyz, valid, &steps);
        let t = Target {
            m: 0,
            data,
            hole: None,
        };
        let span = Span::new(first, last, data.frames);
        let opts = FillOptions::default();
        let plan = Plan::build(&t, span, &opts);
        fill_with(method, &t, span, &plan, &opts)
    }

    pub fn max_err(fill: &[[f64; 3]], truth: impl Fn(usize) -> [f64; 3], first: usize) -> f64 {
        fill.iter()
            .enumerate()
            .map(|(i, p)| {
                let q = truth(first + i);
                ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
            })
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two neighbouring markers missing over overlapping frames: the second pass fills each
    /// with the other's first-pass fill as a donor, closer to the truth than the first
    /// pass (which had to do without its nearest marker), and its expected error comes from
    /// the first pass's evidence, marked as refilled.
    #[test]
    fn second_pass_uses_a_co_missing_neighbour() {
        let trial = crate::synth::gait_like(24, 8, 2000, 100.0, 0.3, 7);
        // The marker nearest marker 0 (the synthetic segments are round-robin: 8 apart).
        let mean_dist = |j: usize| {
            (0..2000)
                .map(|f| dist(trial.xyz[0][f], trial.xyz[j][f]))
                .sum::<f64>()
        };
        let near = (1..24)
            .min_by(|&a, &b| mean_dist(a).total_cmp(&mean_dist(b)))
            .unwrap();
        // Gaps of 20 frames, overlapping by 10. On this clean synthetic trial the published
        // PCA and (from 40 frames) the Kalman smoother bridge the co-missing neighbour in the
        // first pass already from 30 frames (30 frames: 0.583 mm first, 0.586 mm refilled;
        // 20 frames: 0.574 and 0.528 mm first, 0.568 and 0.513 refilled).
        let mut valid = trial.valid.clone();
        let gaps = [(0, 1000), (near, 1010)].map(|(m, a)| {
            valid[m][a..a + 20].fill(false);
            Gap {
                marker: m,
                first: a,
                last: a + 19,
                len: 20,
                at_start: false,
                at_end: false,
            }
        });
        let steps = max_steps(&trial.xyz, &valid);
        let data = Data::new(&trial.xyz, &valid, &steps);
        let opts = FillOptions::default();
        let mut xyz = trial.xyz.clone();
        let err = |g: &Gap, v: &[[f64; 3]]| {
            v.iter()
                .enumerate()
                .map(|(i, p)| dist(*p, trial.xyz[g.marker][g.first + i]))
                .sum::<f64>()
                / v.len() as f64
        };
        let both = fill_gaps(&mut xyz, &valid, &steps, &gaps, &opts, true);
        for (g, (v, outcome, diag)) in gaps.iter().zip(&both) {
            let v = v.as_ref().unwrap();
            assert_eq!(&xyz[g.marker][g.first..=g.last], &v[..]);
            let (alone, first, _) = fill_gap_diag(data, g, &opts, true);
            let (a, b) = (err(g, &alone.unwrap()), err(g, v));
            assert!(b < a, "marker {}: {b} not below {a}", g.marker);
            let expected = |o: &FillOutcome| match o {
                FillOutcome::Filled { expected_error, .. } => *expected_error,
                FillOutcome::Skipped(_) => None,
            };
            // The first pass's evidence, marked as refilled, with the second pass's score.
            let diag = diag.expect("auto's evidence");
            assert!(diag.refilled && diag.rescored.is_some());
            assert!(expected(&first).is_some());
            assert_eq!(expected(outcome), Some(auto::calibrated(&diag)));
        }
    }

    #[test]
    fn skip_reason_names_are_the_serialized_tags() {
        for r in [
            SkipReason::MethodNone,
            SkipReason::TooLong { max_gap: 3 },
            SkipReason::TouchesEdge,
            SkipReason::NoDonors,
            SkipReason::NoContext,
            SkipReason::Degenerate,
            SkipReason::Implausible { step_ratio: 2.0 },
            SkipReason::Uncertain {
                expected_error: 9.0,
                max_expected_error: 5.0,
            },
        ] {
            let v = serde_json::to_value(r).unwrap();
            assert_eq!(v["reason"], r.name());
        }
    }
}
