//! How well gait events are found, per lab, on the corpora's walking trials.
//!
//! ```sh
//! cargo run --release -p c3dfix --example events_eval            # the constants as shipped
//! cargo run --release -p c3dfix --example events_eval -- --strike zeni:0.02 --off desailly:-0.012,zeni:-0.015
//! cargo run --release -p c3dfix --example events_eval -- --misses       # each missed event, where, and where its markers are seen
//! cargo run --release -p c3dfix --example events_eval -- --strike landing:0 --landing-height 0 --landing-speed 0.15  # landing as a fraction of the swing
//! cargo run --release -p c3dfix --example events_eval -- --cut-min-fall 1 --pelvis-extend 0.25  # extremes at a cut as before; the pelvis carried past its ends
//! cargo run --release -p c3dfix --example events_eval -- --dump e.csv   # each method's error per event
//! cargo run --release -p c3dfix --example events_eval -- --dump e.csv --touchdown-mm 5 --touchdown-speed 50 --liftoff-mm 5 --liftoff-speed 200  # the touchdown method's thresholds
//! cargo run --release -p c3dfix --example events_eval -- --off-stride-slope 0 --off zeni:-0.0149  # offs with a constant offset, as before
//! cargo run --release -p c3dfix --example events_eval -- --correlate --correlate-strike heel  # auto matched to the plate steps
//! cargo run --release -p c3dfix --example events_eval -- --truth-check  # the foot's state at each lab event
//! cargo run --release -p c3dfix --example events_eval -- --without-contradicted  # lab strikes the plates contradict left out
//! cargo run --release -p c3dfix --example events_eval -- --session-per-side --session-min 3 --session-truth plates
//! ```
//!
//! **Session calibration** (`c3dfix events --calibrate-from`): in every lab with two or more
//! trials whose markers give events, each trial's kinematic events are shifted by the
//! offsets learned from the lab's OTHER trials (leave one trial out), and, apart, from each
//! single other trial; both scored against the trial's plates and its lab events beside the
//! same trials' uncalibrated events ("before"). Here c3d-samples' `sample_00` is four labs
//! (one per vendor folder), since its trials come from different systems.
//!
//! Every C3D file of `c3d-samples`, `c3d-more`, `c3d-extra` and `c3d-fullbody` whose foot
//! and pelvis markers are found is read once (copies of one trial in other formats are
//! counted once: same frame count and same left-heel trajectory). Two truths:
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
//! ("tuning") and reported on the others ("held out"), printed apart.
//!
//! The time base check: where a file has both its lab's events and plate events, the signed
//! median of (plate − lab) per event kind shows whether EVENT:TIMES and `frame_time` share
//! their origin (0 ms) or differ by a frame (one frame period).

use c3dfix::events::{self, EventOptions};
use c3dfix::events_session::CalibrationTruth;
use gait::{Event, Kind, Side};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const WINDOW_S: f64 = 0.15;

/// An event as compared: foot, kind, time (s).
type Timed = (Side, Kind, f64);

/// A trial as the session calibration's leave-one-trial-out sees it.
struct SessionTrial {
    /// The session's lab (as [`lab_of`], `sample_00` split by vendor folder).
    lab: String,
    name: String,
    rate: f64,
    t0: f64,
    kin: Vec<Event>,
    plates: Vec<Event>,
    lab_events: Vec<Event>,
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

#[derive(Default)]
struct Tally {
    trials: usize,
    truth: [usize; 2],
    errors: [Vec<f64>; 2],
    signed: [Vec<f64>; 2],
    spanned: usize,
    extra: usize,
}

impl Tally {
    fn add(&mut self, truth: &[(Side, Kind, f64)], found: &[(Side, Kind, f64)], count_extra: bool) {
        self.trials += 1;
        self.add_events(truth, found, count_extra);
    }

