//! What a plot shows, gathered from the files into plain arrays: nothing here draws.

use crate::{Error, Result};
use bvh::error_metric::{Effectors, Evaluator};
use bvh::interp::{Interp, Interpolator};
use bvh::keyframes::greedy;
use c3d::C3d;

/// Columns of panels one picture holds before they get too narrow to read.
pub(super) const MAX_MARKERS: usize = 6;

/// One marker's samples over the trial.
#[derive(Debug, Clone)]
pub struct Track {
    pub xyz: Vec<[f32; 3]>,
    pub valid: Vec<bool>,
}

impl Track {
    fn of(c: &C3d, point: usize) -> Track {
        let p = c.points();
        Track {
            xyz: p.trajectory(point),
            valid: p.validity(point),
        }
    }
}

/// What one marker's panels show.
#[derive(Debug, Clone)]
pub struct MarkerPlot {
    pub label: String,
    /// FILE: the repaired data, or the only data without `--against`.
    pub shown: Track,
    pub original: Option<Track>,
    /// Frames drawn shaded: gaps of the original (of FILE without one).
    pub gaps: Vec<bool>,
    /// Frames filled in FILE: residual 0 where the original was invalid (anywhere without one).
    pub filled: Vec<usize>,
    /// Frames whose original sample the spike stage removed or replaced (see
    /// [`stage_of_changes`]).
    pub spikes: Vec<usize>,
    /// Frames whose original sample a low-pass filter moved.
    pub filtered: Vec<usize>,
}

/// One analog channel in physical units.
#[derive(Debug, Clone)]
pub struct AnalogPlot {
    pub label: String,
    pub units: String,
    pub rate: f64,
    /// Where sample 0 sits on the x axis: its time on the file's base (`C3d::analog_time`).
    pub start: f64,
    pub values: Vec<f32>,
}

/// Everything a plot shows, gathered from the files.
#[derive(Debug, Clone)]
pub struct Plot {
    pub title: String,
    pub units: String,
    /// Frames per second; frame `i` is drawn at `start + i / rate` (at frame numbers when
    /// the rate is unknown).
    pub rate: f64,
    /// Where frame 0 sits on the x axis: its time on the file's one time base
    /// (`C3d::frame_time`), or its frame number without a rate, so a plot's axis reads as the
    /// file's events and the other outputs do.
    pub start: f64,
    pub markers: Vec<MarkerPlot>,
    pub analog: Option<AnalogPlot>,
    /// Events drawn as labelled vertical lines: the file's own (and detected ones when
    /// asked for), at their times on the file's base; none when the axis is in frames.
    pub events: Vec<crate::marks::Mark>,
}

/// The index of marker `name` in `c`, or an error listing the markers there are.
pub fn marker_index(c: &C3d, name: &str, file: &str) -> Result<usize> {
    if c.points().count() == 0 {
        return Err(Error::NoPoints { file: file.into() });
    }
    c.point_index(name).ok_or_else(|| Error::NoMarker {
        file: file.into(),
        name: name.into(),
        available: c.point_labels(),
    })
}

fn analog_index(c: &C3d, name: &str, file: &str) -> Result<usize> {
    let labels = c.analog_labels();
    if labels.is_empty() {
        return Err(Error::NoAnalog { file: file.into() });
    }
    let bare = |s: &str| s.trim().to_ascii_uppercase();
    labels
        .iter()
        .position(|l| l == name)
        .or_else(|| labels.iter().position(|l| bare(l) == bare(name)))
        .or_else(|| {
            // A 1-based channel number, for files whose labels are unhelpful.
            name.parse::<usize>()
                .ok()
                .filter(|n| (1..=labels.len()).contains(n))
                .map(|n| n - 1)
        })
        .ok_or_else(|| Error::NoAnalogChannel {
            file: file.into(),
            name: name.into(),
            available: labels.clone(),
        })
}

/// Which repair stage moved a sample that was valid in the original.
enum Stage {
    Spike,
    Filter,
}

/// The stage that moved a valid sample, read from what the repaired file records of its
/// repair (`C3DFIX`: the stretches c3dfix filled, the spike and filter settings), never
/// guessed from the size of the change. Only two stages move a valid sample: spike removal
/// (which refills it, a stretch in FILLED, or with `--spike-mode median` sets it to the
/// window's median) and the low-pass filter (which moves every sample a little). With a
/// filter and no spike removal it is the filter; with spike removal and no filter, the spike
/// stage; with both, a refilled sample is a spike and any other change the filter's. A file
/// without the record (repaired by another program, or by hand) cannot say: a replaced
/// sample is shown as a spike there, as it always was.
fn stage_of_changes(record: &c3dfix::RepairRecord, refilled: bool) -> Stage {
    match (&record.spikes, &record.filter) {
        (None, None) => Stage::Spike,
        (Some(_), None) => Stage::Spike,
        (Some(_), Some(_)) if refilled => Stage::Spike,
        _ => Stage::Filter,
    }
}

/// Per frame of point `point`, whether the record lists it among c3dfix's fills.
fn refilled_frames(record: &c3dfix::RepairRecord, point: usize, frames: usize) -> Vec<bool> {
    let mut out = vec![false; frames];
    for &(p, a, b) in &record.filled {
        if p == point {
            for v in out.iter_mut().take(b.saturating_add(1).min(frames)).skip(a) {
                *v = true;
            }
        }
    }
    out
}

