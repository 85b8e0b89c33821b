//! The lab's axes: which way is up, found once for every output (`info`, the viewer, plots,
//! the OpenSim export), and [`Axes`], the proper rotation that turns the lab's axes into
//! another program's (an export's axes setting, OpenSim's Y-up frame).
//!
//! Up comes from the plates when the file has any: a plate lies in the floor, so the normal
//! of its CORNERS' plane is the lab's vertical, and the manual's corner order (quadrants
//! +x+y, −x+y, −x−y, +x−y of the plate's own axes, whose z points down into the plate) gives
//! its sign. Without plates it comes from the markers (never model outputs, whose angles and
//! moments are no positions): first from the floor, where one shows (the one direction along
//! which each frame's lowest marker stays just above the lab's origin: a body keeps touching
//! the floor, and labs put their origin on it); else a person is taller than wide or deep,
//! so the axis along which the markers of one frame spread most is vertical, and they stand
//! above the floor, so the sign is that of their median height.

use crate::error::{Error, Result, Setting};
use serde::Serialize;
use std::fmt;

/// A lab axis with a sign: `+z`, `-y`, ….
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Direction {
    /// 0 x, 1 y, 2 z.
    pub axis: usize,
    /// True for the axis' positive direction.
    pub positive: bool,
}

impl Direction {
    /// The direction as a unit vector of the lab frame.
    pub fn vector(self) -> [f64; 3] {
        let mut v = [0.0; 3];
        v[self.axis] = if self.positive { 1.0 } else { -1.0 };
        v
    }

    fn sign(self) -> f64 {
        if self.positive {
            1.0
        } else {
            -1.0
        }
    }
}

impl fmt::Display for Direction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = if self.positive { '+' } else { '-' };
        write!(f, "{s}{}", ['x', 'y', 'z'][self.axis.min(2)])
    }
}

impl Serialize for Direction {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// What the lab's up was read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum UpSource {
    /// The normal of the force plates' CORNERS.
    Plates,
    /// The markers' spread and height.
    Markers,
}

impl fmt::Display for UpSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            UpSource::Plates => "the force plates",
            UpSource::Markers => "the markers",
        })
    }
}

/// The lab's vertical, and what it was read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Up {
    pub up: Direction,
    pub source: UpSource,
}

/// The lab's up for `c`: from the plates when their CORNERS say it, else from the markers;
/// `None` when neither does (no plates and no valid marker sample).
pub fn up(c: &c3d::C3d) -> Option<Up> {
    plates_up(c)
        .map(|up| Up {
            up,
            source: UpSource::Plates,
        })
        .or_else(|| {
            markers_up(c).map(|up| Up {
                up,
                source: UpSource::Markers,
            })
        })
}

/// The up the plates' corners give: each plate's working surface faces the opposite of the
/// plate's own z, i.e. −(c1 − c3) × (c2 − c4) in the manual's corner order. Plates whose
/// corners are absent, not finite or degenerate are skipped; the plates that remain vote,
/// each for the lab axis its normal is closest to.
pub fn plates_up(c: &c3d::C3d) -> Option<Direction> {
    vote(c.platform_params().plates.iter().filter_map(|p| p.corners))
}

/// [`plates_up`] for plates already computed.
pub fn platforms_up(fp: &crate::ForcePlatforms) -> Option<Direction> {
    vote(fp.platforms.iter().map(|p| p.corners))
}

/// The direction most plates' corners give (ties: the earlier axis, +z before others only
/// through the vote).
fn vote(corners: impl Iterator<Item = [[f64; 3]; 4]>) -> Option<Direction> {
    let mut votes = [0usize; 6];
    for k in corners {
        if let Some(d) = corners_up(&k) {
            votes[d.axis * 2 + usize::from(d.positive)] += 1;
        }
    }
    let (best, &n) = votes
        .iter()
        .enumerate()
        .max_by_key(|&(i, &n)| (n, std::cmp::Reverse(i)))?;
    (n > 0).then_some(Direction {
        axis: best / 2,
        positive: best % 2 == 1,
    })
}

