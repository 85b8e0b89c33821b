//! How well gait events are found, per lab, on the corpora's walking trials.
//!
//! ```sh
//! cargo run --release -p evals --bin events_eval            # the constants as shipped
//! cargo run --release -p evals --bin events_eval -- --strike zeni:0.02 --off desailly:-0.012,zeni:-0.015
//! cargo run --release -p evals --bin events_eval -- --misses       # each missed event, where, and where its markers are seen
//! cargo run --release -p evals --bin events_eval -- --strike landing:0 --landing-height 0 --landing-speed 0.15  # landing as a fraction of the swing
//! cargo run --release -p evals --bin events_eval -- --cut-min-fall 1 --pelvis-extend 0.25  # extremes at a cut as before; the pelvis carried past its ends
//! cargo run --release -p evals --bin events_eval -- --dump e.csv   # each method's error per event
//! cargo run --release -p evals --bin events_eval -- --dump e.csv --touchdown-mm 5 --touchdown-speed 50 --liftoff-mm 5 --liftoff-speed 200  # the touchdown method's thresholds
//! cargo run --release -p evals --bin events_eval -- --off-stride-slope 0 --off zeni:-0.0149  # offs with a constant offset, as before
//! cargo run --release -p evals --bin events_eval -- --correlate --correlate-strike heel  # auto matched to the plate steps
//! cargo run --release -p evals --bin events_eval -- --truth-check  # the foot's state at each lab event
//! cargo run --release -p evals --bin events_eval -- --without-contradicted  # lab strikes the plates contradict left out
//! cargo run --release -p evals --bin events_eval -- --session-per-side --session-min 3 --session-truth plates
//! ```
//!
//! **Session calibration** (`c3dfix events --calibrate-from`): in every lab with two or more
//! trials whose markers give events, each trial's kinematic events are shifted by the
//! offsets learned from the lab's OTHER trials (leave one trial out), and, apart, from each
//! single other trial; both scored against the trial's plates and its lab events beside the
//! same trials' uncalibrated events ("before"). Here c3d-samples' `sample_00` is four labs
//! (one per vendor folder), since its trials come from different systems.
//!
//! Every C3D file of `c3d-samples`, `c3d-more`, `c3d-extra`, `c3d-fullbody` and `c3d-labs`
//! whose foot and pelvis markers are found and hold marker data (not every sample at
//! (0, 0, 0)) is read once (copies of one trial in other formats are counted once: same
//! frame count and same left-heel trajectory). Two truths:
//!
//! - **lab**: the file's own Foot Strike / Foot Off events (EVENT group, Left/Right);
//! - **plate**: foot strikes and offs where one foot alone loads a force plate
//!   ([`gait::plate_events`]).
//!
//! Compared against them: the kinematic detector (Zeni 2008) and, against the lab's events,
//! the plate detector. An event is found when a detected event of the same foot and kind
//! lies within ±150 ms; its |error| enters the median and 95th percentile. Extra: detected
//! events of a foot and kind within the span of that foot's and kind's lab events (±150 ms)
//! matched to none (only against lab events: a plate covers one step, so the markers' other
//! events are no extras there).
//!
//! Labs: each `sample_NN` folder of c3d-samples is a lab, each `owner__repository` of
//! c3d-more (and its trial's name, for the three labs of `tsalemink__C3D-parser`), c3d-extra
//! is BTK's, c3d-fullbody's CMU and numediart. Constants are chosen on the c3d-samples labs
//! ("tuning") and reported on the others ("held out"), printed apart. Each table ends with
//! the walking and running trials pooled (`ALL walking and running`: the activity by the
//! corpus README's words, so drop jumps, cutting and free movement stay out), the share of
//! events found that issue 45 sets its goal on.
//! `--edge-min-fall`, `--edge-beyond` and `--bridge` vary the rules for extremes at a
//! trial's edges and across short gaps.
//!
//! The time base check: where a file has both its lab's events and plate events, the signed
//! median of (plate − lab) per event kind shows whether EVENT:TIMES and `frame_time` share
//! their origin (0 ms) or differ by a frame (one frame period).

mod cli;
mod dump;
mod misses;
mod peers;
mod report;
mod session;
mod tally;
mod truth;

use c3dfix::events;
use clap::Parser;
use gait::{Event, Kind, Side};
use session::SessionTrial;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use tally::Tally;

