//! The evaluation's command line: each detector constant it may vary (unset: as shipped),
//! and what it prints besides the tables.

use c3dfix::events::EventOptions;
use c3dfix::CalibrationTruth;
use clap::Parser;
use std::path::PathBuf;

/// How well gait events are found, per lab, on the corpora's walking trials (see the
/// module's documentation). A constant not given is the shipped one.
#[derive(Parser)]
#[command(name = "events_eval")]
pub struct Cli {
    /// Smoothing of the marker signals (s).
    #[arg(long, value_name = "S")]
    smooth: Option<f64>,
    /// The ankle's strike offset (s).
    #[arg(long, value_name = "S")]
    ankle_offset: Option<f64>,
    /// The impact method's search after the landing (s).
    #[arg(long, value_name = "S")]
    impact_after: Option<f64>,
    /// The impact method's low-pass (Hz).
    #[arg(long, value_name = "HZ")]
    impact_hz: Option<f64>,
    /// The pelvis carried past its ends (s).
    #[arg(long, value_name = "S")]
    pelvis_extend: Option<f64>,
    /// The least fall of an extreme at a cut.
    #[arg(long, value_name = "F")]
    cut_min_fall: Option<f64>,
    /// The least fall of an extreme where the trial's edge cuts it.
    #[arg(long, value_name = "F")]
    edge_min_fall: Option<f64>,
    /// How far beyond the trial's ends an extreme may peak (s; 0: none).
    #[arg(long, value_name = "S")]
    edge_beyond: Option<f64>,
    /// Zeni's signals bridged over gaps this short (s; 0: none).
    #[arg(long, value_name = "S")]
    bridge: Option<f64>,
    /// Landing: height as a fraction of the swing.
    #[arg(long, value_name = "F")]
    landing_height: Option<f64>,
    /// Landing: speed as a fraction of the swing's.
    #[arg(long, value_name = "F")]
    landing_speed: Option<f64>,
    /// Landing: vertical speed as a fraction of the swing's.
    #[arg(long, value_name = "F")]
    landing_vspeed: Option<f64>,
    /// Lift: height as a fraction of the swing.
    #[arg(long, value_name = "F")]
    lift_height: Option<f64>,
    /// Lift: speed as a fraction of the swing's.
    #[arg(long, value_name = "F")]
    lift_speed: Option<f64>,
    /// Lift: the toe's speed instead of the heel's.
    #[arg(long)]
    lift_toe: bool,
    /// The foot off's shift per second of stride.
    #[arg(long, value_name = "F")]
    off_stride_slope: Option<f64>,
    /// The stride the foot off's shift is measured from (s).
    #[arg(long, value_name = "S")]
    off_stride_ref: Option<f64>,
    /// Touchdown: height above stance (mm).
    #[arg(long, value_name = "MM")]
    touchdown_mm: Option<f64>,
    /// Touchdown: speed (mm/s).
    #[arg(long, value_name = "MM_S")]
    touchdown_speed: Option<f64>,
    /// Touchdown: low-pass (Hz).
    #[arg(long, value_name = "HZ")]
    touchdown_hz: Option<f64>,
    /// Lift-off: height above stance (mm).
    #[arg(long, value_name = "MM")]
    liftoff_mm: Option<f64>,
    /// Lift-off: speed (mm/s).
    #[arg(long, value_name = "MM_S")]
    liftoff_speed: Option<f64>,
    /// Touch height (mm).
    #[arg(long, value_name = "MM")]
    touch: Option<f64>,
    /// The plates' contact threshold (N).
    #[arg(long, value_name = "N")]
    threshold: Option<f64>,
    /// The least walking speed (mm/s).
    #[arg(long, value_name = "MM_S")]
    min_speed: Option<f64>,
    /// O'Connor's low-pass (Hz).
    #[arg(long, value_name = "HZ")]
    oconnor_hz: Option<f64>,
    /// Lift height (mm).
    #[arg(long, value_name = "MM")]
    lift: Option<f64>,
    /// The velocity method's heel ratio.
    #[arg(long, value_name = "F")]
    heel_ratio: Option<f64>,
    /// The velocity method's toe ratio.
    #[arg(long, value_name = "F")]
    toe_ratio: Option<f64>,
    /// Desailly's cut-off as a ratio of the stride frequency.
    #[arg(long, value_name = "F")]
    desailly_ratio: Option<f64>,
    /// Strike estimates, `METHOD[:OFFSET_S],…` (e.g. `zeni:0.02`).
    #[arg(long, value_name = "SPEC")]
    strike: Option<String>,
    /// Off estimates, `METHOD[:OFFSET_S],…`.
    #[arg(long, value_name = "SPEC")]
    off: Option<String>,
    /// Off estimates on runs, `METHOD[:OFFSET_S],…` (`none`: as on walks).
    #[arg(long, value_name = "SPEC")]
    running_off: Option<String>,
    /// The kinematics not calibrated on the trial's own plates.
    #[arg(long)]
    no_calibrate: bool,
    /// `auto`'s kinematic events matched to the plate steps' marker heights.
    #[arg(long)]
    correlate: bool,
    /// --correlate's half window (s).
    #[arg(long, value_name = "S")]
    correlate_window: Option<f64>,
    /// --correlate's search (s).
    #[arg(long, value_name = "S")]
    correlate_search: Option<f64>,
    /// --correlate without removing the mean.
    #[arg(long)]
    correlate_raw: bool,
    /// --correlate's part for strikes.
    #[arg(long, value_name = "PART")]
    correlate_strike: Option<String>,
    /// --correlate's part for offs.
    #[arg(long, value_name = "PART")]
    correlate_off: Option<String>,
    /// Session offsets per side.
    #[arg(long)]
    session_per_side: bool,
    /// The least contacts per kind a session offset needs.
    #[arg(long, value_name = "N")]
    session_min: Option<usize>,
    /// The truth the session calibration learns from.
    #[arg(long, value_name = "TRUTH")]
    session_truth: Option<String>,
    /// Each trial's events, the session offsets used and the trials skipped.
    #[arg(short = 'v')]
    verbose: bool,
    /// Each missed event, where, and where its markers are seen.
    #[arg(long)]
    misses: bool,
    /// The foot's state at each lab event.
    #[arg(long)]
    truth_check: bool,
    /// The lab strikes the trial's plates contradict left out of the lab truth.
    #[arg(long)]
    without_contradicted: bool,
    /// One CSV row per truth event with each method's signed error (s).
    #[arg(long, value_name = "FILE")]
    dump: Option<PathBuf>,
    /// The trials counted and c3dfix's markers for them, one per line (for the peers).
    #[arg(long, value_name = "FILE")]
    list: Option<PathBuf>,
    /// The peers' events (`scripts/events_peers.py`), scored beside c3dfix's.
    #[arg(long, value_name = "FILE")]
    peers: Option<PathBuf>,
    /// With `--peers`: one CSV row per truth event and detector, its signed error (ms;
    /// empty where not found), to compare the detectors on the same events.
    #[arg(long, value_name = "FILE", requires = "peers")]
    peers_dump: Option<PathBuf>,
}

