//! Gait cycles and time normalisation on plain arrays.
//!
//! A cycle of one foot runs from one of its foot strikes to its next foot strike (the
//! stride, as gait labs and Nexus define it). A signal over a cycle is brought to 0–100 %
//! of the cycle in [`SAMPLES`] samples by linear interpolation at evenly spaced times from
//! the cycle's start to its end, both included.
//!
//! The rule is Kinetics Toolkit's `cycles.time_normalize` (kineticstoolkit/cycles.py): it
//! resamples each cycle linearly at `np.linspace(begin, end, n_points + 1)` and then drops
//! the last point, which "belongs to the next cycle", so its default (`n_points = 100`)
//! gives 0–99 %. We keep the last point, as gait reports plot 0–100 %: our samples 0–99
//! are Kinetics Toolkit's 100, sample 100 is the next strike.
//!
//! Missing data are never invented: a normalised sample whose two neighbouring samples of
//! the signal are not both finite is NaN, and so is one that falls outside the signal.

use crate::{Error, Result};

/// Samples per normalised cycle: 0, 1, …, 100 % of the cycle.
pub const SAMPLES: usize = 101;

/// One cycle: from a foot strike to the next foot strike of the same foot, in seconds on
/// the caller's time base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cycle {
    pub start: f64,
    pub end: f64,
}

impl Cycle {
    /// The cycle's duration (s).
    pub fn duration(&self) -> f64 {
        self.end - self.start
    }

    /// The time (s) at `percent` of the cycle.
    pub fn time_at(&self, percent: f64) -> f64 {
        self.start + percent / 100.0 * self.duration()
    }
}

/// The cycles of one foot from its foot strike times (any order; non-finite times are
/// ignored, and two strikes at the same time count once): each strike to the next.
pub fn cycles(strikes: &[f64]) -> Vec<Cycle> {
    let mut t: Vec<f64> = strikes.iter().copied().filter(|x| x.is_finite()).collect();
    t.sort_by(f64::total_cmp);
    t.dedup();
    t.windows(2)
        .map(|w| Cycle {
            start: w[0],
            end: w[1],
        })
        .collect()
}

/// A signal sampled evenly: `frames × channels` values, row-major (one row per sample),
/// NaN where missing, sample 0 at `start` seconds, `rate` samples per second.
#[derive(Debug, Clone, Copy)]
pub struct Signal<'a> {
    pub values: &'a [f64],
    pub channels: usize,
    pub rate: f64,
    pub start: f64,
}

impl Signal<'_> {
    /// Samples (rows).
    pub fn samples(&self) -> usize {
        self.values.len().checked_div(self.channels).unwrap_or(0)
    }

    /// The time (s) of the last sample.
    pub fn end(&self) -> f64 {
        self.start + self.samples().saturating_sub(1) as f64 / self.rate
    }

    fn check(&self) -> Result<()> {
        if !(self.rate > 0.0 && self.rate.is_finite()) {
            return Err(Error::Input(format!(
                "rate {}: expected a positive number of samples per second",
                self.rate
            )));
        }
        if self.channels == 0 || !self.values.len().is_multiple_of(self.channels) {
            return Err(Error::Input(format!(
                "{} values do not make rows of {} channels",
                self.values.len(),
                self.channels
            )));
        }
        if !self.start.is_finite() {
            return Err(Error::Input("the signal's start time is not finite".into()));
        }
        Ok(())
    }
}

/// How near (in samples) a time must be to a sample to be read as that sample alone, and
/// how far outside the signal it may fall and still be read at its end. Event times are
/// stored as 32-bit floats (EVENT:TIMES), whose rounding puts a strike meant to be on a
/// frame up to about 1e-4 frames off it at 100 s and 1000 Hz; without this a missing
/// neighbour weighted by a millionth would blank the sample. Snapping moves a value by at
/// most a thousandth of one sample step.
const EDGE: f64 = 1e-3;

/// The signal at time `t`, channel `c`: linear between the two samples around it, NaN
/// when either is missing or `t` lies outside the signal.
fn at(s: &Signal, t: f64, c: usize) -> f64 {
    let n = s.samples();
    let u = (t - s.start) * s.rate;
    if n == 0 || !u.is_finite() || u < -EDGE || u > (n - 1) as f64 + EDGE {
        return f64::NAN;
    }
    let u = u.clamp(0.0, (n - 1) as f64);
    let i = u.floor() as usize;
    let frac = u - i as f64;
    let a = s.values[i * s.channels + c];
    // On a sample (or on the last one), that sample alone.
    if frac <= EDGE || i + 1 >= n {
        return a;
    }
    if 1.0 - frac <= EDGE {
        return s.values[(i + 1) * s.channels + c];
    }
    let b = s.values[(i + 1) * s.channels + c];
    if a.is_finite() && b.is_finite() {
        a + (b - a) * frac
    } else {
        f64::NAN
    }
}

/// `signal` over `cycle`, normalised to [`SAMPLES`] samples × its channels (row-major:
/// sample `k` is at `k` % of the cycle). A cycle that is not forward in time is an error.
pub fn time_normalize(signal: &Signal, cycle: &Cycle) -> Result<Vec<f64>> {
    signal.check()?;
    if !(cycle.start.is_finite() && cycle.end.is_finite() && cycle.end > cycle.start) {
        return Err(Error::Input(format!(
            "cycle {}–{} s: expected an end after its start",
            cycle.start, cycle.end
        )));
    }
    let mut out = Vec::with_capacity(SAMPLES * signal.channels);
    for k in 0..SAMPLES {
        let t = cycle.start + k as f64 / (SAMPLES - 1) as f64 * cycle.duration();
        for c in 0..signal.channels {
            out.push(at(signal, t, c));
        }
    }
    Ok(out)
}

