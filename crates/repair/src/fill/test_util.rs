//! Helpers the fill methods' tests share: a trial with a gap, one method's fill of it, and
//! its largest error.

use super::apply::fill_with;
use super::data::{Data, Span, Target};
use super::method::FillMethod;
use super::options::FillOptions;
use super::outcome::Fill;
use super::plan::Plan;
use super::step::max_steps;

/// A one-marker-or-more trial with marker 0's frames `first..=last` invalid.
pub fn with_gap(
    mut xyz: Vec<Vec<[f64; 3]>>,
    first: usize,
    last: usize,
) -> (Vec<Vec<[f64; 3]>>, Vec<Vec<bool>>) {
    let n = xyz[0].len();
    let mut valid = vec![vec![true; n]; xyz.len()];
    for f in first..=last {
        valid[0][f] = false;
        xyz[0][f] = [f64::NAN; 3];
    }
    (xyz, valid)
}

/// Fills marker 0's gap `first..=last` with `method` and returns the fill.
pub fn fill(
    xyz: &[Vec<[f64; 3]>],
    valid: &[Vec<bool>],
    first: usize,
    last: usize,
    method: FillMethod,
) -> Fill {
    let steps = max_steps(xyz, valid);
    let data = Data::new(xyz, valid, &steps);
    let t = Target {
        m: 0,
        data,
        hole: None,
    };
    let span = Span::new(first, last, data.frames);
    let opts = FillOptions::default();
    let plan = Plan::build(&t, span, &opts);
    fill_with(method, &t, span, &plan, &opts)
}

pub fn max_err(fill: &[[f64; 3]], truth: impl Fn(usize) -> [f64; 3], first: usize) -> f64 {
    fill.iter()
        .enumerate()
        .map(|(i, p)| {
            let q = truth(first + i);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}
