//! Matching one frame's points to the template from nothing: a beam search over the
//! markers in the model's order, each placed on a free point (or left absent) by its
//! distances to the markers placed before it.

use super::cost::marker_cost;
use super::model::handedness;
use super::model::Model;
use super::options::dist;
use super::options::LabelOptions;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

const NONE: u16 = u16::MAX;

#[derive(Clone)]
struct State {
    at: Vec<u16>,
    used: Vec<bool>,
    cost: f64,
}

/// A way to extend the beam: its cost, the state it extends and the point it gives the
/// marker. Ordered by cost, then state, then point: the beam keeps the least.
#[derive(Clone, Copy)]
struct Cand(f64, usize, u16);

impl PartialEq for Cand {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Cand {}
impl PartialOrd for Cand {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cand {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0
            .total_cmp(&o.0)
            .then(self.1.cmp(&o.1))
            .then(self.2.cmp(&o.2))
    }
}

/// The `size` least candidates offered, in a heap whose top is the worst kept: a new
/// candidate above it cannot enter, so its cost need not be finished.
struct Best {
    heap: BinaryHeap<Cand>,
    size: usize,
}

impl Best {
    fn offer(&mut self, c: Cand) {
        if self.heap.len() < self.size {
            self.heap.push(c);
        } else if self.heap.peek().is_some_and(|top| c < *top) {
            self.heap.pop();
            self.heap.push(c);
        }
    }

    /// The cost a candidate must not pass to enter (with a margin for rounding: the
    /// candidates it lets through are compared exactly).
    fn bar(&self) -> f64 {
        match self.heap.peek() {
            Some(top) if self.heap.len() >= self.size => top.0 + 1e-9 * top.0.abs().max(1.0),
            _ => f64::INFINITY,
        }
    }
}

/// The best assignment of template markers to `points`: `out[m]` is the point of marker `m`,
/// kept only where the marker fits its placed pairs with a mean cost of at most
/// `opts.accept` over at least `opts.min_neighbours` of them.
/// `fixed` places markers on points before the search (`(marker, point)`): the search
/// places the others around them.
pub(crate) fn seed(
    model: &Model,
    points: &[[f64; 3]],
    fixed: &[(usize, usize)],
    opts: &LabelOptions,
) -> Vec<Option<usize>> {
    let k = model.markers;
    let np = points.len().min(NONE as usize - 1);
    let mut start = State {
        at: vec![NONE; k],
        used: vec![false; np],
        cost: 0.0,
    };
    for &(m, p) in fixed {
        if m < k && p < np && start.at[m] == NONE && !start.used[p] {
            start.at[m] = p as u16;
            start.used[p] = true;
        }
    }
    let mut beam = vec![start];
    let mut best = Best {
        heap: BinaryHeap::with_capacity(opts.beam + 1),
        size: opts.beam.max(1),
    };
    // Every distance between the frame's points, once: a pair's term is then a lookup.
    let frame = Frame {
        model,
        points,
        np,
        d: (0..np * np)
            .map(|i| dist(&points[i / np], &points[i % np]))
            .collect(),
        opts,
    };
    let widest = model.nb.iter().map(Vec::len).max().unwrap_or(0);
    let mut scratch = Scratch {
        rows: vec![None; widest * np],
        pairs: Vec::new(),
        hands: Vec::new(),
    };
    for &m in &model.order {
        if beam.first().is_some_and(|s| s.at[m] != NONE) {
            continue;
        }
        scratch.rows.iter_mut().for_each(|r| *r = None);
        for (si, s) in beam.iter().enumerate() {
            extend(&frame, m, si, s, &mut scratch, &mut best);
        }
        let mut cands = std::mem::take(&mut best.heap).into_sorted_vec();
        beam = cands
            .drain(..)
            .map(|Cand(cost, si, p)| {
                let mut s = beam[si].clone();
                s.at[m] = p;
                if p != NONE {
                    s.used[p as usize] = true;
                }
                s.cost = cost;
                s
            })
            .collect();
        best.heap = BinaryHeap::from(cands);
    }
    match beam.first() {
        Some(best) => accepted(model, points, best, opts),
        None => vec![None; k],
    }
}

/// What one frame's search reads: the model, the frame's points, every distance between
/// them (`d[p * np + q]`) and the options.
struct Frame<'a> {
    model: &'a Model,
    points: &'a [[f64; 3]],
    np: usize,
    d: Vec<f64>,
    opts: &'a LabelOptions,
}

