//! The optimal method: the key set of least error, searched exhaustively where that is
//! affordable and coarse-to-fine where it is not.
//!
//! The exhaustive search (dynamic programming with branch and bound, in `dp.rs`) needs, for `n`
//! frames and keys about `s` frames apart, on the order of `n · s²` frame evaluations *even
//! with perfect pruning bounds*: every plausible segment must be summed nearly in full before
//! it can be ruled out. For 20 keys on the 2752-frame CMU file, restricted to gaps of at most
//! 514 frames and given the exact prefix and suffix optima as bounds, 992 021 segments still
//! need evaluating, 1.0·10⁸ frames in all: over a minute and a half. No lower bound cheap
//! enough to rule out segments in bulk is known for this error (the interpolated pose is a
//! nonlinear function of both keys, and the best solutions include long, expensive gaps), so
//! neither optimality nor a gap to it can be certified for less. Hence:
//!
//! - When the search is small (`n · L · (s + K/64)` at most [`EXHAUSTIVE_WORK`], `L` the
//!   longest possible gap, `K` the keys), every frame is a candidate and the result is exact.
//! - Otherwise the search runs on a grid of every `step`-th frame first, with segment costs
//!   estimated from sampled frames (`step ≈ s / SAMPLES_PER_GAP`, at most [`MAX_SAMPLES`]
//!   samples per segment): about `step³` times less work. Gaps up to twice the average spacing
//!   (or greedy's longest) join any two grid frames, longer ones join anchors spread so that
//!   there are about [`LONG_WORK`]` / K` of them: the best key sets often give up on one hard
//!   stretch with a single long gap. The grid keys are then refined by exact searches over
//!   windows around each key: first with the step halved at each level (windows of the
//!   previous step, costs sampled at the new step), then at full resolution within ±2 frames,
//!   repeated around each improvement, then again from the halving levels while that helps.
//!   Two grids (offset by half a step) are searched and the better result kept.
//!
//! The coarse-to-fine result is never worse than greedy (for an error bound: never more keys)
//! and no key moved by up to 2 frames, all keys at once, improves it; but it is not proven
//! optimal, and [`Search::exact`] says so. On the CMU file with 20 keys it finds an error of
//! 140 442 (greedy: 195 544; the exhaustive optimum among gaps of at most 514 frames, the
//! former default, 142 629 after 80 s) in about twelve times greedy's time
//! (`cargo bench -p bvh --bench keyframes`).
//!
//! The budget of every search is the best error known so far, so each one only looks for
//! improvements, and segments that cannot give one are abandoned early.

use std::collections::HashMap;
use std::sync::Mutex;

use super::dp::{self, Problem};
use super::greedy::{self, GreedyRun};
use super::{check, total_bound, KeyframeError, Reduction, Target};
use crate::error_metric::{Evaluator, Scratch};

/// Grid samples per average gap in the coarse search: enough for the estimated costs to rank
/// key sets like the exact ones, few enough for the coarse search to be cheap.
pub const SAMPLES_PER_GAP: usize = 16;

/// Largest worst-case work, in frame evaluations, for which the exhaustive search is used by
/// default: a few seconds at most. Each of its `frames × longest gap` segments may take up to
/// an average gap of frame evaluations, and a check against each key count, at about 1/64 of
/// a frame evaluation each ([`LAYER_CHECKS_PER_FRAME`]).
pub const EXHAUSTIVE_WORK: usize = 1 << 22;

/// Key-count checks of the search that cost about one frame evaluation (measured: a frame of
/// the 31-joint CMU skeleton takes about 0.9 µs, a check about 10 ns).
pub const LAYER_CHECKS_PER_FRAME: usize = 64;

/// Most frames sampled per segment in the grid search (long gaps are sampled more sparsely).
pub const MAX_SAMPLES: usize = 2 * SAMPLES_PER_GAP;

/// Segments longer than the grid search's usual gap cap are tried only between anchors, spaced
/// so that these segments times the key count (the layers each is checked against) stay about
/// this many.
pub const LONG_WORK: usize = 1 << 19;

/// Radius, in frames, of the full-resolution windows of the refinement.
const FINE_RADIUS: usize = 2;

/// Cycles of the halving search around the refined keys at most.
const CYCLES: usize = 4;

