//! `--dump`: one CSV row per truth event with each method's signed error (s) and what the
//! foot did around it, for studying combinations offline (choose on tuning, report on held
//! out).

use super::{Detected, Timed, WINDOW_S};
use c3dfix::events::EventOptions;
use evals::stats::quantile;
use gait::{Kind, Side};
use std::io::Write as _;
use std::path::Path;

/// The dump file, created with its header line.
pub fn create(p: &Path) -> Result<std::fs::File, String> {
    let mut f = std::fs::File::create(p)
        .map_err(|_| format!("--dump {}: cannot create the file", p.display()))?;
    let _ = writeln!(
        f,
        "lab,group,truth,file,rate,side,kind,time,zeni_raw,zeni_refined,oconnor,desailly_03,desailly_05,velocity,zeni_lift,impact,touchdown,stride_s,speed_m_s,shipped,heel_above_mm,toe_above_mm,heel_vz_mm_s,toe_vz_mm_s,foot_len_mm,heel_p5_mm,toe_p5_mm,heel_swing_mm,toe_swing_mm,ankle"
    );
    Ok(f)
}

/// Trial `t`'s rows against its lab events and its plate events: each single method's
/// signed error to the truth event (none beyond ±[`WINDOW_S`]), the trial's stride and
/// walking speed from the markers alone, the shipped detector's error and the foot's state
/// at its event ([`DumpFeatures`]).
pub fn rows(f: &mut std::fs::File, t: &Detected, lab_events: &[Timed], opts: &EventOptions) {
    let (c, feet, rate, name, lab, corpus) = (&t.c, &t.feet, t.rate, &t.name, &t.lab, &t.corpus);
    let (kin, plates): (&Option<Vec<Timed>>, &[Timed]) = (&t.kin, &t.plates);
    let triple = |v: &[gait::Event]| t.triple(v);
    let variant = |method: gait::Method, ratio: f64| {
        let e = gait::Estimate {
            method,
            offset_s: 0.0,
        };
        let o = gait::KinematicOptions {
            strike: vec![e],
            off: vec![e],
            running_off: Vec::new(),
            desailly_cutoff_ratio: ratio,
            oconnor_lowpass_hz: 10.0,
            ankle_strike_offset_s: 0.0,
            ..opts.kinematic.clone()
        };
        gait::kinematic_events(feet, rate, &o)
            .map(|k| triple(&k))
            .unwrap_or_default()
    };
    let variants = [
        variant(gait::Method::Zeni, 0.5),
        variant(gait::Method::ZeniLanding, 0.5),
        variant(gait::Method::OConnor, 0.5),
        variant(gait::Method::Desailly, 0.3),
        variant(gait::Method::Desailly, 0.5),
        variant(gait::Method::Velocity, 0.3),
        variant(gait::Method::ZeniLift, 0.3),
        variant(gait::Method::Impact, 0.3),
        variant(gait::Method::Touchdown, 0.3),
    ];
    let group = if *corpus == "c3d-samples" {
        "tuning"
    } else {
        "held_out"
    };
    // The trial's rhythm, from the markers alone: each foot's median interval
    // between Zeni strikes, and the pelvis' median speed over ±0.5 s.
    let stride = |side: Side| {
        let mut d: Vec<f64> = variants[0]
            .iter()
            .filter(|e| e.0 == side && e.1 == Kind::FootStrike)
            .map(|e| e.2)
            .collect::<Vec<_>>()
            .windows(2)
            .map(|w| w[1] - w[0])
            .collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let h = (0.5 * rate) as usize;
    let speeds: Vec<f64> = (h..feet.pelvis.len().saturating_sub(h))
        .map(|i| {
            let (a, b) = (feet.pelvis[i - h], feet.pelvis[i + h]);
            ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
                / (2.0 * h as f64 / rate)
                / 1000.0
        })
        .filter(|v| v.is_finite() && *v > 0.2)
        .collect();
    let speed = quantile(&speeds, 0.5);
    let feats = DumpFeatures::new(feet, rate);
    for (truth_name, truth) in [("lab", &lab_events), ("plate", &plates)] {
        for &(side, kind, t) in truth.iter() {
            let shipped = kin
                .iter()
                .flatten()
                .filter(|f| f.0 == side && f.1 == kind)
                .map(|f| f.2 - t)
                .filter(|d| d.abs() <= WINDOW_S)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()));
            let at = shipped.map_or(f64::NAN, |d| (t + d - c.frame_time(0)) * rate);
            let extra = format!(
                "{},{}",
                shipped.map_or("nan".to_string(), |d| format!("{d:.5}")),
                feats.row(side, kind, at)
            );
            let errs: Vec<String> = variants
                .iter()
                .map(|v| {
                    v.iter()
                        .filter(|f| f.0 == side && f.1 == kind)
                        .map(|f| f.2 - t)
                        .filter(|d| d.abs() <= WINDOW_S)
                        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
                        .map_or("nan".to_string(), |d| format!("{d:.5}"))
                })
                .collect();
            let _ = writeln!(
                f,
                "{lab},{group},{truth_name},{},{rate},{side:?},{kind:?},{t:.5},{},{:.4},{speed:.3},{extra}",
                name.replace(',', ";"),
                errs.join(","),
                stride(side)
            );
        }
    }
}

