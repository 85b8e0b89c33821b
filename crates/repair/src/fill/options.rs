//! Fill settings, checked once, and how the file will store the fills.

use serde::Serialize;

use super::method::FillMethod;
#[cfg(doc)]
use super::step::STEP_FACTOR;
use crate::error::{RepairError, Result};

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
