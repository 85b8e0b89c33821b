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
    LearnedLinks::learn(trial, max_spread_mm, min_support, max_links).links
}

/// A trial's links with what they were learned from: the frames [`learn_links`] samples
/// (coordinates, NaN where missing), its parameters and each pair's verdict. A pair's
/// verdict is a function of its two markers' sampled coordinates alone, so a later stage
/// that learns the links of the same markers with some samples left out or added (the
/// reclaim stage after the swap stage, which leaves out the samples a capture system
/// computed) learns again only the pairs of markers whose samples differ
/// ([`LearnedLinks::learn_again`]), and gets the very links [`learn_links`] gives.
#[derive(Debug, Clone, PartialEq)]
pub struct LearnedLinks {
    /// Each marker's links, as [`learn_links`] returns them.
    pub links: Vec<Vec<Link>>,
    frames: usize,
    params: (f64, f64, usize),
    sampled: Vec<[Vec<f64>; 3]>,
    /// Each marker's links to the markers after it, before each marker's best are kept.
    pairs: Vec<PairLinks>,
}

/// One marker's links to the markers after it: `(other, link)`, by other.
type PairLinks = Vec<(usize, Link)>;

/// What [`LearnedLinks::learn_again`] did: of `pairs` pairs of markers, `learned` were
/// learned again (the others' samples were the same).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Relearned {
    pub pairs: usize,
    pub learned: usize,
}

impl LearnedLinks {
    /// [`learn_links`], keeping what the links were learned from.
    pub fn learn(
        trial: &Trial,
        max_spread_mm: f64,
        min_support: f64,
        max_links: usize,
    ) -> LearnedLinks {
        let sampled = sample(trial);
        let pairs = pair_links(&sampled, trial.frames(), max_spread_mm, min_support);
        LearnedLinks {
            links: best_links(&pairs, max_links),
            frames: trial.frames(),
            params: (max_spread_mm, min_support, max_links),
            sampled,
            pairs,
        }
    }

    /// The links [`learn_links`] gives on `trial` with these parameters, learning only the
    /// pairs of markers whose sampled coordinates differ (bit for bit, or missing in one)
    /// from those these were learned from; every pair when the trial has other markers or
    /// frames, or the parameters differ. Reading the sampled frames costs a small part of
    /// learning from them (1 770 pairs for 60 markers).
    pub fn learn_again(
        &self,
        trial: &Trial,
        max_spread_mm: f64,
        min_support: f64,
        max_links: usize,
    ) -> (Vec<Vec<Link>>, Relearned) {
        let demand = LinksOnDemand::new(trial, (max_spread_mm, min_support, max_links), Some(self));
        let links = (0..trial.markers()).map(|k| demand.of(k)).collect();
        (links, demand.relearned())
    }
}