/// A detected event is found when it lies this close to the truth's (s).
const WINDOW_S: f64 = 0.15;

/// An event as compared: foot, kind, time (s).
type Timed = (Side, Kind, f64);

pub use cli::Settings;

/// What the trials add up to, in the order they are read.
#[derive(Default)]
pub struct Run {
    /// (truth, detector) → lab → tally.
    table: BTreeMap<(&'static str, &'static str), BTreeMap<String, Tally>>,
    /// (truth, detector) → the walking and running trials' tally, every lab pooled (the
    /// goal's share of events found is set on these activities; a drop jump's landing or a
    /// cutting step is not gait).
    gait: BTreeMap<(&'static str, &'static str), Tally>,
    /// Each counted trial's frame count and left heel's sum: copies are counted once.
    seen: Vec<(usize, i64)>,
    /// Trials left out, and why (printed with `-v`).
    skipped: Vec<String>,
    /// Each lab's point rates (Hz).
    rates: BTreeMap<String, BTreeSet<i64>>,
    session_trials: Vec<SessionTrial>,
    /// Trials whose markers show flight phases (offs as on runs).
    running: Vec<String>,
    /// `--list`'s file, `--peers`' answers and where they gave none.
    list: Option<std::fs::File>,
    peers: Option<peers::Peers>,
    /// `--peers-dump`'s file.
    peers_dump: Option<std::fs::File>,
    failures: peers::Failures,
    /// The peers' names as the tables key them.
    detectors: BTreeMap<String, &'static str>,
}

/// One trial read and its events found, as every table judges them.
pub struct Detected {
    c: c3d::C3d,
    feet: gait::Feet,
    corpus: &'static str,
    /// The trial's short name (`testkit::short`).
    name: String,
    lab: String,
    /// The trial's activity by its corpus README's words (`evals::corpus::activity`).
    activity: &'static str,
    rate: f64,
    /// The kinematic events as detected and as compared (None: the markers gave none).
    kin_raw: Option<Vec<Event>>,
    kin: Option<Vec<Timed>>,
    plates_raw: Vec<Event>,
    plates: Vec<Timed>,
    /// `auto` as `c3dfix events` gives it.
    auto: Option<Vec<Timed>>,
    /// Each plate event with the kinematics calibrated on the trial's other plate events.
    loo: Vec<(Timed, Vec<Timed>)>,
}

impl Detected {
    /// `v` as compared: foot, kind and the file's time of each event.
    fn triple(&self, v: &[Event]) -> Vec<Timed> {
        v.iter()
            .map(|e| (e.side, e.kind, events::to_trial_event(&self.c, e).time))
            .collect()
    }
}

