//! c3dfix as a library: open a C3D trial, repair its marker data, save it atomically — the
//! same code the `c3dfix` command and the Python package run.
//!
//! The format itself is the [`c3d`] crate (bytes ⇄ model, lossless, and the one definition
//! of a missing sample, [`c3d::is_missing`]); trajectory processing is the [`repair`] crate
//! (plain arrays and masks). This crate is the bridge between them: which points are markers
//! ([`markers`]), trajectories in and repaired samples back with the C3D manual's flags
//! (read by [`open`] and [`open_mapped`]), options as people write them ([`RepairOptions`]), reports, and atomic
//! writing ([`save()`], [`mod@save`]); a file in and a file out, as the command does, in
//! [`files`]; the text exports (TRC, MOT, CSV, JSON, the OpenSim pair) in [`export`], the
//! lab's up and axis rotations in [`axes`], length units in [`units`].
//!
//! ```no_run
//! use c3dfix::{RepairOptions, SaveOptions};
//!
//! let mut trial = c3dfix::open("walk.c3d")?;
//! let opts = RepairOptions { lowpass: Some("butterworth:4:6".parse()?), ..RepairOptions::default() };
//! let done = c3dfix::repair(&mut trial, &opts, "walk.c3d".as_ref())?;
//! println!("{} of {} gaps filled", done.summary.filled, done.summary.gaps);
//! c3dfix::save(&trial, "walk_repaired.c3d".as_ref(), &SaveOptions::default())?;
//! # Ok::<(), c3dfix::Error>(())
//! ```

pub mod analysis_group;
pub mod annotate;
pub mod axes;
pub mod batch;
pub mod cycles;
mod error;
pub mod evaluate;
pub mod event_group;
pub mod event_labels;
pub mod events;
mod events_session;
mod events_stand_in;
mod events_tracks;
pub mod export;
mod feet;
pub mod files;
pub mod gait_params;
mod gaps;
pub mod info;
pub mod jobs;
pub mod keyframes;
mod label_gaps;
pub mod label_stage;
mod label_write;
pub mod markers;
mod options;
pub mod plate_silence;
pub mod platforms;
mod reclaim_stage;
mod repair;
pub mod report;
mod rerun;
pub mod save;
mod session_calibration;
mod swap_stage;
mod swaps;
mod tally;
pub mod targets;
mod trial;
pub mod units;

pub use ::repair::{FillMethod, FilterSpec, ParseError, SkipKind, SpikeMode, SpikeSpec};
pub use axes::{Axes, Direction, Up, UpSource};
pub use cycles::{cycles, CycleInfo, CycleOptions, Cycles};
pub use error::{Conflict, Error, Result, Setting, PLATES_NEED_FEET};
pub use evaluate::{evaluate, EvaluateOptions, Evaluation};
pub use events::{detect_events, Detected, EventOptions, EventSource, TrialEvent};
pub use events_session::{
    lab_events, session_from, CalibrationTruth, KindReport, SessionCalibration, SessionLags,
    SessionReport,
};
pub use feet::Feet;
pub use gait_params::{gait_parameters, GaitOptions, GaitReport};
pub use gaps::{gaps, GapInfo};
pub use jobs::Jobs;
pub use keyframes::{keyframes, KeyMethod, KeyframeOptions, KeyframeReport, Keyframed};
pub use label_stage::{label, LabelReport, LabelSettings};
pub use options::{
    max_expected_error, ReclaimMode, RepairOptions, SwapsMode, DEFAULT_MAX_EXPECTED_ERROR_MM,
    DEFAULT_RECLAIM, DEFAULT_SWAPS,
};
pub use platforms::{
    force_platforms, Baseline, BaselineSource, Contact, ForceOptions, ForcePlatforms, ForcesReport,
    PlateWarning, Platform,
};
pub use reclaim_stage::{
    reclaim, Reclaim, ReclaimAction, ReclaimBrief, Reclaimed, UnsettledBrief, UnsettledWhy,
};
pub use repair::{
    repair, GapBrief, GapRow, MarkerChange, RepairBrief, Repaired, SegmentRow, SpikeRow, Summary,
    UnlabelledBrief,
};
pub use rerun::Record as RepairRecord;
pub use swap_stage::{SwapAction, SwapBrief};
pub use swaps::{swaps, SwapFind, Swaps};
pub use tally::Tally;
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