/// The same numbers, NaN included (every missing sample is the one NaN [`sample`] writes).
fn bits_equal(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Each marker's coordinates at the frames the learning samples, one array per axis, NaN
/// where the sample is missing: every pair reads them (1 770 pairs for 60 markers), and
/// read from the trial's rows, a frame apart by the step, each sample was a cache miss and
/// its validity checked again per pair.
fn sample(trial: &Trial) -> Vec<[Vec<f64>; 3]> {
    let (m, n) = (trial.markers(), trial.frames());
    let step = n.div_ceil(LEARN_FRAMES).max(1);
    (0..m)
        .map(|i| {
            let at = |c: usize| -> Vec<f64> {
                (0..n)
                    .step_by(step)
                    .map(|f| {
                        let p = &trial.xyz[i][f];
                        if trial.valid[i][f] && finite(p) {
                            p[c]
                        } else {
                            f64::NAN
                        }
                    })
                    .collect()
            };
            [at(0), at(1), at(2)]
        })
        .collect()
}

/// Each marker's links to the markers after it, `(other, link)` by other, from `sampled`
/// (from [`sample`] of a trial of `n` frames).
fn pair_links(
    sampled: &[[Vec<f64>; 3]],
    n: usize,
    max_spread_mm: f64,
    min_support: f64,
) -> Vec<PairLinks> {
    let m = sampled.len();
    if n == 0 || m < 2 {
        return vec![Vec::new(); m];
    }
    // Per axis, a pair's distances are computed over all the sampled frames at once,
    // several at a time, and the missing ones (NaN, as any distance with a missing end is)
    // dropped after. Markers in parallel.
    (0..m)
        .into_par_iter()
        .map(|a| {
            let len = sampled[a][0].len();
            let mut ds: Vec<u64> = Vec::with_capacity(len);
            let mut near: Vec<u64> = Vec::with_capacity(len);
            let mut all = vec![0.0f64; len];
            let mut mine = Vec::new();
            for b in a + 1..m {
                let mut bufs = (&mut all, &mut ds, &mut near);
                if let Some(l) = pair_link(sampled, (a, b), max_spread_mm, min_support, &mut bufs) {
                    mine.push((b, l));
                }
            }
            mine
        })
        .collect()
}

/// The link of markers `a < b` (`other` is `b`), from their sampled coordinates, or `None`
/// when the pair keeps no distance; `bufs` are buffers kept across pairs.
fn pair_link(
    sampled: &[[Vec<f64>; 3]],
    (a, b): (usize, usize),
    max_spread_mm: f64,
    min_support: f64,
    (all, ds, near): &mut (&mut Vec<f64>, &mut Vec<u64>, &mut Vec<u64>),
) -> Option<Link> {
    let len = sampled[a][0].len();
    all.resize(len, 0.0);
    let ([xa, ya, za], [xb, yb, zb]) = (&sampled[a], &sampled[b]);
    // All of one length, so that the loop checks no index.
    let (xa, ya, za) = (&xa[..len], &ya[..len], &za[..len]);
    let (xb, yb, zb) = (&xb[..len], &yb[..len], &zb[..len]);
    // The same sum, in the same order, as [`dist`].
    for (k, d) in all.iter_mut().enumerate() {
        *d = ((xa[k] - xb[k]).powi(2) + (ya[k] - yb[k]).powi(2) + (za[k] - zb[k]).powi(2)).sqrt();
    }
    ds.clear();
    ds.extend(all.iter().filter(|d| !d.is_nan()).map(|d| d.to_bits()));
    let (d0, spread) = cluster(ds, near, max_spread_mm, min_support)?;
    Some(Link {
        other: b,
        d0_mm: d0,
        tol_mm: (4.0 * spread).max(4.0),
        spread_mm: spread,
    })
}

/// The links of single markers, learned when first asked for: a stage that needs the links
/// of a few markers only (the reclaim judging: those with a piece to score) learns the
/// pairs of those markers, not all of the trial's. Each marker's links are those
/// [`learn_links`] gives it, and with `known` (an earlier stage's links on the same
/// markers, as [`LearnedLinks::learn_again`] takes them) a pair of two markers that sample
/// as they did then takes its earlier verdict.
#[derive(Debug)]
pub struct LinksOnDemand<'a> {
    sampled: Vec<[Vec<f64>; 3]>,
    params: (f64, f64, usize),
    /// The earlier stage's pairs, and which markers sample as they did then.
    known: Option<(&'a [PairLinks], Vec<bool>)>,
    /// Each pair's verdict, `(a, b)` with `a < b`, once learned or taken.
    verdicts: std::cell::RefCell<std::collections::HashMap<(usize, usize), Option<Link>>>,
    learned: std::cell::Cell<usize>,
}

impl<'a> LinksOnDemand<'a> {
    /// Ready to learn the links of `trial`'s markers with [`learn_links`]' parameters.
    pub fn new(
        trial: &Trial,
        (max_spread_mm, min_support, max_links): (f64, f64, usize),
        known: Option<&'a LearnedLinks>,
    ) -> LinksOnDemand<'a> {
        let sampled = sample(trial);
        let known = known
            .filter(|k| {
                k.params.0.to_bits() == max_spread_mm.to_bits()
                    && k.params.1.to_bits() == min_support.to_bits()
                    && trial.frames() == k.frames
                    && sampled.len() == k.sampled.len()
            })
            .map(|k| {
                let same = sampled
                    .iter()
                    .zip(&k.sampled)
                    .map(|(a, b)| (0..3).all(|c| bits_equal(&a[c], &b[c])))
                    .collect();
                (&k.pairs[..], same)
            });
        LinksOnDemand {
            sampled,
            params: (max_spread_mm, min_support, max_links),
            known,
            verdicts: Default::default(),
            learned: Default::default(),
        }
    }

    /// Marker `k`'s links, as [`learn_links`] gives them on the trial.
    pub fn of(&self, k: usize) -> Vec<Link> {
        let m = self.sampled.len();
        let (max_spread_mm, min_support, max_links) = self.params;
        let (mut all, mut ds, mut near) = (Vec::new(), Vec::new(), Vec::new());
        let mut verdicts = self.verdicts.borrow_mut();
        // Others in ascending order, as [`best_links`] lists them before its stable sort.
        let mut mine: Vec<Link> = (0..m)
            .filter(|&b| b != k)
            .filter_map(|b| {
                let key = (k.min(b), k.max(b));
                let verdict = *verdicts.entry(key).or_insert_with(|| match &self.known {
                    Some((pairs, same)) if same[key.0] && same[key.1] => pairs[key.0]
                        .binary_search_by_key(&key.1, |p| p.0)
                        .ok()
                        .map(|i| pairs[key.0][i].1),
                    _ => {
                        self.learned.set(self.learned.get() + 1);
                        let mut bufs = (&mut all, &mut ds, &mut near);
                        pair_link(&self.sampled, key, max_spread_mm, min_support, &mut bufs)
                    }
                });
                verdict.map(|l| Link { other: b, ..l })
            })
            .collect();
        mine.sort_by(|p, q| p.spread_mm.total_cmp(&q.spread_mm));
        mine.truncate(max_links);
        mine
    }

    /// Of the trial's pairs of markers, how many were learned (not taken from `known`).
    pub fn relearned(&self) -> Relearned {
        let m = self.sampled.len();
        Relearned {
            pairs: m * m.saturating_sub(1) / 2,
            learned: self.learned.get(),
        }
    }
}

