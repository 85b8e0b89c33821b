//! A trial as OpenSim takes it: `NAME.trc` (markers) and `NAME.mot` (ground reaction) on one
//! time base, in OpenSim's frame (Y up, X the direction of travel when there is one).

use super::{mot, trc, Points};
use crate::axes::{self, Axes, Direction, Up};
use crate::error::{Error, Result};
use crate::save::{write_all, Content, Output};
use crate::{ForceOptions, PlateWarning};
use std::path::{Path, PathBuf};

/// Travel shorter than this (mm) is no direction of walking: a step or a sway.
const MIN_TRAVEL_MM: f64 = 500.0;

/// How [`opensim`] writes.
#[derive(Debug, Clone, Default)]
pub struct OpenSimOptions {
    /// The points of the TRC (default: the markers, no model outputs).
    pub points: Points,
    /// The lab axes as OpenSim's X, Y, Z; `None` turns the lab's up ([`axes::up`]) to Y
    /// and the direction of travel, when there is one, to X.
    pub axes: Option<Axes>,
    /// How the plates are computed for the MOT.
    pub forces: ForceOptions,
    /// Replace existing files.
    pub force: bool,
}

/// What [`opensim`] wrote.
#[derive(Debug, Clone)]
pub struct OpenSimExport {
    pub trc: PathBuf,
    /// `None` when the trial has no force plates that can be computed.
    pub mot: Option<PathBuf>,
    /// The rotation applied (lab axes as OpenSim's X, Y, Z).
    pub axes: Axes,
    /// The lab's up, when found (not needed when the axes were given).
    pub up: Option<Up>,
    /// The direction of travel turned to X, when one was found.
    pub forward: Option<Direction>,
    /// Labels changed to fit the TRC header.
    pub changed_labels: Vec<String>,
    /// The plates' warnings.
    pub warnings: Vec<PlateWarning>,
}

/// Write `NAME.trc` and, when the trial has force plates, `NAME.mot` into `out_dir` (NAME:
/// `input`'s stem), together or not at all. Marker coordinates stay in POINT:UNITS (the TRC
/// says which, and OpenSim scales them); the MOT is in N, m and N·m. Refused when POINT:UNITS
/// is no length unit, or when no up can be found and no axes were given.
pub fn opensim(
    c: &c3d::C3d,
    input: &Path,
    out_dir: &Path,
    opts: &OpenSimOptions,
) -> Result<OpenSimExport> {
    let units = c.point_units();
    let mm = crate::units::length_mm(&units).map_err(|source| Error::Unit {
        path: input.to_path_buf(),
        parameter: "POINT:UNITS".into(),
        source,
    })?;
    let stem = input
        .file_stem()
        .map_or_else(|| "trial".into(), |s| s.to_string_lossy().into_owned());
    let up = axes::up(c);
    let (rotation, forward) = match (opts.axes, up) {
        (Some(a), _) => (a, None),
        (None, Some(u)) => {
            let forward = axes::travel(c, u.up, MIN_TRAVEL_MM / mm);
            (Axes::opensim(u.up, forward), forward)
        }
        (None, None) => {
            return Err(Error::NoUp {
                path: input.to_path_buf(),
            })
        }
    };
    let points = opts.points.indices(c)?;
    let name = input
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let t = trc(c, &name, &points, &rotation)?;
    let has_plates = !c.platform_params().plates.is_empty();
    // A file whose FORCE_PLATFORM names plates none of which can be computed gets its TRC
    // and the plates' warnings.
    let (mot_text, warnings) = if has_plates {
        let fp = crate::force_platforms(c, &opts.forces)?;
        let text = if fp.platforms.is_empty() {
            None
        } else {
            Some(mot(c, &fp, input, &rotation)?)
        };
        (text, fp.warnings)
    } else {
        (None, Vec::new())
    };
    let trc_path = out_dir.join(format!("{stem}.trc"));
    let mot_path = out_dir.join(format!("{stem}.mot"));
    let mut outs = vec![Output {
        path: &trc_path,
        bytes: Content::Bytes(t.text.as_bytes()),
        replace: opts.force,
    }];
    if let Some(m) = &mot_text {
        outs.push(Output {
            path: &mot_path,
            bytes: Content::Bytes(m.as_bytes()),
            replace: opts.force,
        });
    }
    // The folder is made only once both files are ready, as `batch --out-dir` makes its
    // folders: a refused export leaves nothing behind.
    std::fs::create_dir_all(out_dir)
        .map_err(|e| Error::Output(format!("cannot make the folder {}: {e}", out_dir.display())))?;
    write_all(&outs)?;
    Ok(OpenSimExport {
        trc: trc_path.clone(),
        mot: mot_text.map(|_| mot_path.clone()),
        axes: rotation,
        up,
        forward,
        changed_labels: t.changed_labels,
        warnings,
    })
}
