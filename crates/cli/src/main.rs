//! `c3dfix`: a thin command-line layer over the `c3dfix` library and the `c3d`, `repair`
//! and `bvh` crates.
//!
//! Exit codes: 0 success, 1 "differences found" (diff), 2 error.

use c3dfix_cli::commands;
use c3dfix_cli::console::{describe, flush_stdout, write_stderr};
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "c3dfix",
    version,
    about = "Read, write, repair and inspect C3D motion-capture files"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Header, formats, counts, rates, gaps per marker, force plates, parameter groups,
    /// warnings.
    Info(commands::info::Args),
    /// Rewrite files (byte-identical by default), or convert their processor/number format:
    /// one file to -o, or many (folders recursively) in place or into a folder, in parallel.
    Convert(commands::convert::Args),
    /// Compare two files: header, parameters, point and analog data (exit 1 if different).
    Diff(commands::diff::Args),
    /// Export point (and analog) data as CSV, TRC or JSON, or the force plates as an OpenSim
    /// MOT file.
    Export(commands::export::Args),
    /// List every gap of every marker.
    Gaps(commands::gaps::Args),
    /// Find marker label swaps and label jumps (reported with their frames and confidence).
    Swaps(commands::swaps::Args),
    /// Find the unlabelled samples that are a labelled marker's, in its gaps (reported; repair
    /// --reclaim on moves them).
    Reclaim(commands::reclaim::Args),
    /// Label a trial's unlabelled trajectories from a labelled trial of the same marker set
    /// (--template), written as an ordinary labelled C3D.
    Label(commands::label::Args),
    /// Force platforms: ground reaction force, moment, centre of pressure, free moment and
    /// contact intervals of every plate.
    Forces(commands::forces::Args),
    /// Gait events: foot strike and foot off of each foot, from the force plates and the
    /// heel, toe and pelvis markers.
    Events(commands::events::Args),
    /// Gait-cycle parameters per side as Vicon Nexus reports them (cadence, speed, stride
    /// and step times and lengths, foot off, support times), from the file's events or
    /// detected ones; optionally written into the ANALYSIS group
    Gait(commands::gait::Args),
    /// Gait cycles: markers, analog channels and plate forces from each foot strike to the
    /// next of the same foot, time-normalised to 0–100 % (101 rows per cycle), as CSV.
    Cycles(commands::cycles::Args),
    /// Remove spikes, fill gaps and low-pass filter one file.
    Repair(commands::repair::Args),
    /// Repair many files (folders recursively, lists, shards), in parallel.
    Batch(commands::batch::Args),
    /// One offline page over a session of trials (and their repaired copies): a sortable,
    /// filterable table, one row per trial, with its pictures; optionally as JSON.
    Report(commands::report::Args),
    /// Measure fill accuracy: knock out recorded data (never points computed from other
    /// markers, which refill exactly, nor samples at exactly (0, 0, 0), a writer's mark of a
    /// lost one), refill it, report the error per method.
    Evaluate(commands::evaluate::Args),
    /// Reduce a BVH motion to key frames; rebuild it by interpolation and report the error.
    Keyframes(commands::keyframes::Args),
    /// Draw marker x, y, z against time (optionally over the original), or the force plates,
    /// as SVG or PNG.
    Plot(commands::plot::Args),
    /// Write a self-contained HTML page that plays the trial in 3D, with its force plates
    /// (offline, no network).
    View(commands::view::Args),
}

fn main() {
    reset_sigpipe();
    // Help and version go to standard output, which may fail like any other output.
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => match e.print() {
            Ok(()) => std::process::exit(0),
            Err(err) => {
                write_stderr(format_args!(
                    "c3dfix: error: cannot write to standard output: {err}\n"
                ));
                std::process::exit(2);
            }
        },
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        Command::Info(a) => commands::info::run(a),
        Command::Convert(a) => commands::convert::run(a),
        Command::Diff(a) => commands::diff::run(a),
        Command::Export(a) => commands::export::run(a),
        Command::Gaps(a) => commands::gaps::run(a),
        Command::Swaps(a) => commands::swaps::run(a),
        Command::Reclaim(a) => commands::reclaim::run(a),
        Command::Label(a) => commands::label::run(a),
        Command::Forces(a) => commands::forces::run(a),
        Command::Events(a) => commands::events::run(a),
        Command::Gait(a) => commands::gait::run(a),
        Command::Cycles(a) => commands::cycles::run(a),
        Command::Repair(a) => commands::repair::run(a),
        Command::Batch(a) => commands::batch::run(a),
        Command::Report(a) => commands::report::run(a),
        Command::Evaluate(a) => commands::evaluate::run(a),
        Command::Keyframes(a) => commands::keyframes::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::View(a) => commands::view::run(a),
    };
    // `process::exit` skips the flush at the end of `main`: a last buffered line is flushed
    // here, where a failure can still be reported.
    match result.and_then(|code| flush_stdout().map(|()| code)) {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            write_stderr(format_args!("c3dfix: error: {}\n", describe(&e)));
            std::process::exit(2);
        }
    }
}

/// Let a closed pipe (`c3dfix info x.c3d | head`) end the process quietly, as command-line
/// tools do, instead of failing on the next print.
fn reset_sigpipe() {
    #[cfg(unix)]
    // SAFETY: restoring the default action of a signal at start-up, before any threads exist.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
