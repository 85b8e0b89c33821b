//! Which points are a model's outputs rather than markers: the one definition every command
//! uses (fills, donors, swaps, events, exports).
//!
//! Three pieces of evidence, each the file's own: the type lists models write
//! ([`MODEL_OUTPUT_TYPES`]), the order in which Plug-in Gait writers store points (markers
//! first, outputs after), and the geometry of a segment's axes, which no marker can have.

use crate::{C3d, Points};

/// The POINT parameters in which models list the labels of their outputs by type (Plug-in
/// Gait's angles, forces, moments and powers, and the like): see
/// [`C3d::model_output_labels`].
pub const MODEL_OUTPUT_TYPES: [&str; 6] = [
    "ANGLES",
    "FORCES",
    "MOMENTS",
    "POWERS",
    "SCALARS",
    "REACTIONS",
];

/// How many frames, spread over the trial, the axes test reads. A segment's axes hold their
/// shape in every frame by construction, so a few dozen frames spread over the trial already
/// refuse any set of markers (skin, noise) while keeping the test's cost independent of the
/// trial's length.
const AXES_FRAMES: usize = 64;

/// Relative agreement of the three axes' lengths and of their perpendicularity (cosine) in
/// float files: a model's axes agree to the rounding of 32-bit coordinates (under 10⁻⁵ on
/// the corpora's Plug-in Gait files), markers of one cluster to no better than their noise
/// over their spacing (10⁻³ and more).
const AXES_TOLERANCE: f64 = 1e-4;

/// The most points a trial may have for the axes test to run: its cost grows with the square
/// of the points (every pair's distance), and the corpora's largest Plug-in Gait trial has 264.
/// Above this the test is skipped rather than let a damaged or hostile header stall a read.
const AXES_MAX_POINTS: usize = 1_000;

/// The most points at one distance from an origin that are searched for three axes: a
/// segment's axes are three, and a longer run of equal distances (points piled at one place)
/// would cost its cube in triples.
const AXES_MAX_RUN: usize = 16;

impl C3d {
    /// Labels of the points that are model outputs, not markers: Plug-in Gait and other
    /// models store angles, forces, moments, powers and the like as points and list their
    /// labels in POINT:ANGLES, FORCES, MOMENTS, POWERS, SCALARS and REACTIONS.
    ///
    /// The points stored after the first listed output are model outputs too. Nexus and the
    /// other Plug-in Gait writers store the labelled trajectories first and the model's
    /// outputs after them, and only the angles, forces, moments and powers are listed by
    /// type: the segments' bone points (PELO, LFEO, …), virtual markers, the centre of mass
    /// and muscle lengths follow unlisted. They are computed from the markers, so filling
    /// them invents a model's output, and as donors they carry a knocked-out marker's own
    /// samples back into its fill. On the corpora, the 9 files with listed outputs after
    /// their first point hold 1 to 154 unlisted points after the first output (sample_11's
    /// 36 bones, HansUniVie's 154 bones, virtual markers and muscle lengths, pyCGM's centre
    /// of mass) and no marker among them (`tests/model_outputs.rs`). A file whose first
    /// point is itself a listed output keeps the lists alone: there is no marker block to
    /// end.
    ///
    /// Last, the points that form a segment's axes wherever they are stored
    /// ([`segment_axes`]): writers that store the bones before or among the markers, or list
    /// no output at all (pyCGM's and puppeteer's full-body trials, biomechZoo's ice-hockey
    /// trial, the tsalemink gait trials, a Plug-in Gait static trial), are read by their
    /// geometry, not by their labels, so no marker set is written into the rule.
    pub fn model_output_labels(&self) -> Vec<String> {
        let mut listed: Vec<String> = MODEL_OUTPUT_TYPES
            .iter()
            .flat_map(|p| self.parameters.get_strings("POINT", p).unwrap_or_default())
            .filter(|s| !s.is_empty())
            .collect();
        let labels = self.point_labels();
        let first = labels.iter().position(|l| listed.contains(l));
        if let Some(i) = first.filter(|&i| i > 0) {
            for l in &labels[i..] {
                if !l.is_empty() && !listed.contains(l) {
                    listed.push(l.clone());
                }
            }
        }
        let layout = self.layout();
        let quantum = if layout.float {
            0.0
        } else {
            f64::from(layout.point_scale)
        };
        let sampled = self.point_frames(&spread_frames(self.frames()));
        for i in segment_axes(&sampled, quantum) {
            if let Some(l) = labels.get(i).filter(|l| !l.is_empty()) {
                if !listed.contains(l) {
                    listed.push(l.clone());
                }
            }
        }
        listed
    }
}

