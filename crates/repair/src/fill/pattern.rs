//! Pattern fill: the straight line across the gap plus the donor's deviation from its own
//! straight line over the same frames. At a trial edge, the donor's path offset to meet the
//! target's one anchor.

use super::{blend_edges, Fill, Plan, SkipReason, Span, Target};

pub(super) fn fill(t: &Target, span: Span, plan: &Plan) -> Fill {
    let d = t.data;
    let (lo, hi) = span.outer();
    let Some(j) = plan.pattern.filter(|&j| d.ok_through(j, lo, hi)) else {
        return Err(SkipReason::NoDonors);
    };
    let mut out: Vec<[f64; 3]> = (span.first..=span.last).map(|f| d.at(j, f)).collect();
    let pb = span.before.map(|f| d.at(j, f));
    let pa = span.after.map(|f| d.at(j, f));
    blend_edges(&mut out, t, span, pb, pa);
    Ok(out)
}
