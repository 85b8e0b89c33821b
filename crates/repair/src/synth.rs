//! Synthetic gait-like trials with known truth, for this crate's tests, benchmarks and example:
//! markers on rigid segments (pelvis, legs, trunk) driven by sinusoidal joint angles while
//! walking forward, plus Gaussian noise.

use nalgebra::{Rotation3, Vector3};

use crate::rng::SplitMix64;
use crate::Trial;

/// Segment chain: (parent, joint position in the parent's frame, nominal size of the
/// marker cloud in the segment's frame, mm).
const SEGMENTS: [(Option<usize>, [f64; 3], [f64; 3]); 8] = [
    (None, [0.0, 0.0, 0.0], [120.0, 140.0, 60.0]), // 0 pelvis
    (Some(0), [0.0, 90.0, -80.0], [60.0, 60.0, 400.0]), // 1 left thigh
    (Some(1), [0.0, 0.0, -420.0], [50.0, 50.0, 380.0]), // 2 left shank
    (Some(2), [0.0, 0.0, -400.0], [180.0, 60.0, 60.0]), // 3 left foot
    (Some(0), [0.0, -90.0, -80.0], [60.0, 60.0, 400.0]), // 4 right thigh
    (Some(4), [0.0, 0.0, -420.0], [50.0, 50.0, 380.0]), // 5 right shank
    (Some(5), [0.0, 0.0, -400.0], [180.0, 60.0, 60.0]), // 6 right foot
    (Some(0), [0.0, 0.0, 60.0], [120.0, 160.0, 450.0]), // 7 trunk
];

/// A trial of `markers` markers spread round-robin over the first `segments` (1..=8)
/// segments, `frames` frames at `rate_hz`, all valid, with `noise_mm` Gaussian noise.
pub fn gait_like(
    markers: usize,
    segments: usize,
    frames: usize,
    rate_hz: f64,
    noise_mm: f64,
    seed: u64,
) -> Trial {
    let segments = segments.clamp(1, SEGMENTS.len());
    let mut rng = SplitMix64::new(seed);
    let local: Vec<(usize, [f64; 3])> = (0..markers)
        .map(|m| {
            let s = m % segments;
            let size = SEGMENTS[s].2;
            // Thigh/shank markers hang below the joint; others sit around the origin.
            let down = if matches!(s, 1 | 2 | 4 | 5) {
                -0.5
            } else {
                0.0
            };
            let p = [
                size[0] * (rng.uniform() - 0.5),
                size[1] * (rng.uniform() - 0.5),
                size[2] * (rng.uniform() - 0.5 + down),
            ];
            (s, p)
        })
        .collect();
    let mut xyz = vec![Vec::with_capacity(frames); markers];
    let stride_hz = 0.9;
    for f in 0..frames {
        let t = f as f64 / rate_hz;
        let ph = 2.0 * std::f64::consts::PI * stride_hz * t;
        let deg = |d: f64| d.to_radians();
        let mut poses: Vec<(Rotation3<f64>, Vector3<f64>)> = Vec::with_capacity(SEGMENTS.len());
        for (s, (parent, joint, _)) in SEGMENTS.iter().enumerate() {
            let side = if (4..=6).contains(&s) {
                std::f64::consts::PI
            } else {
                0.0
            };
            let p = ph + side;
            let (rot, pos) = match parent {
                None => (
                    Rotation3::from_euler_angles(
                        deg(4.0 * p.sin()),
                        deg(3.0 * p.cos()),
                        deg(6.0 * p.sin()),
                    ),
                    Vector3::new(1200.0 * t, 20.0 * p.sin(), 950.0 + 15.0 * (2.0 * p).sin()),
                ),
                Some(par) => {
                    let (pr, pp) = poses[*par];
                    let angle = match s {
                        1 | 4 => deg(20.0 * p.sin() + 5.0),
                        2 | 5 => deg(-(30.0 + 28.0 * (p - 1.0).sin())),
                        3 | 6 => deg(12.0 * (p + 0.5).sin()),
                        _ => deg(5.0 * (2.0 * p).sin()),
                    };
                    let rel = Rotation3::from_euler_angles(deg(2.0 * p.cos()), angle, 0.0);
                    (pr * rel, pp + pr * Vector3::from(*joint))
                }
            };
            poses.push((rot, pos));
        }
        for (m, (s, l)) in local.iter().enumerate() {
            let (r, p) = poses[*s];
            let q = r * Vector3::from(*l) + p;
            xyz[m].push([
                q.x + noise_mm * rng.normal(),
                q.y + noise_mm * rng.normal(),
                q.z + noise_mm * rng.normal(),
            ]);
        }
    }
    let valid = vec![vec![true; frames]; markers];
    Trial {
        rate_hz,
        xyz,
        valid,
    }
}

/// Knocks out gaps of random lengths in `min_len..=max_len` at random places until about
/// `fraction` of all samples are invalid. Returns how many samples were knocked out.
pub fn knock_out(
    trial: &mut Trial,
    fraction: f64,
    min_len: usize,
    max_len: usize,
    seed: u64,
) -> usize {
    let (m, n) = (trial.markers(), trial.frames());
    if m == 0 || n < 3 || max_len < min_len.max(1) {
        return 0;
    }
    let target = (fraction * (m * n) as f64) as usize;
    let mut rng = SplitMix64::new(seed);
    let mut out = 0;
    let mut attempts = 0;
    while out < target && attempts < 100 * target.max(1) {
        attempts += 1;
        let len = rng.range(min_len.max(1), max_len + 1).min(n - 2);
        let mk = rng.range(0, m);
        let a = rng.range(1, n - len);
        for f in a..a + len {
            if trial.valid[mk][f] {
                trial.valid[mk][f] = false;
                out += 1;
            }
        }
    }
    out
}