fn main() {
    let s = match cli::Cli::parse().settings() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let mut dump = match s.dump.as_deref().map(dump::create).transpose() {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let corpora: Vec<(&'static str, Option<PathBuf>)> = vec![
        ("c3d-samples", testkit::c3d_samples()),
        ("c3d-more", testkit::c3d_more()),
        ("c3d-extra", testkit::c3d_extra()),
        ("c3d-fullbody", testkit::c3d_fullbody()),
        ("c3d-labs", testkit::c3d_labs()),
    ];
    let mut run = Run::default();
    let opened = s
        .list
        .as_deref()
        .map(|p| std::fs::File::create(p).map_err(|e| format!("--list {}: {e}", p.display())))
        .transpose()
        .and_then(|l| {
            let p = s.peers.as_deref().map(peers::Peers::read).transpose()?;
            Ok((l, p))
        });
    match opened {
        Ok((l, p)) => (run.list, run.peers) = (l, p),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    }
    match s.peers_dump.as_deref().map(peers::dump_create).transpose() {
        Ok(f) => run.peers_dump = f,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    }
    for (corpus, root) in &corpora {
        let Some(root) = root else { continue };
        for path in testkit::files_with_ext(root, "c3d") {
            if let Some(t) = run.detect(&s, corpus, root, &path) {
                run.trial(&s, &t, root, &path, dump.as_mut());
            }
        }
    }
    let offsets_used = session::score(&mut run, &s);
    report::print(&run, &s);
    run.failures.print();
    println!();
    println!("read as runs: {}", run.running.join(", "));
    if s.verbose {
        println!();
        for o in &offsets_used {
            println!("session offsets {o}");
        }
        for o in &run.skipped {
            println!("skipped {o}");
        }
    }
}

impl Run {
    /// Trial `path` read, its markers and plates found and its events detected; None (the
    /// reason in `skipped` where there is one) for a trial the evaluation leaves out: not
    /// readable, without feet, a copy of one counted, or a jump.
    fn detect(
        &mut self,
        s: &Settings,
        corpus: &'static str,
        root: &Path,
        path: &Path,
    ) -> Option<Detected> {
        let opts = &s.opts;
        let name = testkit::short(path);
        let Ok(c) = c3dfix::open(path) else {
            self.skipped.push(format!("{name}: unreadable"));
            return None;
        };
        let mut choice = match events::choose_markers(&c, &opts.markers, path) {
            Ok(m) => m,
            Err(e) => {
                self.skipped.push(format!("{name}: {e}"));
                return None;
            }
        };
        let feet = events::feet(&c, &mut choice, path).ok()?;
        if no_marker_data(&feet) {
            self.skipped.push(format!(
                "{name}: no marker data: every sample of its foot and pelvis markers is (0, 0, 0)"
            ));
            return None;
        }
        let labels = c.point_labels();
        let names = |r: &[usize]| -> Vec<String> {
            r.iter()
                .filter_map(|&i| labels.get(i).map(|l| l.trim().to_string()))
                .collect()
        };
        let roles = [
            names(&choice.left_heel),
            names(&choice.left_toe),
            names(&choice.right_heel),
            names(&choice.right_toe),
            names(&choice.pelvis),
        ];
        let key = (
            c.frames(),
            feet.left_heel
                .iter()
                .filter(|p| p[0].is_finite())
                .map(|p| p[0] + p[1] + p[2])
                .sum::<f64>()
                .div_euclid(1000.0) as i64,
        );
        if self.seen.contains(&key) {
            self.skipped
                .push(format!("{name}: a copy of a trial already counted"));
            return None;
        }
        self.seen.push(key);
        if let Some(out) = self.list.as_mut() {
            peers::list_line(out, path, roles);
        }
        let lab = evals::labs::of_trial(corpus, path, root);
        let readme = std::fs::read_to_string(root.join("README.md")).ok();
        let rel = path.strip_prefix(root).unwrap_or(path).to_string_lossy();
        let activity = evals::corpus::activity(readme.as_deref(), &rel, "walking");
        let rate = c.point_rate() as f64;
        let kin_raw = match gait::kinematic::kinematic_gait(&feet, rate, &opts.kinematic) {
            Ok((k, running)) => {
                if running {
                    self.running.push(name.clone());
                }
                Some(k)
            }
            Err(e) => {
                self.skipped.push(format!("{name}: kinematics: {e}"));
                None
            }
        };
        let plates_raw = if c.platform_params().plates.is_empty() {
            Vec::new()
        } else {
            events::plate_events(&c, &feet, &opts.plate).unwrap_or_default()
        };
        if jumps(&plates_raw, rate) {
            self.skipped.push(format!(
                "{name}: both feet land on the plates together (a jump or landing, not walking)"
            ));
            return None;
        }
        let mut t = Detected {
            c,
            feet,
            corpus,
            name,
            lab,
            activity,
            rate,
            kin_raw,
            kin: None,
            plates_raw,
            plates: Vec::new(),
            auto: None,
            loo: Vec::new(),
        };
        t.kin = t.kin_raw.as_ref().map(|k| t.triple(k));
        t.plates = t.triple(&t.plates_raw);
        t.auto = auto(&t, opts);
        t.loo = leave_one_out(&t, opts);
        Some(t)
    }

    /// Trial `t` counted: its rates, its lab events (checked against the plates with
    /// `--truth-check`, the contradicted left out with `--without-contradicted`), its
    /// session trial, what `-v`, `--dump` and `--misses` print of it, and its tallies.
    fn trial(
        &mut self,
        s: &Settings,
        t: &Detected,
        root: &Path,
        path: &Path,
        dump: Option<&mut std::fs::File>,
    ) {
        let (c, lab, rate) = (&t.c, &t.lab, t.rate);
        self.rates
            .entry(lab.clone())
            .or_default()
            .insert(rate as i64);
        let session_lab = if lab == "c3d-samples/sample_00" {
            let rel = path.strip_prefix(root).unwrap_or(path);
            let vendor = rel
                .components()
                .nth(1)
                .map(|c| c.as_os_str().to_string_lossy().to_string())
                .unwrap_or_default();
            format!("{lab}/{vendor}")
        } else {
            lab.clone()
        };
        self.rates
            .entry(session_lab.clone())
            .or_default()
            .insert(rate as i64);
        let mut lab_events: Vec<Timed> = c
            .events()
            .iter()
            .filter_map(|e| {
                c3dfix::event_labels::gait_event(&e.context, &e.label).map(|(s, k)| (s, k, e.time))
            })
            .collect();
        if s.truth_check && !t.plates.is_empty() {
            truth::truth_state(&t.name, lab, c, &t.feet, &lab_events, &t.plates, rate);
        }
        if s.without_contradicted {
            let bad = truth::contradicted(c, &t.feet, rate, &lab_events, &t.plates);
            lab_events.retain(|e| !bad.contains(e));
        }
        if let Some(k) = &t.kin_raw {
            let t0 = c.frame_time(0);
            let as_event = |&(side, kind, time): &Timed| Event {
                side,
                kind,
                index: (time - t0) * rate,
                source: gait::Source::Plate,
                plate: None,
            };
            self.session_trials.push(SessionTrial {
                lab: session_lab,
                name: t.name.clone(),
                rate,
                t0,
                kin: k.clone(),
                plates: t.plates_raw.clone(),
                lab_events: lab_events.iter().map(as_event).collect(),
            });
        }
        if s.verbose {
            print_trial(t, &lab_events);
        }
        if let Some(f) = dump {
            dump::rows(f, t, &lab_events, &s.opts);
        }
        if s.misses {
            misses::print(t, &lab_events);
        }
        self.tally(t, &lab_events);
        self.side_by_side(t, path, &lab_events);
    }

    /// `--peers`: c3dfix's markers-alone events and each peer's, on the same trial against
    /// the same truth, a trial a detector could not read counting its truth as missed.
    fn side_by_side(&mut self, t: &Detected, path: &Path, lab_events: &[Timed]) {
        let Some(p) = &self.peers else { return };
        let mut rows: Vec<(String, Vec<Timed>)> = vec![(
            "c3dfix (markers alone)".to_string(),
            t.kin.clone().unwrap_or_default(),
        )];
        for (name, got) in p.of(t, path) {
            match got {
                Ok(v) => rows.push((name, v)),
                Err(e) => {
                    self.failures.add(&name, &e, &t.name);
                    rows.push((name, Vec::new()));
                }
            }
        }
        for (name, found) in rows {
            let name: &'static str = match self.detectors.get(&name) {
                Some(n) => n,
                None => {
                    let leaked: &'static str = Box::leak(name.clone().into_boxed_str());
                    self.detectors.insert(name, leaked);
                    leaked
                }
            };
            for (truth, events, extra) in [
                ("lab (side by side)", lab_events, true),
                ("plate (side by side)", &t.plates[..], false),
            ] {
                if let Some(f) = self.peers_dump.as_mut() {
                    peers::dump_rows(f, t, truth, name, events, &found);
                }
                if !events.is_empty() {
                    self.put((truth, name), t, events, &found, extra);
                }
            }
        }
    }

    /// Trial `t`'s events added to the tables: the kinematics, the plates and `auto` against
    /// the lab's events; the kinematics, as detected and calibrated leave one out, against
    /// the plates.
    fn tally(&mut self, t: &Detected, lab_events: &[Timed]) {
        let (kin, plates, auto, loo) = (&t.kin, &t.plates, &t.auto, &t.loo);
        if !lab_events.is_empty() {
            if let Some(k) = kin {
                self.put(("lab", "kinematics"), t, lab_events, k, true);
            }
            if !plates.is_empty() {
                self.put(("lab", "plates"), t, lab_events, plates, false);
            }
            if let Some(a) = auto {
                let key = ("lab", "auto (plates, calibrated kinematics elsewhere)");
                self.put(key, t, lab_events, a, true);
            }
        }
        if !plates.is_empty() {
            if let Some(k) = kin {
                self.put(("plate", "kinematics"), t, plates, k, false);
            }
            if !loo.is_empty() {
                let t = self
                    .table
                    .entry((
                        "plate",
                        "kinematics calibrated on the trial's other plate events",
                    ))
                    .or_default()
                    .entry(t.lab.clone())
                    .or_default();
                t.trials += 1;
                for (truth, found) in loo {
                    t.add_events(std::slice::from_ref(truth), found, false);
                }
            }
        }
    }

    /// Trial `t`'s `found` against `truth` added to its lab's tally under `key`, and to
    /// the walking and running trials' when it is one.
    fn put(
        &mut self,
        key: (&'static str, &'static str),
        t: &Detected,
        truth: &[Timed],
        found: &[Timed],
        extra: bool,
    ) {
        self.table
            .entry(key)
            .or_default()
            .entry(t.lab.clone())
            .or_default()
            .add(truth, found, extra);
        if matches!(t.activity, "walking" | "running") {
            self.gait.entry(key).or_default().add(truth, found, extra);
        }
    }
}

