//! Session calibration (`c3dfix events --calibrate-from`) judged leave one trial out: in
//! every lab of two or more trials, each trial's kinematics shifted by the offsets learned
//! from the lab's other trials, and from each single other trial.

use super::{Run, Settings, Timed};
use c3dfix::CalibrationTruth;
use gait::Event;
use std::collections::BTreeMap;

/// A trial as the session calibration's leave-one-trial-out sees it.
pub struct SessionTrial {
    /// The session's lab (as [`evals::labs::of_trial`], `sample_00` split by vendor folder).
    pub lab: String,
    pub name: String,
    pub rate: f64,
    pub t0: f64,
    pub kin: Vec<Event>,
    pub plates: Vec<Event>,
    pub lab_events: Vec<Event>,
}

impl SessionTrial {
    fn timed(&self, v: &[Event]) -> Vec<Timed> {
        v.iter()
            .map(|e| (e.side, e.kind, self.t0 + e.index / self.rate))
            .collect()
    }

    /// The lags this trial teaches, against the truth `truth` picks.
    fn lags(&self, truth: CalibrationTruth, window_s: f64) -> Vec<gait::session::Lag> {
        let known = match truth {
            CalibrationTruth::Plates => &self.plates,
            CalibrationTruth::Events => &self.lab_events,
            CalibrationTruth::PlatesElseEvents if self.plates.is_empty() => &self.lab_events,
            CalibrationTruth::PlatesElseEvents => &self.plates,
        };
        gait::session::trial_lags(known, &self.kin, self.rate, window_s)
    }
}

/// Every session trial of `run` scored before and after its session calibration (into
/// `run.table`); the offsets each trial was calibrated with, one line per trial.
pub fn score(run: &mut Run, s: &Settings) -> Vec<String> {
    let (session_trials, table) = (&run.session_trials, &mut run.table);
    let (session_truth, session_opts) = (s.session_truth, &s.session);
    // Session calibration, leave one trial out within each lab of two or more trials.
    const BEFORE: &str = "session: markers alone (before)";
    const ALL: &str = "session: calibrated on the lab's other trials";
    const ONE: &str = "session: calibrated on one other trial (each)";
    let mut session_labs: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    // Only trials with a truth (plates or the lab's events) teach or are judged.
    for (i, t) in session_trials.iter().enumerate() {
        if !(t.plates.is_empty() && t.lab_events.is_empty()) {
            session_labs.entry(t.lab.as_str()).or_default().push(i);
        }
    }
    let lags: Vec<Vec<gait::session::Lag>> = session_trials
        .iter()
        .map(|t| t.lags(session_truth, session_opts.window_s))
        .collect();
    let mut offsets_used: Vec<String> = Vec::new();
    for (lab, members) in &session_labs {
        if members.len() < 2 {
            continue;
        }
        for &i in members {
            let t = &session_trials[i];
            let mut score = |detector: &'static str, found: &[Event], first: bool| {
                let found = t.timed(found);
                for (truth_name, truth) in [("plate", &t.plates), ("lab", &t.lab_events)] {
                    if truth.is_empty() {
                        continue;
                    }
                    let e = table
                        .entry((truth_name, detector))
                        .or_default()
                        .entry(lab.to_string())
                        .or_default();
                    if first {
                        e.add(&t.timed(truth), &found, truth_name == "lab");
                    } else {
                        e.add_events(&t.timed(truth), &found, truth_name == "lab");
                    }
                }
            };
            score(BEFORE, &t.kin, true);
            let others: Vec<gait::session::Lag> = members
                .iter()
                .filter(|&&j| j != i)
                .flat_map(|&j| lags[j].iter().copied())
                .collect();
            let o = gait::session_offsets(&others, session_opts);
            let ms = |k: &gait::session::KindOffset| {
                k.seconds
                    .map(|s| s.map_or("none".into(), |v| format!("{:+.1}", v * 1000.0)))
                    .join("/")
            };
            offsets_used.push(format!(
                "{lab}: strikes {} ms ({} contacts), offs {} ms ({} contacts): {}",
                ms(&o.strike),
                o.strike.contacts[0] + o.strike.contacts[1],
                ms(&o.off),
                o.off.contacts[0] + o.off.contacts[1],
                t.name
            ));
            score(ALL, &gait::session::apply(&t.kin, &o, t.rate), true);
            let mut first = true;
            for &j in members.iter().filter(|&&j| j != i) {
                let o = gait::session_offsets(&lags[j], session_opts);
                score(ONE, &gait::session::apply(&t.kin, &o, t.rate), first);
                first = false;
            }
        }
    }
    offsets_used
}
