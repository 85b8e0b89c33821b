//! The template's size fitted to the trial's body ([`super::LabelOptions::fit_scale`]): a
//! template of another subject holds the same markers on a body of another size, so its
//! distances differ by a factor more than their tolerances allow. The factor is found from
//! the trial itself: where the trial labels some template markers already, from their
//! distances; else from a few frames matched from nothing on a ladder of sizes, the size
//! that places the most markers, then refined by the distances of the markers it placed.
//! (On the corpora one factor is not enough between two subjects: docs/label.md.)

use super::fragments::Pieces;
use super::model::Model;
use super::options::{dist, LabelOptions};
use super::seed;
use rayon::prelude::*;

/// Frames matched from nothing at each size of the ladder (the frame with the most points
/// in each of as many stretches of the trial).
const FRAMES: usize = 3;

/// In each frame matched, the markers placed and the fragment each is on.
type Placed = Vec<Vec<(usize, usize)>>;

/// Frames read to measure the given labels' distances (evenly spaced).
const READ: usize = 400;

/// The factor by which the template's distances are multiplied to fit the trial (1 when
/// nothing measures it). `given[fragment]` is the template marker the trial labels it as.
pub(crate) fn fit(model: &Model, pc: &Pieces, given: &[Option<usize>], opts: &LabelOptions) -> f64 {
    let n = pc.frames();
    if n == 0 {
        return 1.0;
    }
    if given.iter().any(|g| g.is_some_and(|m| model.present[m])) {
        let step = n.div_ceil(READ).max(1);
        let placed: Vec<Vec<(usize, usize)>> = (0..n)
            .step_by(step)
            .map(|f| {
                pc.active[f]
                    .iter()
                    .filter_map(|&g| given[g as usize].map(|m| (m, g as usize)))
                    .collect()
            })
            .collect();
        let frames: Vec<usize> = (0..n).step_by(step).collect();
        return ratio(model, pc, &frames, &placed).unwrap_or(1.0);
    }
    let frames: Vec<usize> = (0..FRAMES)
        .filter_map(|i| {
            let (a, b) = (i * n / FRAMES, ((i + 1) * n / FRAMES).min(n));
            (a..b).max_by(|&x, &y| pc.active[x].len().cmp(&pc.active[y].len()).then(y.cmp(&x)))
        })
        .collect();
    let steps = opts.scale_steps as i32;
    let ladder: Vec<i32> = (-steps..=steps).collect();
    // Each size's placements `(marker, fragment)` in each frame, and how many markers it
    // placed in all.
    let tried: Vec<(i32, usize, Placed)> = ladder
        .par_iter()
        .map(|&i| {
            let s = opts.scale_ratio.powi(i);
            let ms = model.scaled(s, opts);
            let placed: Vec<Vec<(usize, usize)>> = frames
                .iter()
                .map(|&f| {
                    let points: Vec<[f64; 3]> = pc.active[f]
                        .iter()
                        .map(|&g| *pc.at(g as usize, f))
                        .collect();
                    seed::seed(&ms, &points, &[], opts)
                        .iter()
                        .enumerate()
                        .filter_map(|(m, p)| p.map(|p| (m, pc.active[f][p] as usize)))
                        .collect()
                })
                .collect();
            let count = placed.iter().map(Vec::len).sum();
            (i, count, placed)
        })
        .collect();
    // The most markers placed; between equals, the size nearest the template's own.
    let Some((_, _, placed)) = tried.iter().max_by(|a, b| {
        a.1.cmp(&b.1)
            .then(b.0.abs().cmp(&a.0.abs()))
            .then(b.0.cmp(&a.0))
    }) else {
        return 1.0;
    };
    ratio(model, pc, &frames, placed).unwrap_or(1.0)
}

/// The median, over the placed pairs of `placed[i]` (markers and their fragments in frame
/// `frames[i]`), of the trial's distance over the template's.
fn ratio(
    model: &Model,
    pc: &Pieces,
    frames: &[usize],
    placed: &[Vec<(usize, usize)>],
) -> Option<f64> {
    let mut rs = Vec::new();
    let mut holder: Vec<Option<usize>> = vec![None; model.markers];
    for (&f, at) in frames.iter().zip(placed) {
        holder.iter_mut().for_each(|h| *h = None);
        for &(m, g) in at {
            holder[m].get_or_insert(g);
        }
        for &(m, g) in at {
            if holder[m] != Some(g) {
                continue;
            }
            for nb in &model.nb[m] {
                if let Some(h) = holder[nb.other] {
                    if nb.other > m && nb.d0 > 0.0 {
                        rs.push(dist(pc.at(g, f), pc.at(h, f)) / nb.d0);
                    }
                }
            }
        }
    }
    if rs.is_empty() {
        return None;
    }
    let k = rs.len() / 2;
    Some(*rs.select_nth_unstable_by(k, f64::total_cmp).1)
}
