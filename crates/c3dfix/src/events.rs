//! Gait events of an opened trial: the markers and plates as the `gait` crate's arrays,
//! and its events back with the file's time base and frame numbering.
//!
//! Times are on the EVENT group's base ([`c3d::C3d::frame_time`]: frame `n` of the capture
//! at (`n` − 1) / POINT:RATE); a fractional event index `i` (0-based from the first stored
//! frame) is at `frame_time(0) + i / rate`, and its frame is the nearest one, numbered as
//! the file numbers frames ([`c3d::C3d::frame_number`]).

use crate::error::{Error, Result, Setting};
use crate::events_tracks::{marker_labels, tracks, trial_error};
use crate::platforms::{force_platforms, ForceOptions};
use gait::{
    Feet, Kind, KinematicOptions, MarkerChoice, MarkerNames, PlateInput, PlateOptions, Side, Source,
};
use serde::Serialize;
use std::path::Path;

/// Where events come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EventSource {
    /// The force plates only.
    Plates,
    /// The markers only (the file's own events are never read).
    Kinematics,
    /// Plate events where a foot lands on a plate, kinematic events elsewhere.
    #[default]
    Auto,
}

impl std::str::FromStr for EventSource {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "plates" | "plate" => Ok(EventSource::Plates),
            "kinematics" | "kinematic" | "markers" => Ok(EventSource::Kinematics),
            "auto" => Ok(EventSource::Auto),
            _ => Err(Error::OutOfRange {
                setting: Setting::EventSource,
                value: s.to_string(),
                limits: "expected plates, kinematics or auto".into(),
            }),
        }
    }
}

/// How to detect events.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EventOptions {
    pub from: EventSource,
    /// Marker names given by a person (`--markers lheel=…`).
    pub markers: MarkerNames,
    pub kinematic: KinematicOptions,
    pub plate: PlateOptions,
    /// In `auto`, keep the kinematic events as detected. By default they are shifted by their
    /// median lead or lag against the trial's own plate events of the same kind
    /// ([`gait::calibrate()`]).
    pub no_calibrate: bool,
    /// In `auto`, after the calibration, move each kinematic event to where its foot's
    /// markers match their heights at the trial's plate events of its kind
    /// ([`gait::correlate()`], as Nexus' "Autocorrelate Events"). Off by default: the
    /// setting chosen on the tuning labs was worse than the median shift alone on the
    /// held-out labs' plates (docs/events.md).
    pub correlate: Option<gait::CorrelateOptions>,
    /// The offsets learned from other trials of the session
    /// ([`crate::session_from`]): added to the kinematic events of each kind, except in
    /// `auto` for a kind the trial's own plates calibrate.
    pub session: Option<crate::session_calibration::SessionCalibration>,
}

/// One detected event, as printed and written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrialEvent {
    /// The foot, written as the EVENT group's context: "Left" or "Right".
    #[serde(rename = "context")]
    pub side: Side,
    /// What the foot did, written as Nexus' label: "Foot Strike" or "Foot Off".
    #[serde(rename = "label", serialize_with = "nexus_label")]
    pub kind: Kind,
    /// Seconds on the EVENT group's time base.
    pub time: f64,
    /// The nearest frame, in the file's numbering.
    pub frame: usize,
    /// Where it was found: "plate" or "kinematics".
    pub source: Source,
    /// The 1-based plate, for plate events.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate: Option<usize>,
}

/// A kind of event as Nexus labels it ("Foot Strike", "Foot Off").
fn nexus_label<S: serde::Serializer>(kind: &Kind, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(kind.label())
}

/// The events of a trial and what was used to find them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Detected {
    pub events: Vec<TrialEvent>,
    /// The labels used for each role (`lheel`, `ltoe`, `rheel`, `rtoe`, `pelvis`).
    pub markers: Vec<(String, Vec<String>)>,
    /// What could not be used, in words (e.g. the markers show no walking, so only the
    /// plates' events are given).
    pub warnings: Vec<String>,
    /// How the markers and the direction were found where names alone did not say (a
    /// foot's heel and toe told apart by position; a treadmill), in words.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// The session calibration applied, when one was given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub session_calibration: Option<crate::session_calibration::SessionReport>,
}

