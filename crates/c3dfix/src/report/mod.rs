//! A session at a glance: one row per trial of a folder (or list) of trials, before and after
//! repair, and a summary of the whole session — what `c3dfix report` and `batch
//! --report-html` show as a page (the `show` crate draws it) and print as JSON.
//!
//! Nothing here is worked out anew that the library already reports: the trial's numbers are
//! [`crate::info::describe`]'s, its gaps [`crate::gaps()`]'s, its plates
//! [`crate::force_platforms`]', its events the file's and [`crate::detect_events`]'s, its gait
//! parameters [`crate::gait_parameters`]'; what a repair did is the repair's own
//! [`crate::Summary`] when the report is made right after it (`batch`), else what the
//! repaired file records in its `C3DFIX` group ([`crate::rerun::Record`]), which is what a
//! rerun trusts too. A trial that cannot be read is a row with the error, never a missing
//! row nor a failed report.

mod pictures;
mod row;
mod session;

use crate::error::Result;
use crate::targets::{plan, Destination};
use crate::{Direction, Summary};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub use pictures::{Coverage, FillCurve, ForceCurve, Mark, Pictures, Run};
pub use row::LOOK_AT_ERROR_MM;
pub use session::{SessionSummary, Worst};

/// What to report on.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ReportOptions {
    /// Files and folders (walked for `*.c3d`, each file once, sorted: the plan of `batch`).
    pub paths: Vec<PathBuf>,
    /// A folder of repaired copies, matched by the path below the given folder as `batch
    /// --out-dir` writes it, else by file name; a trial without one says so in its row.
    pub repaired: Option<PathBuf>,
    /// Name a view page per trial (rows get [`TrialRow::view`]; the page writer writes them).
    pub views: bool,
}

/// One trial to report on, with what is known of its repair.
#[derive(Debug, Clone, Default)]
pub struct TrialInput {
    /// The trial as recorded (as named).
    pub input: PathBuf,
    /// Its repaired copy, if any.
    pub repaired: Option<PathBuf>,
    /// The repair's own summary, when the report is made by the run that repaired it: `Err`
    /// holds why the repair failed.
    pub summary: Option<std::result::Result<Summary, String>>,
}

/// The whole report: the session's summary, then one row per trial in the plan's order.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SessionReport {
    pub summary: SessionSummary,
    pub trials: Vec<TrialRow>,
}

/// One plate of a trial, as [`crate::info::PlateInfo`] gives it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PlateRow {
    /// 1-based, as FORCE_PLATFORM numbers it.
    pub index: usize,
    #[serde(rename = "type")]
    pub kind: i32,
    pub contacts: usize,
    /// Largest push over the trial (N), its unloaded level removed.
    pub peak_force: f64,
}

/// One gait-cycle parameter ([`gait::params::Parameter`]).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct GaitValue {
    pub context: String,
    pub name: String,
    pub value: f64,
    pub unit: String,
}

/// One trial: what it holds, what its repair did, and the first thing worth a look.
#[derive(Debug, Clone, Serialize, PartialEq, Default)]
pub struct TrialRow {
    /// The trial as named.
    pub file: String,
    /// Its file name.
    pub name: String,
    /// Why the trial could not be read (the other fields are then empty).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The repaired copy, when one was given or written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repaired: Option<String>,
    /// Why the repaired copy could not be read, or the repair failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repaired_error: Option<String>,
    pub frames: usize,
    /// The file's first frame number; every frame in the row is in the file's numbering.
    pub first_frame: usize,
    pub rate: f32,
    pub duration_s: f64,
    /// Markers (model outputs left out).
    pub markers: usize,
    /// Marker samples (markers × frames).
    pub samples: usize,
    /// Marker samples missing in the trial as given.
    pub missing_before: usize,
    /// Marker samples missing in the repaired copy.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub missing_after: Option<usize>,
    /// Gaps of the markers in the trial as given.
    pub gaps_before: usize,
    /// Where the repair's numbers come from: `summary` (the repair's own, made by this run)
    /// or `record` (the repaired file's C3DFIX group); none without a repair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repair_source: Option<&'static str>,
    /// Gaps the repair filled and left, and the left ones per reason (`too_long`,
    /// `uncertain`, `touches_edge`, `no_donors`, …).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub filled: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub left: Option<usize>,
    pub left_because: BTreeMap<String, usize>,
    /// Of the gaps left, those at the trial's first or last frame.
    pub left_at_trial_end: usize,
    /// Largest expected error of a fill, mm (the repair's summary; a file records none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm_max: Option<f64>,
    /// Label swaps and jumps found (the repair's summary only: a file records those undone).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub swaps_found: Option<usize>,
    pub swaps_undone: usize,
    pub jumps_to_gaps: usize,
    /// Spikes removed (the repair's summary only: a file records the setting, not the count).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spikes: Option<usize>,
    /// Events by source: `file` (the EVENT group), `plate` and `kinematics` (detected).
    pub events: BTreeMap<String, usize>,
    /// Why events could not be detected, or gait parameters not computed (a trial that is
    /// no walk says so here, not among the warnings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub events_note: Option<String>,
    /// Gait-cycle parameters from the file's own Foot Strike / Foot Off events, if any.
    pub gait: Vec<GaitValue>,
    pub plates: Vec<PlateRow>,
    /// Plates named in FORCE_PLATFORM and not computed, with why.
    pub plates_refused: Vec<String>,
    /// What the reader, the plates and the event detector noticed.
    pub warnings: Vec<String>,
    /// The lab's up ([`crate::axes::up`]).
    pub up: Option<Direction>,
    /// The first problem worth a look, in words; none for a clean trial.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub problem: Option<String>,
    /// The trial's view page, a file name (written beside the report by the page writer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub view: Option<String>,
    pub pictures: Pictures,
}

