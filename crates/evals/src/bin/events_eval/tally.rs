//! Per lab, how many of the truth's events a detector finds within ±[`WINDOW_S`], its
//! errors, and the events it finds that no truth event answers.

use super::WINDOW_S;
use evals::stats::quantile;
use gait::{Kind, Side};

#[derive(Default)]
pub struct Tally {
    pub trials: usize,
    truth: [usize; 2],
    errors: [Vec<f64>; 2],
    signed: [Vec<f64>; 2],
    spanned: usize,
    extra: usize,
}

impl Tally {
    pub fn add(
        &mut self,
        truth: &[(Side, Kind, f64)],
        found: &[(Side, Kind, f64)],
        count_extra: bool,
    ) {
        self.trials += 1;
        self.add_events(truth, found, count_extra);
    }

    /// As [`Tally::add`], without counting a trial (one trial's events added in parts).
    pub fn add_events(
        &mut self,
        truth: &[(Side, Kind, f64)],
        found: &[(Side, Kind, f64)],
        count_extra: bool,
    ) {
        for &(side, kind, t) in truth {
            let k = kind_index(kind);
            self.truth[k] += 1;
            let best = found
                .iter()
                .filter(|f| f.0 == side && f.1 == kind)
                .map(|f| f.2 - t)
                .filter(|d| d.abs() <= WINDOW_S)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()));
            if let Some(d) = best {
                self.errors[k].push(d.abs() * 1000.0);
                self.signed[k].push(d * 1000.0);
            }
        }
        if !count_extra {
            return;
        }
        for side in Side::BOTH {
            for kind in [Kind::FootStrike, Kind::FootOff] {
                let ts: Vec<f64> = truth
                    .iter()
                    .filter(|e| e.0 == side && e.1 == kind)
                    .map(|e| e.2)
                    .collect();
                let (Some(lo), Some(hi)) = (
                    ts.iter().copied().reduce(f64::min),
                    ts.iter().copied().reduce(f64::max),
                ) else {
                    continue;
                };
                for f in found.iter().filter(|f| {
                    f.0 == side && f.1 == kind && f.2 >= lo - WINDOW_S && f.2 <= hi + WINDOW_S
                }) {
                    self.spanned += 1;
                    if !ts.iter().any(|t| (t - f.2).abs() <= WINDOW_S) {
                        self.extra += 1;
                    }
                }
            }
        }
    }

    pub fn merge(&mut self, o: &Tally) {
        self.trials += o.trials;
        for k in 0..2 {
            self.truth[k] += o.truth[k];
            self.errors[k].extend_from_slice(&o.errors[k]);
            self.signed[k].extend_from_slice(&o.signed[k]);
        }
        self.spanned += o.spanned;
        self.extra += o.extra;
    }

    pub fn line(&self, name: &str, extra: bool) -> String {
        let mut s = format!("{name:<44} {:>3}", self.trials);
        for k in 0..2 {
            let e = &self.errors[k];
            let found = if self.truth[k] > 0 {
                100.0 * e.len() as f64 / self.truth[k] as f64
            } else {
                f64::NAN
            };
            s += &format!(
                " | {:>4} {:>5.1}% {:>6.1} {:>6.1} {:>+6.1}",
                self.truth[k],
                found,
                quantile(e, 0.5),
                quantile(e, 0.95),
                quantile(&self.signed[k], 0.5)
            );
        }
        if extra && self.spanned > 0 {
            s += &format!(
                " | {:>5.1}% ({}/{})",
                100.0 * self.extra as f64 / self.spanned as f64,
                self.extra,
                self.spanned
            );
        } else {
            s += " |     -";
        }
        s
    }
}

fn kind_index(k: Kind) -> usize {
    match k {
        Kind::FootStrike => 0,
        Kind::FootOff => 1,
    }
}
