//! `c3dfix repair`: spikes → fill → filter on one file, written back as a valid C3D, through
//! the library ([`c3dfix::repair`]).

use crate::commands::destination::DestinationArgs;
use crate::commands::repair_io::RepairArgs;
use crate::console::outln;
use anyhow::Result;
use c3dfix::ReclaimAction;
use c3dfix::SwapAction;
use c3dfix::{RepairBrief, SkipKind};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    pub input: PathBuf,
    #[command(flatten)]
    pub dest: DestinationArgs,
    /// Write the full report (every gap and what filled it, spikes, filter segments) here;
    /// an existing file is replaced only with --force, and never the input or the output.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub repair: RepairArgs,
}

pub fn run(a: Args) -> Result<i32> {
    // The library checks that the flags go together (see c3dfix::files); its kinds are said
    // with the flags by crate::flags.
    let dest = a.dest.destination();
    // C3DFIX_PROFILE=1: where the fills' time went, on stderr (see repair::profile and
    // crates/cli/benches/price.sh).
    let profiling = std::env::var_os("C3DFIX_PROFILE").is_some_and(|v| v == "1");
    repair::profile::enable(profiling);
    let done = c3dfix::files::repair(&a.input, &dest, &a.repair.options(), a.report.as_deref())?;
    if profiling {
        eprint!("{}", repair::profile::take());
    }
    let s = done.brief();
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&s)?)?;
    } else {
        print_summary(&s)?;
    }
    Ok(0)
}

/// The few lines a person reads after a repair.
pub fn print_summary(b: &RepairBrief) -> Result<()> {
    let s = &b.summary;
    outln!("repaired {} -> {}", s.file, s.output)?;
    print_gaps(b)?;
    print_swaps(b)?;
    print_reclaim(b)?;
    print_changes(b)
}

/// The gaps found, filled and left (by method and reason), the unlabelled points and the
/// fills' expected error, and each gap left as uncertain.
fn print_gaps(b: &RepairBrief) -> Result<()> {
    let s = &b.summary;
    let by: Vec<String> = s
        .filled_by
        .iter()
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    let left: Vec<String> = s
        .left_because
        .iter()
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    outln!(
        "  gaps     {} found in {} markers: {} filled ({}), {} left{}",
        s.gaps,
        s.markers,
        s.filled,
        if by.is_empty() {
            "-".into()
        } else {
            by.join(", ")
        },
        s.left,
        if left.is_empty() {
            String::new()
        } else {
            format!(" ({})", left.join(", "))
        }
    )?;
    if let Some(u) = &s.unlabelled {
        outln!(
            "  unlabelled {} points ({} samples): not markers, left as recorded",
            u.points,
            u.samples
        )?;
    }
    if let (Some(mean), Some(max)) = (s.expected_error_mm_mean, s.expected_error_mm_max) {
        outln!("  expected fill error {mean:.2} mm on average, {max:.2} mm at most")?;
    }
    for g in b
        .gap_list
        .iter()
        .filter(|g| g.reason == Some(SkipKind::Uncertain))
    {
        outln!(
            "  uncertain {} frames {}–{}: expected error {:.1} mm (left unfilled)",
            g.label,
            g.first_frame,
            g.last_frame,
            g.expected_error_mm.unwrap_or(f64::NAN)
        )?;
    }
    Ok(())
}

/// Every label swap and jump found, and what was done with it (or why none was looked for).
fn print_swaps(b: &RepairBrief) -> Result<()> {
    let s = &b.summary;
    if let Some(note) = &s.swaps_note {
        outln!("  swaps    not checked: {note}")?;
    }
    for b in &b.swap_list {
        let x = &b.find;
        let kind = match x.kind {
            repair::swaps::FindKind::Swap => "swap",
            repair::swaps::FindKind::Jump => "jump",
        };
        let action = match b.action {
            SwapAction::Undone => "exchanged back",
            SwapAction::Gap => "made a gap for the fill",
            SwapAction::Reported => {
                if x.settled {
                    "reported (--swaps fix undoes it)"
                } else {
                    "reported (not settled)"
                }
            }
            SwapAction::OutOfScope => "reported (a marker outside --markers)",
        };
        outln!(
            "  {kind}     {} frames {}–{}, confidence {:.2}: {action}",
            x.markers.join(" ↔ "),
            x.first_frame,
            x.last_frame,
            x.confidence
        )?;
    }
    Ok(())
}

/// Every piece of unlabelled samples settled into a marker's gap, and how many fit one
/// without being settled.
fn print_reclaim(brief: &RepairBrief) -> Result<()> {
    for b in &brief.reclaim_list {
        let action = match b.action {
            ReclaimAction::Moved => "moved",
            ReclaimAction::Reported => "reported (--reclaim on moves it)",
            ReclaimAction::OutOfScope => "reported (a marker outside --markers)",
        };
        outln!(
            "  reclaim  {} ← {} frames {}–{} ({} samples, link rms {:.2} mm): {action}",
            b.marker,
            b.source,
            b.first_frame,
            b.last_frame,
            b.samples,
            b.fit.rms_mm
        )?;
    }
    if !brief.reclaim_unsettled.is_empty() {
        outln!(
            "  reclaim  {} pieces fit a gap and are not settled (c3dfix reclaim lists them): left as they are",
            brief.reclaim_unsettled.len()
        )?;
    }
    Ok(())
}

/// The steps an earlier repair did, the spikes and filtered segments, the samples changed,
/// what was kept as recorded, and the backup.
fn print_changes(b: &RepairBrief) -> Result<()> {
    let s = &b.summary;
    for done in &s.already_applied {
        outln!("  skipped  {done}: the file records it as done by an earlier repair")?;
    }
    if s.spikes > 0 {
        outln!("  spikes   {} found", s.spikes)?;
    }
    if s.segments_filtered + s.segments_too_short > 0 {
        outln!(
            "  filter   {} segments filtered, {} too short (left unfiltered)",
            s.segments_filtered,
            s.segments_too_short
        )?;
    }
    outln!(
        "  changed  {} samples in {} markers",
        s.samples_changed,
        s.markers_changed
    )?;
    if c3dfix::info::zeros_look_missing(s.samples_at_origin) {
        outln!(
            "  note     {} samples sit exactly at (0, 0, 0) and were kept as recorded; if this writer stores missing points that way, repair with --zero-invalid",
            s.samples_at_origin
        )?;
    }
    if s.model_outputs_left > 0 {
        outln!(
            "  kept     {} model outputs (angles, forces, …) untouched",
            s.model_outputs_left
        )?;
    }
    if let Some(b) = &s.backup {
        outln!("  backup   {b}")?;
    }
    Ok(())
}
