//! Real unlabelled samples put into a labelled marker's gap by `label` only where
//! reclaiming's path check accepts them (docs/label.md): in a partly labelled trial, the
//! template's distances alone cannot tell a marker's own return from a nearby point, while
//! the marker's position and velocity at the gap's ends can.

use repair::label::{FragmentLabel, Outcome, Reason};
use repair::reclaim::{judge, ReclaimOptions, Verdict};
use repair::Trial;

/// Withdraw the label of each fragment of an unlabelled point (rows after the trial's
/// `common` labelled markers in `trial`) that `label` gave a marker the trial already labels,
/// unless reclaiming judges the stretch of that point inside the marker's gap on the
/// marker's path at the gap's end(s) and not contradicted by its segment's distances
/// ([`Verdict::Fits`] or [`Verdict::FewLinks`]). Such a fragment stays unlabelled
/// ([`Reason::OffPath`]).
pub(crate) fn keep_on_path(
    frags: &mut [FragmentLabel],
    trial: &Trial,
    common: &[(usize, usize)],
    mm_per_unit: f64,
) {
    let nc = common.len();
    let into_marker = |a: &FragmentLabel| {
        a.given.is_none()
            && a.fragment.row >= nc
            && a.label.is_some_and(|m| common.iter().any(|&(_, t)| t == m))
    };
    if !frags.iter().any(into_marker) {
        return;
    }
    let part = |rows: std::ops::Range<usize>| Trial {
        rate_hz: trial.rate_hz,
        xyz: trial.xyz[rows.clone()].to_vec(),
        valid: trial.valid[rows].to_vec(),
    };
    let (markers, candidates) = (part(0..nc), part(nc..trial.markers()));
    let pieces = judge(
        &markers,
        &candidates,
        mm_per_unit,
        &ReclaimOptions::default(),
    );
    for a in frags.iter_mut().filter(|a| into_marker(a)) {
        let Some(m) = a.label else { continue };
        let Some(j) = common.iter().position(|&(_, t)| t == m) else {
            continue;
        };
        let g = a.fragment;
        let accepted = pieces.iter().any(|(p, fit)| {
            p.marker == j
                && p.source == g.row - nc
                && p.first <= g.first
                && g.last <= p.last
                && matches!(fit.verdict, Verdict::Fits | Verdict::FewLinks)
        });
        if !accepted {
            a.label = None;
            a.outcome = Outcome::Unlabelled {
                reason: Reason::OffPath { marker: m },
            };
        }
    }
}