/// The up of one plate from its four corners (see [`plates_up`]). `None` for corners that
/// are no plate lying in a lab plane: not finite, degenerate, diagonals of unequal length
/// (vendor test files hold 0 and 1e10 there), or a normal more than ~25° off every lab axis.
pub fn corners_up(k: &[[f64; 3]; 4]) -> Option<Direction> {
    let d1 = [k[0][0] - k[2][0], k[0][1] - k[2][1], k[0][2] - k[2][2]];
    let d2 = [k[1][0] - k[3][0], k[1][1] - k[3][1], k[1][2] - k[3][2]];
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let (l1, l2) = (norm(d1), norm(d2));
    // A rectangle's diagonals are equally long.
    if !(l1.is_finite() && l2.is_finite() && l1 > 0.0 && l2 > 0.0)
        || (l1 - l2).abs() > 0.1 * l1.max(l2)
    {
        return None;
    }
    // The plate's z (down into it) is d1 × d2; its surface faces the opposite.
    let n = [
        -(d1[1] * d2[2] - d1[2] * d2[1]),
        -(d1[2] * d2[0] - d1[0] * d2[2]),
        -(d1[0] * d2[1] - d1[1] * d2[0]),
    ];
    let len = norm(n);
    if !(len.is_finite() && len > 0.0) {
        return None;
    }
    let axis = (0..3).max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))?;
    (n[axis].abs() >= 0.9 * len).then_some(Direction {
        axis,
        positive: n[axis] > 0.0,
    })
}

/// The up the markers give (model outputs left out): the floor's, where one shows (the one
/// direction along which every sampled frame's lowest marker stays in a narrow band just
/// above the origin); else the axis of the largest median spread
/// within a frame, over up to 64 frames spread through the trial, signed by the markers'
/// median coordinate along it (a body stands above a floor at 0). The spread is that of the
/// middle 80 % of the frame's markers (10th to 90th percentile), so a hockey stick's blade
/// or a few points computed far from the body (Plug-in Gait's segment axes) do not outweigh
/// the body's height. `None` without a frame holding two valid markers.
pub fn markers_up(c: &c3d::C3d) -> Option<Direction> {
    let markers = crate::markers::marker_indices(c);
    let frames = c.frames();
    let step = (frames / 64).max(1);
    // Only the sampled frames are read, chunk by chunk from the file's bytes where the points
    // are not decoded yet: `info` on a long trial stays within a little more than the file.
    let chunk = c.point_chunk_frames().max(1);
    let states: Vec<usize> = (0..c.point_chunks()).collect();
    let per_chunk: Vec<Vec<[Vec<f32>; 3]>> = c.map_point_chunks(states, |i, view| {
        let first = i * chunk;
        let mut out = Vec::new();
        let start = first.div_ceil(step) * step;
        for f in (start..first + view.frames).step_by(step) {
            let mut frame: [Vec<f32>; 3] = [Vec::new(), Vec::new(), Vec::new()];
            for &m in &markers {
                let (v, r, _) = view.sample(f - first, m);
                if !c3d::is_missing(v, r) {
                    for a in 0..3 {
                        frame[a].push(v[a]);
                    }
                }
            }
            out.push(frame);
        }
        out
    });
    let mm = c3d::mm_per_unit(&c.point_units()) as f32;
    let frames: Vec<[Vec<f32>; 3]> = per_chunk.into_iter().flatten().collect();
    let mut lowest = lowest_per_direction(&frames, mm);
    if let Some(d) = floor(&mut lowest) {
        return Some(d);
    }
    trunk_up(c, step, mm).or_else(|| frames_up(frames.into_iter(), mm))
}

/// The least length (mm) of the pelvis-to-upper-trunk vector for it to say where up is: a
/// seated or stooping adult's trunk is longer than this, a pelvis and a shoulder marker of
/// a lying subject come no nearer to vertical.
const TRUNK_MM: f64 = 250.0;