/// Whether `cycle` lies within the signal's time span (a cycle outside it would be NaN
/// throughout, or partly).
pub fn within(signal: &Signal, cycle: &Cycle) -> bool {
    let tol = EDGE / signal.rate;
    cycle.start >= signal.start - tol && cycle.end <= signal.end() + tol
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The obviously-correct reading of the rule, written from numpy's `linspace` and
    /// `interp`, as the oracle.
    fn naive(values: &[f64], rate: f64, start: f64, c: Cycle) -> Vec<f64> {
        (0..SAMPLES)
            .map(|k| {
                let t = c.start + (c.end - c.start) * k as f64 / 100.0;
                let x = (t - start) * rate;
                let i = x.floor() as usize;
                let f = x - i as f64;
                if f == 0.0 {
                    values[i]
                } else {
                    values[i] * (1.0 - f) + values[i + 1] * f
                }
            })
            .collect()
    }

    #[test]
    fn cycles_run_strike_to_next_strike() {
        let c = cycles(&[2.0, 1.0, f64::NAN, 3.5, 2.0]);
        assert_eq!(
            c,
            vec![
                Cycle {
                    start: 1.0,
                    end: 2.0
                },
                Cycle {
                    start: 2.0,
                    end: 3.5
                }
            ]
        );
        assert!(cycles(&[1.0]).is_empty());
        assert_eq!(c[1].time_at(50.0), 2.75);
    }

    #[test]
    fn a_line_stays_a_line_and_ends_are_included() {
        // 100 Hz, value = time in ms; a cycle from 0.213 s to 1.187 s.
        let values: Vec<f64> = (0..200).map(|i| i as f64 * 10.0).collect();
        let s = Signal {
            values: &values,
            channels: 1,
            rate: 100.0,
            start: 0.0,
        };
        let c = Cycle {
            start: 0.213,
            end: 1.187,
        };
        let n = time_normalize(&s, &c).unwrap();
        assert_eq!(n.len(), 101);
        for (k, v) in n.iter().enumerate() {
            let t = c.time_at(k as f64) * 1000.0;
            assert!((v - t).abs() < 1e-9, "sample {k}: {v} against {t}");
        }
        let oracle = naive(&values, 100.0, 0.0, c);
        for (k, (a, b)) in n.iter().zip(&oracle).enumerate() {
            assert!((a - b).abs() < 1e-9, "sample {k}: {a} against {b}");
        }
    }

    #[test]
    fn channels_and_a_start_offset() {
        // Two channels at 50 Hz from 2.0 s: sin and cos of time.
        let rate = 50.0;
        let start = 2.0;
        let values: Vec<f64> = (0..150)
            .flat_map(|i| {
                let t = start + i as f64 / rate;
                [t.sin(), t.cos()]
            })
            .collect();
        let s = Signal {
            values: &values,
            channels: 2,
            rate,
            start,
        };
        let c = Cycle {
            start: 2.5,
            end: 3.9,
        };
        let n = time_normalize(&s, &c).unwrap();
        let sin: Vec<f64> = values.iter().step_by(2).copied().collect();
        let oracle = naive(&sin, rate, start, c);
        for k in 0..SAMPLES {
            assert!((n[2 * k] - oracle[k]).abs() < 1e-12);
            // Linear interpolation of a smooth signal at 50 Hz: within 1e-4 of the truth.
            assert!((n[2 * k + 1] - c.time_at(k as f64).cos()).abs() < 1e-4);
        }
    }

    #[test]
    fn gaps_give_nan_only_where_they_are() {
        let mut values: Vec<f64> = (0..100).map(|i| i as f64).collect();
        values[50] = f64::NAN;
        let s = Signal {
            values: &values,
            channels: 1,
            rate: 100.0,
            start: 0.0,
        };
        // From 0.1 s to 0.9 s: samples at 0.1 + 0.008 k s.
        let c = Cycle {
            start: 0.1,
            end: 0.9,
        };
        let n = time_normalize(&s, &c).unwrap();
        for (k, v) in n.iter().enumerate() {
            let t = c.time_at(k as f64);
            // Read from samples floor(100 t) and the next; NaN exactly when one is sample 50.
            let i = (t * 100.0 + 1e-9).floor() as usize;
            let on = (t * 100.0 - i as f64).abs() < 1e-6;
            let touches = i == 50 || (!on && i + 1 == 50);
            assert_eq!(v.is_nan(), touches, "sample {k} at {t} s");
        }
    }

    #[test]
    fn outside_the_signal_is_nan_and_bad_input_an_error() {
        let values = vec![1.0; 10];
        let s = Signal {
            values: &values,
            channels: 1,
            rate: 10.0,
            start: 0.0,
        };
        let c = Cycle {
            start: 0.5,
            end: 1.5,
        };
        assert!(!within(&s, &c));
        let n = time_normalize(&s, &c).unwrap();
        assert_eq!(n[0], 1.0);
        assert!(n[100].is_nan());
        assert!(time_normalize(
            &s,
            &Cycle {
                start: 1.0,
                end: 1.0
            }
        )
        .is_err());
        let bad = Signal { rate: 0.0, ..s };
        assert!(time_normalize(
            &bad,
            &Cycle {
                start: 0.1,
                end: 0.5
            }
        )
        .is_err());
        let ragged = Signal { channels: 3, ..s };
        assert!(time_normalize(
            &ragged,
            &Cycle {
                start: 0.1,
                end: 0.5
            }
        )
        .is_err());
        assert!(within(
            &s,
            &Cycle {
                start: 0.0,
                end: 0.9
            }
        ));
    }
}
