//! `--misses`: each truth event the shipped kinematics miss, where it lies in the trial and
//! where its foot's and the pelvis' markers are seen around it.

use super::{Detected, Timed, WINDOW_S};

/// Trial `t`'s missed lab and plate events, each printed once.
pub fn print(t: &Detected, lab_events: &[Timed]) {
    let (c, feet, rate, name, lab) = (&t.c, &t.feet, t.rate, &t.name, &t.lab);
    let (kin, plates): (&Option<Vec<Timed>>, &[Timed]) = (&t.kin, &t.plates);
    if let Some(k) = &kin {
        let t0 = c.frame_time(0);
        let n = feet.frames();
        let span = (n.saturating_sub(1)) as f64 / rate;
        let mut shown = Vec::new();
        for (truth_name, truth) in [("lab", &lab_events), ("plate", &plates)] {
            for &(side, kind, t) in truth.iter() {
                let nearest = k
                    .iter()
                    .filter(|f| f.0 == side && f.1 == kind)
                    .map(|f| f.2 - t)
                    .min_by(|a, b| a.abs().total_cmp(&b.abs()));
                if nearest.is_some_and(|d| d.abs() <= WINDOW_S)
                    || shown.contains(&(side, kind, (t * 1000.0) as i64))
                {
                    continue;
                }
                shown.push((side, kind, (t * 1000.0) as i64));
                let i = ((t - t0) * rate).round().max(0.0) as usize;
                let (a, b) = (
                    i.saturating_sub((0.25 * rate) as usize),
                    (i + (0.25 * rate) as usize + 1).min(n),
                );
                let (heel, toe) = feet.foot(side);
                let valid = |x: &[[f64; 3]]| {
                    let w = &x[a.min(n)..b.max(a.min(n))];
                    100.0 * w.iter().filter(|p| p[0].is_finite()).count() as f64
                        / w.len().max(1) as f64
                };
                println!(
                        "missed {name} [{lab}] {truth_name} {side:?} {kind:?} at {t:.3} s: {:.2} s after the start, {:.2} s before the end; nearest kinematic {} ; heel {:.0} % toe {:.0} % pelvis {:.0} % valid within 0.25 s",
                        t - t0,
                        t0 + span - t,
                        nearest.map_or("none".to_string(), |d| format!("{:+.0} ms", d * 1000.0)),
                        valid(heel),
                        valid(toe),
                        valid(&feet.pelvis),
                    );
                // Where each marker is seen, ±0.6 s around the event (s from
                // the event), so a gap's edge or the trial's tells itself.
                let w = (0.6 * rate) as usize;
                let (lo, hi) = (i.saturating_sub(w), (i + w + 1).min(n));
                let runs = |x: &[[f64; 3]]| {
                    let v: Vec<f64> = x[lo.min(n)..hi.max(lo.min(n))]
                        .iter()
                        .map(|p| p[0])
                        .collect();
                    let mut spans: Vec<(usize, usize)> = Vec::new();
                    for (k, x) in v.iter().enumerate() {
                        match spans.last_mut() {
                            Some(r) if x.is_finite() && r.1 == k => r.1 = k + 1,
                            _ if x.is_finite() => spans.push((k, k + 1)),
                            _ => {}
                        }
                    }
                    spans
                        .iter()
                        .map(|&(a, b)| {
                            let at = |k: usize| (lo + k) as f64 / rate + t0 - t;
                            format!("{:+.2}..{:+.2}", at(a), at(b - 1))
                        })
                        .collect::<Vec<_>>()
                        .join(" ")
                };
                println!(
                    "    seen (s from the event): heel {} | toe {} | pelvis {}",
                    runs(heel),
                    runs(toe),
                    runs(&feet.pelvis)
                );
            }
        }
    }
}