/// The up of a trunk that stands: where the markers name the pelvis (ASIS, PSIS, sacrum) and
/// the upper trunk (C7, T1, clavicle, sternum, acromion, shoulder, head), the median over
/// the sampled frames of the vector from the pelvis markers' mean to the upper ones'. Taken
/// when it is at least [`TRUNK_MM`] long and lies within ~37° of one lab axis: a person
/// standing, walking, lifting or seated holds the trunk up, while the markers' spread may
/// lie across (an upper-body set whose box is held at arm's length spreads farther
/// forward than the pelvis-to-shoulder height: `c3d-labs`' pyomeca lifting read +x).
/// A subject lying down is stood up by the floor first ([`floor`]).
fn trunk_up(c: &c3d::C3d, step: usize, mm: f32) -> Option<Direction> {
    let labels = c.point_labels();
    let markers = crate::markers::marker_indices(c);
    let named = |is: fn(&str) -> bool| -> Vec<usize> {
        markers
            .iter()
            .copied()
            .filter(|&i| {
                labels
                    .get(i)
                    .is_some_and(|l| is(&gait::markers::canonical(l)))
            })
            .collect()
    };
    let pelvis = named(is_pelvis);
    let upper = named(is_upper_trunk);
    if pelvis.is_empty() || upper.is_empty() {
        return None;
    }
    // The sampled frames only, chunk by chunk, as [`markers_up`] reads them.
    let chunk = c.point_chunk_frames().max(1);
    let states: Vec<usize> = (0..c.point_chunks()).collect();
    let per_chunk: Vec<Vec<[f64; 3]>> = c.map_point_chunks(states, |i, view| {
        let first = i * chunk;
        let start = first.div_ceil(step) * step;
        let mean = |f: usize, set: &[usize]| -> Option<[f64; 3]> {
            let mut s = [0.0; 3];
            let mut n = 0.0;
            for &m in set {
                let (v, r, _) = view.sample(f - first, m);
                if !c3d::is_missing(v, r) {
                    for k in 0..3 {
                        s[k] += f64::from(v[k]);
                    }
                    n += 1.0;
                }
            }
            (n > 0.0).then(|| s.map(|x| x / n))
        };
        (start..first + view.frames)
            .step_by(step)
            .filter_map(|f| {
                let (a, b) = (mean(f, &pelvis)?, mean(f, &upper)?);
                Some([0, 1, 2].map(|k| (b[k] - a[k]) * f64::from(mm)))
            })
            .collect()
    });
    let mut comp: [Vec<f64>; 3] = Default::default();
    for v in per_chunk.into_iter().flatten() {
        for k in 0..3 {
            comp[k].push(v[k]);
        }
    }
    let v: Vec<f64> = comp
        .iter_mut()
        .map(|x| {
            x.sort_by(f64::total_cmp);
            x.get(x.len() / 2).copied()
        })
        .collect::<Option<Vec<f64>>>()?;
    let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let axis = (0..3).max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))?;
    (len >= TRUNK_MM && v[axis].abs() >= 0.8 * len).then_some(Direction {
        axis,
        positive: v[axis] > 0.0,
    })
}

/// A pelvis landmark's label (as [`gait::markers::canonical`] gives it).
fn is_pelvis(n: &str) -> bool {
    let part = n.strip_prefix(['l', 'r']).unwrap_or(n);
    ["asi", "psi", "ias", "ips"].contains(&part)
        || ["asis", "psis", "sacr", "sacrum", "vsac"]
            .iter()
            .any(|s| n.starts_with(s) || part.starts_with(s))
}

/// An upper-trunk or head landmark's label (as [`gait::markers::canonical`] gives it).
fn is_upper_trunk(n: &str) -> bool {
    let part = n.strip_prefix(['l', 'r']).unwrap_or(n);
    ["c7", "t1", "sho", "fhd", "bhd"].contains(&n)
        || ["sho", "fhd", "bhd", "acr"].contains(&part)
        || ["clav", "strn", "ster", "acro", "head"]
            .iter()
            .any(|s| n.starts_with(s) || part.starts_with(s))
}

/// Per direction (−x, +x, −y, …), the height (mm) of each sampled frame's lowest marker,
/// for [`floor`].
fn lowest_per_direction(frames: &[[Vec<f32>; 3]], mm: f32) -> [Vec<f32>; 6] {
    let mut lowest: [Vec<f32>; 6] = Default::default();
    for frame in frames {
        if frame[0].len() >= 2 {
            for a in 0..3 {
                let lo = frame[a].iter().copied().fold(f32::INFINITY, f32::min);
                let hi = frame[a].iter().copied().fold(f32::NEG_INFINITY, f32::max);
                lowest[2 * a].push(-hi * mm);
                lowest[2 * a + 1].push(lo * mm);
            }
        }
    }
    lowest
}

