//! c3dfix as a library: open a C3D trial, repair its marker data, save it atomically — the
//! same code the `c3dfix` command and the Python package run.
//!
//! The format itself is the [`c3d`] crate (bytes ⇄ model, lossless, and the one definition
//! of a missing sample, [`c3d::is_missing`]); trajectory processing is the [`repair`] crate
//! (plain arrays and masks). This crate is the bridge between them: which points are markers
//! ([`markers`]), trajectories in and repaired samples back with the C3D manual's flags
//! ([`trial`]), options as people write them ([`RepairOptions`]), reports, and atomic
//! writing ([`save()`], [`mod@save`]); a file in and a file out, as the command does, in
//! [`files`]; the text exports (TRC, MOT, CSV, JSON, the OpenSim pair) in [`export`], the
//! lab's up and axis rotations in [`axes`], length units in [`units`].
//!
//! ```no_run
//! use c3dfix::{RepairOptions, SaveOptions};
//!
//! let mut trial = c3dfix::open("walk.c3d")?;
//! let opts = RepairOptions { lowpass: Some("butterworth:4:6".into()), ..RepairOptions::default() };
//! let done = c3dfix::repair(&mut trial, &opts, "walk.c3d".as_ref())?;
//! println!("{} of {} gaps filled", done.summary.filled, done.summary.gaps);
//! c3dfix::save(&trial, "walk_repaired.c3d".as_ref(), &SaveOptions::default())?;
//! # Ok::<(), c3dfix::Error>(())
//! ```

pub mod analysis_group;
pub mod axes;
pub mod cycles;
mod error;
pub mod evaluate;
pub mod event_group;
pub mod events;
pub mod export;
pub mod files;
pub mod gait_params;
mod gaps;
pub mod markers;
mod options;
pub mod platforms;
mod repair;
pub mod rerun;
pub mod save;
pub mod swap_stage;
mod swaps;
pub mod trial;
pub mod units;

pub use ::c3d;
pub use ::gait;
pub use ::kinetics;
pub use ::repair as repair_lib;
pub use axes::{Axes, Direction, Up, UpSource};
pub use cycles::{cycles, CycleInfo, CycleOptions, Cycles};
pub use error::{Error, Result};
pub use evaluate::{evaluate, EvaluateOptions, Evaluation};
pub use events::{detect_events, Detected, EventOptions, EventSource, TrialEvent};
pub use gait_params::{gait_parameters, GaitOptions, GaitReport};
pub use gaps::{gaps, GapInfo};
pub use options::{
    fill_method, filter_spec, max_expected_error, method_name, spike_options, RepairOptions,
    SwapsMode, DEFAULT_MAX_EXPECTED_ERROR_MM, DEFAULT_SWAPS,
};
pub use platforms::{
    force_platforms, Baseline, BaselineSource, Contact, ForceOptions, ForcePlatforms, PlateWarning,
    Platform,
};
pub use repair::{repair, GapBrief, Repaired, Summary};
pub use swaps::{swaps, SwapFind, Swaps};
pub use trial::{open, open_mapped};

use std::path::{Path, PathBuf};

/// How [`save()`] treats what is already at the destination.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SaveOptions {
    /// Replace an existing file.
    pub force: bool,
    /// Before replacing an existing file, keep it as `FILE.bak` (the first backup is kept).
    pub backup: bool,
}

/// Encode `c` and write it to `path` atomically (see [`save::write_all`]). With `backup`,
/// the file being replaced is kept first as `FILE.bak` (unless a backup exists: the first
/// is the true original), written together with the new file, all or nothing. Returns the
/// backup's path when one was written.
pub fn save(c: &c3d::C3d, path: &Path, opts: &SaveOptions) -> Result<Option<PathBuf>> {
    let replace = opts.force || opts.backup;
    save::check_destination(path, replace)?;
    let bytes = c.encoded().map_err(|source| Error::C3d {
        path: path.to_path_buf(),
        source,
    })?;
    let backup = if opts.backup && path.exists() {
        save::new_backup(path)
    } else {
        None
    };
    let outs = save::replacing(path, &bytes, replace, backup.as_deref());
    save::write_all(&outs)?;
    Ok(backup)
}

/// Open `input`, repair it, and save the result to `output` atomically: what
/// `c3dfix repair` does. The summary names both files (and the backup, if one was made).
pub fn repair_file(
    input: &Path,
    output: &Path,
    opts: &RepairOptions,
    save_opts: &SaveOptions,
) -> Result<Repaired> {
    let mut c = open(input)?;
    repair_opened(&mut c, input, output, opts, save_opts)
}

/// [`repair_file`] for a trial already opened from `input` (callers that look at a file
/// first read and parse it once). The destination is checked before any work is done.
pub fn repair_opened(
    c: &mut c3d::C3d,
    input: &Path,
    output: &Path,
    opts: &RepairOptions,
    save_opts: &SaveOptions,
) -> Result<Repaired> {
    save::check_destination(output, save_opts.force || save_opts.backup)?;
    let mut done = repair(c, opts, input)?;
    done.summary.output = output.display().to_string();
    // A rerun that changes nothing leaves the file alone in place (not even its time stamp
    // or a backup): `batch --in-place` run twice touches no file the second time.
    let same_bytes = c.encoded().is_ok_and(|b| c.source_bytes() == Some(&b[..]));
    if same_bytes && save::same_file(input, output) {
        done.summary.unchanged = true;
        return Ok(done);
    }
    if let Some(b) = save(c, output, save_opts)? {
        done.summary.backup = Some(b.display().to_string());
    }
    Ok(done)
}
