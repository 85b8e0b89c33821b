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
use std::path::{Path, PathBuf};

pub use pictures::{Coverage, FillCurve, ForceCurve, Mark, Pictures, Run};
pub use row::{GaitValue, PlateRow, TrialInput, TrialRow, LOOK_AT_ERROR_MM};
pub use session::{SessionReport, SessionSummary, Worst};

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