/// What the search reuses from state to state: for the marker being placed, the points in
/// order of the term of one pair (its `j`-th neighbour at point `q`, filled when first
/// asked), and the placed pairs and handedness triples of the state at hand.
struct Scratch {
    rows: Vec<Option<Vec<(f64, u16)>>>,
    pairs: Vec<(usize, f64, f64)>,
    hands: Vec<(usize, usize, usize, f64)>,
}

/// Offer `best` every way state `si` (`s`) can place marker `m`: on each free point whose
/// cost can still enter the beam, or left out.
fn extend(f: &Frame<'_>, m: usize, si: usize, s: &State, sc: &mut Scratch, best: &mut Best) {
    let Scratch { rows, pairs, hands } = sc;
    let (model, points, np, d, opts) = (f.model, f.points, f.np, &f.d, f.opts);
    pairs.clear();
    let mut first = None;
    for (j, n) in model.nb[m].iter().enumerate() {
        let i = s.at[n.other];
        if i != NONE {
            first.get_or_insert((j, i as usize, n.d0, n.sigma));
            pairs.push((i as usize, n.d0, n.sigma));
        }
    }
    hands.clear();
    for c in &model.chiral[m] {
        let (a, b, cc) = (s.at[c.a], s.at[c.b], s.at[c.c]);
        if a != NONE && b != NONE && cc != NONE {
            hands.push((a as usize, b as usize, cc as usize, c.sign));
        }
    }
    let (pairs, hands) = (&*pairs, &*hands);
    // The cost at point `p`, as `marker_cost` adds it; `None` past `limit`.
    let cost = |p: usize, limit: f64| {
        let mut sum = 0.0;
        for &(q, d0, sigma) in pairs {
            let e = (d[p * np + q] - d0) / sigma;
            sum += (e * e).min(opts.cap);
            if sum > limit {
                return None;
            }
        }
        for &(a, b, c, sign) in hands {
            let h = handedness(&points[p], &points[a], &points[b], &points[c]);
            if h * sign < -0.05 {
                sum += opts.cap;
            }
        }
        Some(sum)
    };
    let any_free = s.used.iter().any(|u| !u);
    match first {
        // The points in order of the first pair's term, which no other term can
        // lower: once it alone keeps a point out of the beam, it keeps the rest out.
        Some((j, q, d0, sigma)) => {
            let row = rows[j * np + q].get_or_insert_with(|| {
                let mut r: Vec<(f64, u16)> = (0..np)
                    .map(|p| {
                        let e = (d[p * np + q] - d0) / sigma;
                        ((e * e).min(opts.cap), p as u16)
                    })
                    .collect();
                r.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                r
            });
            for &(t1, p) in row.iter() {
                if s.used[p as usize] {
                    continue;
                }
                if s.cost + t1 > best.bar() {
                    break;
                }
                if let Some(sum) = cost(p as usize, best.bar() - s.cost) {
                    best.offer(Cand(s.cost + sum, si, p));
                }
            }
        }
        None => {
            for p in (0..np).filter(|&p| !s.used[p]) {
                if let Some(sum) = cost(p, f64::INFINITY) {
                    best.offer(Cand(s.cost + sum, si, p as u16));
                }
            }
        }
    }
    // Leaving the marker out costs as a poor fit to each placed pair would.
    let placed = if any_free { pairs.len() } else { 0 };
    best.offer(Cand(s.cost + opts.absent * placed.max(1) as f64, si, NONE));
}

/// The best state's markers kept where each fits its placed pairs with a mean cost of at
/// most `opts.accept` over at least `opts.min_neighbours` of them.
fn accepted(
    model: &Model,
    points: &[[f64; 3]],
    best: &State,
    opts: &LabelOptions,
) -> Vec<Option<usize>> {
    let at = |n: usize| {
        let i = best.at[n];
        (i != NONE).then(|| &points[i as usize])
    };
    (0..model.markers)
        .map(|m| {
            let i = best.at[m];
            if i == NONE {
                return None;
            }
            let (sum, terms) = marker_cost(model, m, &points[i as usize], at, opts, f64::INFINITY);
            (terms >= opts.min_neighbours && sum <= opts.accept * terms as f64)
                .then_some(i as usize)
        })
        .collect()
}
