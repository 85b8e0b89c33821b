//! The export job: one trial written in one format to one destination, with the rules of
//! which settings go with which format and which points each format takes by default. Both
//! fronts call [`export`]; they only parse what a person wrote and print what comes back.

use super::{analog_csv, json, mot, opensim, points_csv, trc, OpenSimExport, OpenSimOptions};
use super::{Points, Trc};
use crate::axes::Axes;
use crate::error::{Conflict, Error, Result};
use crate::save::{refuse_input, write_all, write_atomic, Content, Output};
use crate::{force_platforms, ForceOptions, PlateWarning};
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The formats a trial is exported in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportFormat {
    /// The points (and, in a second table, the analog channels) as comma-separated values.
    Csv,
    /// The markers as Motion Analysis' TRC, as OpenSim reads it.
    Trc,
    /// The whole trial as one JSON document.
    Json,
    /// The plates' ground reaction as OpenSim's motion file.
    Mot,
    /// `NAME.trc` and `NAME.mot` into a folder, turned to OpenSim's frame.
    Opensim,
}

impl ExportFormat {
    /// The format's name as people write it.
    pub fn name(self) -> &'static str {
        match self {
            ExportFormat::Csv => "csv",
            ExportFormat::Trc => "trc",
            ExportFormat::Json => "json",
            ExportFormat::Mot => "mot",
            ExportFormat::Opensim => "opensim",
        }
    }

    /// Whether an axis rotation applies: the formats OpenSim reads, whose frame it fixes.
    pub fn takes_axes(self) -> bool {
        matches!(
            self,
            ExportFormat::Trc | ExportFormat::Mot | ExportFormat::Opensim
        )
    }

    /// The points a format holds when none are named: JSON keeps the whole trial, the
    /// marker tables leave model outputs (angles, moments stored as points) out.
    pub fn default_points(self) -> Points {
        match self {
            ExportFormat::Json => Points::All,
            _ => Points::Markers,
        }
    }
}

impl fmt::Display for ExportFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ExportFormat {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        [
            ExportFormat::Csv,
            ExportFormat::Trc,
            ExportFormat::Json,
            ExportFormat::Mot,
            ExportFormat::Opensim,
        ]
        .into_iter()
        .find(|f| f.name().eq_ignore_ascii_case(s))
        .ok_or_else(|| {
            Error::options(format!(
                "unknown export format {s:?}: expected csv, trc, json, mot or opensim"
            ))
        })
    }
}

/// Where an export goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ExportDestination {
    /// Returned as text for the caller to print (every format but `opensim`).
    Text,
    /// One file (every format but `opensim`); CSV's analog table goes beside it as
    /// `NAME.analog.csv`.
    File(PathBuf),
    /// A folder (`opensim` only, whose two files are named after the trial).
    Folder(PathBuf),
}

/// What an export is asked to do.
#[derive(Debug, Clone)]
pub struct ExportOptions {
    pub format: ExportFormat,
    /// The points of a marker table; `None` takes the format's default
    /// ([`ExportFormat::default_points`]).
    pub points: Option<Points>,
    /// The lab axes as the output's X, Y, Z (the formats OpenSim reads only).
    pub axes: Option<Axes>,
    /// How the plates are computed (MOT, `opensim`).
    pub forces: ForceOptions,
    /// Replace existing files.
    pub force: bool,
}

/// What an export did.
#[derive(Debug, Clone, Default)]
pub struct Exported {
    /// The export itself, when its destination is [`ExportDestination::Text`].
    pub text: Option<String>,
    /// The files written, in order.
    pub written: Vec<PathBuf>,
    /// Labels changed to fit a TRC header (empty, or holding a tab or a line break).
    pub changed_labels: Vec<String>,
    /// The pair's report, for `opensim`.
    pub opensim: Option<OpenSimExport>,
}

/// The CSV's analog table beside its points table: `NAME.analog.csv`.
pub fn analog_csv_path(points_csv: &Path) -> PathBuf {
    points_csv.with_extension("analog.csv")
}