/// How to search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Options {
    /// At most this many frames between consecutive keys (`None`: no limit).
    pub max_segment: Option<usize>,
    pub strategy: Strategy,
}

/// Which search to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strategy {
    /// Exhaustive when its worst-case work is at most [`EXHAUSTIVE_WORK`], else coarse-to-fine.
    #[default]
    Auto,
    /// Every frame a candidate from the start, however long that takes: always exact.
    Exhaustive,
    /// The grid search and its refinement, whatever the size (never worse than greedy).
    CoarseToFine,
}

/// The outcome of the optimal search.
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    pub reduction: Reduction,
    /// True when the keys are proven optimal: no key set with as many keys (and, for an error
    /// bound, none with fewer) and gaps within `max_segment` has a smaller error.
    pub exact: bool,
    /// Grid step of the first search, in frames (1: exhaustive).
    pub step: usize,
}

/// Optimal reduction to a target.
pub fn reduce(
    eval: &Evaluator,
    target: Target,
    options: Options,
) -> Result<Reduction, KeyframeError> {
    check(eval, target)?;
    search(eval, &greedy::run(eval), target, options).map(|s| s.reduction)
}

/// [`reduce`], reusing a greedy run of the same evaluator, and saying whether the result is
/// proven optimal.
pub fn search(
    eval: &Evaluator,
    run: &GreedyRun,
    target: Target,
    options: Options,
) -> Result<Search, KeyframeError> {
    check(eval, target)?;
    let n = eval.frames();
    // Greedy gives a feasible solution, hence an upper bound on the key count and the error.
    let g = greedy::pick(run, eval, target);
    let k_max = g.keys.len();
    let cap = options.max_segment.unwrap_or(n).clamp(1, n);
    if (k_max - 1).saturating_mul(cap) < n - 1 {
        return Err(KeyframeError::SegmentCapTooSmall {
            max_segment: cap,
            frames: n,
            keys: k_max,
        });
    }
    if k_max >= n {
        return Ok(Search {
            reduction: Reduction {
                keys: (0..n).collect(),
                total_error: 0.0,
            },
            exact: true,
            step: 1,
        });
    }
    // The longest gap any solution with these keys can have.
    let max_len = cap.min(n - k_max + 1);
    let spacing = (n - 1) / (k_max - 1);
    let per_segment = spacing + k_max / LAYER_CHECKS_PER_FRAME;
    let work = n.saturating_mul(max_len).saturating_mul(per_segment);
    let small = match options.strategy {
        Strategy::Auto => work <= EXHAUSTIVE_WORK,
        Strategy::Exhaustive => true,
        Strategy::CoarseToFine => false,
    };
    if small {
        let (reduction, exact) = exhaustive(eval, target, g, max_len);
        return Ok(Search {
            reduction,
            exact,
            step: 1,
        });
    }
    let step = grid_step(n, k_max);
    // The grid search only: a gap cap as in earlier versions of this search (twice the average
    // spacing, at least greedy's longest gap) keeps it cheap; refinement is not capped by it.
    let greedy_longest = g.keys.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(1);
    let lengths = Lengths {
        fine: max_len,
        coarse: max_len.min((2 * spacing).max(greedy_longest)),
    };
    let reduction = match target {
        Target::Keys(k) => coarse_to_fine(eval, g, k, lengths, step),
        Target::MaxError(rms) => fewest_keys(eval, g, total_bound(eval, rms), lengths, step),
    };
    Ok(Search {
        reduction,
        exact: false,
        step,
    })
}

/// The coarse grid's step for `keys` keys over `n` frames: about [`SAMPLES_PER_GAP`] grid
/// frames per average gap, and at least 2.
pub fn grid_step(n: usize, keys: usize) -> usize {
    let spacing = (n - 1) / (keys.max(2) - 1);
    (spacing / SAMPLES_PER_GAP).max(2)
}

/// Gap lengths: the user's cap (or the longest possible gap), and the grid search's longest
/// gap between any two grid frames (longer ones are tried between anchors only).
#[derive(Debug, Clone, Copy)]
struct Lengths {
    fine: usize,
    coarse: usize,
}

/// Whether every gap between `keys` is at most `max_len` frames.
fn fits(keys: &[usize], max_len: usize) -> bool {
    keys.windows(2).all(|w| w[1] - w[0] <= max_len)
}

