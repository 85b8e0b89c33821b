//! The search behind the optimal method: dynamic programming over key sets, with branch and
//! bound.
//!
//! `cost(i, j)` is the error of the frames strictly between keys `i` and `j` when interpolated
//! from them, and `D[k][j] = min_i D[k-1][i] + cost(i, j)` is the least error of frames `0..=j`
//! with `k + 1` keys, the last at `j` (after Roberts et al., 2019). Keys are drawn from a list
//! of candidate frames (every frame, a coarse grid, or narrow windows around a known solution),
//! so that the same search serves all three; with windows, each key (layer) only takes the
//! candidates of its own window, and the table only holds those.
//!
//! The DP pulls: for each end `j`, the candidate segments `(i, j)` are tried with the best
//! predecessors of the previous candidate first, then the rest. A segment is evaluated (from
//! the middle outwards, where errors are largest) only while, for some key count `k` from which
//! `i` can still lead to a full solution, `D[k][i] + partial cost` beats both the best way into
//! `j` found so far and the budget. A segment abandoned past these bounds is in no better
//! solution, so the result is the exact optimum over the candidates (and the allowed gaps)
//! whenever it is within the budget. Larger batches of segments are evaluated in parallel.

use crate::error_metric::Scratch;
use rayon::prelude::*;

/// A segment cost: `cost(a, b, bound, scratch)` is the error of the frames strictly between
/// keys `a` and `b`, or any value above `bound` once it is known to exceed it.
pub(crate) type Cost<'c> = dyn Fn(usize, usize, f64, &mut Scratch) -> f64 + Sync + 'c;

/// Segments per end below which evaluating them in parallel costs more than it saves.
const PARALLEL_FROM: usize = 8;

/// What to search.
pub(crate) struct Problem<'p> {
    /// Candidate key frames, sorted and distinct; the first is frame 0, the last frame `n - 1`.
    pub candidates: &'p [usize],
    /// The largest number of keys (first and last included).
    pub keys: usize,
    /// The longest gap between consecutive keys, in frames.
    pub max_len: usize,
    /// Gaps longer than this (in frames) are only tried between anchors: every `anchor`-th
    /// candidate, and the last. Keeps long gaps affordable on a dense candidate list.
    pub short_len: usize,
    pub anchor: usize,
    /// Solutions above this error are not looked for.
    pub budget: f64,
    /// Per key (layer), the inclusive range of frames it may take, both ends increasing with
    /// the layer; `None`: any candidate.
    pub windows: Option<&'p [(usize, usize)]>,
}

/// The DP table: for each candidate, one entry per layer it may take.
pub(crate) struct Table {
    candidates: Vec<usize>,
    keys: usize,
    /// Per candidate, the inclusive range of layers it may take (empty: `lo > hi`).
    layers: Vec<(usize, usize)>,
    /// Per candidate, where its entries start in `d` and `from`.
    base: Vec<usize>,
    /// Least error up to the candidate with `k + 1` keys, the last at it.
    d: Vec<f64>,
    /// The previous key (candidate index) on that best path.
    from: Vec<usize>,
    /// Per candidate already processed, the inclusive range of layers with a finite `d`
    /// (empty: `lo > hi`), so that segments from it only look at those.
    finite: Vec<(usize, usize)>,
}

impl Table {
    /// Index of layer `k` of candidate `j` in `d` and `from`.
    fn at(&self, k: usize, j: usize) -> Option<usize> {
        let (lo, hi) = self.layers[j];
        (lo <= k && k <= hi).then(|| self.base[j] + k - lo)
    }

    fn d(&self, k: usize, j: usize) -> f64 {
        self.at(k, j).map_or(f64::INFINITY, |x| self.d[x])
    }

    /// The least error with `keys` keys, when a solution within the budget was found.
    pub fn best(&self, keys: usize) -> Option<f64> {
        let last = self.candidates.len().checked_sub(1)?;
        let v = self.d(keys.checked_sub(1)?, last);
        v.is_finite().then_some(v)
    }

    /// The key frames of that best solution.
    pub fn keys(&self, keys: usize) -> Option<Vec<usize>> {
        if keys < 2 || keys > self.keys {
            return None;
        }
        self.best(keys)?;
        let mut j = self.candidates.len() - 1;
        let mut out = vec![self.candidates[j]];
        for k in (1..keys).rev() {
            j = self.from[self.at(k, j)?];
            out.push(self.candidates[j]);
        }
        out.reverse();
        (out.first() == Some(&0)).then_some(out)
    }
}