/// Whether every sample of the trial's foot and pelvis markers sits exactly at (0, 0, 0):
/// a file that stores no marker data (BTK's `parameterOverflow`, a parameter-section test
/// whose events are a template's), whose events no marker method can find.
fn no_marker_data(feet: &gait::Feet) -> bool {
    [
        &feet.left_heel,
        &feet.left_toe,
        &feet.right_heel,
        &feet.right_toe,
        &feet.pelvis,
    ]
    .iter()
    .all(|m| m.iter().all(|p| p.iter().all(|v| *v == 0.0)))
}

/// Whether both feet leave the plates together and land together: a jump or a landing, not
/// a step, so the trial is not walking and its plates are no truth for gait events.
fn jumps(plates: &[Event], rate: f64) -> bool {
    let together = |kind: Kind| {
        plates.iter().any(|a| {
            plates.iter().any(|b| {
                a.kind == kind
                    && b.kind == kind
                    && a.side != b.side
                    && (a.index - b.index).abs() <= 0.05 * rate
            })
        })
    };
    together(Kind::FootStrike) && together(Kind::FootOff)
}

/// `auto` as `c3dfix events` gives it: kinematics shifted by the trial's own plate lag,
/// plate events where a foot lands on a plate.
fn auto(t: &Detected, opts: &events::EventOptions) -> Option<Vec<Timed>> {
    t.kin_raw.as_ref().map(|k| {
        let k = if opts.no_calibrate {
            k.clone()
        } else {
            events::calibrated(&t.feet, t.rate, &t.plates_raw, k, opts)
        };
        t.triple(&events::merge_auto(&t.plates_raw, &k, t.rate))
    })
}

