//! Between a C3D file and the repair library: a file opened with its name attached to any
//! error, trajectories as a [`repair::Trial`] with validity from the C3D crate's one rule,
//! and repaired samples written back with the C3D manual's flags.

use crate::error::{Error, Result};
use c3d::Mark;
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

/// [`open`] for a command that reads a file and is soon done: the file is mapped rather
/// than copied into memory ([`c3d::read_file_mapped`]), so a long trial is held once, by
/// the page cache. The file must not be truncated or rewritten in place by another program
/// while the result lives; objects that live long should come from [`open`].
pub fn open_mapped(path: impl AsRef<Path>) -> Result<c3d::C3d> {
    let path = path.as_ref();
    c3d::read_file_mapped(path).map_err(|source| Error::C3d {
        path: path.to_path_buf(),
        source,
    })
}

/// The given points of `c` as a repair trial. A sample is valid unless [`c3d::is_missing`]
/// says otherwise; `zero_invalid` also treats samples at exactly (0, 0, 0) as missing, for
/// writers that store missing points that way with a valid fourth word.
///
/// The trajectories are gathered chunk by chunk from the file's bytes
/// ([`c3d::C3d::map_point_chunks`]), so the trial is the only decoded copy of them.
pub fn to_trial(c: &c3d::C3d, points: &[usize], zero_invalid: bool) -> Result<repair::Trial> {
    let g = gather(c, points, points.len(), zero_invalid);
    trial_of(c, g.xyz, g.valid)
}

fn trial_of(c: &c3d::C3d, xyz: Vec<Vec<[f64; 3]>>, valid: Vec<Vec<bool>>) -> Result<repair::Trial> {
    repair::Trial::new(c.point_rate() as f64, xyz, valid)
        .map_err(|e| Error::options(format!("cannot build the trial: {e}")))
}

/// Points read beside a trial in the same pass: their validity always, their coordinates
/// when asked for (a repair's unlabelled points, which the reclaim stage judges and the
/// summary counts).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Others {
    /// `valid[row][frame]`, by the same rule as the trial's.
    pub valid: Vec<Vec<bool>>,
    /// `xyz[row][frame]`, when decoded.
    pub xyz: Option<Vec<Vec<[f64; 3]>>>,
}

impl Others {
    /// Valid samples in all rows.
    pub fn samples(&self) -> usize {
        self.valid
            .iter()
            .map(|r| r.iter().filter(|&&x| x).count())
            .sum()
    }

    /// The rows (`points` of `c`) as a trial, decoded now if only their validity was read;
    /// the rows are lent, to be put back with [`Others::put_back`].
    pub fn lend(
        &mut self,
        c: &c3d::C3d,
        points: &[usize],
        zero_invalid: bool,
    ) -> Result<repair::Trial> {
        match self.xyz.take() {
            Some(xyz) => trial_of(c, xyz, std::mem::take(&mut self.valid)),
            None => to_trial(c, points, zero_invalid),
        }
    }

    /// The rows lent by [`Others::take_trial`], as the trial holds them now.
    pub fn put_back(&mut self, t: repair::Trial) {
        self.xyz = Some(t.xyz);
        self.valid = t.valid;
    }
}

/// [`to_trial`] of `points`, and `others` read in the same pass over the data (one walk of
/// the file's chunks rather than two): their validity, and their coordinates with
/// `others_xyz`.
pub(crate) fn to_trial_and(
    c: &c3d::C3d,
    points: &[usize],
    others: &[usize],
    others_xyz: bool,
    zero_invalid: bool,
) -> Result<(repair::Trial, Others)> {
    let all: Vec<usize> = points.iter().chain(others).copied().collect();
    let with_xyz = points.len() + if others_xyz { others.len() } else { 0 };
    let mut g = gather(c, &all, with_xyz, zero_invalid);
    let valid = g.valid.split_off(points.len());
    let xyz = others_xyz.then(|| g.xyz.split_off(points.len()));
    g.xyz.truncate(points.len());
    Ok((trial_of(c, g.xyz, g.valid)?, Others { valid, xyz }))
}

/// Which samples of some points are valid, without decoding the trial into memory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Validity {
    /// `valid[row][frame]` for the row's point (as given).
    pub valid: Vec<Vec<bool>>,
    /// Samples valid by [`c3d::is_missing`] that sit at exactly (0, 0, 0) (counted whatever
    /// `zero_invalid` says): the sign of a writer that stores missing points that way.
    pub at_origin: usize,
}

/// The validity of the given points of `c` over all frames, by the same rule as
/// [`to_trial`], in one pass over the data that holds one chunk of it at a time.
pub fn validity(c: &c3d::C3d, points: &[usize], zero_invalid: bool) -> Validity {
    let g = gather(c, points, 0, zero_invalid);
    Validity {
        valid: g.valid,
        at_origin: g.at_origin,
    }
}

struct Gathered {
    xyz: Vec<Vec<[f64; 3]>>,
    valid: Vec<Vec<bool>>,
    at_origin: usize,
}