/// Half the window (s) within which a plate event replaces a kinematic event of the same
/// foot and kind in `auto`: less than half the shortest step, more than any method's error.
pub const AUTO_MERGE_S: f64 = 0.2;

/// Half the window (s) within which a kinematic event is paired with a plate event of the
/// same foot and kind to measure the trial's lead or lag ([`gait::calibrate()`]): wider than
/// the methods' lags on the tuning labs (up to 70 ms), narrow enough that a step on the
/// plate is not paired with the neighbouring step's event. Chosen on the tuning labs
/// (c3d-samples; docs/events.md).
pub const CALIBRATE_WINDOW_S: f64 = 0.06;

/// The markers of each role (point indices), found among the markers of `c` (model outputs
/// are never taken).
pub fn choose_markers(c: &c3d::C3d, names: &MarkerNames, path: &Path) -> Result<MarkerChoice> {
    let labels = marker_labels(c);
    gait::find_markers(&labels, names).map_err(|source| Error::Markers {
        path: path.to_path_buf(),
        source,
        for_plates: false,
    })
}

/// The trajectories of the chosen markers in millimetres, NaN where missing (a role of
/// several markers is their mean where all are present; a role of none, a side the marker
/// set does not mark, is missing throughout). A heel found by name whose every sample is
/// missing is replaced by the ankle marker of its side, when there is one; a side given as
/// a foot cluster gets the cluster's rearmost marker as its heel and its foremost as its
/// toe, along the walking direction ([`gait::markers::cluster_heel_toe`]). The choice is
/// updated to say so.
pub fn feet(c: &c3d::C3d, choice: &mut MarkerChoice, path: &Path) -> Result<Feet> {
    let mut f = feet_of(c, choice, path)?;
    if choice.foot_cluster.iter().any(|&k| k) {
        resolve_clusters(c, choice, &f, path)?;
        f = feet_of(c, choice, path)?;
    }
    let labels = marker_labels(c);
    let mut swapped = false;
    for (k, (heel, side)) in [(&f.left_heel, 'l'), (&f.right_heel, 'r')]
        .into_iter()
        .enumerate()
    {
        let seen = heel.iter().any(|p| p[0].is_finite());
        let role = if k == 0 {
            &choice.left_heel
        } else {
            &choice.right_heel
        };
        if !seen && !choice.heel_is_ankle[k] && !role.is_empty() {
            if let Some(a) = gait::markers::ankle_for(&labels, side) {
                let slot = if k == 0 {
                    &mut choice.left_heel
                } else {
                    &mut choice.right_heel
                };
                *slot = vec![a];
                choice.heel_is_ankle[k] = true;
                swapped = true;
            }
        }
    }
    if swapped {
        f = feet_of(c, choice, path)?;
    }
    crate::events_stand_in::stand_in(c, choice, &mut f, path)?;
    Ok(f)
}

