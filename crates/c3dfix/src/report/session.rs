//! The session's summary: totals over the trials and the ones to look at first.

use super::row::TrialRow;
use crate::tally::Tally;
use repair::SkipKind;
use serde::Serialize;
use std::collections::BTreeMap;

/// The whole report: the session's summary, then one row per trial in the plan's order.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SessionReport {
    pub summary: SessionSummary,
    pub trials: Vec<TrialRow>,
}

/// Trials listed as the worst.
const WORST: usize = 5;

/// Totals over every trial of the report.
#[derive(Debug, Clone, Serialize, PartialEq, Default)]
pub struct SessionSummary {
    pub trials: usize,
    /// Trials that could not be read.
    pub unreadable: usize,
    /// Trials with a repair's numbers (a summary or a record).
    pub repaired: usize,
    /// Trials with nothing worth a look.
    pub clean: usize,
    pub frames: usize,
    pub samples: usize,
    pub missing_before: usize,
    /// Over the trials with a repaired copy; `None` when no trial has one (nothing to count:
    /// not zero).
    pub missing_after: Option<usize>,
    pub gaps_before: usize,
    pub filled: usize,
    pub left: usize,
    pub left_because: Tally<SkipKind>,
    pub left_at_trial_end: usize,
    pub expected_error_mm_max: Option<f64>,
    pub swaps_found: usize,
    pub swaps_undone: usize,
    pub jumps_to_gaps: usize,
    pub spikes: usize,
    pub events: BTreeMap<String, usize>,
    pub plates: usize,
    pub contacts: usize,
    pub plates_refused: usize,
    pub warnings: usize,
    /// The trials to look at first: unreadable ones, then by gaps left inside, samples still
    /// missing, and the largest expected error.
    pub worst: Vec<Worst>,
}

/// One trial of [`SessionSummary::worst`]: its row (0-based) and its problem.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Worst {
    pub row: usize,
    pub name: String,
    pub problem: String,
}

pub(super) fn summarise(rows: &[TrialRow]) -> SessionSummary {
    let mut s = SessionSummary {
        trials: rows.len(),
        ..SessionSummary::default()
    };
    for r in rows {
        s.unreadable += usize::from(r.error.is_some());
        s.repaired += usize::from(r.repair_source.is_some());
        s.clean += usize::from(r.problem.is_none());
        s.frames += r.frames;
        s.samples += r.samples;
        s.missing_before += r.missing_before;
        if let Some(after) = r.missing_after {
            *s.missing_after.get_or_insert(0) += after;
        }
        s.gaps_before += r.gaps_before;
        s.filled += r.filled.unwrap_or(0);
        s.left += r.left.unwrap_or(0);
        s.left_because.add_all(&r.left_because);
        s.left_at_trial_end += r.left_at_trial_end;
        if let Some(e) = r.expected_error_mm_max {
            s.expected_error_mm_max = Some(s.expected_error_mm_max.map_or(e, |m| m.max(e)));
        }
        s.swaps_found += r.swaps_found.unwrap_or(0);
        s.swaps_undone += r.swaps_undone;
        s.jumps_to_gaps += r.jumps_to_gaps;
        s.spikes += r.spikes.unwrap_or(0);
        for (k, n) in &r.events {
            *s.events.entry(k.clone()).or_default() += n;
        }
        s.plates += r.plates.len();
        s.contacts += r.plates.iter().map(|p| p.contacts).sum::<usize>();
        s.plates_refused += r.plates_refused.len();
        s.warnings += r.warnings.len();
    }
    let mut order: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].problem.is_some())
        .collect();
    order.sort_by(|&a, &b| {
        let key = |r: &TrialRow| {
            (
                r.error.is_some() || r.repaired_error.is_some(),
                r.left.unwrap_or(0) - r.left_at_trial_end.min(r.left.unwrap_or(0)),
                r.missing_after.unwrap_or(r.missing_before),
            )
        };
        key(&rows[b])
            .cmp(&key(&rows[a]))
            .then(
                rows[b]
                    .expected_error_mm_max
                    .unwrap_or(0.0)
                    .total_cmp(&rows[a].expected_error_mm_max.unwrap_or(0.0)),
            )
            .then(a.cmp(&b))
    });
    s.worst = order
        .into_iter()
        .take(WORST)
        .map(|i| Worst {
            row: i,
            name: rows[i].name.clone(),
            problem: rows[i].problem.clone().unwrap_or_default(),
        })
        .collect();
    s
}