/// Run the search.
pub(crate) fn solve(p: &Problem, cost: &Cost) -> Table {
    let m = p.candidates.len();
    let top = p.keys.saturating_sub(1);
    let layers: Vec<(usize, usize)> = match p.windows {
        None => vec![(0, top); m],
        // Windows rise with the layer, so the layers whose window holds a frame are a range.
        Some(w) => p
            .candidates
            .iter()
            .map(|&f| {
                let lo = w.partition_point(|&(_, hi)| hi < f);
                let hi = w.partition_point(|&(lo, _)| lo <= f);
                match hi {
                    0 => (1, 0),
                    hi => (lo, (hi - 1).min(top)),
                }
            })
            .collect(),
    };
    let mut base = Vec::with_capacity(m);
    let mut size = 0;
    for &(lo, hi) in &layers {
        base.push(size);
        size += (hi + 1).saturating_sub(lo);
    }
    let mut t = Table {
        candidates: p.candidates.to_vec(),
        keys: p.keys,
        layers,
        base,
        d: vec![f64::INFINITY; size],
        from: vec![0; size],
        finite: vec![(1, 0); m],
    };
    let Some(x) = (m > 0).then(|| t.at(0, 0)).flatten() else {
        return t;
    };
    t.d[x] = 0.0;
    t.finite[0] = (0, 0);
    let mut scratch = Scratch::default();
    let mut first = 0;
    let mut first_short = 0;
    let anchor = p.anchor.max(1);
    let is_anchor = |i: usize| i == m - 1 || i.checked_rem(anchor) == Some(0);
    let mut seeds = Vec::new();
    let mut rest = Vec::new();
    for j in 1..m {
        let fj = p.candidates[j];
        while p.candidates[first].saturating_add(p.max_len) < fj {
            first += 1;
        }
        first_short = first_short.max(first);
        while p.candidates[first_short].saturating_add(p.short_len) < fj {
            first_short += 1;
        }
        let (lj, hj) = t.layers[j];
        if lj > hj || hj == 0 {
            continue;
        }
        // Predecessors sit in the windows of the layers just before j's.
        let (lowest, short) = match p.windows {
            Some(w) => {
                let lo = w[lj.saturating_sub(1)].0;
                let lowest = first.max(p.candidates.partition_point(|&f| f < lo));
                (lowest, first_short.max(lowest))
            }
            None => (first, first_short),
        };
        // Long gaps only from anchors to anchors.
        let long_ok = is_anchor(j);
        let allowed = |i: usize| i >= short || (long_ok && is_anchor(i));
        // Seeds: the best predecessors of the previous candidate, which are usually near-best
        // for this one too, so that the bounds below are tight before the bulk is looked at.
        seeds.clear();
        seeds.push(j - 1);
        let (lo, hi) = t.finite[j - 1];
        for k in lo.max(1)..hi + 1 {
            if let Some(x) = t.at(k, j - 1) {
                if t.d[x].is_finite() {
                    seeds.push(t.from[x]);
                }
            }
        }
        seeds.retain(|&i| i >= lowest && allowed(i));
        seeds.sort_unstable();
        seeds.dedup();
        relax(p, cost, &mut t, j, &seeds, &mut scratch);
        rest.clear();
        if long_ok {
            let from = lowest.next_multiple_of(anchor);
            rest.extend(
                (from..short)
                    .step_by(anchor)
                    .filter(|i| seeds.binary_search(i).is_err()),
            );
        }
        rest.extend((short.max(lowest)..j).filter(|i| seeds.binary_search(i).is_err()));
        relax(p, cost, &mut t, j, &rest, &mut scratch);
        let mut finite = (lj..hj + 1).filter(|&k| t.d(k, j).is_finite());
        t.finite[j] = match (finite.next(), finite.next_back()) {
            (Some(lo), None) => (lo, lo),
            (Some(lo), Some(hi)) => (lo, hi),
            _ => (1, 0),
        };
    }
    t
}

/// Try segments `(i, j)` for every candidate `i` of `starts` (all before `j`). A segment is
/// evaluated only as far as it can still matter: its cost must stay within the budget left after
/// the cheapest way to reach `i`, and, for some key count, must improve on the best way into `j`
/// found so far. Both bounds are exact: a segment abandoned past them is in no better solution.
fn relax(
    p: &Problem,
    cost: &Cost,
    t: &mut Table,
    j: usize,
    starts: &[usize],
    scratch: &mut Scratch,
) {
    let work: Vec<(usize, f64)> = starts
        .iter()
        .filter_map(|&i| {
            let mut room = f64::NEG_INFINITY;
            for k in layers_into(p, t, i, j) {
                let beat = t.d(k + 1, j).min(p.budget);
                room = room.max(beat - t.d(k, i));
            }
            (room >= 0.0).then_some((i, room))
        })
        .collect();
    let (fj, candidates) = (p.candidates[j], p.candidates);
    let costs: Vec<f64> = if work.len() < PARALLEL_FROM {
        work.iter()
            .map(|&(i, room)| cost(candidates[i], fj, room, scratch))
            .collect()
    } else {
        work.par_iter()
            .with_min_len(PARALLEL_FROM / 2)
            .map_init(Scratch::default, |s, &(i, room)| {
                cost(candidates[i], fj, room, s)
            })
            .collect()
    };
    for (&(i, room), &c) in work.iter().zip(&costs) {
        if c > room {
            continue;
        }
        let layers: Vec<usize> = layers_into(p, t, i, j).collect();
        for k in layers {
            let v = t.d(k, i) + c;
            let Some(x) = t.at(k + 1, j) else {
                continue;
            };
            // Ties go to the earliest start, whatever order the candidates came in.
            if v < t.d[x] || (v == t.d[x] && i < t.from[x]) {
                t.d[x] = v;
                t.from[x] = i;
            }
        }
    }
}

/// The layers `k` (`k + 1` keys up to candidate `i`, the last at `i`) from which a segment
/// `(i, j)` can lead to a solution: `D[k][i]` is known, key `k + 1` may sit at `j`, and the
/// `keys - k - 2` keys left after `j` can cover the frames after it with gaps of at most
/// `max_len`.
fn layers_into<'t>(
    p: &'t Problem,
    t: &'t Table,
    i: usize,
    j: usize,
) -> impl Iterator<Item = usize> + 't {
    let last = p.candidates[p.candidates.len() - 1];
    let after = last - p.candidates[j];
    let (fi, gi) = t.finite[i];
    let (lj, hj) = t.layers[j];
    let lo = fi.max(lj.saturating_sub(1));
    let hi = gi
        .min(hj.saturating_sub(1))
        .min(p.keys.saturating_sub(2))
        .min(i);
    (lo..hi + 1).filter(move |&k| {
        let left = p.keys - k - 2;
        t.d(k, i).is_finite() && (after == 0 || left.saturating_mul(p.max_len) >= after)
    })
}