/// What a run detects with and prints.
pub struct Settings {
    pub opts: EventOptions,
    pub session: gait::SessionOptions,
    pub session_truth: CalibrationTruth,
    pub verbose: bool,
    pub misses: bool,
    pub truth_check: bool,
    pub without_contradicted: bool,
    pub dump: Option<PathBuf>,
    pub list: Option<PathBuf>,
    pub peers: Option<PathBuf>,
    pub peers_dump: Option<PathBuf>,
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

/// `value` parsed, or the message the evaluation stops with (`FLAG VALUE: why`).
fn parsed<T: std::str::FromStr>(flag: &str, value: &str) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    value.parse().map_err(|e| format!("{flag} {value}: {e}"))
}

impl Cli {
    /// The settings: the shipped options with each given constant in place.
    pub fn settings(self) -> Result<Settings, String> {
        let mut opts = EventOptions::default();
        let k = &mut opts.kinematic;
        for (value, slot) in [
            (self.smooth, &mut k.smooth_s),
            (self.ankle_offset, &mut k.ankle_strike_offset_s),
            (self.impact_after, &mut k.impact_after_s),
            (self.impact_hz, &mut k.impact_lowpass_hz),
            (self.pelvis_extend, &mut k.pelvis_extend_s),
            (self.cut_min_fall, &mut k.cut_min_fall),
            (self.edge_min_fall, &mut k.edge_min_fall),
            (self.edge_beyond, &mut k.edge_beyond_s),
            (self.bridge, &mut k.bridge_s),
            (self.landing_height, &mut k.landing_height_frac),
            (self.landing_speed, &mut k.landing_speed_frac),
            (self.landing_vspeed, &mut k.landing_vspeed_frac),
            (self.lift_height, &mut k.lift_height_frac),
            (self.lift_speed, &mut k.lift_speed_frac),
            (self.off_stride_slope, &mut k.off_stride_slope),
            (self.off_stride_ref, &mut k.off_stride_ref_s),
            (self.touchdown_mm, &mut k.touchdown_mm),
            (self.touchdown_speed, &mut k.touchdown_speed_mm_s),
            (self.touchdown_hz, &mut k.touchdown_lowpass_hz),
            (self.liftoff_mm, &mut k.liftoff_mm),
            (self.liftoff_speed, &mut k.liftoff_speed_mm_s),
            (self.touch, &mut k.touch_mm),
            (self.min_speed, &mut k.min_speed_mm_s),
            (self.oconnor_hz, &mut k.oconnor_lowpass_hz),
            (self.lift, &mut k.lift_mm),
            (self.heel_ratio, &mut k.velocity_heel_ratio),
            (self.toe_ratio, &mut k.velocity_toe_ratio),
            (self.desailly_ratio, &mut k.desailly_cutoff_ratio),
        ] {
            if let Some(v) = value {
                *slot = v;
            }
        }
        k.lift_speed_of_toe = self.lift_toe;
        for (flag, spec, slot) in [
            ("--strike", &self.strike, &mut k.strike),
            ("--off", &self.off, &mut k.off),
            ("--running-off", &self.running_off, &mut k.running_off),
        ] {
            if spec.as_deref() == Some("none") {
                slot.clear();
                continue;
            }
            if let Some(spec) = spec {
                *slot = estimates(spec).map_err(|e| format!("{flag} {spec}: {e}"))?;
            }
        }
        if let Some(v) = self.threshold {
            opts.plate.threshold_n = v;
        }
        opts.no_calibrate = self.no_calibrate;
        let mut corr = gait::CorrelateOptions::default();
        if let Some(v) = self.correlate_window {
            corr.half_window_s = v;
        }
        if let Some(v) = self.correlate_search {
            corr.search_s = v;
        }
        corr.remove_mean = !self.correlate_raw;
        if let Some(v) = &self.correlate_strike {
            corr.strike_part = parsed("--correlate-strike", v)?;
        }
        if let Some(v) = &self.correlate_off {
            corr.off_part = parsed("--correlate-off", v)?;
        }
        if self.correlate {
            opts.correlate = Some(corr);
        }
        let mut session = gait::SessionOptions {
            per_side: self.session_per_side,
            ..gait::SessionOptions::default()
        };
        if let Some(v) = self.session_min {
            session.min_contacts = v;
        }
        let session_truth = match &self.session_truth {
            Some(v) => parsed("--session-truth", v)?,
            None => CalibrationTruth::default(),
        };
        Ok(Settings {
            opts,
            session,
            session_truth,
            verbose: self.verbose,
            misses: self.misses,
            truth_check: self.truth_check,
            without_contradicted: self.without_contradicted,
            dump: self.dump,
            list: self.list,
            peers: self.peers,
            peers_dump: self.peers_dump,
        })
    }
}
