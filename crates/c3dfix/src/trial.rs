//! Between a C3D file and the repair library: a file opened with its name attached to any
//! error, trajectories as a [`repair::Trial`] with validity from the C3D crate's one rule,
//! and repaired samples written back with the C3D manual's flags.

use crate::error::{Error, Result};
use repair::change;
use std::path::Path;

/// Read a C3D file; any error names the file (and the section and byte offset).
pub fn open(path: impl AsRef<Path>) -> Result<c3d::C3d> {
    let path = path.as_ref();
    c3d::read_file(path).map_err(|source| Error::C3d {
        path: path.to_path_buf(),
        source,
    })
}

/// The given points of `c` as a repair trial. A sample is valid unless [`c3d::is_missing`]
/// says otherwise; `zero_invalid` also treats samples at exactly (0, 0, 0) as missing, for
/// writers that store missing points that way with a valid fourth word.
pub fn to_trial(c: &c3d::C3d, points: &[usize], zero_invalid: bool) -> Result<repair::Trial> {
    let p = c.points();
    let mut xyz = Vec::with_capacity(points.len());
    let mut valid = Vec::with_capacity(points.len());
    for &i in points {
        let t: Vec<[f64; 3]> = p
            .trajectory(i)
            .into_iter()
            .map(|v| [v[0] as f64, v[1] as f64, v[2] as f64])
            .collect();
        let v: Vec<bool> = (0..p.frames())
            .map(|f| p.is_valid(f, i) && !(zero_invalid && t[f] == [0.0; 3]))
            .collect();
        valid.push(v);
        xyz.push(t);
    }
    repair::Trial::new(c.point_rate() as f64, xyz, valid)
        .map_err(|e| Error::options(format!("cannot build the trial: {e}")))
}

/// What [`write_back`] did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct WriteBack {
    /// Samples given new values or flags.
    pub changed: usize,
    /// Of those, samples clamped to the integer range of the file's POINT:SCALE.
    pub clamped: usize,
}

/// Write the repair of `points` (the trial's rows) back into `c`. Filled, despiked and
/// filtered samples get their new coordinates with residual 0 and camera mask 0, the C3D
/// manual's mark for processed points; samples invalidated and not refilled become missing;
/// every other sample keeps its bits. A sample that was missing comes out valid only where a
/// fill method filled it (`trial.valid` is then true), never through a filter. Only markers
/// in `only` (point indices) are written when given.
pub fn write_back(
    c: &mut c3d::C3d,
    trial: &repair::Trial,
    points: &[usize],
    changes: &[Vec<u8>],
    only: Option<&[usize]>,
) -> WriteBack {
    let mut w = WriteBack::default();
    let frames = c.points().frames();
    // Integer files hold ±32767 × POINT:SCALE at most; a filter's overshoot or a fill near
    // that edge is clamped to it (and counted) rather than making the file unwritable.
    let limit = match c.format() {
        c3d::NumberFormat::Integer => Some(c.layout().point_scale as f64 * 32767.0),
        c3d::NumberFormat::Float => None,
    };
    let pts = c.points_mut();
    for (row, &i) in points.iter().enumerate() {
        if only.is_some_and(|o| !o.contains(&i)) {
            continue;
        }
        for (f, &ch) in changes[row].iter().enumerate().take(frames) {
            if ch == 0 {
                continue;
            }
            let k = pts.index(f, i);
            if ch & (change::FILLED | change::DESPIKED | change::FILTERED) != 0
                && trial.valid[row][f]
            {
                let mut v = trial.xyz[row][f];
                if let Some(l) = limit {
                    if v.iter().any(|x| x.abs() > l) {
                        w.clamped += 1;
                        v = v.map(|x| x.clamp(-l, l));
                    }
                }
                pts.xyz[k] = [v[0] as f32, v[1] as f32, v[2] as f32];
                pts.residual[k] = 0.0;
                pts.camera_mask[k] = 0;
                w.changed += 1;
            } else if ch & change::INVALIDATED != 0 {
                pts.xyz[k] = [0.0; 3];
                pts.residual[k] = -1.0;
                pts.camera_mask[k] = 0;
                w.changed += 1;
            }
        }
    }
    w
}