/// [`markers_up`]'s rule for positions held in memory (a BVH skeleton's joints, which have
/// no C3D file to read them from): every point of `p` counts, over the same sampled frames,
/// in `mm` millimetres per unit of the data.
pub fn points_up(p: &c3d::Points, mm: f32) -> Option<Direction> {
    let step = (p.frames() / 64).max(1);
    let frames = (0..p.frames()).step_by(step).map(|f| {
        let mut frame: [Vec<f32>; 3] = [Vec::new(), Vec::new(), Vec::new()];
        for i in 0..p.count() {
            if p.is_valid(f, i) {
                let v = p.xyz[p.index(f, i)];
                for a in 0..3 {
                    frame[a].push(v[a]);
                }
            }
        }
        frame
    });
    frames_up(frames, mm)
}

/// The decision of [`markers_up`] from the valid samples of each sampled frame (per axis),
/// `mm` millimetres per unit.
fn frames_up(frames: impl Iterator<Item = [Vec<f32>; 3]>, mm: f32) -> Option<Direction> {
    let mut spread = [Vec::new(), Vec::new(), Vec::new()];
    let mut heights = [Vec::new(), Vec::new(), Vec::new()];
    // Per direction (−x, +x, −y, …), the height of each sampled frame's lowest marker.
    let mut lowest: [Vec<f32>; 6] = Default::default();
    for mut frame in frames {
        for a in 0..3 {
            heights[a].extend_from_slice(&frame[a]);
        }
        if frame[0].len() >= 2 {
            for a in 0..3 {
                frame[a].sort_by(f32::total_cmp);
                let n = frame[a].len() - 1;
                let at = |q: usize| frame[a][(n * q + 50) / 100];
                spread[a].push(at(90) - at(10));
                lowest[2 * a].push(-frame[a][n] * mm);
                lowest[2 * a + 1].push(frame[a][0] * mm);
            }
        }
    }
    let median = |v: &mut Vec<f32>| {
        v.sort_by(f32::total_cmp);
        v.get(v.len() / 2).copied()
    };
    if let Some(d) = floor(&mut lowest) {
        return Some(d);
    }
    let m: Vec<f32> = spread
        .iter_mut()
        .map(median)
        .collect::<Option<Vec<f32>>>()?;
    // Ties go to z, then y: the conventions labs use most.
    let axis = (0..3).max_by(|&a, &b| m[a].total_cmp(&m[b]).then(a.cmp(&b)))?;
    let h = median(&mut heights[axis]).unwrap_or(0.0);
    Some(Direction {
        axis,
        positive: h >= 0.0,
    })
}

/// The up a floor gives, where one shows: the direction along which every sampled frame's
/// lowest marker stays in a narrow band just above the lab's origin. A body on a floor
/// touches it again and again whatever it does (feet in a walk, a back, hips and hands in
/// a roll), so its lowest marker hovers a marker's radius to a foot's height above it, and
/// labs put their origin on the floor; along a horizontal axis the lowest marker moves
/// with the body. This is what a subject lying or rolling on the floor, wider than tall,
/// is stood up by. `lowest[2a + s]` holds each frame's lowest height (mm) along axis `a`
/// (s = 1 for the positive direction). `None` unless exactly one direction has such a
/// floor (a standing trial keeps every axis' lowest marker still; the origin decides it
/// only when it lies under the body alone).
fn floor(lowest: &mut [Vec<f32>; 6]) -> Option<Direction> {
    let mut found = None;
    for (i, v) in lowest.iter_mut().enumerate() {
        if v.len() < 8 {
            return None;
        }
        v.sort_by(f32::total_cmp);
        let n = v.len() - 1;
        let (p5, p95) = (v[(n * 5 + 50) / 100], v[(n * 95 + 50) / 100]);
        if p5 >= FLOOR_BELOW && p95 <= FLOOR_ABOVE && p95 - p5 <= FLOOR_BAND {
            if found.is_some() {
                return None;
            }
            found = Some(Direction {
                axis: i / 2,
                positive: i % 2 == 1,
            });
        }
    }
    found
}

