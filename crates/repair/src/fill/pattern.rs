//! Pattern fill: the straight line across the gap plus the donor's deviation from its own
//! straight line over the same frames. At a trial edge, the donor's path offset to meet the
//! target's one anchor.

use super::anchor::Raw;
use super::data::{Span, Target};
use super::donors::Donors;
use super::outcome::SkipReason;

/// The donor's path over the span, with residuals at up to `per_side` frames per side
/// (see [`Raw`]).
pub(super) fn raw(
    t: &Target,
    span: Span,
    plan: &Donors,
    per_side: usize,
) -> Result<Raw, SkipReason> {
    let d = t.data;
    let (lo, hi) = span.outer();
    let Some(j) = plan.pattern.filter(|&j| d.ok_through(j, lo, hi)) else {
        return Err(SkipReason::NoDonors);
    };
    Raw::gather(t, span, per_side, |f| d.ok(j, f).then(|| d.at(j, f))).ok_or(SkipReason::NoDonors)
}
