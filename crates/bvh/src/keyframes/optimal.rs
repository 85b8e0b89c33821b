//! Optimal keyframe selection by dynamic programming over key sets (after Roberts et al.,
//! 2019): `cost(i, j)` is the error of the frames strictly between keys `i` and `j` when
//! interpolated from them, and `D[k][j] = min_i D[k-1][i] + cost(i, j)` is the least error of
//! frames `0..=j` with `k` keys ending at `j`. The answer is `D[K][n-1]`; it is exact.
//!
//! Complexity, with `n` frames, `K` keys, `L` the longest segment considered and `J` joints:
//! in the worst case O(n · L² · J) for segment costs plus O(n · L · K) for the recurrence, in
//! O(n · K) memory (no cost table is stored). The work actually done is much less, and the
//! result still exact, thanks to branch and bound:
//! - the DP pulls: for each end frame `j`, the candidate segments `(i, j)` are tried with the
//!   best predecessors of `j - 1` first, then the rest; a segment is evaluated (from the middle
//!   outwards, where errors are largest) only while, for some key count `k` from which `i` can
//!   still lead to a full solution, `D[k][i] + partial cost` beats both the best way into `j`
//!   found so far and the budget. A segment abandoned past these bounds is in no better
//!   solution;
//! - the budget is the greedy solution's error after a few sweeps of local search (each key
//!   moved to its best frame between its neighbours), which is much closer to the optimum;
//! - the candidates of each `j` are evaluated in parallel (rayon); segment frames are reached
//!   incrementally ([`Evaluator::segment_cost`]): one quaternion product per rotation factor.
//!
//! `L` decides the running time. Without a cap it is `n - K + 1`, the longest segment any
//! `K`-key solution can have, and the result is the true optimum. By default ([`Cap::Auto`])
//! `L` is twice the average key spacing, raised to the longest segment of the greedy solution;
//! the result is then optimal among key sets whose gaps are at most `L` frames, and never worse
//! than greedy (the greedy key set is one of them).
//!
//! Measured on the 2752-frame, 31-joint CMU file (2 cores, quaternion interpolation, default
//! cap, `c3dfix keyframes … --method optimal`): 400 keys 1.1 s (was 1.4 s), 100 keys 2.9 s
//! (was 6.4 s), 20 keys 57 s (was 166–237 s; the cap is then 514 frames and the cost still
//! grows like n³/K²). See `benches/keyframes.rs`.

use super::greedy;
use super::{check, total_bound, KeyframeError, Reduction, Target};
use crate::error_metric::{Evaluator, Scratch};
use rayon::prelude::*;

/// Local-search sweeps over the greedy keys before the DP (see [`polish`]).
const POLISH_SWEEPS: usize = 4;

/// The longest gap between consecutive keys that the search considers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cap {
    /// Twice the average key spacing, at least the greedy solution's longest gap.
    Auto,
    /// No cap: the exact optimum (slow on long motions).
    None,
    /// At most this many frames between consecutive keys.
    Frames(usize),
}

