//! What happened to one gap: filled (how, and how sure), or left and why.

use serde::Serialize;

use super::method::FillMethod;

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
    /// Every candidate fill has a step between consecutive frames above
    /// [`STEP_FACTOR`](super::step::STEP_FACTOR) times the marker's largest recorded step
    /// (`step_ratio`: the smallest such ratio).
    Implausible { step_ratio: f64 },
    /// The fill's expected error is above `max_expected_error` (both in the data's units).
    Uncertain {
        expected_error: f64,
        max_expected_error: f64,
    },
}

impl SkipReason {
    /// The reason's kind, without its figures: what reports count gaps left by.
    pub fn kind(self) -> SkipKind {
        match self {
            SkipReason::MethodNone => SkipKind::MethodNone,
            SkipReason::TooLong { .. } => SkipKind::TooLong,
            SkipReason::TouchesEdge => SkipKind::TouchesEdge,
            SkipReason::NoDonors => SkipKind::NoDonors,
            SkipReason::NoContext => SkipKind::NoContext,
            SkipReason::Degenerate => SkipKind::Degenerate,
            SkipReason::Implausible { .. } => SkipKind::Implausible,
            SkipReason::Uncertain { .. } => SkipKind::Uncertain,
        }
    }

    /// The reason's name as reports spell it (`no_donors`, `too_long`, …).
    pub fn name(self) -> &'static str {
        self.kind().name()
    }
}

/// Why a gap was left, as a kind: [`SkipReason`] without the figures each reason carries,
/// so that reports can count and compare reasons. Serialized as its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SkipKind {
    MethodNone,
    TooLong,
    TouchesEdge,
    NoDonors,
    NoContext,
    Degenerate,
    Implausible,
    Uncertain,
}

impl SkipKind {
    /// The kind's name as reports spell it (`no_donors`, `too_long`, …).
    pub fn name(self) -> &'static str {
        match self {
            SkipKind::MethodNone => "method_none",
            SkipKind::TooLong => "too_long",
            SkipKind::TouchesEdge => "touches_edge",
            SkipKind::NoDonors => "no_donors",
            SkipKind::NoContext => "no_context",
            SkipKind::Degenerate => "degenerate",
            SkipKind::Implausible => "implausible",
            SkipKind::Uncertain => "uncertain",
        }
    }
}

impl std::fmt::Display for SkipKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
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

impl FillOutcome {
    /// This outcome with `expected` as its expected error (when it is a fill).
    pub(super) fn with_expected_error(self, expected: Option<f64>) -> FillOutcome {
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

    /// A single method's fill as the method made it: no blend, no expected error.
    pub(super) fn single(method: FillMethod) -> FillOutcome {
        FillOutcome::Filled {
            method,
            blended_with: None,
            weight: None,
            blended_with_2: None,
            weight_2: None,
            blended_with_3: None,
            weight_3: None,
            expected_error: None,
            skeleton: false,
        }
    }
}

/// One method's fill of a span, or why it left it.
pub(crate) type Fill = std::result::Result<Vec<[f64; 3]>, SkipReason>;

#[cfg(test)]
mod tests {
    use super::*;

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
            assert_eq!(serde_json::to_value(r.kind()).unwrap(), r.name());
        }
    }
}
