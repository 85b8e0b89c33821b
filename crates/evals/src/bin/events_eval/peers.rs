//! The peers side by side (`--list`, `--peers`): other packages' gait events on the same
//! trials, scored against the same truth with the same matching as c3dfix's own.
//!
//! `--list FILE` writes the trials the evaluation counts, one per line: the path, then the
//! markers c3dfix chose for the left heel, left toe, right heel, right toe and pelvis (tab
//! separated, several names joined by `+`). `scripts/events_peers.py` runs the peers on
//! those trials and writes their events as JSON, which `--peers FILE` reads:
//!
//! ```json
//! {"trials": {"PATH": {"gaitkit zeni": {"events": [["Left", "FootStrike", 12.0], …]},
//!                      "gaitalytics": {"error": "why it could not run"}}}}
//! ```
//!
//! Each event's third value is its 0-based frame index (the file's first frame is 0). A
//! peer that cannot run on a trial finds none of its events there: its hits count that.

use super::{Detected, Timed};
use gait::{Kind, Side};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::Path;

/// One peer's answer on one trial.
#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Answer {
    Events(Vec<(String, String, f64)>),
    Error(String),
}

#[derive(Deserialize)]
struct File {
    trials: BTreeMap<String, BTreeMap<String, Answer>>,
}

/// The peers' answers per trial path.
pub struct Peers {
    trials: BTreeMap<String, BTreeMap<String, Answer>>,
    /// Every peer named in the file, so each is scored on every trial.
    pub names: Vec<String>,
}

impl Peers {
    /// The answers of `path` (a file `scripts/events_peers.py` wrote).
    pub fn read(path: &Path) -> Result<Peers, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("--peers {}: {e}", path.display()))?;
        let f: File = serde_json::from_str(&text)
            .map_err(|e| format!("--peers {}: not the peers' JSON: {e}", path.display()))?;
        let mut names: Vec<String> = f.trials.values().flat_map(|t| t.keys().cloned()).collect();
        names.sort();
        names.dedup();
        Ok(Peers {
            trials: f.trials,
            names,
        })
    }

    /// Each peer's events on trial `t` (as compared), or why it gave none.
    pub fn of(&self, t: &Detected, path: &Path) -> Vec<(String, Result<Vec<Timed>, String>)> {
        let answers = self.trials.get(&path.to_string_lossy().to_string());
        let t0 = t.c.frame_time(0);
        self.names
            .iter()
            .map(|name| {
                let got = match answers.and_then(|a| a.get(name)) {
                    None => Err("not run on this trial".to_string()),
                    Some(Answer::Error(e)) => Err(e.clone()),
                    Some(Answer::Events(v)) => Ok(v
                        .iter()
                        .filter_map(|(side, kind, index)| {
                            let side = match side.as_str() {
                                "Left" => Side::Left,
                                "Right" => Side::Right,
                                _ => return None,
                            };
                            let kind = match kind.as_str() {
                                "FootStrike" => Kind::FootStrike,
                                "FootOff" => Kind::FootOff,
                                _ => return None,
                            };
                            Some((side, kind, t0 + index / t.rate))
                        })
                        .collect()),
                };
                (name.clone(), got)
            })
            .collect()
    }
}

/// `--list`: trial `t` at `path` and the markers c3dfix chose for it.
pub fn list_line(out: &mut std::fs::File, path: &Path, roles: [Vec<String>; 5]) {
    let cells: Vec<String> = roles.iter().map(|r| r.join("+")).collect();
    let _ = writeln!(out, "{}\t{}", path.display(), cells.join("\t"));
}

/// `--peers-dump`'s file, its header written.
pub fn dump_create(path: &Path) -> Result<std::fs::File, String> {
    let mut f =
        std::fs::File::create(path).map_err(|e| format!("--peers-dump {}: {e}", path.display()))?;
    let _ = writeln!(
        f,
        "truth,lab,trial,activity,side,kind,time_s,detector,error_ms"
    );
    Ok(f)
}

/// One row per event of `truth` (named `truth_name`) on trial `t`: `detector`'s signed
/// error (ms, detected − truth) to its nearest event of the same foot and kind within the
/// matching window, empty where it has none.
pub fn dump_rows(
    f: &mut std::fs::File,
    t: &Detected,
    truth_name: &str,
    detector: &str,
    truth: &[Timed],
    found: &[Timed],
) {
    let truth_name = truth_name.split(' ').next().unwrap_or(truth_name);
    for &(side, kind, time) in truth {
        let err = found
            .iter()
            .filter(|e| e.0 == side && e.1 == kind)
            .map(|e| e.2 - time)
            .filter(|d| d.abs() <= super::WINDOW_S)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .map_or(String::new(), |d| format!("{:.2}", d * 1000.0));
        let _ = writeln!(
            f,
            "{truth_name},{},\"{}\",{},{side:?},{kind:?},{time:.4},{detector},{err}",
            t.lab, t.name, t.activity
        );
    }
}

/// The reasons the peers gave no events, counted per peer and reason.
#[derive(Default)]
pub struct Failures(pub BTreeMap<String, BTreeMap<String, Vec<String>>>);

impl Failures {
    pub fn add(&mut self, peer: &str, reason: &str, trial: &str) {
        // The first line of a reason, without the trial's own numbers, groups alike failures.
        let short: String = reason
            .lines()
            .next()
            .unwrap_or("")
            .chars()
            .take(160)
            .collect();
        self.0
            .entry(peer.to_string())
            .or_default()
            .entry(short)
            .or_default()
            .push(trial.to_string());
    }

    pub fn print(&self) {
        if self.0.is_empty() {
            return;
        }
        println!();
        println!("== where a peer gave no events (trials: reason)");
        for (peer, reasons) in &self.0 {
            for (reason, trials) in reasons {
                println!("{peer}: {} trial(s): {reason}", trials.len());
                for t in trials.iter().take(3) {
                    println!("    e.g. {t}");
                }
            }
        }
    }
}
