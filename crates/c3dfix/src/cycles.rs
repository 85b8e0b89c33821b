//! Gait cycles of an opened trial: markers, analog channels and plate forces cut from each
//! foot strike to the next of the same foot and time-normalised to 0–100 % (the `gait`
//! crate's [`gait::cycles`], Kinetics Toolkit's rule).
//!
//! Every signal is read on the file's one time base: marker frame `i` at
//! [`c3d::C3d::frame_time`], analog sample `s` at [`c3d::C3d::analog_time`], plate outputs
//! from [`crate::ForcePlatforms::start_time`] at the analog rate. The file's EVENT times are
//! on that base already, and detected events are put on it by [`crate::events`], so a
//! cycle's percentages land on the same instants for every signal whatever its rate.

use crate::error::{Error, Result};
use crate::events::{detect_events, EventOptions};
use crate::platforms::{force_platforms, ForceOptions};
use gait::cycles::{time_normalize, Cycle, Signal, SAMPLES};
use gait::Side;
use serde::Serialize;
use std::path::Path;

/// What to cut into cycles, and from which events.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CycleOptions {
    /// The feet whose cycles are wanted (both when empty).
    pub sides: Vec<Side>,
    /// Markers by label (x, y, z in mm each). When no signal at all is named, every marker
    /// of the trial (model outputs left out).
    pub markers: Vec<String>,
    /// Analog channels by label, in their physical units.
    pub analog: Vec<String>,
    /// Each plate's force (x, y, z in the lab frame).
    pub forces: bool,
    /// How plate forces are computed.
    pub force: ForceOptions,
    /// Detect events with these options instead of reading the file's EVENT group.
    pub detect: Option<EventOptions>,
}

/// One cycle: its foot, its number among that foot's cycles (from 1), and its bounds on
/// the file's time base and in its frame numbering.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleInfo {
    /// The foot, written as the EVENT group's context: "Left" or "Right".
    #[serde(rename = "context")]
    pub side: Side,
    pub number: usize,
    /// The foot strike that opens the cycle (s).
    pub start_time: f64,
    /// The next foot strike of the same foot (s).
    pub end_time: f64,
    /// The frames nearest those strikes, as the file numbers frames.
    pub start_frame: usize,
    pub end_frame: usize,
}

/// One column of the normalised data.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Column {
    /// `LHEE_x`, `Fz1` as the file labels its channel, `FP1_Fz`.
    pub name: String,
    pub unit: String,
}

/// A trial's cycles, each with [`SAMPLES`] rows (0–100 %) of every column.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cycles {
    pub cycles: Vec<CycleInfo>,
    pub columns: Vec<Column>,
    /// Per cycle, `SAMPLES × columns` values row-major (row `k` at `k` %), NaN where the
    /// signal is missing.
    #[serde(skip)]
    pub data: Vec<Vec<f64>>,
    /// "file" (the EVENT group's foot strikes) or "detected".
    pub events: &'static str,
    /// Cycles left out and why.
    pub warnings: Vec<String>,
}

fn trial_error(path: &Path, what: impl std::fmt::Display) -> Error {
    Error::Trial {
        path: path.to_path_buf(),
        what: what.to_string(),
    }
}

/// The foot strike times (s, on the file's base) of each side: the file's own, or detected.
fn strikes(
    c: &c3d::C3d,
    opts: &CycleOptions,
    path: &Path,
) -> Result<(Vec<(Side, f64)>, &'static str)> {
    match &opts.detect {
        Some(e) => {
            let d = detect_events(c, e, path)?;
            let s = d
                .events
                .iter()
                .filter(|e| e.kind == gait::Kind::FootStrike)
                .map(|e| (e.side, e.time))
                .collect();
            Ok((s, "detected"))
        }
        None => {
            let s = crate::event_labels::file_gait_events(c)
                .into_iter()
                .filter(|e| e.kind == gait::Kind::FootStrike)
                .map(|e| (e.side, e.time))
                .collect();
            Ok((s, "file"))
        }
    }
}

/// A signal's values and its columns, before normalisation.
struct Source {
    values: Vec<f64>,
    channels: usize,
    rate: f64,
    start: f64,
    columns: Vec<Column>,
}

impl Source {
    fn signal(&self) -> Signal<'_> {
        Signal {
            values: &self.values,
            channels: self.channels,
            rate: self.rate,
            start: self.start,
        }
    }
}