/// Indices of the points that form a segment's axes: an origin O and three points A, B, C
/// whose offsets from O have one length and are mutually perpendicular in every frame where
/// the four are recorded. This is how Plug-in Gait and its descendants store a segment's
/// pose (PELO with PELA, PELL, PELP: the origin and one point along each axis, the axes
/// scaled by a common length that may change from frame to frame), and how other models
/// store a global or trunk frame. Markers on skin or on a cluster never keep three equal
/// distances and right angles to the rounding of the coordinates, frame after frame.
///
/// `quantum` is the size of one step of an integer file's coordinates (|POINT:SCALE|), 0
/// for float files: each coordinate is then off by up to half a step, a distance by up to
/// √3 steps at each end, so two lengths may differ by 2√3 steps and a cosine by 2√3 steps
/// over the length (ti003's bones: lengths within 0.26 mm at a step of 0.088 mm, cosines
/// within 0.0026 over 88 mm).
pub fn segment_axes(points: &Points, quantum: f64) -> Vec<usize> {
    let (frames, count) = (points.frames(), points.count());
    if frames == 0 || !(4..=AXES_MAX_POINTS).contains(&count) {
        return Vec::new();
    }
    let sampled = spread_frames(frames);
    let at = |f: usize, p: usize| -> Option<[f64; 3]> {
        let k = points.index(f, p);
        let xyz = points.xyz[k];
        let ok = points.is_valid_at(k) && xyz.iter().all(|v| v.is_finite());
        ok.then(|| xyz.map(f64::from))
    };
    let slack = 2.0 * 3f64.sqrt() * quantum;
    let mut found = vec![false; count];
    for o in 0..count {
        let Some(&f0) = sampled.iter().find(|&&f| at(f, o).is_some()) else {
            continue;
        };
        let Some(origin) = at(f0, o) else { continue };
        // Partners by their distance from O in the first sampled frame; only runs of three
        // or more equal distances can hold a segment's axes.
        let mut near: Vec<(f64, usize)> = (0..count)
            .filter(|&p| p != o)
            .filter_map(|p| at(f0, p).map(|x| (norm(sub(x, origin)), p)))
            .filter(|(d, _)| *d > slack && *d > 0.0)
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut i = 0;
        while i < near.len() {
            let mut j = i;
            while j + 1 < near.len() && near[j + 1].0 - near[i].0 <= tolerance(near[i].0, slack) {
                j += 1;
            }
            let run: Vec<usize> = near[i..=j.min(i + AXES_MAX_RUN - 1)]
                .iter()
                .map(|&(_, p)| p)
                .collect();
            for (a, &pa) in run.iter().enumerate() {
                for (b, &pb) in run.iter().enumerate().skip(a + 1) {
                    for &pc in run.iter().skip(b + 1) {
                        let quad = [o, pa, pb, pc];
                        if is_axes(&sampled, &at, quad, slack) {
                            for q in quad {
                                found[q] = true;
                            }
                        }
                    }
                }
            }
            i = j + 1;
        }
    }
    (0..count).filter(|&p| found[p]).collect()
}

/// The indices of [`AXES_FRAMES`] frames spread evenly over `frames` (first and last
/// included), or of every frame of a shorter trial.
fn spread_frames(frames: usize) -> Vec<usize> {
    let take = frames.min(AXES_FRAMES);
    let mut sampled: Vec<usize> = (0..take)
        .map(|k| {
            if take > 1 {
                k * (frames - 1) / (take - 1)
            } else {
                0
            }
        })
        .collect();
    sampled.dedup();
    sampled
}

