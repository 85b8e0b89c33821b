//! Matching one frame's points to the template from nothing: a beam search over the
//! markers in the model's order, each placed on a free point (or left absent) by its
//! distances to the markers placed before it.

use super::cost::marker_cost;
use super::model::Model;
use super::options::LabelOptions;

const NONE: u16 = u16::MAX;

#[derive(Clone)]
struct State {
    at: Vec<u16>,
    used: Vec<bool>,
    cost: f64,
}

/// The best assignment of template markers to `points`: `out[m]` is the point of marker `m`,
/// kept only where the marker fits its placed pairs with a mean cost of at most
/// `opts.accept` over at least `opts.min_neighbours` of them.
pub(crate) fn seed(model: &Model, points: &[[f64; 3]], opts: &LabelOptions) -> Vec<Option<usize>> {
    let k = model.markers;
    let np = points.len().min(NONE as usize - 1);
    let mut beam = vec![State {
        at: vec![NONE; k],
        used: vec![false; np],
        cost: 0.0,
    }];
    let mut cands: Vec<(f64, usize, u16)> = Vec::new();
    for &m in &model.order {
        cands.clear();
        for (si, s) in beam.iter().enumerate() {
            let at = |n: usize| {
                let i = s.at[n];
                (i != NONE).then(|| &points[i as usize])
            };
            let mut placed = 0usize;
            for (p, point) in points.iter().enumerate().take(np) {
                if s.used[p] {
                    continue;
                }
                let (sum, terms) = marker_cost(model, m, point, at, opts, f64::INFINITY);
                placed = terms;
                cands.push((s.cost + sum, si, p as u16));
            }
            // Leaving the marker out costs as a poor fit to each placed pair would.
            cands.push((s.cost + opts.absent * placed.max(1) as f64, si, NONE));
        }
        cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        cands.truncate(opts.beam);
        beam = cands
            .iter()
            .map(|&(cost, si, p)| {
                let mut s = beam[si].clone();
                s.at[m] = p;
                if p != NONE {
                    s.used[p as usize] = true;
                }
                s.cost = cost;
                s
            })
            .collect();
    }
    let Some(best) = beam.first() else {
        return vec![None; k];
    };
    let at = |n: usize| {
        let i = best.at[n];
        (i != NONE).then(|| &points[i as usize])
    };
    (0..k)
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