/// The unit of the point labelled `label`, and the factor its stored values are multiplied
/// by: a marker's position in mm (from POINT:UNITS); a model output (an angle, force,
/// moment, power… listed in POINT:ANGLES, FORCES, …) as stored, in the unit its group's
/// `*_UNITS` parameter names, for a Plug-in Gait angle is no length.
fn point_unit(c: &c3d::C3d, label: &str) -> (String, f64) {
    let ps = &c.parameters;
    for (list, units) in [
        ("ANGLES", "ANGLE_UNITS"),
        ("FORCES", "FORCE_UNITS"),
        ("MOMENTS", "MOMENT_UNITS"),
        ("POWERS", "POWER_UNITS"),
        ("SCALARS", "SCALAR_UNITS"),
        ("REACTIONS", "REACTION_UNITS"),
    ] {
        let listed = ps
            .get_strings("POINT", list)
            .unwrap_or_default()
            .iter()
            .any(|l| l.trim() == label.trim());
        if listed {
            let unit = ps
                .get_strings("POINT", units)
                .and_then(|v| v.into_iter().next())
                .map(|u| u.trim().to_string())
                .unwrap_or_default();
            return (unit, 1.0);
        }
    }
    ("mm".into(), c3d::mm_per_unit(&c.point_units()))
}

fn marker_source(c: &c3d::C3d, names: &[String], path: &Path) -> Result<Option<Source>> {
    let points = if names.is_empty() {
        crate::markers::marker_indices(c)
    } else {
        crate::markers::select(c, names)?
    };
    if points.is_empty() {
        return Ok(None);
    }
    let trial = crate::trial::to_trial(c, &points, false).map_err(|e| trial_error(path, e))?;
    let labels = c.point_labels();
    let units: Vec<(String, f64)> = points
        .iter()
        .map(|&p| point_unit(c, labels.get(p).map_or("", String::as_str)))
        .collect();
    let frames = c.frames();
    let mut values = Vec::with_capacity(frames * points.len() * 3);
    for f in 0..frames {
        for (row, (_, scale)) in units.iter().enumerate() {
            let v = trial.xyz[row][f];
            if trial.valid[row][f] && v.iter().all(|x| x.is_finite()) {
                values.extend(v.map(|x| x * scale));
            } else {
                values.extend([f64::NAN; 3]);
            }
        }
    }
    let columns = points
        .iter()
        .zip(&units)
        .flat_map(|(&p, (unit, _))| {
            let l = labels.get(p).cloned().unwrap_or_default();
            ["x", "y", "z"].map(|a| Column {
                name: format!("{}_{a}", l.trim()),
                unit: unit.clone(),
            })
        })
        .collect();
    Ok(Some(Source {
        values,
        channels: points.len() * 3,
        rate: c.point_rate() as f64,
        start: c.frame_time(0),
        columns,
    }))
}

fn analog_source(c: &c3d::C3d, names: &[String]) -> Result<Option<Source>> {
    if names.is_empty() {
        return Ok(None);
    }
    let labels = c.analog_labels();
    let units = c.analog_units();
    let mut chosen = Vec::new();
    for n in names.iter().map(|n| n.trim()).filter(|n| !n.is_empty()) {
        let i = labels
            .iter()
            .position(|l| l.trim() == n)
            .or_else(|| labels.iter().position(|l| l.trim().eq_ignore_ascii_case(n)))
            .ok_or_else(|| {
                Error::options(format!(
                    "no analog channel {n:?}; the file has: {}",
                    labels.join(", ")
                ))
            })?;
        chosen.push(i);
    }
    let all = c.analog_physical();
    let width = c.analog_channels();
    let samples = all.len().checked_div(width).unwrap_or(0);
    let mut values = Vec::with_capacity(samples * chosen.len());
    for s in 0..samples {
        for &i in &chosen {
            values.push(all[s * width + i] as f64);
        }
    }
    let columns = chosen
        .iter()
        .map(|&i| Column {
            name: labels[i].trim().to_string(),
            unit: units
                .get(i)
                .map(|u| u.trim().to_string())
                .unwrap_or_default(),
        })
        .collect();
    Ok(Some(Source {
        values,
        channels: chosen.len(),
        rate: c.analog_rate() as f64,
        start: c.analog_time(0),
        columns,
    }))
}

fn force_sources(c: &c3d::C3d, opts: &ForceOptions, path: &Path) -> Result<Vec<Source>> {
    let fp = force_platforms(c, opts)?;
    if fp.platforms.is_empty() {
        return Err(trial_error(
            path,
            "force-plate columns were asked for, but the trial has no force plate that can be computed",
        ));
    }
    Ok(fp
        .platforms
        .iter()
        .map(|p| Source {
            values: p.force.iter().flatten().copied().collect(),
            channels: 3,
            rate: p.rate,
            start: fp.start_time,
            columns: ["Fx", "Fy", "Fz"]
                .map(|a| Column {
                    name: format!("FP{}_{a}", p.index),
                    unit: p.units.force.clone(),
                })
                .to_vec(),
        })
        .collect())
}