impl ExportOptions {
    /// Refuse settings that do not go together, before anything is read: an output that is
    /// the input, axes for a format that has no frame to turn, a folder for a one-file format
    /// or a file for the pair.
    pub fn check(&self, input: &Path, dest: &ExportDestination) -> Result<()> {
        if let ExportDestination::File(out) = dest {
            refuse_input(out, &[input], "output")?;
        }
        if self.axes.is_some() && !self.format.takes_axes() {
            return Err(Error::Conflict(Conflict::AxesFormat));
        }
        match (self.format, dest) {
            (ExportFormat::Opensim, ExportDestination::Folder(_)) => Ok(()),
            (ExportFormat::Opensim, _) => Err(Error::Conflict(Conflict::PairNeedsFolder)),
            (_, ExportDestination::Folder(_)) => Err(Error::Conflict(Conflict::FolderForPair)),
            _ => Ok(()),
        }
    }
}

/// Export the trial `c`, read from `input`, as `opts` asks, to `dest` (files written
/// atomically, the CSV's two tables together or not at all). The plates' warnings go to
/// `warn` as soon as the plates are computed, so a person hears of a plate left out even
/// when the export then fails for want of plates.
pub fn export(
    c: &c3d::C3d,
    input: &Path,
    dest: &ExportDestination,
    opts: &ExportOptions,
    warn: &mut dyn FnMut(&PlateWarning),
) -> Result<Exported> {
    opts.check(input, dest)?;
    let points = opts
        .points
        .clone()
        .unwrap_or_else(|| opts.format.default_points());
    let axes = opts.axes.unwrap_or_default();
    let mut done = Exported::default();
    let text = match opts.format {
        ExportFormat::Csv => return csv_tables(c, input, dest, &points, opts.force),
        ExportFormat::Trc => {
            let name = input.file_name().map_or_else(
                || input.display().to_string(),
                |n| n.to_string_lossy().into(),
            );
            let Trc {
                text,
                changed_labels,
            } = trc(c, &name, &points.indices(c)?, &axes)?;
            done.changed_labels = changed_labels;
            text
        }
        ExportFormat::Json => json(c, &points.indices(c)?)?,
        ExportFormat::Mot => {
            let fp = force_platforms(c, &opts.forces)?;
            fp.warnings.iter().for_each(&mut *warn);
            mot(c, &fp, input, &axes)?
        }
        ExportFormat::Opensim => {
            let ExportDestination::Folder(dir) = dest else {
                return Err(Error::Conflict(Conflict::PairNeedsFolder));
            };
            let pair = opensim(
                c,
                input,
                dir,
                &OpenSimOptions {
                    points,
                    axes: opts.axes,
                    forces: opts.forces.clone(),
                    force: opts.force,
                },
            )?;
            done.written.push(pair.trc.clone());
            done.written.extend(pair.mot.clone());
            done.changed_labels = pair.changed_labels.clone();
            pair.warnings.iter().for_each(&mut *warn);
            done.opensim = Some(pair);
            return Ok(done);
        }
    };
    match dest {
        ExportDestination::File(out) => {
            write_atomic(out, text.as_bytes(), opts.force)?;
            done.written.push(out.clone());
        }
        _ => done.text = Some(text),
    }
    Ok(done)
}

/// The points table and, when the trial has analog channels, the analog table: to a file and
/// its `NAME.analog.csv` together, or as one text with a blank line between them.
fn csv_tables(
    c: &c3d::C3d,
    input: &Path,
    dest: &ExportDestination,
    points: &Points,
    force: bool,
) -> Result<Exported> {
    let pts = points_csv(c, &points.indices(c)?);
    let ana = (c.analog().channels() > 0).then(|| analog_csv(c));
    let mut done = Exported::default();
    match dest {
        ExportDestination::File(out) => {
            let ana_path = analog_csv_path(out);
            let mut outs = vec![Output {
                path: out,
                bytes: Content::Bytes(pts.as_bytes()),
                replace: force,
            }];
            if let Some(text) = &ana {
                refuse_input(&ana_path, &[input], "analog output")?;
                outs.push(Output {
                    path: &ana_path,
                    bytes: Content::Bytes(text.as_bytes()),
                    replace: force,
                });
            }
            write_all(&outs)?;
            done.written = outs.iter().map(|o| o.path.to_path_buf()).collect();
        }
        _ => {
            let mut text = pts;
            if let Some(a) = ana {
                text.push('\n');
                text.push_str(&a);
            }
            done.text = Some(text);
        }
    }
    Ok(done)
}
