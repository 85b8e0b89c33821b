//! `c3dfix batch`: repair every C3D file under the given paths (and those of `--files-from`,
//! or one `--shard` of them), in parallel, each once. A file that fails is reported and left
//! untouched; the others go on. Each output is a synced temporary file
//! renamed into place, so stopping the process at any moment leaves every file either as it
//! was or fully repaired.

use crate::commands::parallel::run_each;
use crate::commands::repair::print_summary;
use crate::commands::repair_io::RepairArgs;
use crate::commands::targets::TargetArgs;
use crate::console::outln;
use anyhow::{bail, Result};
use c3dfix::batch::{BatchTotals, RunDestination};
use c3dfix::targets::plan;
use c3dfix::RepairBrief;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub targets: TargetArgs,
    #[command(flatten)]
    pub repair: RepairArgs,
    /// Also write the session's report page (as `c3dfix report --repaired`), from each
    /// repair's own numbers.
    #[arg(long, value_name = "FILE")]
    pub report_html: Option<PathBuf>,
}

pub fn run(a: Args) -> Result<i32> {
    let t = &a.targets;
    let dest = t.destination()?;
    // Options are checked before any file is touched.
    let opts = a.repair.options();
    opts.config()?;
    let plan = plan(&t.named_paths()?, dest, t.shard)?;
    if plan.listed == 0 {
        bail!("no C3D files found");
    }
    if let Some(page) = &a.report_html {
        // Checked before any file is repaired: a run never ends without its page.
        let inputs: Vec<&Path> = plan
            .targets
            .iter()
            .flat_map(|t| [t.input.as_path(), t.output.as_path()])
            .collect();
        crate::output::refuse_input(page, &inputs, "the report")?;
        c3dfix::save::check_destination(page, t.force)?;
    }
    let run_dest = RunDestination {
        in_place: t.in_place,
        backup: t.backup,
        force: t.force,
    };
    let results = run_each(
        &plan.targets,
        t.jobs,
        t.json,
        |job| -> Result<RepairBrief> { Ok(c3dfix::batch::repair_target(job, run_dest, &opts)?) },
        "summary",
    )?;
    if let Some(page) = &a.report_html {
        session_page(&plan.targets, &results, t.in_place, page, t.force, t.json)?;
    }
    let totals = BatchTotals::of(&results);
    if t.json {
        let mut summary = serde_json::to_value(&totals)?;
        summary["listed"] = plan.listed.into();
        summary["duplicates"] = plan.duplicates.into();
        summary["shard"] = t.shard.map(|s| s.to_string()).into();
        outln!("{}", serde_json::json!({ "summary": summary }))?;
    } else {
        let ok: Vec<&RepairBrief> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
        if ok.len() <= 3 {
            for s in &ok {
                print_summary(s)?;
            }
        }
        print_totals(&totals)?;
    }
    Ok(if totals.failed > 0 { 1 } else { 0 })
}

/// The run's totals in the few lines a person reads.
fn print_totals(n: &BatchTotals) -> Result<()> {
    outln!(
        "{} files: {} repaired, {} skipped (no points), {} failed; {} gaps, {} filled, {} spikes, {} samples changed{}",
        n.files,
        n.repaired,
        n.skipped,
        n.failed,
        n.gaps,
        n.filled,
        n.spikes,
        n.samples_changed,
        if n.unchanged > 0 {
            format!("; {} files unchanged (not rewritten)", n.unchanged)
        } else {
            String::new()
        }
    )?;
    if n.swaps_found > 0 {
        outln!(
            "  swaps    {} label swaps and jumps found: {} swaps exchanged back, {} jumps made gaps, {} reported",
            n.swaps_found,
            n.swaps_undone,
            n.jumps_to_gaps,
            n.swaps_found.saturating_sub(n.swaps_undone + n.jumps_to_gaps)
        )?;
    }
    if n.left > 0 {
        let by: Vec<String> = n
            .left_because
            .iter()
            .map(|(k, c)| format!("{k} {c}"))
            .collect();
        outln!(
            "  left     {} gaps ({}): {} at a trial's start or end, {} inside",
            n.left,
            by.join(", "),
            n.left_at_trial_ends,
            n.left_inside
        )?;
    }
    Ok(())
}

/// The session's page from the repairs just made: each trial with its repaired copy and the
/// repair's own summary (in place, the file as it is now: the recorded one is gone).
fn session_page(
    targets: &[c3dfix::targets::Target],
    results: &[std::result::Result<RepairBrief, String>],
    in_place: bool,
    page: &Path,
    force: bool,
    json: bool,
) -> Result<()> {
    let trials: Vec<c3dfix::report::TrialInput> = targets
        .iter()
        .zip(results)
        .map(|(t, r)| c3dfix::report::TrialInput {
            input: t.input.clone(),
            repaired: (!in_place && r.is_ok()).then(|| t.output.clone()),
            summary: Some(r.clone()),
        })
        .collect();
    let mut rep = crate::commands::report::with_progress(trials.len(), !json, |done| {
        c3dfix::report::report_trials_with(&trials, false, done)
    });
    show::report::write(&mut rep, page, force)?;
    Ok(())
}