/// The report over the trials `opts` names: planned as `batch` plans them, each matched to
/// its repaired copy, read in parallel. Errors only when a named path does not exist; a trial
/// that cannot be read is a row saying why.
pub fn report(opts: &ReportOptions) -> Result<SessionReport> {
    let trials = plan_inputs(opts)?;
    Ok(report_trials(&trials, opts.views))
}

/// The trials of `opts.paths`, each with its repaired copy when one is found.
pub fn plan_inputs(opts: &ReportOptions) -> Result<Vec<TrialInput>> {
    let p = plan(&opts.paths, Destination::InPlace, None)?;
    Ok(p.targets
        .into_iter()
        .map(|t| {
            // No copy found: the path it was looked for by name, which the row then says
            // it cannot read, so a trial the repair missed shows among those to look at.
            let repaired = opts.repaired.as_deref().map(|d| {
                matching_copy(d, &t.input, &opts.paths)
                    .unwrap_or_else(|| d.join(t.input.file_name().unwrap_or_default()))
            });
            TrialInput {
                input: t.input,
                repaired,
                summary: None,
            }
        })
        .collect())
}

/// The repaired copy of `input` in `dir`: at its path below the named folder it was found
/// in (where `batch --out-dir` writes it), else by file name directly in `dir`.
fn matching_copy(dir: &Path, input: &Path, named: &[PathBuf]) -> Option<PathBuf> {
    let below = named
        .iter()
        .filter(|n| n.is_dir())
        .find_map(|n| input.strip_prefix(n).ok())
        .map(|rel| dir.join(rel));
    if let Some(p) = below.filter(|p| p.is_file()) {
        return Some(p);
    }
    let by_name = dir.join(input.file_name()?);
    by_name.is_file().then_some(by_name)
}

/// The report over `trials`, in their order, read in parallel in the process's pool (see
/// `forkpool`). `views`: name a view page per readable trial.
pub fn report_trials(trials: &[TrialInput], views: bool) -> SessionReport {
    report_trials_with(trials, views, &|_| {})
}

/// [`report_trials`], calling `done` with each row as soon as it is made (in any order),
/// for a progress bar.
pub fn report_trials_with(
    trials: &[TrialInput],
    views: bool,
    done: &(dyn Fn(&TrialRow) + Sync),
) -> SessionReport {
    use rayon::prelude::*;
    let mut rows: Vec<TrialRow> = forkpool::install(|| {
        trials
            .par_iter()
            .map(|t| {
                let r = row::row(t);
                done(&r);
                r
            })
            .collect()
    });
    if views {
        for (i, r) in rows.iter_mut().enumerate() {
            if r.error.is_none() {
                r.view = Some(view_name(i, &r.name));
            }
        }
    }
    SessionReport {
        summary: session::summarise(&rows),
        trials: rows,
    }
}

/// The view page's file name of the `i`-th trial: numbered, so two trials of one name in two
/// folders get two pages; the name kept to letters, digits, `-`, `_` and `.`.
fn view_name(i: usize, name: &str) -> String {
    let stem = Path::new(name)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let safe: String = stem
        .chars()
        .map(|ch| {
            if ch.is_ascii_alphanumeric() || "-_.".contains(ch) {
                ch
            } else {
                '_'
            }
        })
        .take(80)
        .collect();
    format!("{:04}_{safe}.html", i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_names_are_numbered_and_plain() {
        assert_eq!(view_name(0, "walk 1.c3d"), "0001_walk_1.html");
        assert_eq!(
            view_name(41, "</script><svg onload=alert(1)>.c3d"),
            "0042_script__svg_onload_alert_1__.html"
        );
    }
}