/// The exhaustive search over every frame, with the greedy solution as the budget (when it
/// respects the gap cap), and whether it found the optimum.
fn exhaustive(eval: &Evaluator, target: Target, g: Reduction, max_len: usize) -> (Reduction, bool) {
    let n = eval.frames();
    let k_max = g.keys.len();
    let g_fits = fits(&g.keys, max_len);
    let budget = match target {
        Target::Keys(_) if g_fits => g.total_error,
        Target::Keys(_) => f64::INFINITY,
        Target::MaxError(rms) => total_bound(eval, rms),
    };
    let candidates: Vec<usize> = (0..n).collect();
    let table = dp::solve(
        &Problem {
            candidates: &candidates,
            keys: k_max,
            max_len,
            short_len: max_len,
            anchor: 1,
            budget: slack(budget),
            windows: None,
        },
        &|a, b, bound, s| eval.segment_cost(a, b, bound, s),
    );
    // Smallest key count whose optimum meets the target (for Keys: exactly K).
    let k = match target {
        Target::Keys(k) => k,
        Target::MaxError(_) => (2..=k_max)
            .find(|&k| table.best(k).is_some_and(|e| e <= slack(budget)))
            .unwrap_or(k_max),
    };
    match table.keys(k) {
        Some(keys) => {
            let total_error = eval.frame_errors(&keys).iter().sum();
            let found = Reduction { keys, total_error };
            // Fewer keys always wins for an error bound; otherwise keep the smaller error
            // (the same up to rounding: the search found the optimum).
            if !g_fits || found.keys.len() < g.keys.len() || found.total_error <= g.total_error {
                (found, true)
            } else {
                (g, true)
            }
        }
        // Only reachable for an error bound that no key set within the cap, with at most
        // greedy's key count, meets: greedy's own answer is then the best we can offer.
        None => (g, false),
    }
}

/// Slack for rounding, so that the solution that set a budget is never pruned away.
fn slack(budget: f64) -> f64 {
    budget * (1.0 + 1e-9) + 1e-12
}

/// Exactly `k` keys: the grid searches, then refinement; never worse than the greedy `g`.
fn coarse_to_fine(
    eval: &Evaluator,
    g: Reduction,
    k: usize,
    lengths: Lengths,
    step: usize,
) -> Reduction {
    let n = eval.frames();
    let cache = SegmentCache::default();
    // Greedy's keys bound the error only when they respect the cap.
    let mut best = match fits(&g.keys, lengths.fine) {
        true => g.clone(),
        false => Reduction {
            keys: g.keys.clone(),
            total_error: f64::INFINITY,
        },
    };
    let mut searched = false;
    for offset in [0, step / 2] {
        let grid = grid(n, step, offset);
        let Some(keys) =
            coarse_search(eval, &grid, k, lengths, step, &best.keys, None).and_then(|t| t.keys(k))
        else {
            continue;
        };
        searched = true;
        let keys = narrow(eval, keys, step, lengths.fine);
        let total_error = eval.frame_errors(&keys).iter().sum();
        let start = Reduction { keys, total_error };
        let found = improve(eval, start, step, lengths.fine, &cache);
        if found.total_error < best.total_error {
            best = found;
        }
    }
    if !searched {
        // More keys than grid frames: refine the greedy keys themselves.
        best = improve(eval, best, step, lengths.fine, &cache);
    }
    match best.total_error.is_finite() {
        true => best,
        // Nothing within the cap was found: greedy's answer is the best we can offer.
        false => g,
    }
}

/// As few keys as possible within the total-error `bound`: the grid search proposes a key
/// count, refinement checks it at full resolution, adding keys until the bound is met. Never
/// more keys than greedy (`g`, which meets the bound).
fn fewest_keys(
    eval: &Evaluator,
    g: Reduction,
    bound: f64,
    lengths: Lengths,
    step: usize,
) -> Reduction {
    let n = eval.frames();
    let cache = SegmentCache::default();
    let grid = grid(n, step, 0);
    let k_max = g.keys.len();
    let Some(table) = coarse_search(eval, &grid, k_max, lengths, step, &g.keys, Some(bound)) else {
        return g;
    };
    let first = (2..k_max).find(|&k| table.best(k).is_some_and(|e| e <= bound));
    for k in first.into_iter().flat_map(|k| k..k_max) {
        let Some(keys) = table.keys(k) else {
            continue;
        };
        let keys = narrow(eval, keys, step, lengths.fine);
        let total_error: f64 = eval.frame_errors(&keys).iter().sum();
        let start = Reduction { keys, total_error };
        let r = improve(eval, start, step, lengths.fine, &cache);
        if r.total_error <= bound {
            return r;
        }
    }
    g
}