/// Optimal reduction to a target, searching key sets whose gaps respect `cap`.
pub fn reduce(eval: &Evaluator, target: Target, cap: Cap) -> Result<Reduction, KeyframeError> {
    check(eval, target)?;
    let n = eval.frames();
    let run = greedy::run(eval);
    // Greedy gives a feasible solution, hence an upper bound on the key count and the error.
    let g = greedy::pick(&run, eval, target);
    let (k_max, budget) = match target {
        Target::Keys(k) => (k, g.total_error),
        Target::MaxError(rms) => (g.keys.len(), total_bound(eval, rms)),
    };
    let cap = match cap {
        Cap::None => n,
        Cap::Frames(f) => f.clamp(1, n),
        Cap::Auto => {
            let spacing = (n - 1).div_ceil(k_max.max(2) - 1);
            let greedy_longest = g.keys.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(1);
            (2 * spacing).max(greedy_longest)
        }
    };
    if (k_max - 1).saturating_mul(cap) < n - 1 {
        return Err(KeyframeError::SegmentCapTooSmall {
            max_segment: cap,
            frames: n,
            keys: k_max,
        });
    }
    if k_max >= n {
        let keys: Vec<usize> = (0..n).collect();
        return Ok(Reduction {
            keys,
            total_error: 0.0,
        });
    }
    let budget = match target {
        Target::Keys(_) => {
            let mut keys = g.keys.clone();
            budget.min(polish(eval, &mut keys, cap, POLISH_SWEEPS))
        }
        Target::MaxError(_) => budget,
    };
    // Slack for rounding, so the solution that set the budget is never pruned away.
    let budget = budget * (1.0 + 1e-9) + 1e-12;
    let max_len = cap.min(n - k_max + 1).max(1);
    let dp = solve(eval, k_max, max_len, budget);
    // Smallest key count whose optimum meets the target (for Keys: exactly K).
    let k = match target {
        Target::Keys(k) => k,
        Target::MaxError(_) => (2..=k_max)
            .find(|&k| dp.best(k).is_some_and(|e| e <= budget))
            .unwrap_or(k_max),
    };
    match dp.keys(k) {
        Some(keys) => {
            let total_error = eval.frame_errors(&keys).iter().sum();
            Ok(Reduction { keys, total_error })
        }
        // Only reachable if a cap excludes every solution within the budget: the greedy
        // answer is then the best we can honestly offer.
        None => Ok(g),
    }
}

/// Improve a key set by moving one interior key at a time to the best frame between its
/// neighbours (gaps kept within `cap`), sweeping until nothing moves or `sweeps` run out.
/// Returns the new total error. Its only purpose is a tighter budget for the DP's pruning: the
/// closer the budget is to the optimum, the sooner hopeless segments are abandoned.
fn polish(eval: &Evaluator, keys: &mut [usize], cap: usize, sweeps: usize) -> f64 {
    let mut s = Scratch::default();
    let mut seg: Vec<f64> = keys
        .windows(2)
        .map(|w| eval.segment_cost(w[0], w[1], f64::INFINITY, &mut s))
        .collect();
    for _ in 0..sweeps {
        let mut moved = false;
        for k in 1..keys.len().saturating_sub(1) {
            let (a, p, b) = (keys[k - 1], keys[k], keys[k + 1]);
            let now = seg[k - 1] + seg[k];
            let lo = (a + 1).max(b.saturating_sub(cap));
            let hi = (b - 1).min(a + cap);
            let best = (lo..hi + 1)
                .into_par_iter()
                .with_min_len(4)
                .map_init(Scratch::default, |s, q| {
                    let left = eval.segment_cost(a, q, now, s);
                    if left > now {
                        return (f64::INFINITY, 0.0, 0.0, q);
                    }
                    let right = eval.segment_cost(q, b, now - left, s);
                    (left + right, left, right, q)
                })
                .min_by(|x, y| x.0.total_cmp(&y.0).then(x.3.cmp(&y.3)));
            if let Some((total, left, right, q)) = best {
                if q != p && total < now {
                    keys[k] = q;
                    seg[k - 1] = left;
                    seg[k] = right;
                    moved = true;
                }
            }
        }
        if !moved {
            break;
        }
    }
    eval.frame_errors(keys).iter().sum()
}

struct Dp {
    n: usize,
    k_max: usize,
    /// `d[k * n + j]`: least error of frames `0..=j` with `k + 1` keys, the last at `j`.
    d: Vec<f64>,
    /// The previous key on that best path.
    from: Vec<u32>,
}

impl Dp {
    fn best(&self, keys: usize) -> Option<f64> {
        let v = *self.d.get((keys - 1) * self.n + self.n - 1)?;
        v.is_finite().then_some(v)
    }

    fn keys(&self, keys: usize) -> Option<Vec<usize>> {
        if keys < 2 || keys > self.k_max {
            return None;
        }
        self.best(keys)?;
        let mut out = vec![self.n - 1];
        let mut j = self.n - 1;
        for k in (1..keys).rev() {
            j = self.from[k * self.n + j] as usize;
            out.push(j);
        }
        out.reverse();
        (out.first() == Some(&0)).then_some(out)
    }
}

