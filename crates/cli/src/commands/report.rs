//! `c3dfix report`: one page (and optionally JSON) over a session of trials, before and
//! after repair: the library's session report, drawn by `show::report`.

use crate::console::outln;
use crate::output::refuse_input;
use anyhow::{bail, Result};
use c3dfix::report::{plan_inputs, report_trials_with, ReportOptions, SessionReport, TrialRow};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// C3D files and folders (walked for *.c3d).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// The page to write (.html).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// A folder of repaired copies (as `batch --out-dir` writes them), matched by path below
    /// the given folder, else by file name.
    #[arg(long)]
    pub repaired: Option<PathBuf>,
    /// Write each trial's view page into NAME_views/ beside the page, linked from its row.
    #[arg(long)]
    pub views: bool,
    /// Print the report as JSON on standard output.
    #[arg(long)]
    pub json: bool,
    /// Replace an existing page (and view pages).
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<i32> {
    if a.output.is_none() && !a.json {
        bail!("give -o REPORT.html, --json, or both");
    }
    if a.views && a.output.is_none() {
        bail!("--views writes the view pages beside the page: give -o REPORT.html");
    }
    let opts = ReportOptions {
        paths: a.paths.clone(),
        repaired: a.repaired.clone(),
        views: a.views,
    };
    let trials = plan_inputs(&opts)?;
    if trials.is_empty() {
        bail!("no C3D files found");
    }
    if let Some(out) = &a.output {
        let inputs: Vec<&Path> = trials
            .iter()
            .flat_map(|t| std::iter::once(t.input.as_path()).chain(t.repaired.as_deref()))
            .collect();
        refuse_input(out, &inputs, "the report")?;
        c3dfix::save::check_destination(out, a.force)?;
    }
    let mut rep = with_progress(trials.len(), !a.json, |done| {
        report_trials_with(&trials, a.views, done)
    });
    finish(&mut rep, a.output.as_deref(), a.json, a.force)
}

/// Run `work` with a progress bar on a terminal's standard error (none when piped, nor when
/// `shown` is false: with JSON, as `batch` does), ticked by each row made.
pub fn with_progress<R>(
    n: usize,
    shown: bool,
    work: impl FnOnce(&(dyn Fn(&TrialRow) + Sync)) -> R,
) -> R {
    let bar = (shown && std::io::stderr().is_terminal()).then(|| {
        let b = indicatif::ProgressBar::new(n as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let tick = |r: &TrialRow| {
        if let Some(b) = &bar {
            b.set_message(r.name.clone());
            b.inc(1);
        }
    };
    let out = work(&tick);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    out
}

/// Write the page (with its view pages) and print the JSON or a line of totals.
pub fn finish(rep: &mut SessionReport, out: Option<&Path>, json: bool, force: bool) -> Result<i32> {
    if let Some(out) = out {
        show::report::write(rep, out, force)?;
    }
    let s = &rep.summary;
    if json {
        outln!("{}", serde_json::to_string(rep)?)?;
    } else {
        outln!(
            "{} trials: {} clean, {} worth a look, {} unreadable; {} samples missing before{}{}",
            s.trials,
            s.clean,
            s.trials - s.clean - s.unreadable,
            s.unreadable,
            s.missing_before,
            s.missing_after
                .map(|a| format!(", {a} after"))
                .unwrap_or_default(),
            out.map(|o| format!("; {}", o.display()))
                .unwrap_or_default()
        )?;
    }
    Ok(0)
}
