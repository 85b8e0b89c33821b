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
use c3dfix::files::Destination;
use c3dfix::save::write_atomic;
use c3dfix::targets::plan;
use c3dfix::Summary;
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
    let overwrite = t.force || t.in_place;
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
    let results = run_each(
        &plan.targets,
        t.jobs,
        t.json,
        |job| -> Result<Summary> {
            let (input, output) = (&job.input, &job.output);
            if !t.in_place {
                c3dfix::save::refuse_own_input(input, output)?;
            }
            job.prepare_output(overwrite)?;
            // A trial without points (EMG only) has nothing to repair; it is skipped, and
            // copied unchanged so the output folder holds every trial.
            let c = c3dfix::open_mapped(input)?;
            if c.point_count() == 0 {
                if !t.in_place {
                    write_atomic(output, c.source_bytes().unwrap_or_default(), overwrite)?;
                }
                return Ok(Summary {
                    file: input.display().to_string(),
                    output: output.display().to_string(),
                    skipped: Some("no points".into()),
                    ..Summary::default()
                });
            }
            drop(c);
            // The one path that repairs a file, as `c3dfix repair` and Python's repair_file.
            let dest = Destination {
                output: (!t.in_place).then(|| output.clone()),
                in_place: t.in_place,
                backup: t.backup,
                force: t.force,
            };
            Ok(c3dfix::files::repair(input, &dest, &opts, None)?.summary)
        },
        "summary",
    )?;
    if let Some(page) = &a.report_html {
        session_page(&plan.targets, &results, t.in_place, page, t.force, t.json)?;
    }
    let ok: Vec<&Summary> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
    let failed = results.len() - ok.len();
    let skipped = ok.iter().filter(|s| s.skipped.is_some()).count();
    let unchanged = ok.iter().filter(|s| s.unchanged).count();
    // Gaps left over every file, by reason, and how many of them are at a trial's ends
    // (where only donors can fill) rather than inside it.
    let mut left_because: std::collections::BTreeMap<String, usize> = Default::default();
    for (k, n) in ok.iter().flat_map(|s| &s.left_because) {
        *left_because.entry(k.clone()).or_default() += n;
    }
    let left_at_ends = ok
        .iter()
        .flat_map(|s| &s.gap_list)
        .filter(|g| g.reason.is_some() && g.at_trial_end)
        .count();
    let left: usize = left_because.values().sum();
    let filled: usize = ok.iter().map(|s| s.filled).sum();
    let gaps: usize = ok.iter().map(|s| s.gaps).sum();
    let spikes: usize = ok.iter().map(|s| s.spikes).sum();
    let changed: usize = ok.iter().map(|s| s.samples_changed).sum();
    // Label swaps and jumps over every file: found, exchanged back, made gaps.
    let swaps_found: usize = ok.iter().map(|s| s.swap_list.len()).sum();
    let swaps_undone: usize = ok.iter().map(|s| s.swaps_undone).sum();
    let jumps_to_gaps: usize = ok.iter().map(|s| s.jumps_to_gaps).sum();
    if t.json {
        outln!(
            "{}",
            serde_json::json!({"summary": {"files": results.len(), "repaired": ok.len() - skipped, "skipped": skipped, "unchanged": unchanged, "failed": failed,
                "gaps": gaps, "filled": filled, "left": left, "left_because": left_because,
                "left_at_trial_ends": left_at_ends, "left_inside": left - left_at_ends, "spikes": spikes, "samples_changed": changed,
                "swaps_found": swaps_found, "swaps_undone": swaps_undone, "jumps_to_gaps": jumps_to_gaps,
                "listed": plan.listed, "duplicates": plan.duplicates, "shard": t.shard.map(|s| s.to_string())}})
        )?;
    } else {
        if ok.len() <= 3 {
            for s in &ok {
                print_summary(s)?;
            }
        }
        outln!(
            "{} files: {} repaired, {skipped} skipped (no points), {} failed; {gaps} gaps, {filled} filled, {spikes} spikes, {changed} samples changed{}",
            results.len(),
            ok.len() - skipped,
            failed,
            if unchanged > 0 {
                format!("; {unchanged} files unchanged (not rewritten)")
            } else {
                String::new()
            }
        )?;
        if swaps_found > 0 {
            outln!(
                "  swaps    {swaps_found} label swaps and jumps found: {swaps_undone} swaps exchanged back, {jumps_to_gaps} jumps made gaps, {} reported",
                swaps_found - swaps_undone - jumps_to_gaps
            )?;
        }
        if left > 0 {
            let by: Vec<String> = left_because
                .iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect();
            outln!(
                "  left     {left} gaps ({}): {left_at_ends} at a trial's start or end, {} inside",
                by.join(", "),
                left - left_at_ends
            )?;
        }
    }
    Ok(if failed > 0 { 1 } else { 0 })
}

/// The session's page from the repairs just made: each trial with its repaired copy and the
/// repair's own summary (in place, the file as it is now: the recorded one is gone).
fn session_page(
    targets: &[c3dfix::targets::Target],
    results: &[std::result::Result<Summary, String>],
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