/// Give each side held as a foot cluster its heel and toe (see [`feet`]); `f` has the
/// pelvis. A cluster whose markers are never seen together while walking keeps no side.
fn resolve_clusters(c: &c3d::C3d, choice: &mut MarkerChoice, f: &Feet, path: &Path) -> Result<()> {
    let rate = c.point_rate() as f64;
    let opts = KinematicOptions::default();
    for k in 0..2 {
        if !choice.foot_cluster[k] {
            continue;
        }
        let cluster = if k == 0 {
            choice.left_heel.clone()
        } else {
            choice.right_heel.clone()
        };
        let tracks = tracks(c, &cluster, path)?;
        let refs: Vec<&[[f64; 3]]> = tracks.iter().map(|t| t.as_slice()).collect();
        let vertical = gait::axes::vertical(&f.pelvis, &refs);
        let picked = vertical.and_then(|v| {
            if !(rate.is_finite() && rate > 0.0) {
                return None;
            }
            let (dir, _) = gait::kinematic::travel_direction(&f.pelvis, &refs, v, rate, &opts);
            gait::markers::cluster_heel_toe(&refs, &dir)
        });
        let (heel, toe) = match picked {
            Some((h, t)) => (vec![cluster[h]], vec![cluster[t]]),
            None => (Vec::new(), Vec::new()),
        };
        if k == 0 {
            (choice.left_heel, choice.left_toe) = (heel, toe);
        } else {
            (choice.right_heel, choice.right_toe) = (heel, toe);
        }
        choice.foot_cluster[k] = false;
        choice.by_position[k] = cluster;
    }
    Ok(())
}

fn feet_of(c: &c3d::C3d, choice: &MarkerChoice, path: &Path) -> Result<Feet> {
    let roles = [
        &choice.left_heel,
        &choice.left_toe,
        &choice.right_heel,
        &choice.right_toe,
        &choice.pelvis,
    ];
    let mut points: Vec<usize> = roles.iter().flat_map(|r| r.iter().copied()).collect();
    points.sort_unstable();
    points.dedup();
    let all = tracks(c, &points, path)?;
    let frames = c.frames();
    let mean = |role: &[usize]| -> Vec<[f64; 3]> {
        (0..frames)
            .map(|f| {
                if role.is_empty() {
                    return [f64::NAN; 3];
                }
                let mut s = [0.0; 3];
                for &p in role {
                    let Ok(row) = points.binary_search(&p) else {
                        return [f64::NAN; 3];
                    };
                    let v = all[row][f];
                    for k in 0..3 {
                        s[k] += v[k] / role.len() as f64;
                    }
                }
                s
            })
            .collect()
    };
    Ok(Feet {
        left_heel: mean(&choice.left_heel),
        left_toe: mean(&choice.left_toe),
        right_heel: mean(&choice.right_heel),
        right_toe: mean(&choice.right_toe),
        pelvis: mean(&choice.pelvis),
        heel_is_ankle: choice.heel_is_ankle,
    })
}

/// Plate events of `c` (fractional frame indices) from its computable plates.
pub fn plate_events(c: &c3d::C3d, feet: &Feet, opts: &PlateOptions) -> Result<Vec<gait::Event>> {
    let fp = force_platforms(c, &ForceOptions::default())?;
    let mm = c3d::mm_per_unit(&c.point_units());
    let cops: Vec<Vec<[f64; 3]>> = fp
        .platforms
        .iter()
        .map(|p| {
            p.cop
                .iter()
                .map(|v| [v[0] * mm, v[1] * mm, v[2] * mm])
                .collect()
        })
        .collect();
    let inputs: Vec<PlateInput> = fp
        .platforms
        .iter()
        .zip(&cops)
        .map(|(p, cop)| PlateInput {
            index: p.index,
            samples_per_frame: fp.samples_per_frame,
            push: &p.push,
            cop,
        })
        .collect();
    Ok(gait::plate_events(
        &inputs,
        feet,
        c.analog_rate() as f64,
        opts,
    ))
}

/// An event at fractional index `e.index` on the file's time base and numbering.
pub fn to_trial_event(c: &c3d::C3d, e: &gait::Event) -> TrialEvent {
    let rate = c.point_rate() as f64;
    let time = if rate > 0.0 && rate.is_finite() {
        c.frame_time(0) + e.index / rate
    } else {
        0.0
    };
    TrialEvent {
        side: e.side,
        kind: e.kind,
        time,
        frame: c.frame_number(e.index.round().max(0.0) as usize),
        source: e.source,
        plate: e.plate,
    }
}

