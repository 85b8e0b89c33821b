//! Greedy keyframe reduction: start with every frame as a key and repeatedly drop the key
//! whose removal adds the least error.
//!
//! Each key's removal cost (error of the merged segment minus the two segments it splits) sits
//! in a min-heap; when a key is removed only its two neighbours' costs change, so they are
//! recomputed and pushed again, and stale heap entries are skipped when popped (lazy update).
//! Cost: O(n log n) heap work plus the segment evaluations, each O(segment length · joints);
//! since segments are short while most keys remain, the whole run is close to
//! O(n log n · joints) on real motion, and O(n² · joints) in the worst case.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::{check, total_bound, KeyframeError, Reduction, Target};
use crate::error_metric::{Evaluator, Scratch};

/// The full greedy removal sequence, from all frames down to the first and last.
#[derive(Debug, Clone, PartialEq)]
pub struct GreedyRun {
    pub frames: usize,
    /// Frames in the order they were removed.
    pub removed: Vec<usize>,
    /// Total error after each removal (`totals[i]` once `i + 1` frames are removed).
    pub totals: Vec<f64>,
}

impl GreedyRun {
    /// The keys left once `removed_count` frames are gone.
    pub fn keys_after(&self, removed_count: usize) -> Vec<usize> {
        let mut keep = vec![true; self.frames];
        for &f in self.removed.iter().take(removed_count) {
            keep[f] = false;
        }
        (0..self.frames).filter(|&f| keep[f]).collect()
    }

    /// Total error once `removed_count` frames are gone.
    pub fn total_after(&self, removed_count: usize) -> f64 {
        match removed_count {
            0 => 0.0,
            r => self.totals.get(r - 1).copied().unwrap_or(0.0),
        }
    }

    /// The accumulated-error curve: (removed frames, total error), starting at (0, 0).
    pub fn curve(&self) -> Vec<(usize, f64)> {
        std::iter::once((0, 0.0))
            .chain(self.totals.iter().enumerate().map(|(i, &e)| (i + 1, e)))
            .collect()
    }
}

struct Entry {
    delta: f64,
    frame: usize,
    version: u32,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    /// Reversed, so that `BinaryHeap` pops the smallest delta (ties: the earliest frame).
    fn cmp(&self, o: &Self) -> Ordering {
        o.delta
            .total_cmp(&self.delta)
            .then_with(|| o.frame.cmp(&self.frame))
    }
}

/// Remove frames one by one down to the first and last, recording the order and the error.
pub fn run(eval: &Evaluator) -> GreedyRun {
    let n = eval.frames();
    let mut run = GreedyRun {
        frames: n,
        removed: Vec::new(),
        totals: Vec::new(),
    };
    if n < 3 {
        return run;
    }
    let mut s = Scratch::default();
    let mut prev: Vec<usize> = (0..n).map(|i| i.saturating_sub(1)).collect();
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1).min(n - 1)).collect();
    // seg[k]: error of the segment from key k to its next key.
    let mut seg = vec![0.0; n];
    // merged[k]: error of the segment that removing k would create.
    let mut merged = vec![0.0; n];
    let mut version = vec![0u32; n];
    let mut removed = vec![false; n];
    let mut heap = BinaryHeap::with_capacity(n);
    for (k, m) in merged.iter_mut().enumerate().take(n - 1).skip(1) {
        *m = eval.frame_error(k - 1, k + 1, k, &mut s);
        heap.push(Entry {
            delta: *m,
            frame: k,
            version: 0,
        });
    }
    let mut total = 0.0;
    while let Some(e) = heap.pop() {
        let k = e.frame;
        if removed[k] || e.version != version[k] {
            continue;
        }
        removed[k] = true;
        total += e.delta;
        run.removed.push(k);
        run.totals.push(total);
        let (p, nx) = (prev[k], next[k]);
        seg[p] = merged[k];
        next[p] = nx;
        prev[nx] = p;
        for j in [p, nx] {
            if j == 0 || j == n - 1 {
                continue;
            }
            let (a, b) = (prev[j], next[j]);
            merged[j] = eval.segment_cost(a, b, f64::INFINITY, &mut s);
            version[j] += 1;
            heap.push(Entry {
                delta: merged[j] - seg[a] - seg[j],
                frame: j,
                version: version[j],
            });
        }
    }
    run
}

/// Greedy reduction to a target.
pub fn reduce(eval: &Evaluator, target: Target) -> Result<Reduction, KeyframeError> {
    check(eval, target)?;
    let greedy = run(eval);
    Ok(pick(&greedy, eval, target))
}

/// [`reduce`] from a run already made with the same evaluator.
pub fn reduce_run(
    eval: &Evaluator,
    run: &GreedyRun,
    target: Target,
) -> Result<Reduction, KeyframeError> {
    check(eval, target)?;
    Ok(pick(run, eval, target))
}

/// The point of a greedy run that meets `target` (assumed valid).
pub fn pick(greedy: &GreedyRun, eval: &Evaluator, target: Target) -> Reduction {
    let n = greedy.frames;
    let removed_count = match target {
        Target::Keys(k) => n.saturating_sub(k),
        Target::MaxError(rms) => {
            let bound = total_bound(eval, rms);
            greedy
                .totals
                .iter()
                .position(|&t| t > bound)
                .unwrap_or(greedy.totals.len())
        }
    };
    let keys = greedy.keys_after(removed_count);
    // Recomputed rather than taken from the running sum, which drifts by rounding.
    let total_error = eval.frame_errors(&keys).iter().sum();
    Reduction { keys, total_error }
}