/// The frame nearest `time` (s on the file's base) in the file's numbering.
fn frame_at(rate: f64, time: f64) -> usize {
    if rate > 0.0 && rate.is_finite() && time.is_finite() {
        (time * rate).round().max(0.0) as usize + 1
    } else {
        0
    }
}

/// The cycles of `c` with the chosen signals time-normalised (`path` names it in messages).
/// A cycle that reaches outside the trial's frames is left out with a warning; no cycle at
/// all on the asked-for feet is an error that says how many strikes each foot has.
pub fn cycles(c: &c3d::C3d, opts: &CycleOptions, path: &Path) -> Result<Cycles> {
    let rate = c.point_rate() as f64;
    if !(rate > 0.0 && rate.is_finite()) {
        return Err(trial_error(path, "POINT:RATE is not a positive number"));
    }
    if c.frames() < 2 {
        return Err(trial_error(
            path,
            format!("{} frame(s): a cycle needs at least two", c.frames()),
        ));
    }
    let sides: Vec<Side> = if opts.sides.is_empty() {
        Side::BOTH.to_vec()
    } else {
        opts.sides.clone()
    };
    let none_named = opts.markers.is_empty() && opts.analog.is_empty() && !opts.forces;
    let mut sources = Vec::new();
    if none_named || !opts.markers.is_empty() {
        sources.extend(marker_source(c, &opts.markers, path)?);
    }
    sources.extend(analog_source(c, &opts.analog)?);
    if opts.forces {
        sources.extend(force_sources(c, &opts.force, path)?);
    }
    if sources.is_empty() {
        return Err(trial_error(path, "no markers to cut into cycles"));
    }
    let (strikes, from) = strikes(c, opts, path)?;
    // The trial's span, from its first to its last frame: a cycle must lie within it.
    let first = c.frame_time(0);
    let last = c.frame_time(c.frames() - 1);
    let mut out = Cycles {
        cycles: Vec::new(),
        columns: sources.iter().flat_map(|s| s.columns.clone()).collect(),
        data: Vec::new(),
        events: from,
        warnings: Vec::new(),
    };
    let mut counts = Vec::new();
    for &side in &sides {
        let times: Vec<f64> = strikes
            .iter()
            .filter(|(s, _)| *s == side)
            .map(|(_, t)| *t)
            .collect();
        counts.push(format!("{} {}", side.context(), times.len()));
        let mut number = 0;
        for cy in gait::cycles::cycles(&times) {
            let inside = cy.start >= first - 1e-9 / rate && cy.end <= last + 1e-9 / rate;
            if !inside {
                out.warnings.push(format!(
                    "{} cycle {:.4}–{:.4} s left out: it reaches outside the trial ({:.4}–{:.4} s)",
                    side.context(),
                    cy.start,
                    cy.end,
                    first,
                    last
                ));
                continue;
            }
            number += 1;
            out.data.push(normalise_all(&sources, &cy, path)?);
            out.cycles.push(CycleInfo {
                side,
                number,
                start_time: cy.start,
                end_time: cy.end,
                start_frame: frame_at(rate, cy.start),
                end_frame: frame_at(rate, cy.end),
            });
        }
    }
    if out.cycles.is_empty() {
        return Err(trial_error(
            path,
            format!(
                "no complete gait cycle in the trial (Foot Strike events from the {}: {}; a cycle runs from one foot strike to the next of the same foot){}",
                if from == "file" { "file's EVENT group" } else { "detector" },
                counts.join(", "),
                if out.warnings.is_empty() { String::new() } else { format!("; {}", out.warnings.join("; ")) }
            ),
        ));
    }
    Ok(out)
}

/// Every source over one cycle, side by side: `SAMPLES` rows of all the columns.
fn normalise_all(sources: &[Source], cy: &Cycle, path: &Path) -> Result<Vec<f64>> {
    let width: usize = sources.iter().map(|s| s.channels).sum();
    let mut rows = vec![f64::NAN; SAMPLES * width];
    let mut at = 0;
    for s in sources {
        let sig = s.signal();
        let n = time_normalize(&sig, cy).map_err(|e| trial_error(path, e))?;
        for k in 0..SAMPLES {
            let dst = k * width + at;
            rows[dst..dst + s.channels].copy_from_slice(&n[k * s.channels..(k + 1) * s.channels]);
        }
        at += s.channels;
    }
    Ok(rows)
}