fn solve(eval: &Evaluator, k_max: usize, max_len: usize, budget: f64) -> Dp {
    let n = eval.frames();
    let mut dp = Dp {
        n,
        k_max,
        d: vec![f64::INFINITY; k_max * n],
        from: vec![0; k_max * n],
    };
    dp.d[0] = 0.0;
    let mut seeds = Vec::new();
    let mut rest = Vec::new();
    for j in 1..n {
        let first = j.saturating_sub(max_len);
        // Seeds: the best predecessors of j - 1, which are usually near-best for j too, so
        // that the bounds below are tight before the bulk of the candidates is looked at.
        seeds.clear();
        seeds.push(j - 1);
        if j >= 2 {
            for k in 1..k_max {
                let slot = k * n + j - 1;
                let i = dp.from[slot] as usize;
                if dp.d[slot].is_finite() && i >= first {
                    seeds.push(i);
                }
            }
        }
        seeds.sort_unstable();
        seeds.dedup();
        relax(eval, &mut dp, (budget, max_len), j, &seeds);
        rest.clear();
        rest.extend((first..j).filter(|i| seeds.binary_search(i).is_err()));
        relax(eval, &mut dp, (budget, max_len), j, &rest);
    }
    dp
}

/// Try segments `(i, j)` for every `i` of `starts` (all before `j`). A segment is evaluated only
/// as far as it can still matter: its cost must stay within the budget left after the cheapest
/// way to reach `i`, and, for some key count, must improve on the best way into `j` found so
/// far. Both bounds are exact: a segment abandoned past them is in no better solution.
fn relax(
    eval: &Evaluator,
    dp: &mut Dp,
    (budget, max_len): (f64, usize),
    j: usize,
    starts: &[usize],
) {
    let n = dp.n;
    let work: Vec<(usize, f64)> = starts
        .iter()
        .filter_map(|&i| {
            // Layer k (k + 1 keys up to i) can take one more key at j, if the keys left after
            // j can still cover the remaining frames with gaps of at most `max_len`.
            let mut room = f64::NEG_INFINITY;
            for k in layers_into(dp, i, j, max_len) {
                let at = dp.d[k * n + i];
                let beat = dp.d[(k + 1) * n + j].min(budget);
                room = room.max(beat - at);
            }
            (room >= 0.0).then_some((i, room))
        })
        .collect();
    let costs: Vec<f64> = work
        .par_iter()
        .with_min_len(4)
        .map_init(Scratch::default, |s, &(i, room)| {
            eval.segment_cost(i, j, room, s)
        })
        .collect();
    for (&(i, room), &c) in work.iter().zip(&costs) {
        if c > room {
            continue;
        }
        let layers: Vec<usize> = layers_into(dp, i, j, max_len).collect();
        for k in layers {
            let v = dp.d[k * n + i] + c;
            let slot = (k + 1) * n + j;
            // Ties go to the earliest start, whatever order the candidates came in.
            if v < dp.d[slot] || (v == dp.d[slot] && i < dp.from[slot] as usize) {
                dp.d[slot] = v;
                dp.from[slot] = i as u32;
            }
        }
    }
}

/// The layers `k` (`k + 1` keys up to `i`, the last at `i`) from which a segment `(i, j)` can
/// lead to a solution: `D[k][i]` is known and within reach, and the `k_max - k - 2` keys left
/// after `j` can cover the frames after it with gaps of at most `max_len`.
fn layers_into(dp: &Dp, i: usize, j: usize, max_len: usize) -> impl Iterator<Item = usize> + '_ {
    let n = dp.n;
    let after = n - 1 - j;
    (0..(dp.k_max - 1).min(i + 1)).filter(move |&k| {
        let left = dp.k_max - k - 2;
        dp.d[k * n + i].is_finite() && (after == 0 || left.saturating_mul(max_len) >= after)
    })
}
