//! One gap's fill with the configured method: the rules that refuse it whatever the data
//! (`none`, `max_gap`, the edge rule), the donor plan, and the fill itself, either checked as a
//! repair writes it or as the method made it ([`Vetting`]).

use super::apply::fill_with;
use super::auto;
use super::data::{Data, Span, Target};
use super::method::FillMethod;
use super::options::FillOptions;
use super::outcome::{FillOutcome, SkipReason};
use super::plan::Plan;
use crate::gaps::Gap;

/// One gap's fill: the samples for `gap.first..=gap.last` (none when skipped), the
/// outcome, and for `auto` the evidence behind its expected error (for calibration).
pub(crate) type GapFill = (Option<Vec<[f64; 3]>>, FillOutcome, Option<auto::Diag>);

/// What a fill must pass before it is used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Vetting {
    /// Held to the step rule as the file will store it and to `max_expected_error`, with
    /// an expected error for `auto`: what a repair writes.
    Checked,
    /// A single method's fill as the method makes it, without the plausibility check or an
    /// expected error (evaluations of the methods themselves); `auto` is checked all the
    /// same.
    AsMade,
}

/// Fills one gap of marker `gap.marker` with the configured method, applying `max_gap` and
/// the edge rule, vetted as `vetting` says.
pub(crate) fn fill_gap_diag(
    data: Data,
    gap: &Gap,
    opts: &FillOptions,
    vetting: Vetting,
) -> GapFill {
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
    fill_planned(&t, span, &plan, opts, vetting)
}

/// Why the configured method leaves `gap` whatever the data (`None`: it may fill it).
pub(super) fn refused(gap: &Gap, opts: &FillOptions) -> Option<SkipReason> {
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
pub(super) fn fill_planned(
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
    vetting: Vetting,
) -> GapFill {
    match vetting {
        Vetting::AsMade if opts.method != FillMethod::Auto => as_made(t, span, plan, opts),
        _ => checked(t, span, plan, opts),
    }
}

/// The method's fill as it makes it (see [`Vetting::AsMade`]).
fn as_made(t: &Target, span: Span, plan: &Plan, opts: &FillOptions) -> GapFill {
    match fill_with(opts.method, t, span, plan, opts) {
        Ok(v) => (Some(v), FillOutcome::single(opts.method), None),
        Err(r) => (None, FillOutcome::Skipped(r), None),
    }
}

/// The method's fill (`auto`'s choice among its candidates) held to `max_expected_error`
/// and to the step rule as the file will store it.
fn checked(t: &Target, span: Span, plan: &Plan, opts: &FillOptions) -> GapFill {
    let skip = |r| (None, FillOutcome::Skipped(r), None);
    let single = [opts.method];
    let cands = if opts.method == FillMethod::Auto {
        auto::candidates(span)
    } else {
        &single
    };
    match auto::fill(t, span, plan, opts, cands) {
        Ok((v, choice)) => match (choice.expected_error, opts.max_expected_error) {
            (Some(e), Some(max)) if e > max => skip(SkipReason::Uncertain {
                expected_error: e,
                max_expected_error: max,
            }),
            // Fills are held to the step rule as the file will store them.
            _ => match auto::steps::as_stored(t, span, v, opts.storage) {
                Ok(v) => (Some(v), choice.outcome(), choice.diag),
                Err(r) => skip(SkipReason::Implausible { step_ratio: r }),
            },
        },
        Err(r) => skip(r),
    }
}