/// Each marker's links from the pairs' ([`pair_links`]), its best `max_links` (lowest
/// spread first).
fn best_links(pairs: &[PairLinks], max_links: usize) -> Vec<Vec<Link>> {
    let mut out = vec![Vec::new(); pairs.len()];
    for (a, mine) in pairs.iter().enumerate() {
        for &(b, l) in mine {
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
///
/// The distances come as the bits of their `f64`s: a distance is never negative (nor NaN),
/// and the bits of such numbers order as the numbers do, so they are selected and sorted as
/// integers, with no comparison function called per step (what the search spent most on in
/// trials of many markers, most of whose pairs are no link). The ranks, and so every result,
/// are the same as sorting the numbers.
fn cluster(
    ds: &mut [u64],
    near: &mut Vec<u64>,
    max_spread_mm: f64,
    min_support: f64,
) -> Option<(f64, f64)> {
    if ds.len() < 20 {
        return None;
    }
    let val = f64::from_bits;
    // Most pairs are no link, and need no sort to say so: a window holding at least half
    // the distances (`min_support` is at least 0.5) holds the median or the distance just
    // below it, so all of its distances are within the window's width of one of those two.
    let m = ds.len() / 2;
    let (lower, &mut median, _) = ds.select_nth_unstable(m);
    let median = val(median);
    let below = lower
        .iter()
        .map(|&d| val(d))
        .fold(f64::NEG_INFINITY, f64::max);
    let w = window_mm(median);
    // Both counts in one pass over the distances.
    let (mut at_median, mut at_below) = (0usize, 0usize);
    for &d in ds.iter() {
        let d = val(d);
        at_median += usize::from((d - median).abs() <= w);
        at_below += usize::from((d - below).abs() <= w);
    }
    if (at_median.max(at_below) as f64) < min_support * ds.len() as f64 {
        return None;
    }
    // Only the distances a window of that size can hold are sorted: such a window holds the
    // median or the one below it (it spans at least half the ranks), so each of its
    // distances is within `w` above `below` or below `median`, computed as the scan below
    // computes a window's width (a difference rounds the same way or less when its smaller
    // term grows). The densest window is then the same, and the first of its size the same,
    // as over all the distances; when it is too small, it was too small over all of them.
    // Sorting those (half to two thirds of a link's distances) instead of all was a third
    // of the sort's time.
    //
    // The selection left the distances below the median's rank before it, the rest from
    // it on: those two parts are sorted apart and follow each other (two sorts of half the
    // length, 12 % fewer comparisons), into a buffer kept across the pairs.
    let n = ds.len();
    let is_near = |d: u64| below - val(d) <= w && val(d) - median <= w;
    near.clear();
    near.extend(ds[..m].iter().copied().filter(|&d| is_near(d)));
    let split = near.len();
    near.extend(ds[m..].iter().copied().filter(|&d| is_near(d)));
    near[..split].sort_unstable();
    near[split..].sort_unstable();
    let near = &near[..];
    // Densest window [i, j).
    let (mut best, mut bi, mut j) = (0usize, 0usize, 0usize);
    for i in 0..near.len() {
        while j < near.len() && val(near[j]) - val(near[i]) <= w {
            j += 1;
        }
        if j - i > best {
            best = j - i;
            bi = i;
        }
    }
    if (best as f64) < min_support * n as f64 {
        return None;
    }
    let win = &near[bi..bi + best];
    let c = val(win[win.len() / 2]);
    // Deviations are not negative either: ordered by their bits too.
    let mut dev: Vec<u64> = win.iter().map(|&d| (val(d) - c).abs().to_bits()).collect();
    let mid = dev.len() / 2;
    let spread = 1.4826 * val(*dev.select_nth_unstable(mid).1);
    (spread <= max_spread_mm && c >= 5.0).then_some((c, spread))
}

pub(crate) fn dist(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

pub(crate) fn finite(p: &[f64; 3]) -> bool {
    p.iter().all(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`cluster`] as it was before the densest window was sought among the distances near
    /// the median: every distance sorted and scanned.
    fn cluster_all(ds: &mut [u64], max_spread_mm: f64, min_support: f64) -> Option<(f64, f64)> {
        if ds.len() < 20 {
            return None;
        }
        let val = f64::from_bits;
        ds.sort_unstable();
        let w = window_mm(val(ds[ds.len() / 2]));
        let (mut best, mut bi, mut j) = (0usize, 0usize, 0usize);
        for i in 0..ds.len() {
            while j < ds.len() && val(ds[j]) - val(ds[i]) <= w {
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
        let c = val(win[win.len() / 2]);
        let mut dev: Vec<u64> = win.iter().map(|&d| (val(d) - c).abs().to_bits()).collect();
        let mid = dev.len() / 2;
        let spread = 1.4826 * val(*dev.select_nth_unstable(mid).1);
        (spread <= max_spread_mm && c >= 5.0).then_some((c, spread))
    }

    /// The same answer as sorting every distance, on sets made to sit at the edges of the
    /// rule: a cluster with a tail at exactly the window's width, two clusters of nearly
    /// equal size, distances on a grid (ties everywhere), and wide noise.
    #[test]
    fn near_median_window_is_the_whole_sorts() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut agreed, mut links) = (0, 0);
        for case in 0..4000 {
            let n = 20 + case % 400;
            let centre = 5.0 + 400.0 * next();
            let w = window_mm(centre);
            let ds: Vec<f64> = (0..n)
                .map(|_| match case % 4 {
                    0 => centre + w * (2.0 * next() - 1.0) * if next() < 0.6 { 0.3 } else { 1.5 },
                    1 => centre + if next() < 0.5 { 0.0 } else { 1.05 * w } + next(),
                    2 => centre + (4.0 * next()).floor() * 0.5 * w,
                    _ => centre * (0.5 + next()),
                })
                .collect();
            let mut a: Vec<u64> = ds.iter().map(|d| d.to_bits()).collect();
            let mut b = a.clone();
            for support in [0.5, 0.6, 0.9] {
                let (x, y) = (
                    cluster(&mut a, &mut Vec::new(), 2.5, support),
                    cluster_all(&mut b, 2.5, support),
                );
                assert_eq!(x, y, "case {case}, support {support}");
                agreed += 1;
                links += usize::from(x.is_some());
            }
        }
        // Both answers occur: the sets test the window, not only the early rejection.
        assert!(links > 500 && links < agreed - 500, "{links} of {agreed}");
    }
}
