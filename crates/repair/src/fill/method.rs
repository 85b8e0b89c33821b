//! The fill methods a repair can be asked for, and the families they fall in (polynomial,
//! donor). Their names are `names.rs`'s one table ([`FillMethod::NAMED`]).

use serde::{Deserialize, Serialize};

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

    /// Parses the snake_case name used in reports (`"lagrange5"`, `"pca"`, ...), exactly as
    /// spelled in [`FillMethod::NAMED`] (`FromStr` also takes any case).
    pub fn from_name(s: &str) -> Option<FillMethod> {
        FillMethod::NAMED
            .iter()
            .find(|(_, n)| *n == s)
            .map(|&(m, _)| m)
    }

    /// Whether the method predicts from donor markers (and so has a [`fill_raw`](super::fill_raw)).
    pub(crate) fn is_donor(self) -> bool {
        matches!(
            self,
            FillMethod::Rigid | FillMethod::Pattern | FillMethod::Pca | FillMethod::Kalman
        )
    }
}