/// What `--dump` records of the foot beside each event, to look for a per-trial
/// correction of the markers' lab-dependent lag in the trial's own kinematics: the heel's
/// and toe's heights (mm above their stance level: the lowest over the 0.5 s after a strike,
/// before an off) and vertical speeds at the detected event, and per foot the marker
/// placement (heel–toe distance, each marker's 5th-percentile height, its swing range).
pub struct DumpFeatures {
    vertical: Option<gait::axes::Vertical>,
    heel: [Vec<f64>; 2],
    toe: [Vec<f64>; 2],
    foot_len: [f64; 2],
    rate: f64,
    ankle: [bool; 2],
}

impl DumpFeatures {
    fn new(feet: &gait::Feet, rate: f64) -> Self {
        let vertical = gait::axes::vertical(
            &feet.pelvis,
            &[
                &feet.left_heel,
                &feet.right_heel,
                &feet.left_toe,
                &feet.right_toe,
            ],
        );
        let h = |x: &[[f64; 3]]| -> Vec<f64> {
            x.iter()
                .map(|p| vertical.map_or(f64::NAN, |v| v.height(*p)))
                .collect()
        };
        let len = |a: &[[f64; 3]], b: &[[f64; 3]]| {
            let d: Vec<f64> = a
                .iter()
                .zip(b)
                .map(|(p, q)| {
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
                })
                .filter(|v| v.is_finite())
                .collect();
            quantile(&d, 0.5)
        };
        DumpFeatures {
            vertical,
            heel: [h(&feet.left_heel), h(&feet.right_heel)],
            toe: [h(&feet.left_toe), h(&feet.right_toe)],
            foot_len: [
                len(&feet.left_heel, &feet.left_toe),
                len(&feet.right_heel, &feet.right_toe),
            ],
            rate,
            ankle: feet.heel_is_ankle,
        }
    }

    /// The CSV cells after `shipped` for an event of `side` and `kind` detected at frame `at`.
    fn row(&self, side: Side, kind: Kind, at: f64) -> String {
        let s = match side {
            Side::Left => 0,
            Side::Right => 1,
        };
        let (heel, toe) = (&self.heel[s], &self.toe[s]);
        let n = heel.len();
        let finite =
            |x: &[f64]| -> Vec<f64> { x.iter().copied().filter(|v| v.is_finite()).collect() };
        let above = |x: &[f64]| -> (f64, f64) {
            if !at.is_finite() || self.vertical.is_none() || n < 3 {
                return (f64::NAN, f64::NAN);
            }
            let k = (at.round() as usize).clamp(1, n - 2);
            let w = (0.5 * self.rate) as usize;
            let (a, b) = match kind {
                Kind::FootStrike => (k, (k + w).min(n)),
                Kind::FootOff => (k.saturating_sub(w), k + 1),
            };
            let level = quantile(&finite(&x[a..b]), 0.0);
            (x[k] - level, (x[k + 1] - x[k - 1]) * self.rate / 2.0)
        };
        let (ha, hv) = above(heel);
        let (ta, tv) = above(toe);
        let (hf, tf) = (finite(heel), finite(toe));
        format!(
            "{ha:.1},{ta:.1},{hv:.0},{tv:.0},{:.1},{:.1},{:.1},{:.1},{:.1},{}",
            self.foot_len[s],
            quantile(&hf, 0.05),
            quantile(&tf, 0.05),
            quantile(&hf, 0.95) - quantile(&hf, 0.05),
            quantile(&tf, 0.95) - quantile(&tf, 0.05),
            u8::from(self.ankle[s])
        )
    }
}