impl Cycles {
    /// One CSV row per (side, cycle, percent): the foot, the cycle's number, the percentage,
    /// the time of that instant and the cycle's bounds (frames and seconds on the file's
    /// base), then every column, headed `name (unit)`; a missing value is an empty cell, as
    /// CSV readers (pandas, spreadsheets) read one.
    pub fn to_csv(&self) -> String {
        use std::fmt::Write as _;
        let mut s =
            String::from("side,cycle,percent,time,start_frame,start_time,end_frame,end_time");
        for c in &self.columns {
            let name = if c.unit.is_empty() {
                c.name.clone()
            } else {
                format!("{} ({})", c.name, c.unit)
            };
            let _ = write!(s, ",{}", crate::export::csv::field(&name));
        }
        s.push('\n');
        let width = self.columns.len();
        for (info, rows) in self.cycles.iter().zip(&self.data) {
            let cy = Cycle {
                start: info.start_time,
                end: info.end_time,
            };
            for k in 0..SAMPLES {
                let _ = write!(
                    s,
                    "{},{},{k},{:.6},{},{:.6},{},{:.6}",
                    info.side.context(),
                    info.number,
                    cy.time_at(k as f64),
                    info.start_frame,
                    info.start_time,
                    info.end_frame,
                    info.end_time
                );
                for v in &rows[k * width..(k + 1) * width] {
                    if v.is_finite() {
                        let _ = write!(s, ",{v}");
                    } else {
                        s.push(',');
                    }
                }
                s.push('\n');
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use c3d::{Analog, C3d, Parameters, Points, Processor, Value};

    /// 100 Hz, POINT:UNITS metres, a marker moving 1 cm per frame along x and a knee angle
    /// of (frame) degrees; left strikes at 0.1 and 0.5 s.
    fn trial() -> C3d {
        let frames = 100;
        let mut pts = Points::new(frames, 2);
        for f in 0..frames {
            let k = pts.index(f, 0);
            pts.xyz[k] = [f as f32 * 0.01, 0.0, 0.9];
            pts.residual[k] = 0.5;
            let k = pts.index(f, 1);
            pts.xyz[k] = [f as f32, 0.0, 0.0];
            pts.residual[k] = 0.0;
        }
        let mut ps = Parameters::new();
        ps.set_f32("POINT", "RATE", 100.0).unwrap();
        ps.set_strings("POINT", "LABELS", &["SACR".into(), "LKneeAngles".into()])
            .unwrap();
        ps.set_strings("POINT", "UNITS", &["m".into()]).unwrap();
        ps.set_strings("POINT", "ANGLES", &["LKneeAngles".into()])
            .unwrap();
        ps.set_strings("POINT", "ANGLE_UNITS", &["deg".into()])
            .unwrap();
        ps.set_i16("EVENT", "USED", 2).unwrap();
        ps.set(
            "EVENT",
            "TIMES",
            vec![2, 2],
            Value::Float(vec![0.0, 0.1, 0.0, 0.5]),
        )
        .unwrap();
        ps.set_strings("EVENT", "CONTEXTS", &["Left".into(), "left".into()])
            .unwrap();
        ps.set_strings(
            "EVENT",
            "LABELS",
            &["Foot Strike".into(), "FOOT STRIKE".into()],
        )
        .unwrap();
        C3d::new(pts, Analog::new(frames, 0, 1), ps, Processor::Intel, -1.0)
    }

    #[test]
    fn markers_in_mm_and_angles_in_their_own_unit() {
        let c = trial();
        let opts = CycleOptions {
            markers: vec!["SACR".into(), "LKneeAngles".into()],
            ..CycleOptions::default()
        };
        let cy = cycles(&c, &opts, Path::new("t.c3d")).unwrap();
        assert_eq!(cy.cycles.len(), 1);
        let info = &cy.cycles[0];
        assert_eq!((info.side, info.number), (Side::Left, 1));
        assert_eq!((info.start_frame, info.end_frame), (11, 51));
        let units: Vec<&str> = cy.columns.iter().map(|c| c.unit.as_str()).collect();
        assert_eq!(units, ["mm", "mm", "mm", "deg", "deg", "deg"]);
        // k % of 0.1–0.5 s is frame 10 + 0.4 k: x = 100 + 4 k mm (metres × 1000), the
        // angle 10 + 0.4 k degrees (never scaled).
        for k in 0..SAMPLES {
            let row = &cy.data[0][k * 6..(k + 1) * 6];
            assert!(
                (row[0] - (100.0 + 4.0 * k as f64)).abs() < 1e-3,
                "{k}: {row:?}"
            );
            assert!(
                (row[3] - (10.0 + 0.4 * k as f64)).abs() < 1e-3,
                "{k}: {row:?}"
            );
        }
        let csv = cy.to_csv();
        assert!(csv.starts_with(
            "side,cycle,percent,time,start_frame,start_time,end_frame,end_time,SACR_x (mm),"
        ));
        let first = csv.lines().nth(1).unwrap();
        assert!(
            first.starts_with("Left,1,0,0.100000,11,0.100000,51,0.500000,"),
            "{first}"
        );
        let x: f64 = first.split(',').nth(8).unwrap().parse().unwrap();
        assert!((x - 100.0).abs() < 1e-3, "{first}");
    }
}