/// `kinematic` events with those near a plate event of the same foot and kind replaced by
/// it, sorted by time.
pub fn merge_auto(
    plates: &[gait::Event],
    kinematic: &[gait::Event],
    rate: f64,
) -> Vec<gait::Event> {
    let window = AUTO_MERGE_S * rate;
    let mut out: Vec<gait::Event> = kinematic
        .iter()
        .filter(|k| {
            !plates.iter().any(|p| {
                p.side == k.side && p.kind == k.kind && (p.index - k.index).abs() <= window
            })
        })
        .copied()
        .collect();
    out.extend_from_slice(plates);
    gait::sort_events(&mut out);
    out
}

/// Which kinds (strike, off) the trial's own plates calibrate in `auto`: those with a plate
/// event paired with a kinematic one ([`gait::calibrate::plate_offsets`]).
pub fn own_calibration(plates: &[gait::Event], kinematic: &[gait::Event], rate: f64) -> [bool; 2] {
    gait::calibrate::plate_offsets(plates, kinematic, CALIBRATE_WINDOW_S * rate)
        .map(|o| o.is_some())
}

/// `auto`'s kinematic events: shifted by the trial's own median lag against its plates
/// ([`gait::calibrate()`]), a kind without a plate pair by the session's offset where
/// [`EventOptions::session`] gives one (the trial's own plates know this trial better than
/// other trials do), then, with [`EventOptions::correlate`], each moved to the best match of
/// the plate steps' marker heights ([`gait::correlate()`]).
pub fn calibrated(
    feet: &Feet,
    rate: f64,
    plates: &[gait::Event],
    kinematic: &[gait::Event],
    opts: &EventOptions,
) -> Vec<gait::Event> {
    let session = opts.session.as_ref().map(|s| {
        let own = own_calibration(plates, kinematic, rate);
        let mut o = s.offsets;
        if own[0] {
            o.strike.seconds = [None; 2];
        }
        if own[1] {
            o.off.seconds = [None; 2];
        }
        gait::session::apply(kinematic, &o, rate)
    });
    let kinematic = session.as_deref().unwrap_or(kinematic);
    let k = gait::calibrate(plates, kinematic, CALIBRATE_WINDOW_S * rate);
    let mut k = match &opts.correlate {
        Some(c) => gait::correlate(feet, rate, plates, &k, c),
        None => k,
    };
    // A shift can carry an event found at the trial's edge past it: an event the trial
    // does not hold is none of its frames.
    let last = feet.frames().saturating_sub(1) as f64;
    k.retain(|e| (0.0..=last).contains(&e.index));
    k
}

