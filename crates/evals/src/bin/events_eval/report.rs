//! The tables: the settings the run detected with, then per truth and detector one line
//! per lab and one per group of labs (tuning, held out).

use super::tally::Tally;
use super::{Run, Settings, WINDOW_S};
use std::collections::BTreeMap;

/// The run's settings and tables, on stdout.
pub fn print(run: &Run, s: &Settings) {
    let (opts, session_truth, session_opts) = (&s.opts, s.session_truth, &s.session);
    let (table, rates) = (&run.table, &run.rates);
    let show = |v: &[gait::Estimate]| {
        v.iter()
            .map(|e| format!("{:?} {:+.4} s", e.method, e.offset_s))
            .collect::<Vec<_>>()
            .join(" + ")
    };
    println!(
        "kinematic: smoothing {} s, min speed {} mm/s, touch {} mm, ankle {:+} s; plates: threshold {} N",
        opts.kinematic.smooth_s,
        opts.kinematic.min_speed_mm_s,
        opts.kinematic.touch_mm,
        opts.kinematic.ankle_strike_offset_s,
        opts.plate.threshold_n
    );
    println!(
        "strikes: mean of {}; offs: mean of {}; O'Connor low-pass {} Hz; Desailly cut-off {} x stride frequency; calibrated on the trial's plates: {}",
        show(&opts.kinematic.strike),
        show(&opts.kinematic.off),
        opts.kinematic.oconnor_lowpass_hz,
        opts.kinematic.desailly_cutoff_ratio,
        !opts.no_calibrate
    );
    println!(
        "session calibration: from {:?}, at least {} contacts per kind, per side: {}, pairs within {} ms",
        session_truth,
        session_opts.min_contacts,
        session_opts.per_side,
        session_opts.window_s * 1000.0
    );
    println!(
        "found within ±{} ms; |error| in ms; signed = detected − truth (median)",
        WINDOW_S * 1000.0
    );
    for ((truth, detector), labs) in table {
        println!();
        println!("== {detector} against {truth} events");
        println!(
            "{:<44} {:>3} | {:>4} {:>6} {:>6} {:>6} {:>6} | {:>4} {:>6} {:>6} {:>6} {:>6} | extra",
            "lab", "n", "FS", "found", "med", "p95", "sign", "FO", "found", "med", "p95", "sign"
        );
        let mut groups: BTreeMap<&str, Tally> = BTreeMap::new();
        for (lab, t) in labs {
            let hz: Vec<String> = rates
                .get(lab)
                .map(|r| r.iter().map(|v| v.to_string()).collect())
                .unwrap_or_default();
            let name = format!("{lab} ({} Hz)", hz.join("/"));
            println!("{}", t.line(&name, truth.starts_with("lab")));
            let g = if lab.starts_with("c3d-samples") {
                "ALL tuning (c3d-samples)"
            } else if lab.starts_with("c3d-labs") {
                "ALL c3d-labs"
            } else {
                "ALL held out (more, extra, fullbody)"
            };
            groups.entry(g).or_default().merge(t);
            groups.entry("ALL pooled").or_default().merge(t);
        }
        for (g, t) in &groups {
            println!("{}", t.line(g, truth.starts_with("lab")));
        }
        if let Some(t) = run.gait.get(&(*truth, *detector)) {
            println!(
                "{}",
                t.line("ALL walking and running", truth.starts_with("lab"))
            );
        }
    }
}
