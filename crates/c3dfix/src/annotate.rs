//! Annotating a trial file (`c3dfix events`, `c3dfix gait`): open it, compute what it is
//! asked for, write that into the trial's own group (EVENT, ANALYSIS) and save it where
//! asked, on one path for both jobs.

use crate::error::{Error, Result};
use crate::events::{detect_events, Detected, EventOptions};
use crate::gait_params::{gait_parameters, GaitOptions, GaitReport};
use crate::save::refuse_own_input;
use crate::trial::{open, open_mapped};
use crate::SaveOptions;
use std::path::Path;

/// Where an annotated trial goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Annotate<'a> {
    /// Nowhere: the result is only reported, the file is not rewritten.
    Report,
    /// To this file (never the input itself), replacing it only with `force`.
    To { output: &'a Path, force: bool },
    /// Into the input itself (atomically), keeping it first as `FILE.bak` with `backup`.
    InPlace { backup: bool },
}

/// `compute` on the trial at `path`, and, unless `dest` is [`Annotate::Report`], `write`
/// of its result into the trial, saved to `dest` (an output that is the input itself is
/// refused: writing into the input is asked for as in place). A trial to be written is
/// read into memory, not mapped: it may be the file replaced.
fn annotate<R>(
    path: &Path,
    dest: Annotate<'_>,
    compute: impl FnOnce(&c3d::C3d) -> Result<R>,
    write: impl FnOnce(&mut c3d::C3d, &R) -> Result<()>,
) -> Result<R> {
    let (to, save) = match dest {
        Annotate::Report => {
            let c = open_mapped(path)?;
            return compute(&c);
        }
        Annotate::To { output, force } => (
            output,
            SaveOptions {
                force,
                backup: false,
            },
        ),
        Annotate::InPlace { backup } => (
            path,
            SaveOptions {
                force: true,
                backup,
            },
        ),
    };
    let mut c = open(path)?;
    let r = compute(&c)?;
    write(&mut c, &r).map_err(|e| Error::Trial {
        path: path.to_path_buf(),
        what: e.to_string(),
    })?;
    if let Annotate::To { output, .. } = dest {
        refuse_own_input(path, output)?;
    }
    crate::save(&c, to, &save)?;
    Ok(r)
}

/// The gait events of the trial at `path` (see [`detect_events`]), written into its EVENT
/// group as Nexus writes them (with `replace`, in place of its Foot Strike and Foot Off
/// events; see [`crate::event_group::write_events`]) unless `dest` only reports them.
pub fn events_file(
    path: &Path,
    opts: &EventOptions,
    replace: bool,
    dest: Annotate<'_>,
) -> Result<Detected> {
    annotate(
        path,
        dest,
        |c| detect_events(c, opts, path),
        |c, d| crate::event_group::write_events(c, &d.events, replace).map(|_| ()),
    )
}

/// The gait-cycle parameters of the trial at `path` (see [`gait_parameters`]), written into
/// its ANALYSIS group as Nexus writes them unless `dest` only reports them.
pub fn gait_file(path: &Path, opts: &GaitOptions, dest: Annotate<'_>) -> Result<GaitReport> {
    annotate(
        path,
        dest,
        |c| gait_parameters(c, opts, path),
        |c, r| crate::analysis_group::write_parameters(c, &r.parameters).map(|_| ()),
    )
}
