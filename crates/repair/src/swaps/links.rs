//! Links: pairs of markers whose distance stays nearly constant, learned from the trial's
//! own frames.

use crate::Trial;
use rayon::prelude::*;

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
/// cost of all 1 770 pairs of a 60-marker trial low.
const LEARN_FRAMES: usize = 400;

/// Width of the window the densest cluster of a pair's distances is sought in: 4 mm and
/// 2 % of the distance (skin over a long segment moves more).
fn window_mm(d: f64) -> f64 {
    4.0 + 0.02 * d
}

/// The links of every marker, each marker's best `max_links` (lowest spread first).
///
/// A pair is a link when at least `min_support` of the sampled frames where both are valid
/// sit in one window of 4 mm + 2 % of the distance (a majority: a swap in part of the trial moves the
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
    // Each marker's links to the markers after it, markers in parallel.
    let found: Vec<Vec<(usize, Link)>> = (0..m)
        .into_par_iter()
        .map(|a| {
            let mut ds: Vec<f64> = Vec::with_capacity(frames.len());
            let mut mine = Vec::new();
            for b in a + 1..m {
                ds.clear();
                ds.extend(
                    frames
                        .iter()
                        .filter(|&&f| ok(a, f) && ok(b, f))
                        .map(|&f| dist(&trial.xyz[a][f], &trial.xyz[b][f])),
                );
                if let Some((d0, spread)) = cluster(&mut ds, max_spread_mm, min_support) {
                    mine.push((
                        b,
                        Link {
                            other: b,
                            d0_mm: d0,
                            tol_mm: (4.0 * spread).max(4.0),
                            spread_mm: spread,
                        },
                    ));
                }
            }
            mine
        })
        .collect();
    for (a, mine) in found.into_iter().enumerate() {
        for (b, l) in mine {
            out[b].push(Link { other: a, ..l });
            out[a].push(l);
        }
    }
    for l in &mut out {
        l.sort_by(|p, q| p.spread_mm.total_cmp(&q.spread_mm));
        l.truncate(max_links);
    }
    out
}

/// The centre and spread of the densest window of a pair's distances, when it holds
/// `min_support` of them (at least 20), its spread is at most `max_spread_mm` and the
/// markers are at least 5 mm apart.
fn cluster(ds: &mut [f64], max_spread_mm: f64, min_support: f64) -> Option<(f64, f64)> {
    if ds.len() < 20 {
        return None;
    }
    // Most pairs are no link, and need no sort to say so: a window holding at least half
    // the distances (`min_support` is at least 0.5) holds the median or the distance just
    // below it, so all of its distances are within the window's width of one of those two.
    let m = ds.len() / 2;
    let (lower, &mut median, _) = ds.select_nth_unstable_by(m, f64::total_cmp);
    let below = lower.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let w = window_mm(median);
    let near = |c: f64| ds.iter().filter(|&&d| (d - c).abs() <= w).count();
    if (near(median).max(near(below)) as f64) < min_support * ds.len() as f64 {
        return None;
    }
    ds.sort_unstable_by(f64::total_cmp);
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
        return None;
    }
    let win = &ds[bi..bi + best];
    let c = win[win.len() / 2];
    let mut dev: Vec<f64> = win.iter().map(|d| (d - c).abs()).collect();
    let mid = dev.len() / 2;
    let spread = 1.4826 * *dev.select_nth_unstable_by(mid, f64::total_cmp).1;
    (spread <= max_spread_mm && c >= 5.0).then_some((c, spread))
}

pub(crate) fn dist(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

pub(crate) fn finite(p: &[f64; 3]) -> bool {
    p.iter().all(|v| v.is_finite())
}