/// How far below the origin (mm) a frame's lowest marker may be on a floor at the origin:
/// floors are levelled to a few millimetres, and a calibration wand's origin to about as much.
const FLOOR_BELOW: f32 = -20.0;
/// How high (mm) the lowest marker of a frame on the floor may be: a shoe's toe and heel
/// markers, or a marker on a back, stand up to about this.
const FLOOR_ABOVE: f32 = 150.0;
/// How much (mm) the lowest marker's height may wander over the trial (5th to 95th
/// percentile of the frames).
const FLOOR_BAND: f32 = 100.0;

/// The direction of travel on the floor: the horizontal lab axis along which the markers'
/// centroid moves furthest from the first frame to the last, signed by that move. `None`
/// when the centroid moves less than `min_travel` (POINT:UNITS) along every horizontal axis,
/// or comes back most of the way (a walk there and back, a standing trial): there is no
/// one direction to turn to OpenSim's X then.
pub fn travel(c: &c3d::C3d, up: Direction, min_travel: f64) -> Option<Direction> {
    let p = c.points();
    let markers = crate::markers::marker_indices(c);
    let centroid = |f: usize| -> Option<[f64; 3]> {
        let mut s = [0.0f64; 3];
        let mut n = 0usize;
        for &i in &markers {
            if p.is_valid(f, i) {
                let v = p.xyz[p.index(f, i)];
                for a in 0..3 {
                    s[a] += f64::from(v[a]);
                }
                n += 1;
            }
        }
        (n * 2 >= markers.len() && n > 0).then(|| s.map(|x| x / n as f64))
    };
    let path: Vec<[f64; 3]> = (0..p.frames()).filter_map(centroid).collect();
    let (first, last) = (path.first()?, path.last()?);
    let mut best: Option<(f64, Direction)> = None;
    for axis in (0..3).filter(|&a| a != up.axis) {
        let net = last[axis] - first[axis];
        let (lo, hi) = path
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v[axis]), hi.max(v[axis]))
            });
        // Straight travel: the net move is most of the range covered.
        if net.abs() >= min_travel && net.abs() >= 0.8 * (hi - lo) {
            let d = Direction {
                axis,
                positive: net > 0.0,
            };
            if best.is_none_or(|(b, _)| net.abs() > b) {
                best = Some((net.abs(), d));
            }
        }
    }
    best.map(|(_, d)| d)
}

/// A proper rotation of the lab's axes: output axis `k` is `sign × lab[axis]`. Parsed from
/// an export's axes setting ([`Axes::parse`]), e.g. `x,z,-y` for OpenSim's Y-up frame from a Z-up lab, or built from the lab's
/// up ([`Axes::opensim`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes {
    rows: [(usize, f64); 3],
}

impl Default for Axes {
    fn default() -> Self {
        Axes {
            rows: [(0, 1.0), (1, 1.0), (2, 1.0)],
        }
    }
}

impl fmt::Display for Axes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<String> = self
            .rows
            .iter()
            .map(|&(axis, sign)| {
                Direction {
                    axis,
                    positive: sign > 0.0,
                }
                .to_string()
                .trim_start_matches('+')
                .to_string()
            })
            .collect();
        f.write_str(&names.join(","))
    }
}