    /// As [`Tally::add`], without counting a trial (one trial's events added in parts).
    fn add_events(
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

    fn merge(&mut self, o: &Tally) {
        self.trials += o.trials;
        for k in 0..2 {
            self.truth[k] += o.truth[k];
            self.errors[k].extend_from_slice(&o.errors[k]);
            self.signed[k].extend_from_slice(&o.signed[k]);
        }
        self.spanned += o.spanned;
        self.extra += o.extra;
    }

    fn line(&self, name: &str, extra: bool) -> String {
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

/// What `--dump` records of the foot beside each event, to look for a per-trial
/// correction of the markers' lab-dependent lag in the trial's own kinematics: the heel's
/// and toe's heights (mm above their stance level: the lowest over the 0.5 s after a strike,
/// before an off) and vertical speeds at the detected event, and per foot the marker
/// placement (heel–toe distance, each marker's 5th-percentile height, its swing range).
struct DumpFeatures {
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

fn quantile(x: &[f64], q: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    // Linear interpolation between order statistics (numpy's default).
    let pos = (v.len() - 1) as f64 * q;
    let (i, f) = (pos.floor() as usize, pos - pos.floor());
    if i + 1 < v.len() {
        v[i] * (1.0 - f) + v[i + 1] * f
    } else {
        v[i]
    }
}

fn lab_of(corpus: &str, path: &Path, root: &Path) -> String {
    let rel = path.strip_prefix(root).unwrap_or(path);
    let first = rel
        .components()
        .next()
        .map(|c| c.as_os_str().to_string_lossy().to_string())
        .unwrap_or_default();
    match corpus {
        "c3d-samples" => format!("c3d-samples/{first}"),
        "c3d-more" => {
            let parts: Vec<&str> = first.split("__").collect();
            if parts.first() == Some(&"tsalemink") {
                let trial = parts.get(2).and_then(|t| t.split('_').next()).unwrap_or("");
                format!("c3d-more/tsalemink/{trial}")
            } else {
                format!("c3d-more/{}", parts.first().copied().unwrap_or(""))
            }
        }
        "c3d-fullbody" => {
            if first.starts_with("03_") {
                "c3d-fullbody/numediart".into()
            } else {
                "c3d-fullbody/cmu".into()
            }
        }
        _ => format!("{corpus}/btk"),
    }
}

fn side_kind(context: &str, label: &str) -> Option<(Side, Kind)> {
    let side = match context.trim().to_ascii_lowercase().as_str() {
        "left" => Side::Left,
        "right" => Side::Right,
        _ => return None,
    };
    let kind = match label.trim().to_ascii_lowercase().as_str() {
        "foot strike" => Kind::FootStrike,
        "foot off" => Kind::FootOff,
        _ => return None,
    };
    Some((side, kind))
}

fn arg(args: &[String], name: &str) -> Option<f64> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
}

/// `METHOD[:OFFSET_S],…`, e.g. `zeni-landing:-0.0012,zeni:0.0225,desailly:0.021`.
fn estimates(spec: &str) -> Result<Vec<gait::Estimate>, String> {
    spec.split(',')
        .map(|item| {
            let (m, o) = item.split_once(':').unwrap_or((item, "0"));
            Ok(gait::Estimate {
                method: m.parse().map_err(|e: gait::Error| e.to_string())?,
                offset_s: o.parse().map_err(|_| format!("{o}: not a number"))?,
            })
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut opts = EventOptions::default();
    if let Some(v) = arg(&args, "--smooth") {
        opts.kinematic.smooth_s = v;
    }
    if let Some(v) = arg(&args, "--ankle-offset") {
        opts.kinematic.ankle_strike_offset_s = v;
    }
    if let Some(v) = arg(&args, "--impact-after") {
        opts.kinematic.impact_after_s = v;
    }
    if let Some(v) = arg(&args, "--impact-hz") {
        opts.kinematic.impact_lowpass_hz = v;
    }
    if let Some(v) = arg(&args, "--pelvis-extend") {
        opts.kinematic.pelvis_extend_s = v;
    }
    if let Some(v) = arg(&args, "--cut-min-fall") {
        opts.kinematic.cut_min_fall = v;
    }
    if let Some(v) = arg(&args, "--landing-height") {
        opts.kinematic.landing_height_frac = v;
    }
    if let Some(v) = arg(&args, "--landing-speed") {
        opts.kinematic.landing_speed_frac = v;
    }
    if let Some(v) = arg(&args, "--landing-vspeed") {
        opts.kinematic.landing_vspeed_frac = v;
    }
    if let Some(v) = arg(&args, "--lift-height") {
        opts.kinematic.lift_height_frac = v;
    }
    if let Some(v) = arg(&args, "--lift-speed") {
        opts.kinematic.lift_speed_frac = v;
    }
    opts.kinematic.lift_speed_of_toe = args.iter().any(|a| a == "--lift-toe");
    if let Some(v) = arg(&args, "--off-stride-slope") {
        opts.kinematic.off_stride_slope = v;
    }
    if let Some(v) = arg(&args, "--off-stride-ref") {
        opts.kinematic.off_stride_ref_s = v;
    }
    for (flag, slot) in [
        ("--touchdown-mm", &mut opts.kinematic.touchdown_mm),
        (
            "--touchdown-speed",
            &mut opts.kinematic.touchdown_speed_mm_s,
        ),
        ("--touchdown-hz", &mut opts.kinematic.touchdown_lowpass_hz),
        ("--liftoff-mm", &mut opts.kinematic.liftoff_mm),
        ("--liftoff-speed", &mut opts.kinematic.liftoff_speed_mm_s),
    ] {
        if let Some(v) = arg(&args, flag) {
            *slot = v;
        }
    }
    if let Some(v) = arg(&args, "--touch") {
        opts.kinematic.touch_mm = v;
    }
    if let Some(v) = arg(&args, "--threshold") {
        opts.plate.threshold_n = v;
    }
    if let Some(v) = arg(&args, "--min-speed") {
        opts.kinematic.min_speed_mm_s = v;
    }
    if let Some(v) = arg(&args, "--oconnor-hz") {
        opts.kinematic.oconnor_lowpass_hz = v;
    }
    if let Some(v) = arg(&args, "--lift") {
        opts.kinematic.lift_mm = v;
    }
    if let Some(v) = arg(&args, "--heel-ratio") {
        opts.kinematic.velocity_heel_ratio = v;
    }
    if let Some(v) = arg(&args, "--toe-ratio") {
        opts.kinematic.velocity_toe_ratio = v;
    }
    if let Some(v) = arg(&args, "--desailly-ratio") {
        opts.kinematic.desailly_cutoff_ratio = v;
    }
    for (flag, slot) in [
        ("--strike", &mut opts.kinematic.strike),
        ("--off", &mut opts.kinematic.off),
    ] {
        if let Some(spec) = args
            .iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
        {
            match estimates(spec) {
                Ok(v) => *slot = v,
                Err(e) => {
                    eprintln!("{flag} {spec}: {e}");
                    std::process::exit(2);
                }
            }
        }
    }
    opts.no_calibrate = args.iter().any(|a| a == "--no-calibrate");
    // --correlate [--correlate-window S] [--correlate-search S] [--correlate-raw]
    // [--correlate-strike PART] [--correlate-off PART]: auto's kinematic events matched to
    // the plate steps' marker heights (gait::correlate).
    let mut corr = gait::CorrelateOptions::default();
    if let Some(v) = arg(&args, "--correlate-window") {
        corr.half_window_s = v;
    }
    if let Some(v) = arg(&args, "--correlate-search") {
        corr.search_s = v;
    }
    corr.remove_mean = !args.iter().any(|a| a == "--correlate-raw");
    for (flag, slot) in [
        ("--correlate-strike", &mut corr.strike_part),
        ("--correlate-off", &mut corr.off_part),
    ] {
        if let Some(v) = args
            .iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
        {
            match v.parse() {
                Ok(p) => *slot = p,
                Err(e) => {
                    eprintln!("{flag} {v}: {e}");
                    std::process::exit(2);
                }
            }
        }
    }
    if args.iter().any(|a| a == "--correlate") {
        opts.correlate = Some(corr);
    }
    let mut session_opts = gait::SessionOptions {
        per_side: args.iter().any(|a| a == "--session-per-side"),
        ..gait::SessionOptions::default()
    };
    if let Some(v) = arg(&args, "--session-min") {
        session_opts.min_contacts = v as usize;
    }
    let session_truth: CalibrationTruth = match args
        .iter()
        .position(|a| a == "--session-truth")
        .and_then(|i| args.get(i + 1))
    {
        Some(v) => match v.parse() {
            Ok(t) => t,
            Err(e) => {
                eprintln!("--session-truth {v}: {e}");
                std::process::exit(2);
            }
        },
        None => CalibrationTruth::default(),
    };
    let mut session_trials: Vec<SessionTrial> = Vec::new();
    let verbose = args.iter().any(|a| a == "-v");
    let misses = args.iter().any(|a| a == "--misses");
    // --truth-check: each lab event with the foot's state at it (see `truth_check`).
    let truth_check = args.iter().any(|a| a == "--truth-check");
    // --without-contradicted: the lab strikes the trial's plates contradict (`contradicted`)
    // left out of the lab truth.
    let without_contradicted = args.iter().any(|a| a == "--without-contradicted");
    // --dump FILE: one CSV row per truth event with each method's signed error (s), for
    // studying combinations offline (choose on tuning, report on held out).
    let mut dump = args
        .iter()
        .position(|a| a == "--dump")
        .and_then(|i| args.get(i + 1))
        .map(|p| {
            let f = std::fs::File::create(p);
            let Ok(mut f) = f else {
                eprintln!("--dump {p}: cannot create the file");
                std::process::exit(2);
            };
            use std::io::Write as _;
            let _ = writeln!(
                f,
                "lab,group,truth,file,rate,side,kind,time,zeni_raw,zeni_refined,oconnor,desailly_03,desailly_05,velocity,zeni_lift,impact,touchdown,stride_s,speed_m_s,shipped,heel_above_mm,toe_above_mm,heel_vz_mm_s,toe_vz_mm_s,foot_len_mm,heel_p5_mm,toe_p5_mm,heel_swing_mm,toe_swing_mm,ankle"
            );
            f
        });

    let corpora: Vec<(&str, Option<PathBuf>)> = vec![
        ("c3d-samples", testkit::c3d_samples()),
        ("c3d-more", testkit::c3d_more()),
        ("c3d-extra", testkit::c3d_extra()),
        ("c3d-fullbody", testkit::c3d_fullbody()),
    ];
    // (truth, detector) → lab → tally
    let mut table: BTreeMap<(&str, &str), BTreeMap<String, Tally>> = BTreeMap::new();
    let mut seen: Vec<(usize, i64)> = Vec::new();
    let mut skipped: Vec<String> = Vec::new();
    let mut rates: BTreeMap<String, std::collections::BTreeSet<i64>> = BTreeMap::new();
    for (corpus, root) in &corpora {
        let Some(root) = root else { continue };
        for path in testkit::files_with_ext(root, "c3d") {
            let name = testkit::short(&path);
            let Ok(c) = c3dfix::open(&path) else {
                skipped.push(format!("{name}: unreadable"));
                continue;
            };
            let mut choice = match events::choose_markers(&c, &opts.markers, &path) {
                Ok(m) => m,
                Err(e) => {
                    skipped.push(format!("{name}: {e}"));
                    continue;
                }
            };
            let Ok(feet) = events::feet(&c, &mut choice, &path) else {
                continue;
            };
            let key = (
                c.frames(),
                feet.left_heel
                    .iter()
                    .filter(|p| p[0].is_finite())
                    .map(|p| p[0] + p[1] + p[2])
                    .sum::<f64>()
                    .div_euclid(1000.0) as i64,
            );
            if seen.contains(&key) {
                skipped.push(format!("{name}: a copy of a trial already counted"));
                continue;
            }
            seen.push(key);
            let lab = lab_of(corpus, &path, root);
            let rate = c.point_rate() as f64;
            let at = |e: &Event| events::to_trial_event(&c, e).time;
            let triple = |v: &[Event]| -> Vec<(Side, Kind, f64)> {
                v.iter().map(|e| (e.side, e.kind, at(e))).collect()
            };
            let kin_raw = match gait::kinematic_events(&feet, rate, &opts.kinematic) {
                Ok(k) => Some(k),
                Err(e) => {
                    skipped.push(format!("{name}: kinematics: {e}"));
                    None
                }
            };
            let kin = kin_raw.as_ref().map(|k| triple(k));
            let plates_raw = if c.platform_params().plates.is_empty() {
                Vec::new()
            } else {
                events::plate_events(&c, &feet, &opts.plate).unwrap_or_default()
            };
            // Both feet leaving the plates together and landing together is a jump or a
            // landing, not a step: such trials are not walking and their plates are no truth
            // for gait events.
            let together = |kind: Kind| {
                plates_raw.iter().any(|a| {
                    plates_raw.iter().any(|b| {
                        a.kind == kind
                            && b.kind == kind
                            && a.side != b.side
                            && (a.index - b.index).abs() <= 0.05 * rate
                    })
                })
            };
            let jump = together(Kind::FootStrike) && together(Kind::FootOff);
            if jump {
                skipped.push(format!(
                    "{name}: both feet land on the plates together (a jump or landing, not walking)"
                ));
                continue;
            }
            let plates = triple(&plates_raw);
            // auto as `c3dfix events` gives it: kinematics shifted by the trial's own plate
            // lag, plate events where a foot lands on a plate.
            let auto = kin_raw.as_ref().map(|k| {
                let k = if opts.no_calibrate {
                    k.clone()
                } else {
                    events::calibrated(&feet, rate, &plates_raw, k, &opts)
                };
                triple(&events::merge_auto(&plates_raw, &k, rate))
            });
            // Each plate event against the kinematics calibrated on the trial's other plate
            // events (leave one out), so no event judges its own shift.
            let loo: Vec<(Timed, Vec<Timed>)> = match &kin_raw {
                Some(k) if !opts.no_calibrate => (0..plates_raw.len())
                    .map(|i| {
                        let others: Vec<Event> = plates_raw
                            .iter()
                            .enumerate()
                            .filter(|(j, _)| *j != i)
                            .map(|(_, e)| *e)
                            .collect();
                        (
                            plates[i],
                            triple(&events::calibrated(&feet, rate, &others, k, &opts)),
                        )
                    })
                    .collect(),
                _ => Vec::new(),
            };
            rates.entry(lab.clone()).or_default().insert(rate as i64);
            let session_lab = if lab == "c3d-samples/sample_00" {
                let rel = path.strip_prefix(root).unwrap_or(&path);
                let vendor = rel
                    .components()
                    .nth(1)
                    .map(|c| c.as_os_str().to_string_lossy().to_string())
                    .unwrap_or_default();
                format!("{lab}/{vendor}")
            } else {
                lab.clone()
            };
            rates
                .entry(session_lab.clone())
                .or_default()
                .insert(rate as i64);
            let mut lab_events: Vec<(Side, Kind, f64)> = c
                .events()
                .iter()
                .filter_map(|e| side_kind(&e.context, &e.label).map(|(s, k)| (s, k, e.time)))
                .collect();
            if truth_check && !plates.is_empty() {
                truth_state(&name, &lab, &c, &feet, &lab_events, &plates, rate);
            }
            if without_contradicted {
                let bad = contradicted(&c, &feet, rate, &lab_events, &plates);
                lab_events.retain(|e| !bad.contains(e));
            }
            if let Some(k) = &kin_raw {
                let t0 = c.frame_time(0);
                let as_event = |&(side, kind, t): &Timed| Event {
                    side,
                    kind,
                    index: (t - t0) * rate,
                    source: gait::Source::Plate,
                    plate: None,
                };
                session_trials.push(SessionTrial {
                    lab: session_lab,
                    name: name.clone(),
                    rate,
                    t0,
                    kin: k.clone(),
                    plates: plates_raw.clone(),
                    lab_events: lab_events.iter().map(as_event).collect(),
                });
            }
            if verbose {
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
            if let Some(f) = dump.as_mut() {
                use std::io::Write as _;
                let variant = |method: gait::Method, ratio: f64| {
                    let e = gait::Estimate {
                        method,
                        offset_s: 0.0,
                    };
                    let o = gait::KinematicOptions {
                        strike: vec![e],
                        off: vec![e],
                        desailly_cutoff_ratio: ratio,
                        oconnor_lowpass_hz: 10.0,
                        ankle_strike_offset_s: 0.0,
                        ..opts.kinematic.clone()
                    };
                    gait::kinematic_events(&feet, rate, &o)
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
                        ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2))
                            .sqrt()
                            / (2.0 * h as f64 / rate)
                            / 1000.0
                    })
                    .filter(|v| v.is_finite() && *v > 0.2)
                    .collect();
                let speed = quantile(&speeds, 0.5);
                let feats = DumpFeatures::new(&feet, rate);
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
            if misses {
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
            if !lab_events.is_empty() {
                if let Some(k) = &kin {
                    table
                        .entry(("lab", "kinematics"))
                        .or_default()
                        .entry(lab.clone())
                        .or_default()
                        .add(&lab_events, k, true);
                }
                if !plates.is_empty() {
                    table
                        .entry(("lab", "plates"))
                        .or_default()
                        .entry(lab.clone())
                        .or_default()
                        .add(&lab_events, &plates, false);
                }
            }
            if !lab_events.is_empty() {
                if let Some(a) = &auto {
                    table
                        .entry(("lab", "auto (plates, calibrated kinematics elsewhere)"))
                        .or_default()
                        .entry(lab.clone())
                        .or_default()
                        .add(&lab_events, a, true);
                }
            }
            if !plates.is_empty() {
                if let Some(k) = &kin {
                    table
                        .entry(("plate", "kinematics"))
                        .or_default()
                        .entry(lab.clone())
                        .or_default()
                        .add(&plates, k, false);
                }
                if !loo.is_empty() {
                    let t = table
                        .entry((
                            "plate",
                            "kinematics calibrated on the trial's other plate events",
                        ))
                        .or_default()
                        .entry(lab.clone())
                        .or_default();
                    t.trials += 1;
                    for (truth, found) in &loo {
                        t.add_events(std::slice::from_ref(truth), found, false);
                    }
                }
            }
        }
    }
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
            let o = gait::session_offsets(&others, &session_opts);
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
                let o = gait::session_offsets(&lags[j], &session_opts);
                score(ONE, &gait::session::apply(&t.kin, &o, t.rate), first);
                first = false;
            }
        }
    }
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
    for ((truth, detector), labs) in &table {
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
            println!("{}", t.line(&name, *truth == "lab"));
            let g = if lab.starts_with("c3d-samples") {
                "ALL tuning (c3d-samples)"
            } else {
                "ALL held out (other corpora)"
            };
            groups.entry(g).or_default().merge(t);
        }
        for (g, t) in &groups {
            println!("{}", t.line(g, *truth == "lab"));
        }
    }
    if verbose {
        println!();
        for s in &offsets_used {
            println!("session offsets {s}");
        }
        for s in &skipped {
            println!("skipped {s}");
        }
    }
}

/// A foot's state at time `t` (s): how far its heel and its toe stand above their stance
/// level and how fast they move up (mm, mm/s: heel height, heel speed, toe height, toe
/// speed). The stance level is the lowest height over the next 0.5 s for a strike, over the
/// 0.5 s before for an off. `None` at the trial's edges or where the lab has no vertical.
fn foot_state(
    c: &c3d::C3d,
    feet: &gait::Feet,
    rate: f64,
    (side, kind, t): Timed,
) -> Option<[f64; 4]> {
    let v = gait::axes::vertical(
        &feet.pelvis,
        &[
            &feet.left_heel,
            &feet.right_heel,
            &feet.left_toe,
            &feet.right_toe,
        ],
    )?;
    let n = feet.frames();
    let i = ((t - c.frame_time(0)) * rate).round();
    if i < 1.0 || i as usize + 1 >= n {
        return None;
    }
    let i = i as usize;
    let (heel, toe) = feet.foot(side);
    let half = (0.5 * rate) as usize;
    let state = |x: &[[f64; 3]]| {
        let h = |j: usize| v.height(x[j]);
        let (a, b) = if kind == Kind::FootStrike {
            (i, (i + half).min(n))
        } else {
            (i.saturating_sub(half), i + 1)
        };
        let level = (a..b)
            .map(h)
            .filter(|v| v.is_finite())
            .fold(f64::NAN, f64::min);
        (h(i) - level, (h(i + 1) - h(i - 1)) * rate / 2.0)
    };
    let (hh, hs) = state(heel);
    let (th, ts) = state(toe);
    Some([hh, hs, th, ts])
}

/// How much higher (mm) than at every plate strike of the trial the landing part must stand
/// for a lab strike to be contradicted. Over one trial's plate strikes that part's height
/// spreads by 0–5 mm on most corpus trials, more at 60 Hz where the heel descends 3–7 mm
/// a frame (sample_04: 8.6 and 16.1 mm; sample_11: 9.9–22.6 mm); what counts is the
/// excess over the highest (RBWH's two free strikes: 7.2 and 9.5 mm, at 100 Hz with the
/// heel descending under 1 mm a frame). `--truth-check` prints every plate strike's
/// heights.
const CONTRADICTED_MM: f64 = 5.0;

/// The lab's strikes away from the plates whose foot, by the trial's own plate strikes, has
/// not landed yet. The landing part is the heel or the toe, whichever stands lower above its
/// stance level at the trial's plate strikes (the heel for a heel striker); a lab strike
/// where that part stands more than [`CONTRADICTED_MM`] higher than at every plate strike
/// is contradicted. A strike set by hand (or carried over from the markers by the lab's
/// software) can be early or late; where the plates show what a contact looks like in this
/// trial, such a strike is no truth to score against.
fn contradicted(
    c: &c3d::C3d,
    feet: &gait::Feet,
    rate: f64,
    lab_events: &[Timed],
    plates: &[Timed],
) -> Vec<Timed> {
    let at_plates: Vec<[f64; 4]> = plates
        .iter()
        .filter(|p| p.1 == Kind::FootStrike)
        .filter_map(|&p| foot_state(c, feet, rate, p))
        .collect();
    let highest = |k: usize| at_plates.iter().map(|s| s[k]).fold(f64::NAN, f64::max);
    let (heel, toe) = (highest(0), highest(2));
    if !(heel.is_finite() && toe.is_finite()) {
        return Vec::new();
    }
    let (part, level) = if heel <= toe { (0, heel) } else { (2, toe) };
    lab_events
        .iter()
        .filter(|e| e.1 == Kind::FootStrike)
        .filter(|e| {
            !plates
                .iter()
                .any(|p| p.0 == e.0 && p.1 == e.1 && (p.2 - e.2).abs() <= 0.02)
        })
        .filter(|&&e| {
            foot_state(c, feet, rate, e).is_some_and(|s| s[part] > level + CONTRADICTED_MM)
        })
        .copied()
        .collect()
}

/// `--truth-check`: each lab event with the foot's state at it ([`foot_state`]), marked
/// `plate` when a plate event of its foot and kind lies within 20 ms (the lab's event is
/// then the plate's), `free` otherwise, and `CONTRADICTED` as [`contradicted`] finds.
fn truth_state(
    name: &str,
    lab: &str,
    c: &c3d::C3d,
    feet: &gait::Feet,
    lab_events: &[Timed],
    plates: &[Timed],
    rate: f64,
) {
    let bad = contradicted(c, feet, rate, lab_events, plates);
    let short = name.rsplit('/').next().unwrap_or(name);
    for &p in plates.iter().filter(|p| p.1 == Kind::FootStrike) {
        if let Some([hh, _, th, _]) = foot_state(c, feet, rate, p) {
            println!(
                "plate {lab:<28} {short:<40} {:?} FootStrike {:7.3} heel {hh:5.1} mm toe {th:5.1} mm",
                p.0, p.2
            );
        }
    }
    for &e in lab_events {
        let Some([hh, hs, th, ts]) = foot_state(c, feet, rate, e) else {
            continue;
        };
        let (side, kind, t) = e;
        let on_plate = plates
            .iter()
            .any(|p| p.0 == side && p.1 == kind && (p.2 - t).abs() <= 0.02);
        println!(
            "truth {lab:<28} {short:<40} {side:?} {kind:?} {t:7.3} {:<5} heel {hh:5.1} mm {hs:+6.0} mm/s  toe {th:5.1} mm {ts:+6.0} mm/s{}",
            if on_plate { "plate" } else { "free" },
            if bad.contains(&e) { "  CONTRADICTED by the trial's plate strikes" } else { "" }
        );
    }
}
