//! Optimal keyframe selection by dynamic programming over key sets (after Roberts et al.,
//! 2019): `cost(i, j)` is the error of the frames strictly between keys `i` and `j` when
//! interpolated from them, and `D[k][j] = min_i D[k-1][i] + cost(i, j)` is the least error of
//! frames `0..=j` with `k` keys ending at `j`. The answer is `D[K][n-1]`; it is exact.
//!
//! Complexity, with `n` frames, `K` keys, `L` the longest segment considered and `J` joints:
//! segment costs take O(n · L² · J) in the worst case and the recurrence O(n · L · K), in
//! O(n · K) memory; no cost table is stored, since each key's outgoing segments are evaluated
//! once, right when its `D[·][i]` is final. A segment is abandoned as soon as its partial error
//! exceeds the remaining budget (the greedy solution's error, or the error bound, minus the
//! least error needed to reach its first key), visiting frames from the middle outwards where
//! errors are largest; this pruning is exact. Segment frames are reached incrementally
//! ([`Evaluator::segment_cost`]): one quaternion product per rotation factor per frame.
//!
//! `L` decides the running time. Without a cap it is `n - K + 1`, the longest segment any
//! `K`-key solution can have, and the result is the true optimum — but every pair of frames is
//! then looked at, which takes minutes on thousands of frames. By default ([`Cap::Auto`]) `L` is
//! twice the average key spacing, raised to the longest segment of the greedy solution; the
//! result is then optimal among key sets whose gaps are at most `L` frames, and never worse than
//! greedy (the greedy key set is one of them).
//!
//! Measured on the 2752-frame, 31-joint CMU file (one core, quaternion interpolation): 1000 keys
//! 0.4 s, 400 keys 1.5 s, 100 keys 6.5 s with the default cap (47 s uncapped, same result),
//! 20 keys 166 s (the cap is then 514 frames: the cost grows like n³/K²). See
//! `benches/keyframes.rs`.

use super::greedy;
use super::{check, total_bound, KeyframeError, Reduction, Target};
use crate::error_metric::{Evaluator, Scratch};

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
        Cap::Frames(f) => f.max(1),
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
    // Slack for rounding, so the greedy solution itself is never pruned away.
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
    let mut s = Scratch::default();
    for i in 0..n - 1 {
        // Key counts (0-based layer k = keys - 1) with which key i can still lead to a
        // solution with at most k_max keys; D[k][i] is final here, as all segments into i
        // start before i.
        let layers = 0..(k_max - 1).min(i + 1);
        let reach = layers
            .clone()
            .map(|k| dp.d[k * n + i])
            .fold(f64::INFINITY, f64::min);
        if !reach.is_finite() || reach > budget {
            continue;
        }
        let room = budget - reach;
        for j in i + 1..=(i + max_len).min(n - 1) {
            let c = eval.segment_cost(i, j, room, &mut s);
            if c > room {
                continue;
            }
            for k in layers.clone() {
                let v = dp.d[k * n + i] + c;
                let slot = (k + 1) * n + j;
                if v < dp.d[slot] {
                    dp.d[slot] = v;
                    dp.from[slot] = i as u32;
                }
            }
        }
    }
    dp
}