impl Axes {
    /// Parse `a,b,c` where each is `x`, `y` or `z` with an optional sign. Only a permutation
    /// with signs and determinant +1 is taken: anything else would mirror the data (a left
    /// foot becomes a right one, moments change sign), which no export should do silently.
    pub fn parse(spec: &str) -> Result<Axes> {
        let hint = "expected three lab axes with signs, a rotation such as x,z,-y (OpenSim's Y-up from a Z-up lab)";
        let bad = |why: String| Error::Invalid {
            setting: Setting::Axes,
            value: spec.to_string(),
            why,
        };
        let parts: Vec<&str> = spec.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(bad(hint.to_string()));
        }
        let mut rows = [(0usize, 1.0f64); 3];
        let mut seen = [false; 3];
        for (k, part) in parts.iter().enumerate() {
            let (sign, name) = match part.strip_prefix('-') {
                Some(rest) => (-1.0, rest),
                None => (1.0, part.strip_prefix('+').unwrap_or(part)),
            };
            let axis = match name.to_ascii_lowercase().as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => return Err(bad(format!("{part:?} is no lab axis; {hint}"))),
            };
            if seen[axis] {
                return Err(bad(format!("lab axis {name} is used twice; {hint}")));
            }
            seen[axis] = true;
            rows[k] = (axis, sign);
        }
        let a = Axes { rows };
        if a.determinant() < 0.0 {
            return Err(bad(format!(
                "not a rotation (determinant -1: it mirrors the data, turning left into right); {hint}"
            )));
        }
        Ok(a)
    }

    /// OpenSim's frame (X forward, Y up, Z to the right) from the lab's `up` and, when
    /// known, the direction of travel `forward` (horizontal). Without one, X is the first
    /// horizontal axis in cyclic order after up (x under +z, so a Z-up lab gives `x,z,-y`).
    pub fn opensim(up: Direction, forward: Option<Direction>) -> Axes {
        let forward = forward.filter(|f| f.axis != up.axis).unwrap_or(Direction {
            axis: horizontal_axes(up.axis)[0],
            positive: true,
        });
        // Z = X × Y: a unit axis too, since X and Y are two different lab axes.
        let (x, y) = (forward.vector(), up.vector());
        let z = [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ];
        let z_axis = 3 - forward.axis - up.axis;
        Axes {
            rows: [
                (forward.axis, forward.sign()),
                (up.axis, up.sign()),
                (z_axis, z[z_axis].signum()),
            ],
        }
    }

    /// +1 for a rotation, −1 for a reflection: the permutation's parity times the signs.
    fn determinant(&self) -> f64 {
        let p = self.rows.map(|r| r.0);
        let inversions = (0..3)
            .flat_map(|i| (i + 1..3).map(move |j| (i, j)))
            .filter(|&(i, j)| p[i] > p[j])
            .count();
        let parity = if inversions % 2 == 0 { 1.0 } else { -1.0 };
        parity * self.rows.iter().map(|r| r.1).product::<f64>()
    }

    /// `v` (lab frame) in the output's axes.
    pub fn apply(&self, v: [f64; 3]) -> [f64; 3] {
        self.rows.map(|(axis, sign)| sign * v[axis])
    }

    /// [`Axes::apply`] for single-precision samples.
    pub fn apply_f32(&self, v: [f32; 3]) -> [f32; 3] {
        self.rows.map(|(axis, sign)| sign as f32 * v[axis])
    }
}