/// How far apart two lengths near `d` may be and still be one length.
fn tolerance(d: f64, slack: f64) -> f64 {
    AXES_TOLERANCE * d + slack
}

/// Whether `quad` = [O, A, B, C] is a segment's axes in every sampled frame where the four
/// are recorded (and in at least one).
fn is_axes(
    sampled: &[usize],
    at: &impl Fn(usize, usize) -> Option<[f64; 3]>,
    quad: [usize; 4],
    slack: f64,
) -> bool {
    let mut seen = 0;
    for &f in sampled {
        let (Some(o), Some(a), Some(b), Some(c)) = (
            at(f, quad[0]),
            at(f, quad[1]),
            at(f, quad[2]),
            at(f, quad[3]),
        ) else {
            continue;
        };
        let axes = [sub(a, o), sub(b, o), sub(c, o)];
        let lengths = axes.map(norm);
        let (short, long) = lengths
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(s, l), &d| (s.min(d), l.max(d)));
        if short <= slack || short <= 0.0 || long - short > tolerance(long, slack) {
            return false;
        }
        let limit = AXES_TOLERANCE + slack / short;
        for (x, y) in [(0, 1), (0, 2), (1, 2)] {
            let cos = dot(axes[x], axes[y]) / (lengths[x] * lengths[y]);
            if cos.abs() > limit {
                return false;
            }
        }
        seen += 1;
    }
    seen > 0
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points with `xyz[frame][point]`, every sample recorded.
    fn points(xyz: &[Vec<[f32; 3]>]) -> Points {
        let mut p = Points::new(xyz.len(), xyz[0].len());
        for (f, row) in xyz.iter().enumerate() {
            for (i, &x) in row.iter().enumerate() {
                let k = p.index(f, i);
                p.mark(k, crate::Mark::Computed(x));
            }
        }
        p
    }

    #[test]
    fn a_rotating_frame_of_changing_length_is_axes_and_a_cluster_is_not() {
        let frames: Vec<Vec<[f32; 3]>> = (0..50)
            .map(|f| {
                let t = f as f32 * 0.05;
                let (s, c) = t.sin_cos();
                let len = 100.0 + f as f32; // the axes' common length changes
                let o = [500.0 + 3.0 * f as f32, 200.0, 900.0];
                let ax = |v: [f32; 3]| [o[0] + len * v[0], o[1] + len * v[1], o[2] + len * v[2]];
                // a marker cluster at right angles whose lengths carry up to 0.6 mm of noise
                let n = ((f * 7919) % 13) as f32 * 0.05;
                vec![
                    o,
                    ax([c, s, 0.0]),
                    ax([-s, c, 0.0]),
                    ax([0.0, 0.0, 1.0]),
                    [1000.0, 0.0, 0.0],
                    [1100.0 + n, 0.0, 0.0],
                    [1000.0, 100.0 - n, 0.0],
                    [1000.0, 0.0, 100.0 + n],
                ]
            })
            .collect();
        assert_eq!(segment_axes(&points(&frames), 0.0), vec![0, 1, 2, 3]);
    }

    #[test]
    fn too_few_points_or_frames_find_nothing() {
        assert!(segment_axes(&Points::new(0, 8), 0.0).is_empty());
        assert!(segment_axes(&Points::new(10, 3), 0.0).is_empty());
        // every sample missing
        assert!(segment_axes(&Points::new(10, 8), 0.0).is_empty());
        // every point recorded at one place, and too many points to search
        let mut p = Points::new(3, 40);
        for k in 0..p.xyz.len() {
            p.mark(k, crate::Mark::Computed([1.0, 2.0, 3.0]));
        }
        assert!(segment_axes(&p, 0.0).is_empty());
        assert!(segment_axes(&Points::new(2, AXES_MAX_POINTS + 1), 0.0).is_empty());
    }
}
