//! Links: pairs of markers whose distance stays nearly constant, learned from the trial's
//! own frames.

use crate::Trial;

/// A pair of markers that keep their distance: `d0_mm` in most frames, within `tol_mm`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    /// The other marker.
    pub other: usize,
    /// The distance the pair keeps (the centre of the densest cluster of its distances).
    pub d0_mm: f64,
    /// How far a frame's distance may stray before the link counts as broken there.
    pub tol_mm: f64,
    /// Robust spread of the distance inside its cluster.
    pub spread_mm: f64,
}

/// At most this many frames, evenly spaced, are used to learn a trial's links: the
/// distances a segment keeps need hundreds of frames, not every one, and this keeps the
/// cost of all pairs of a 60-marker trial near 2 ms.
const LEARN_FRAMES: usize = 600;

/// Width of the window the densest cluster of a pair's distances is sought in: 4 mm and
/// 2 % of the distance (skin over a long segment moves more).
fn window_mm(d: f64) -> f64 {
    4.0 + 0.02 * d
}

/// The links of every marker, each marker's best `max_links` (lowest spread first).
///
/// A pair is a link when at least `min_support` of the sampled frames where both are valid
/// sit in one window of [`window_mm`] (a majority: a swap in part of the trial moves the
/// rest away, so the centre stays the true distance), its spread inside that window is at
/// most `max_spread_mm`, and it was seen in at least 20 sampled frames.
pub fn learn_links(
    trial: &Trial,
    max_spread_mm: f64,
    min_support: f64,
    max_links: usize,
) -> Vec<Vec<Link>> {
    let m = trial.markers();
    let n = trial.frames();
    let mut out = vec![Vec::new(); m];
    if n == 0 || m < 2 {
        return out;
    }
    let step = n.div_ceil(LEARN_FRAMES).max(1);
    let frames: Vec<usize> = (0..n).step_by(step).collect();
    let ok = |i: usize, f: usize| trial.valid[i][f] && finite(&trial.xyz[i][f]);
    let mut ds: Vec<f64> = Vec::with_capacity(frames.len());
    for a in 0..m {
        for b in a + 1..m {
            ds.clear();
            ds.extend(
                frames
                    .iter()
                    .filter(|&&f| ok(a, f) && ok(b, f))
                    .map(|&f| dist(&trial.xyz[a][f], &trial.xyz[b][f])),
            );
            if ds.len() < 20 {
                continue;
            }
            ds.sort_by(f64::total_cmp);
            let w = window_mm(ds[ds.len() / 2]);
            // Densest window [i, j).
            let (mut best, mut bi, mut j) = (0usize, 0usize, 0usize);
            for i in 0..ds.len() {
                while j < ds.len() && ds[j] - ds[i] <= w {
                    j += 1;
                }
                if j - i > best {
                    best = j - i;
                    bi = i;
                }
            }
            if (best as f64) < min_support * ds.len() as f64 {
                continue;
            }
            let win = &ds[bi..bi + best];
            let c = win[win.len() / 2];
            let mut dev: Vec<f64> = win.iter().map(|d| (d - c).abs()).collect();
            dev.sort_by(f64::total_cmp);
            let spread = 1.4826 * dev[dev.len() / 2];
            if spread > max_spread_mm || c < 5.0 {
                continue;
            }
            let tol = (4.0 * spread).max(4.0);
            for (x, y) in [(a, b), (b, a)] {
                out[x].push(Link {
                    other: y,
                    d0_mm: c,
                    tol_mm: tol,
                    spread_mm: spread,
                });
            }
        }
    }
    for l in &mut out {
        l.sort_by(|p, q| p.spread_mm.total_cmp(&q.spread_mm));
        l.truncate(max_links);
    }
    out
}

pub(crate) fn dist(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

pub(crate) fn finite(p: &[f64; 3]) -> bool {
    p.iter().all(|v| v.is_finite())
}