/// The two horizontal lab axes for a vertical one, in the cyclic order that keeps a top view
/// right-handed (x, y under z; z, x under y; y, z under x).
pub fn horizontal_axes(up: usize) -> [usize; 2] {
    [(up + 1) % 3, (up + 2) % 3]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(axis: usize, positive: bool) -> Direction {
        Direction { axis, positive }
    }

    #[test]
    fn axes_take_rotations_and_refuse_reflections() {
        let a = Axes::parse("x,z,-y").unwrap();
        assert_eq!(a.apply([1.0, 2.0, 3.0]), [1.0, 3.0, -2.0]);
        assert_eq!(Axes::parse(" X , Y , +Z ").unwrap(), Axes::default());
        assert_eq!(
            Axes::parse("y,z,x").unwrap().apply([1.0, 2.0, 3.0]),
            [2.0, 3.0, 1.0]
        );
        assert_eq!(
            Axes::parse("-x,-y,z").unwrap().apply([1.0, 2.0, 3.0]),
            [-1.0, -2.0, 3.0]
        );
        for bad in [
            "x,z,y", "x,y,-z", "-x,y,z", "y,x,z", "x,x,z", "x,y", "x,y,w", "",
        ] {
            assert!(Axes::parse(bad).is_err(), "{bad}");
        }
        // The refusal names the setting in plain words; each front end says its own flag
        // or keyword (the command line's `--axes`).
        match Axes::parse("x,y") {
            Err(e @ Error::Invalid { .. }) => assert_eq!(
                e.to_string(),
                "axes x,y: expected three lab axes with signs, a rotation such as x,z,-y (OpenSim's Y-up from a Z-up lab)"
            ),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn opensim_axes_are_rotations_with_up_as_y() {
        assert_eq!(Axes::opensim(dir(2, true), None).to_string(), "x,z,-y");
        assert_eq!(Axes::opensim(dir(1, true), None).to_string(), "z,y,-x");
        assert_eq!(
            Axes::opensim(dir(2, true), Some(dir(1, true))).to_string(),
            "y,z,x"
        );
        assert_eq!(
            Axes::opensim(dir(2, true), Some(dir(0, false))).to_string(),
            "-x,z,y"
        );
        for axis in 0..3 {
            for positive in [true, false] {
                let up = dir(axis, positive);
                for f in [None, Some(dir((axis + 1) % 3, false))] {
                    let a = Axes::opensim(up, f);
                    assert_eq!(a.determinant(), 1.0, "{up} {f:?}");
                    assert_eq!(a.apply(up.vector()), [0.0, 1.0, 0.0]);
                    assert_eq!(Axes::parse(&a.to_string()).unwrap(), a);
                }
            }
        }
    }

    #[test]
    fn a_plate_faces_up_in_the_manuals_corner_order() {
        // Quadrants +x+y, −x+y, −x−y, +x−y of a plate whose z points down: seen from above
        // (lab +z) the corners go clockwise.
        let k = [
            [500.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 600.0, 0.0],
            [500.0, 600.0, 0.0],
        ];
        assert_eq!(corners_up(&k), Some(dir(2, true)));
        let mut rev = k;
        rev.reverse();
        assert_eq!(corners_up(&rev), Some(dir(2, false)));
        assert_eq!(corners_up(&[[0.0; 3]; 4]), None);
    }

    /// Each frame's lowest height along −x, +x, −y, +y, −z, +z for frames of `pts`.
    fn lowest(frames: &[Vec<[f32; 3]>]) -> [Vec<f32>; 6] {
        let mut out: [Vec<f32>; 6] = Default::default();
        for f in frames {
            for a in 0..3 {
                let lo = f.iter().map(|p| p[a]).fold(f32::INFINITY, f32::min);
                let hi = f.iter().map(|p| p[a]).fold(f32::NEG_INFINITY, f32::max);
                out[2 * a].push(-hi);
                out[2 * a + 1].push(lo);
            }
        }
        out
    }

    #[test]
    fn a_body_rolling_on_the_floor_stands_on_it() {
        // Lying along x, rolling along y and drifting along x: 1.7 m long, 0.4 m high, one
        // side always on z = 0.
        let frames: Vec<Vec<[f32; 3]>> = (0..64)
            .map(|f| {
                let y = f as f32 * 30.0;
                (0..20)
                    .map(|i| {
                        let x = -1700.0 + i as f32 * 85.0 + f as f32 * 20.0;
                        let z = 10.0 + ((f + i) % 5) as f32 * 100.0;
                        [x, y + (i % 3) as f32 * 50.0, z]
                    })
                    .collect()
            })
            .collect();
        assert_eq!(floor(&mut lowest(&frames)), Some(dir(2, true)));
        // Standing still with the origin under the body on x too: two floors, no answer.
        let still: Vec<Vec<[f32; 3]>> = (0..64)
            .map(|_| {
                (0..20)
                    .map(|i| {
                        [
                            10.0 + i as f32,
                            300.0 + i as f32 * 5.0,
                            20.0 + i as f32 * 80.0,
                        ]
                    })
                    .collect()
            })
            .collect();
        assert_eq!(floor(&mut lowest(&still)), None);
        // Too few frames to tell.
        assert_eq!(floor(&mut lowest(&frames[..4])), None);
    }

    #[test]
    fn horizontal_axes_keep_the_top_view_right_handed() {
        assert_eq!(horizontal_axes(2), [0, 1]);
        assert_eq!(horizontal_axes(1), [2, 0]);
        assert_eq!(horizontal_axes(0), [1, 2]);
    }
}