/// True when two samples differ by more than storage round-off.
fn changed(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter()
        .zip(&b)
        .any(|(x, y)| (x - y).abs() > 1e-5 * (1.0 + x.abs().max(y.abs())))
}

impl Plot {
    /// Gather the samples to draw. `file`/`original` come with the names used in titles and
    /// errors; every requested marker must exist in both files.
    pub fn gather(
        file: (&C3d, &str),
        original: Option<(&C3d, &str)>,
        markers: &[String],
        analog: Option<&str>,
    ) -> Result<Plot> {
        let (c, name) = file;
        if markers.is_empty() {
            return Err(Error::NoMarkerGiven);
        }
        if markers.len() > MAX_MARKERS {
            return Err(Error::TooManyMarkers {
                given: markers.len(),
                most: MAX_MARKERS,
            });
        }
        let record = c3dfix::RepairRecord::read(c);
        let mut out = Vec::new();
        for m in markers {
            let i = marker_index(c, m, name)?;
            let label = c.point_labels()[i].clone();
            let shown = Track::of(c, i);
            // Computed rather than measured: valid with residual 0.
            let computed: Vec<bool> = c
                .points()
                .residuals(i)
                .iter()
                .zip(&shown.valid)
                .map(|(&r, &v)| v && r == 0.0)
                .collect();
            let (orig, gaps, filled, spikes, filtered) = match original {
                Some((o, oname)) => {
                    let j = marker_index(o, m, oname)?;
                    let orig = Track::of(o, j);
                    let refilled = refilled_frames(&record, i, computed.len());
                    let mut filled = Vec::new();
                    let mut spikes = Vec::new();
                    let mut filtered = Vec::new();
                    for (f, &computed) in computed.iter().enumerate().take(orig.valid.len()) {
                        if !orig.valid[f] {
                            if computed {
                                filled.push(f);
                            }
                        } else if !shown.valid[f] {
                            spikes.push(f);
                        } else if computed && changed(shown.xyz[f], orig.xyz[f]) {
                            match stage_of_changes(&record, refilled[f]) {
                                Stage::Spike => spikes.push(f),
                                Stage::Filter => filtered.push(f),
                            }
                        }
                    }
                    let gaps = orig.valid.iter().map(|v| !v).collect();
                    (Some(orig), gaps, filled, spikes, filtered)
                }
                None => {
                    let filled = (0..computed.len()).filter(|&f| computed[f]).collect();
                    let gaps = shown.valid.iter().map(|v| !v).collect();
                    (None, gaps, filled, Vec::new(), Vec::new())
                }
            };
            out.push(MarkerPlot {
                label,
                shown,
                original: orig,
                gaps,
                filled,
                spikes,
                filtered,
            });
        }
        let analog = match analog {
            Some(ch) => {
                let k = analog_index(c, ch, name)?;
                let a = c.analog();
                let phys = c.analog_physical();
                let values = phys
                    .iter()
                    .skip(k)
                    .step_by(a.channels().max(1))
                    .copied()
                    .collect();
                Some(AnalogPlot {
                    label: c.analog_labels()[k].clone(),
                    units: c.analog_units()[k].clone(),
                    rate: c.analog_rate() as f64,
                    start: c.analog_time(0),
                    values,
                })
            }
            None => None,
        };
        let labels: Vec<&str> = out.iter().map(|m| m.label.as_str()).collect();
        let title = match original {
            Some((_, oname)) => format!("{name} vs {oname} — {}", labels.join(", ")),
            None => format!("{name} — {}", labels.join(", ")),
        };
        Ok(Plot {
            title,
            units: c.point_units(),
            rate: c.point_rate() as f64,
            start: if c.point_rate() > 0.0 {
                c.frame_time(0)
            } else {
                c.frame_number(0) as f64
            },
            markers: out,
            analog,
            events: if c.point_rate() > 0.0 {
                crate::marks::from_file(c)
            } else {
                Vec::new()
            },
        })
    }
}

/// The greedy accumulated-error curves of a BVH motion, for Euler and quaternion
/// interpolation: (removed frames, total error) per step.
#[derive(Debug, Clone)]
pub struct KeyframeCurves {
    /// The BVH file's name, for the title.
    pub name: String,
    pub frames: usize,
    pub curves: Vec<(Interp, Vec<(usize, f64)>)>,
}

impl KeyframeCurves {
    /// Run greedy reduction to the end with each interpolation; `done` is a run already made
    /// with one of them (same effectors), which is reused rather than run again.
    pub fn gather(
        b: &bvh::Bvh,
        effectors: Effectors,
        name: String,
        done: Option<(Interp, &greedy::GreedyRun)>,
    ) -> KeyframeCurves {
        let curves = [Interp::Euler, Interp::Quat]
            .into_iter()
            .map(|m| match done {
                Some((dm, run)) if dm == m => (m, run.curve()),
                _ => {
                    let eval = Evaluator::new(Interpolator::new(b, m), effectors);
                    (m, greedy::run(&eval).curve())
                }
            })
            .collect();
        KeyframeCurves {
            name,
            frames: b.motion.frames(),
            curves,
        }
    }
}