/// Detect the gait events of `c` (`path` names it in messages).
pub fn detect_events(c: &c3d::C3d, opts: &EventOptions, path: &Path) -> Result<Detected> {
    let mut choice = choose_markers(c, &opts.markers, path).map_err(|e| match e {
        Error::Markers { path, source, .. } if opts.from == EventSource::Plates => Error::Markers {
            path,
            source,
            for_plates: true,
        },
        e => e,
    })?;
    let feet = feet(c, &mut choice, path)?;
    let labels = c.point_labels();
    let names = |r: &[usize]| {
        r.iter()
            .map(|&i| labels.get(i).cloned().unwrap_or_default())
            .collect()
    };
    let markers = vec![
        ("lheel".to_string(), names(&choice.left_heel)),
        ("ltoe".to_string(), names(&choice.left_toe)),
        ("rheel".to_string(), names(&choice.right_heel)),
        ("rtoe".to_string(), names(&choice.right_toe)),
        ("pelvis".to_string(), names(&choice.pelvis)),
    ];
    let mut notes = position_notes(&choice, &labels);
    notes.extend(stand_in_notes(&choice, &labels));
    notes.extend(ankle_notes(&choice, &labels));
    let frames = c.frames();
    if frames < gait::kinematic::MIN_FRAMES {
        return Err(trial_error(
            path,
            gait::Error::TooShort {
                frames,
                needed: gait::kinematic::MIN_FRAMES,
            },
        ));
    }
    let rate = c.point_rate() as f64;
    if gait::kinematic::prepare(&feet, rate, &opts.kinematic).is_ok_and(|p| p.treadmill) {
        notes.push(TREADMILL_NOTE.to_string());
    }
    let mut warnings = Vec::new();
    for (side, heel) in [("left", &choice.left_heel), ("right", &choice.right_heel)] {
        if heel.is_empty() {
            warnings.push(format!(
                "no {side} heel and toe markers: the {side} foot gets no events from the markers, nor from the plates"
            ));
        }
    }
    // Which kinds the trial's own plates calibrated (auto), so that the report says the
    // session's offset was not used for them.
    let mut own = [false; 2];
    // Whether kinematic events were given (auto falls back to the plates alone when the
    // markers show no walking; the session's offsets then moved nothing).
    let mut kinematic = true;
    let events = match opts.from {
        EventSource::Kinematics => {
            let (k, running) = gait::kinematic::kinematic_gait(&feet, rate, &opts.kinematic)
                .map_err(|e| trial_error(path, e))?;
            if running {
                notes.push(RUNNING_NOTE.to_string());
            }
            match &opts.session {
                Some(s) => gait::session::apply(&k, &s.offsets, rate),
                None => k,
            }
        }
        EventSource::Plates => {
            if c.platform_params().plates.is_empty() {
                return Err(trial_error(
                    path,
                    "no force plates (FORCE_PLATFORM:USED is 0 or absent)",
                ));
            }
            let p = plate_events(c, &feet, &opts.plate)?;
            warnings.extend(crate::plate_silence::silent_plates(c, &p, &opts.plate)?);
            p
        }
        EventSource::Auto => {
            let plates = if c.platform_params().plates.is_empty() {
                Vec::new()
            } else {
                let p = plate_events(c, &feet, &opts.plate)?;
                warnings.extend(crate::plate_silence::silent_plates(c, &p, &opts.plate)?);
                p
            };
            let k = gait::kinematic::kinematic_gait(&feet, rate, &opts.kinematic);
            if k.as_ref().is_ok_and(|(_, running)| *running) {
                notes.push(RUNNING_NOTE.to_string());
            }
            match k.map(|(k, _)| k) {
                Ok(k) if opts.no_calibrate => merge_auto(&plates, &k, rate),
                Ok(k) => {
                    own = own_calibration(&plates, &k, rate);
                    merge_auto(&plates, &calibrated(&feet, rate, &plates, &k, opts), rate)
                }
                Err(e) if !plates.is_empty() => {
                    kinematic = false;
                    warnings.push(format!("markers: {e}; only the plates' events are given"));
                    plates
                }
                Err(e) => return Err(trial_error(path, e)),
            }
        }
    };
    let session_calibration = match (&opts.session, opts.from) {
        (Some(s), EventSource::Kinematics | EventSource::Auto) if kinematic => {
            warnings.extend(s.warnings());
            Some(s.report(own))
        }
        _ => None,
    };
    Ok(Detected {
        events: events.iter().map(|e| to_trial_event(c, e)).collect(),
        markers,
        warnings,
        notes,
        session_calibration,
    })
}

/// Whether `c` is a treadmill trial: its markers (found by name) show the pelvis staying
/// while the feet swing back and forth under it ([`gait::treadmill`]). False where the
/// markers cannot tell (no foot or pelvis markers, walking overground, standing).
pub fn is_treadmill(c: &c3d::C3d, path: &Path) -> bool {
    treadmill_direction(c, path).is_some()
}