/// Each plate event against the kinematics calibrated on the trial's other plate events
/// (leave one out), so no event judges its own shift.
fn leave_one_out(t: &Detected, opts: &events::EventOptions) -> Vec<(Timed, Vec<Timed>)> {
    match &t.kin_raw {
        Some(k) if !opts.no_calibrate => (0..t.plates_raw.len())
            .map(|i| {
                let others: Vec<Event> = t
                    .plates_raw
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| *j != i)
                    .map(|(_, e)| *e)
                    .collect();
                (
                    t.plates[i],
                    t.triple(&events::calibrated(&t.feet, t.rate, &others, k, opts)),
                )
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// `-v`: the trial's lab, plate and kinematic events in time order.
fn print_trial(t: &Detected, lab_events: &[Timed]) {
    let (c, name, lab, rate) = (&t.c, &t.name, &t.lab, t.rate);
    let (plates, kin) = (&t.plates, &t.kin);
    println!(
        "{name} [{lab}] rate {rate} first frame {} lab events {} plate events {} kinematic {}",
        c.first_frame(),
        lab_events.len(),
        plates.len(),
        kin.as_ref().map_or(0, Vec::len)
    );
    let mut show: Vec<(&str, &(Side, Kind, f64))> = lab_events
        .iter()
        .map(|e| ("lab", e))
        .chain(plates.iter().map(|e| ("plate", e)))
        .chain(kin.iter().flatten().map(|e| ("kin", e)))
        .collect();
    show.sort_by(|a, b| a.1 .2.total_cmp(&b.1 .2));
    for (src, (s, k, t)) in show {
        println!("    {t:8.3} {src:<6} {:?} {:?}", s, k);
    }
}
