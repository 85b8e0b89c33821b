//! Many trials repaired as one run (`c3dfix batch`): each file of a plan repaired through
//! the one path that repairs a file ([`crate::files::repair`]), a trial without points
//! copied as it is, and the run's totals.

use crate::error::Result;
use crate::files::Destination;
use crate::options::RepairOptions;
use crate::repair::{RepairBrief, Summary};
use crate::save::{refuse_own_input, write_atomic};
use crate::tally::Tally;
use crate::targets::Target;
use crate::trial::open_mapped;
use repair::SkipKind;
use serde::Serialize;

/// Where the files of a run go: beside the plan's outputs, or over the inputs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RunDestination {
    /// Replace each input itself (atomically).
    pub in_place: bool,
    /// In place: keep each original first as `FILE.bak`.
    pub backup: bool,
    /// Replace an existing output.
    pub force: bool,
}

/// The reason a batch leaves a trial as it was: it has no points (EMG only).
pub const NO_POINTS: &str = "no points";

/// Repair one file of a run: its output's folder made, an existing output refused unless
/// replacing is asked for, then the file repaired as `c3dfix repair` does. A trial without
/// points has nothing to repair: it is skipped ([`Summary::skipped`]) and, unless in place,
/// copied unchanged so that the output folder holds every trial.
pub fn repair_target(
    t: &Target,
    dest: RunDestination,
    opts: &RepairOptions,
) -> Result<RepairBrief> {
    let (input, output) = (&t.input, &t.output);
    let overwrite = dest.force || dest.in_place;
    if !dest.in_place {
        refuse_own_input(input, output)?;
    }
    t.prepare_output(overwrite)?;
    let c = open_mapped(input)?;
    if c.point_count() == 0 {
        if !dest.in_place {
            write_atomic(output, c.source_bytes().unwrap_or_default(), overwrite)?;
        }
        return Ok(RepairBrief::of_summary(Summary {
            file: input.display().to_string(),
            output: output.display().to_string(),
            skipped: Some(NO_POINTS.into()),
            ..Summary::default()
        }));
    }
    drop(c);
    let dest = Destination {
        output: (!dest.in_place).then(|| output.clone()),
        in_place: dest.in_place,
        backup: dest.backup,
        force: dest.force,
    };
    Ok(crate::files::repair(input, &dest, opts, None)?.brief())
}

/// What a run did over all its files: how many were repaired, skipped, left unchanged or
/// failed, and the repairs' counts added up.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct BatchTotals {
    pub files: usize,
    pub repaired: usize,
    /// Trials without points, left as they were.
    pub skipped: usize,
    /// In place, files the repair changed no byte of (not rewritten).
    pub unchanged: usize,
    pub failed: usize,
    pub gaps: usize,
    pub filled: usize,
    pub left: usize,
    /// Gaps left over every file, by reason.
    pub left_because: Tally<SkipKind>,
    /// Of the gaps left, those at a trial's first or last frame (where only donors can fill)
    /// and those inside a trial.
    pub left_at_trial_ends: usize,
    pub left_inside: usize,
    pub spikes: usize,
    pub samples_changed: usize,
    /// Label swaps and jumps over every file: found, exchanged back, made gaps.
    pub swaps_found: usize,
    pub swaps_undone: usize,
    pub jumps_to_gaps: usize,
}

impl BatchTotals {
    /// The totals of a run's results, one per file (`Err`: why the file failed).
    pub fn of<E>(results: &[std::result::Result<RepairBrief, E>]) -> BatchTotals {
        let ok: Vec<&RepairBrief> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
        let lists = &ok;
        let ok: Vec<&Summary> = ok.iter().map(|b| &b.summary).collect();
        let skipped = ok.iter().filter(|s| s.skipped.is_some()).count();
        let mut left_because = Tally::default();
        for s in &ok {
            left_because.add_all(&s.left_because);
        }
        let left = left_because.total();
        let left_at_trial_ends = lists
            .iter()
            .flat_map(|b| &b.gap_list)
            .filter(|g| g.reason.is_some() && g.at_trial_end)
            .count();
        let sum = |f: fn(&Summary) -> usize| ok.iter().map(|s| f(s)).sum::<usize>();
        BatchTotals {
            files: results.len(),
            repaired: ok.len() - skipped,
            skipped,
            unchanged: ok.iter().filter(|s| s.unchanged).count(),
            failed: results.len() - ok.len(),
            gaps: sum(|s| s.gaps),
            filled: sum(|s| s.filled),
            left,
            left_because,
            left_at_trial_ends,
            left_inside: left.saturating_sub(left_at_trial_ends),
            spikes: sum(|s| s.spikes),
            samples_changed: sum(|s| s.samples_changed),
            swaps_found: lists.iter().map(|b| b.swap_list.len()).sum(),
            swaps_undone: sum(|s| s.swaps_undone),
            jumps_to_gaps: sum(|s| s.jumps_to_gaps),
        }
    }
}