/// The direction a treadmill trial's subject faces (unit, horizontal, in the lab's axes:
/// the belt carries the feet the other way), when `c` is one ([`is_treadmill`]).
pub fn treadmill_direction(c: &c3d::C3d, path: &Path) -> Option<[f64; 3]> {
    let mut choice = choose_markers(c, &MarkerNames::default(), path).ok()?;
    let feet = feet(c, &mut choice, path).ok()?;
    let rate = c.point_rate() as f64;
    let p = gait::kinematic::prepare(&feet, rate, &KinematicOptions::default()).ok()?;
    if !p.treadmill {
        return None;
    }
    p.dir.into_iter().find(|d| d.iter().all(|v| v.is_finite()))
}

/// What a trial where the pelvis stays while the feet cycle is called, and what that means
/// for its events.
pub const TREADMILL_NOTE: &str = "treadmill: the pelvis stays while the feet swing back and forth under it; the walking direction is the feet's, and events come from the feet relative to the pelvis (as Zeni defined them)";

/// What a trial whose feet show flight phases is called, and what that means for its offs
/// ([`gait::running`]).
pub const RUNNING_NOTE: &str = "running: each foot leaves the floor before the other lands; foot offs from the markers are where the toe rises from its stance level (the toe's backward extreme comes late in a run's flight)";

/// One sentence per marker that stood in for a role's missing one
/// (`events_stand_in::stand_in`).
fn stand_in_notes(choice: &MarkerChoice, labels: &[String]) -> Vec<String> {
    let name = |i: usize| labels.get(i).cloned().unwrap_or_default();
    choice
        .stand_ins
        .iter()
        .map(|st| {
            format!(
                "{}: {} stands in for {} in {} frames where {} is missing (moved by their median offset near each gap{})",
                st.role,
                name(st.marker),
                name(st.chosen),
                st.frames,
                name(st.chosen),
                if st.rigid {
                    "; it keeps one offset from it within 10 mm, as on one rigid part of the foot"
                } else {
                    ""
                }
            )
        })
        .collect()
}

/// One sentence per side whose heel and toe were told apart by position.
/// One sentence per foot whose ankle stands in for a missing heel, with what that costs:
/// on the corpora's ankle sets, from the markers alone, strikes 20–65 ms before the plates'
/// (docs/events.md; `admarche2` 64 ms), which the trial's own plates or a session's
/// calibration remove.
fn ankle_notes(choice: &MarkerChoice, labels: &[String]) -> Vec<String> {
    [("left", 0, &choice.left_heel), ("right", 1, &choice.right_heel)]
        .into_iter()
        .filter(|(_, k, heel)| choice.heel_is_ankle[*k] && !heel.is_empty())
        .map(|(side, _, heel)| {
            let names: Vec<String> = heel
                .iter()
                .map(|&i| labels.get(i).cloned().unwrap_or_default())
                .collect();
            format!(
                "{side} foot: no heel marker, the ankle {} stands in for it; from the markers alone its strikes come 20–65 ms before a heel's, which the trial's own plates or a session's calibration remove",
                names.join("+")
            )
        })
        .collect()
}

fn position_notes(choice: &MarkerChoice, labels: &[String]) -> Vec<String> {
    let name = |i: &usize| labels.get(*i).cloned().unwrap_or_default();
    [
        ("left", &choice.by_position[0], &choice.left_heel, &choice.left_toe),
        ("right", &choice.by_position[1], &choice.right_heel, &choice.right_toe),
    ]
    .into_iter()
    .filter(|(_, among, _, _)| !among.is_empty())
    .map(|(side, among, heel, toe)| {
        let among: Vec<String> = among.iter().map(name).collect();
        if heel.is_empty() {
            format!(
                "{side} foot: {} are never seen together while walking, so its heel and toe could not be told apart",
                among.join(", ")
            )
        } else {
            format!(
                "{side} foot: heel {} and toe {}, the rearmost and foremost along the walking direction of {}",
                heel.iter().map(name).collect::<Vec<_>>().join("+"),
                toe.iter().map(name).collect::<Vec<_>>().join("+"),
                among.join(", ")
            )
        }
    })
    .collect()
}