/// Per-marker rows of validity, and of coordinates for the first `xyz_rows` rows (the
/// others' coordinate rows stay empty), filled in parallel: each chunk of frames writes its
/// own slice of every row.
fn gather(c: &c3d::C3d, points: &[usize], xyz_rows: usize, zero_invalid: bool) -> Gathered {
    let frames = c.frames();
    let rows = points.len();
    let mut xyz: Vec<Vec<[f64; 3]>> = (0..rows)
        .map(|r| vec![[0.0; 3]; if r < xyz_rows { frames } else { 0 }])
        .collect();
    let mut valid: Vec<Vec<bool>> = (0..rows).map(|_| vec![false; frames]).collect();
    let per = c.point_chunk_frames();
    type Slices<'a> = (Vec<&'a mut [[f64; 3]]>, Vec<&'a mut [bool]>);
    let mut states: Vec<Slices> = (0..c.point_chunks())
        .map(|_| (Vec::with_capacity(rows), Vec::with_capacity(rows)))
        .collect();
    for (x, v) in xyz.iter_mut().zip(valid.iter_mut()) {
        for (s, vc) in states.iter_mut().zip(v.chunks_mut(per)) {
            s.1.push(vc);
        }
        for (s, xc) in states.iter_mut().zip(x.chunks_mut(per)) {
            s.0.push(xc);
        }
    }
    let origins = c.map_point_chunks(states, |(mut xs, mut vs), view| {
        let mut origin = 0;
        // Frames outer, markers inner: the chunk is read in the order it is stored.
        for f in 0..view.frames {
            for (row, &i) in points.iter().enumerate() {
                let (p, r, _) = view.sample(f, i);
                let ok = !c3d::is_missing(p, r);
                let zero = p == [0.0; 3];
                origin += usize::from(ok && zero);
                vs[row][f] = ok && !(zero_invalid && zero);
                if row < xyz_rows {
                    xs[row][f] = [p[0] as f64, p[1] as f64, p[2] as f64];
                }
            }
        }
        origin
    });
    Gathered {
        xyz,
        valid,
        at_origin: origins.into_iter().sum(),
    }
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
) -> c3d::Result<WriteBack> {
    let frames = c.frames();
    // Integer files hold ±32767 × POINT:SCALE at most; a filter's overshoot or a fill near
    // that edge is clamped to it (and counted) rather than making the file unwritable.
    let limit = match c.format() {
        c3d::NumberFormat::Integer => Some(c.layout().point_scale as f64 * 32767.0),
        c3d::NumberFormat::Float => None,
    };
    let clamped = std::cell::Cell::new(0usize);
    let samples = points
        .iter()
        .enumerate()
        .filter(|(_, i)| only.is_none_or(|o| o.contains(i)))
        .flat_map(|(row, &i)| {
            let clamped = &clamped;
            changes[row]
                .iter()
                .enumerate()
                .take(frames)
                .filter_map(move |(f, &ch)| {
                    if ch & (change::FILLED | change::DESPIKED | change::FILTERED) != 0
                        && trial.valid[row][f]
                    {
                        let mut v = trial.xyz[row][f];
                        if let Some(l) = limit {
                            if v.iter().any(|x| x.abs() > l) {
                                clamped.set(clamped.get() + 1);
                                v = v.map(|x| x.clamp(-l, l));
                            }
                        }
                        let (xyz, r, m) =
                            Mark::Computed([v[0] as f32, v[1] as f32, v[2] as f32]).stored();
                        Some((f, i, xyz, r, m))
                    } else if ch & change::INVALIDATED != 0 {
                        let (xyz, r, m) = Mark::Missing.stored();
                        Some((f, i, xyz, r, m))
                    } else {
                        None
                    }
                })
        });
    let changed = c.patch_points(samples)?;
    Ok(WriteBack {
        changed,
        clamped: clamped.get(),
    })
}

/// One stored point sample as [`c3d::C3d::patch_points`] takes it: frame (0-based), point,
/// coordinates, residual word and camera mask.
pub(crate) type StoredSample = (usize, usize, [f32; 3], f32, u8);

/// The stored samples `each` makes of every frame of `c` (its 0-based index in the trial
/// and in the chunk's view, pushing what to write), gathered chunk by chunk as the trial is
/// stored, in parallel and without decoding the whole trial: how samples move between
/// points in the file (swaps exchanged back, unlabelled samples reclaimed) with every bit
/// they carry.
pub(crate) fn gather_samples<F>(c: &c3d::C3d, each: F) -> Vec<StoredSample>
where
    F: Fn(&c3d::PointsView<'_>, usize, usize, &mut Vec<StoredSample>) + Sync,
{
    let states = vec![(); c.point_chunks()];
    let chunks: Vec<Vec<StoredSample>> = c.map_point_chunks(states, |(), view| {
        let mut out = Vec::new();
        for f in 0..view.frames {
            each(&view, view.first_frame + f, f, &mut out);
        }
        out
    });
    chunks.into_iter().flatten().collect()
}