/// Frame 0, every `step`-th frame from `offset` (or from `step` when it is 0), and the last.
fn grid(n: usize, step: usize, offset: usize) -> Vec<usize> {
    let from = if offset == 0 { step } else { offset };
    let mut grid = vec![0];
    grid.extend((from..n - 1).step_by(step));
    grid.push(n - 1);
    grid
}

/// The exhaustive search over the grid with sampled segment costs. Its budget is `bound` when
/// given, else the estimated cost of `reference` moved to the grid (a feasible grid solution).
fn coarse_search(
    eval: &Evaluator,
    grid: &[usize],
    keys: usize,
    lengths: Lengths,
    step: usize,
    reference: &[usize],
    bound: Option<f64>,
) -> Option<dp::Table> {
    if grid.len() < keys {
        return None;
    }
    // Long gaps are sampled more sparsely, so that each segment costs at most MAX_SAMPLES
    // frame evaluations.
    let cost = |a: usize, b: usize, bound: f64, s: &mut Scratch| {
        let stride = step.max((b - a) / MAX_SAMPLES);
        eval.sampled_segment_cost(a, b, stride, bound, s)
    };
    // Anchors close enough together that long gaps between them stay within LONG_WORK.
    let m = grid.len();
    let long_pairs = LONG_WORK / keys.max(1);
    let anchor = m.div_ceil(((2 * long_pairs) as f64).sqrt() as usize).max(1);
    let budget = match bound {
        Some(b) => b,
        None => {
            let snapped = snap(reference, grid);
            let mut s = Scratch::default();
            let fits = snapped.windows(2).all(|w| w[1] - w[0] <= lengths.fine);
            if snapped.len() == keys && fits {
                snapped
                    .windows(2)
                    .map(|w| cost(w[0], w[1], f64::INFINITY, &mut s))
                    .sum()
            } else {
                f64::INFINITY
            }
        }
    };
    Some(dp::solve(
        &Problem {
            candidates: grid,
            keys,
            max_len: lengths.fine,
            short_len: lengths.coarse,
            anchor,
            budget: slack(budget),
            windows: None,
        },
        &cost,
    ))
}

/// `keys` moved to the nearest grid frames, kept distinct and in order (first and last stay).
fn snap(keys: &[usize], grid: &[usize]) -> Vec<usize> {
    let m = grid.len();
    let k = keys.len();
    if k < 2 || m < k {
        return Vec::new();
    }
    let mut out = vec![0];
    let mut prev = 0;
    for (r, &x) in keys.iter().enumerate().take(k - 1).skip(1) {
        let i = grid.partition_point(|&f| f < x);
        let nearest = match i {
            0 => 0,
            i if i < m && grid[i] - x <= x - grid[i - 1] => i,
            i => i - 1,
        };
        // Leave room for the keys still to place, each on its own grid frame.
        let highest = m - 1 - (k - 1 - r);
        let i = nearest.max(prev + 1).min(highest);
        out.push(grid[i]);
        prev = i;
    }
    out.push(grid[m - 1]);
    out
}

/// Halve the step down to 2, each time searching windows of the previous step around each key,
/// with candidates and cost samples at the new step (full-resolution refinement takes over
/// from there).
fn narrow(eval: &Evaluator, mut keys: Vec<usize>, mut step: usize, max_len: usize) -> Vec<usize> {
    let n = eval.frames();
    let k = keys.len();
    while step > 2 {
        let next = step / 2;
        let reach = step.div_ceil(next);
        let windows = windows(&keys, next * reach, n);
        let mut candidates = Vec::new();
        for (&x, &(lo, hi)) in keys.iter().zip(&windows) {
            for d in 0..=reach {
                for f in [x.saturating_sub(d * next), x + d * next] {
                    if lo <= f && f <= hi {
                        candidates.push(f);
                    }
                }
            }
        }
        candidates.sort_unstable();
        candidates.dedup();
        let cost = |a: usize, b: usize, bound: f64, s: &mut Scratch| {
            eval.sampled_segment_cost(a, b, next, bound, s)
        };
        let mut s = Scratch::default();
        let now: f64 = keys
            .windows(2)
            .map(|w| cost(w[0], w[1], f64::INFINITY, &mut s))
            .sum();
        let fits = keys.windows(2).all(|w| w[1] - w[0] <= max_len);
        let table = dp::solve(
            &Problem {
                candidates: &candidates,
                keys: k,
                max_len,
                short_len: max_len,
                anchor: 1,
                budget: if fits { slack(now) } else { f64::INFINITY },
                windows: Some(&windows),
            },
            &cost,
        );
        if let Some(found) = table.keys(k) {
            keys = found;
        }
        step = next;
    }
    keys
}

