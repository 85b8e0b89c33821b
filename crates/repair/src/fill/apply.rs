//! One concrete method's fill of a span ([`fill_with`]) and a donor method's raw prediction
//! ([`fill_raw`]): the methods side by side, for `auto` to try and for a single method.

use super::anchor;
use super::data::{Span, Target};
use super::method::FillMethod;
use super::options::FillOptions;
use super::outcome::{Fill, SkipReason};
use super::plan::Plan;
use super::{gloersen, kalman, linear, pattern, pca, poly, rigid, spline};

/// Fills `span` of the target with one concrete method. `none` leaves it, and so does
/// `auto`, which is not one method: it chooses among these one layer up (see `dispatch`).
pub(crate) fn fill_with(
    method: FillMethod,
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
) -> Fill {
    match method {
        FillMethod::None | FillMethod::Auto => Err(SkipReason::MethodNone),
        FillMethod::Linear => linear::fill(t, span),
        FillMethod::Lagrange2 => poly::lagrange(t, span, 3),
        FillMethod::Lagrange5 => poly::lagrange(t, span, 6),
        FillMethod::Spline => spline::fill(t, span, opts.spline_context),
        FillMethod::Rigid | FillMethod::Pattern | FillMethod::Pca | FillMethod::Kalman => {
            fill_raw(method, t, span, plan, opts, 1).map(|r| r.anchored(span))
        }
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
        FillMethod::Pca => pca::raw(
            t,
            span,
            plan,
            &plan.subspace,
            &plan.pca_models,
            opts,
            per_side,
        ),
        FillMethod::Kalman => kalman::raw(
            t,
            span,
            plan,
            &plan.subspace,
            &plan.kalman_models,
            opts,
            per_side,
        ),
        _ => Err(SkipReason::NoDonors),
    }
}