/// Per key, the frames within `radius` of it (first and last key fixed).
fn windows(keys: &[usize], radius: usize, n: usize) -> Vec<(usize, usize)> {
    let k = keys.len();
    keys.iter()
        .enumerate()
        .map(|(r, &x)| match r {
            0 => (0, 0),
            r if r == k - 1 => (n - 1, n - 1),
            _ => (x.saturating_sub(radius).max(1), (x + radius).min(n - 2)),
        })
        .collect()
}

/// Full-resolution refinement until it stops improving; then the halving search again from
/// `wide`, around the refined keys, while that leads somewhere better.
fn improve(
    eval: &Evaluator,
    mut best: Reduction,
    wide: usize,
    max_len: usize,
    cache: &SegmentCache,
) -> Reduction {
    for cycle in 0..=CYCLES {
        let mut improved = false;
        // Each round lowers the error, so this ends; in practice after a few rounds.
        while let Some(r) = refine(eval, &best.keys, max_len, best.total_error, cache) {
            best = r;
            improved = true;
        }
        if cycle == CYCLES || (cycle > 0 && !improved) || wide <= FINE_RADIUS {
            break;
        }
        let keys = narrow(eval, best.keys.clone(), wide, max_len);
        let total_error: f64 = eval.frame_errors(&keys).iter().sum();
        if total_error < best.total_error {
            best = Reduction { keys, total_error };
        } else {
            // Its neighbourhood may still hold something better than the current keys.
            match refine(eval, &keys, max_len, best.total_error, cache) {
                Some(r) => best = r,
                None => break,
            }
        }
    }
    best
}

/// The exact search over key sets whose `k`-th key lies within [`FINE_RADIUS`] frames of
/// `keys[k]` (first and last fixed); `None` unless it finds an error below `budget`.
fn refine(
    eval: &Evaluator,
    keys: &[usize],
    max_len: usize,
    budget: f64,
    cache: &SegmentCache,
) -> Option<Reduction> {
    let n = eval.frames();
    let k = keys.len();
    let windows = windows(keys, FINE_RADIUS, n);
    let mut candidates: Vec<usize> = windows.iter().flat_map(|&(lo, hi)| lo..=hi).collect();
    candidates.sort_unstable();
    candidates.dedup();
    let table = dp::solve(
        &Problem {
            candidates: &candidates,
            keys: k,
            max_len,
            short_len: max_len,
            anchor: 1,
            budget: budget * (1.0 - 1e-12),
            windows: Some(&windows),
        },
        &|a, b, bound, s| cache.cost(eval, a, b, bound, s),
    );
    let keys = table.keys(k)?;
    let total_error: f64 = eval.frame_errors(&keys).iter().sum();
    (total_error < budget).then_some(Reduction { keys, total_error })
}

/// Segment costs already computed, shared by the rounds of refinement (whose windows overlap):
/// the exact cost, or a lower bound (a partial sum) when the walk was abandoned.
#[derive(Default)]
struct SegmentCache {
    known: Mutex<HashMap<(usize, usize), (f64, bool)>>,
}

impl SegmentCache {
    fn cost(&self, eval: &Evaluator, a: usize, b: usize, bound: f64, s: &mut Scratch) -> f64 {
        let seen = self.known.lock().ok().and_then(|m| m.get(&(a, b)).copied());
        match seen {
            Some((c, true)) => return c,
            Some((c, false)) if c > bound => return c,
            _ => {}
        }
        let c = eval.segment_cost(a, b, bound, s);
        if let Ok(mut m) = self.known.lock() {
            m.insert((a, b), (c, c <= bound));
        }
        c
    }
}
