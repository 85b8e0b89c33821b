//! Repairing a whole trial: markers chosen, label swaps undone in the file (see
//! [`crate::swap_stage`]), trajectories repaired (spikes → fill → filter), samples written
//! back with their flags, and a report of every swap, gap, spike and segment.

use crate::error::{Error, Result};
use crate::markers::{mm_per_unit, select, split_unlabelled};
use crate::options::RepairOptions;
use crate::reclaim_stage::{self, Reclaim, ReclaimAction, ReclaimBrief, UnsettledBrief};
use crate::rerun;
use crate::swap_stage::{self, SwapAction, SwapBrief};
use crate::tally::Tally;
use crate::trial::{to_trial_and, write_back, Others};
use repair::{FillMethod, FillOutcome, SkipKind};
use serde::Serialize;
use std::path::Path;

/// What one repair did, in counts: the report's `summary`. The lists behind the counts stand
/// beside it: in the report (`gaps`, `swaps`, `reclaim`) and in a [`RepairBrief`].
#[derive(Debug, Clone, Serialize, Default, PartialEq)]
pub struct Summary {
    pub file: String,
    pub output: String,
    /// Labelled markers: the ones repaired, and the only ones `gaps`, `filled`, the swaps and
    /// every other count below speak of.
    pub markers: usize,
    pub model_outputs_left: usize,
    /// Points a capture system left unlabelled (`*51`, `Unlabeled 3`, an empty label, or the
    /// user's pattern), counted apart and left as recorded; absent when there are none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unlabelled: Option<UnlabelledBrief>,
    pub gaps: usize,
    pub filled: usize,
    /// Gaps filled per method (for `auto`, the method it chose).
    pub filled_by: Tally<FillMethod>,
    pub left: usize,
    /// Gaps left per reason (`too_long`, `no_donors`, …).
    pub left_because: Tally<SkipKind>,
    pub spikes: usize,
    pub segments_filtered: usize,
    pub segments_too_short: usize,
    pub samples_changed: usize,
    /// Repaired samples clamped to the integer range of POINT:SCALE (integer files only).
    pub samples_clamped: usize,
    pub markers_changed: usize,
    /// Samples of the repaired markers kept as recorded although they sit at exactly
    /// (0, 0, 0) (0 under `zero_invalid`, which makes them gaps): some writers store a lost
    /// sample that way with a valid fourth word (ART-Human's lost frames), and only the user
    /// can say so; a filter or a fill next to such a sample takes it for data.
    pub samples_at_origin: usize,
    /// Largest and mean expected error of the filled gaps, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm_max: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm_mean: Option<f64>,
    /// Label swaps exchanged back and label jumps made gaps by the first stage
    /// (`--swaps fix`).
    #[serde(skip_serializing_if = "is_zero")]
    pub swaps_undone: usize,
    #[serde(skip_serializing_if = "is_zero")]
    pub jumps_to_gaps: usize,
    /// Recorded samples moved from unlabelled points into their markers (`--reclaim on`).
    #[serde(skip_serializing_if = "is_zero")]
    pub reclaimed: usize,
    /// Why the swap stage checked nothing (too little to judge), if so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub swaps_note: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backup: Option<String>,
    /// Steps asked for and not taken because the file records them as done by an earlier
    /// repair (`filter …`, `spikes …`): never applied twice (docs/reruns.md).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub already_applied: Vec<String>,
    /// In place, the repair changed no byte and the file was not rewritten.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub unchanged: bool,
    /// Why the file was left as it was (batch only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

/// One repair in brief, as `c3dfix repair --json` prints it and `batch` emits per file: the
/// summary's counts, then every gap, swap and reclaimed piece behind them, each in a line a
/// person can act on (frames in the file's numbering).
#[derive(Debug, Clone, Serialize, Default, PartialEq)]
pub struct RepairBrief {
    #[serde(flatten)]
    pub summary: Summary,
    /// Every gap: where, what became of it, and its expected error in mm.
    pub gap_list: Vec<GapBrief>,
    /// Every label swap and jump found (`--swaps fix` or `report`), with its evidence and
    /// what was done with it.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub swap_list: Vec<SwapBrief>,
    /// Every settled piece of unlabelled samples found in a marker's gap (`--reclaim on` or
    /// `report`), with its fit and what was done with it.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reclaim_list: Vec<ReclaimBrief>,
    /// Pieces that fit a marker's gap and are not settled (a rival fits as well, or too
    /// few segment distances to tell): reported, never moved.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reclaim_unsettled: Vec<UnsettledBrief>,
}

impl RepairBrief {
    /// A trial left as it was, with the summary that says why.
    pub fn of_summary(summary: Summary) -> RepairBrief {
        RepairBrief {
            summary,
            ..RepairBrief::default()
        }
    }
}

/// A trial's unlabelled points in a summary.
#[derive(Debug, Clone, Serialize, Default, PartialEq)]
pub struct UnlabelledBrief {
    /// How many points are unlabelled.
    pub points: usize,
    /// The samples they hold after the repair, over all frames (samples reclaimed into a
    /// marker leave them).
    pub samples: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// One gap in a summary.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct GapBrief {
    pub label: String,
    /// First and last missing frame, numbered as the file numbers them
    /// ([`c3d::C3d::frame_number`]: from the header's first frame), as [`crate::GapInfo`]'s
    /// fields of the same names; the report keeps its keys `first` and `last`.
    #[serde(rename = "first")]
    pub first_frame: usize,
    #[serde(rename = "last")]
    pub last_frame: usize,
    /// Their times in seconds ([`c3d::C3d::frame_time`]: frame n at (n − 1) / rate).
    pub first_time: f64,
    pub last_time: f64,
    /// The gap starts at the trial's first frame or ends at its last: the trial's ends, where
    /// only donors can fill, apart from the gaps inside the trial.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub at_trial_end: bool,
    /// The method that filled it (`auto`: the one it chose), or why it was left.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub method: Option<FillMethod>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<SkipKind>,
    /// Expected mean 3D error of the fill, mm (for `uncertain` gaps: of the fill withheld).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm: Option<f64>,
}

/// The outcome of [`repair()`]: the summary and the details behind it.
#[derive(Debug, Clone)]
pub struct Repaired {
    pub summary: Summary,
    /// Every gap of the markers in scope in brief (with its times), as [`RepairBrief`]
    /// lists it.
    pub gap_list: Vec<GapBrief>,
    /// The configuration the trial was repaired with, in the file's units.
    pub config: repair::RepairConfig,
    /// Every label swap and jump found, with what was done with it.
    pub swaps: Vec<SwapBrief>,
    /// What the reclaim stage found and moved.
    pub reclaim: Reclaim,
    /// Every gap of the markers in scope, with its outcome.
    pub gaps: Vec<GapRow>,
    /// Every spike of the markers in scope.
    pub spikes: Vec<SpikeRow>,
    /// What became of the spikes (`gap` or `median`), when spikes were looked for.
    pub spike_mode: Option<repair::SpikeMode>,
    /// Every continuous segment at the filter step, filtered or too short.
    pub segments: Vec<SegmentRow>,
    /// The samples changed per marker in scope.
    pub markers: Vec<MarkerChange>,
}

/// One gap of the full report: repair's record of it with its marker's label, frames in
/// the file's numbering.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct GapRow {
    pub label: String,
    /// The marker's row among the repaired markers.
    pub marker: usize,
    /// First and last missing frame, in the file's numbering.
    pub first: usize,
    pub last: usize,
    pub len: usize,
    pub at_start: bool,
    pub at_end: bool,
    pub outcome: FillOutcome,
    /// Expected mean 3D error of the fill, mm (for `uncertain` gaps: of the fill withheld).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm: Option<f64>,
}

/// One spike of the full report, its frame in the file's numbering.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SpikeRow {
    pub label: String,
    pub marker: usize,
    pub frame: usize,
    /// Which coordinates (x, y, z) were outliers.
    pub axes: [bool; 3],
    /// What the `median` mode writes (see [`repair::spikes::Spike`]).
    pub median: [f64; 3],
}

/// One continuous valid segment at the filter step, frames in the file's numbering.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SegmentRow {
    pub label: String,
    pub marker: usize,
    pub first: usize,
    pub last: usize,
    pub len: usize,
    pub filtered: bool,
    /// Set when skipped: the filter needs more than `padlen` samples.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub padlen: Option<usize>,
}

/// How many samples of one marker the repair changed.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MarkerChange {
    pub label: String,
    pub samples_changed: usize,
}

impl Repaired {
    /// The repair in brief: the summary and the lists behind it.
    pub fn brief(&self) -> RepairBrief {
        RepairBrief {
            summary: self.summary.clone(),
            gap_list: self.gap_list.clone(),
            swap_list: self.swaps.clone(),
            reclaim_list: self.reclaim.settled.clone(),
            reclaim_unsettled: self.reclaim.unsettled.clone(),
        }
    }

    /// The full report, as `c3dfix repair --report` writes it: the configuration, the
    /// summary, every label swap and jump found (with its evidence and what was done), every
    /// gap (with its outcome), spike and filtered segment, and the samples
    /// changed per marker. Gaps and segments name their marker by label and by its row in
    /// `markers`; frames are the file's own frame numbers ([`c3d::C3d::frame_number`]).
    /// Every object's keys are in alphabetical order, as a JSON value keeps them.
    pub fn report(&self) -> serde_json::Value {
        serde_json::json!({
            "file": self.summary.file,
            "output": self.summary.output,
            "config": value(&self.config),
            "summary": value(&self.summary),
            "swaps": value(&self.swaps),
            "reclaim": value(&self.reclaim),
            "gaps": value(&self.gaps),
            "spikes": value(&self.spikes),
            "spike_mode": value(&self.spike_mode),
            "segments": value(&self.segments),
            "markers": value(&self.markers),
        })
    }
}

/// `x` as a JSON value (whose objects keep their keys in alphabetical order).
fn value<T: Serialize>(x: &T) -> serde_json::Value {
    serde_json::to_value(x).unwrap_or_default()
}

/// Repair the markers of `c` in place as `opts` says. `name` is the trial's file, for
/// messages and the summary. Model outputs are never repaired nor used as donors; samples
/// outside the chosen markers keep their bits; the parameters and analog data are untouched.
pub fn repair(c: &mut c3d::C3d, opts: &RepairOptions, name: &Path) -> Result<Repaired> {
    let cfg = opts.config()?;
    repair_configured(c, opts, cfg, name)
}

/// [`repair`] with the options already checked into `cfg` (in millimetres), for callers that
/// check them once before touching any file.
pub(crate) fn repair_configured(
    c: &mut c3d::C3d,
    opts: &RepairOptions,
    cfg: repair::RepairConfig,
    name: &Path,
) -> Result<Repaired> {
    let (only, split) = markers_of(c, opts, name)?;
    let cfg = in_file_units(c, cfg);
    let points = split.labelled.clone();
    // What an earlier repair of this file did: done steps are not done again, its fills are
    // no data, the gaps it left under these settings stay left (see crate::rerun).
    let record = rerun::Record::read(c);
    let fill_settings = rerun::fill_settings(opts);
    let mut already_applied = Vec::new();
    let reclaim_settings = rerun::reclaim_settings(opts);
    let reclaim_done = record.reclaim.is_some() && reclaim_settings.is_some();
    // The unlabelled points are read with the markers, in one pass over the data: their
    // validity for the summary, their coordinates too when the reclaim stage will judge them.
    let judged = !reclaim_done && opts.reclaim != crate::options::ReclaimMode::Off;
    let (mut trial, mut unlabelled) =
        to_trial_and(c, &points, &split.unlabelled, judged, opts.zero_invalid)?;
    // 0. Label swaps, in the file and the trial, before any other stage reads them.
    let swap_settings = rerun::swap_settings(opts);
    let point_in_scope = |p: usize| only.as_ref().is_none_or(|o| o.contains(&p));
    let stage = match (&record.swaps, &swap_settings) {
        (Some(done), Some(_)) => {
            already_applied.push(format!("swaps ({done})"));
            swap_stage::Stage::default()
        }
        _ => swap_stage::run(c, name, opts.swaps, &point_in_scope, &points, &mut trial)?,
    };
    // 1. Unlabelled samples that are a marker's, moved back before any fill reads the gaps;
    // never twice (a second run would judge against the first run's moves).
    let stage_points = reclaim_stage::Points {
        labelled: &points,
        unlabelled: &split.unlabelled,
        data: &[],
        zero_invalid: opts.zero_invalid,
        links: stage.links.as_ref(),
    };
    let reclaim = match (&record.reclaim, &reclaim_settings) {
        (Some(done), Some(_)) => {
            already_applied.push(format!("reclaim ({done})"));
            Reclaim::default()
        }
        _ => reclaim_now(
            c,
            name,
            opts,
            &stage_points,
            (&mut trial, &mut unlabelled),
            &point_in_scope,
        )?,
    };
    let cfg = without_done_steps(cfg, &record, name, &mut already_applied)?;
    let row_of: std::collections::HashMap<usize, usize> =
        points.iter().enumerate().map(|(r, &p)| (p, r)).collect();
    let jumped = jumps_made_gaps(&stage, &row_of, &mut trial, c.frames());
    let earlier = earlier_of(&record, &row_of, c.frames(), points.len(), &fill_settings);
    // In the process's own pool, so that a forked process repairs too (see forkpool).
    let mut report = forkpool::install(|| repair::repair_trial_after(&mut trial, &cfg, &earlier))
        .map_err(|source| Error::Repair {
        path: name.to_path_buf(),
        source,
    })?;
    for &(r, f) in &jumped {
        if report.changes[r][f] == 0 {
            report.changed_per_marker[r] += 1;
        }
        report.changes[r][f] |= repair::change::INVALIDATED;
    }
    let labels = c.point_labels();
    let row_label = |row: usize| labels[points[row]].clone();
    let in_scope = |row: usize| only.as_ref().is_none_or(|o| o.contains(&points[row]));

    let mut s = Summary {
        file: name.display().to_string(),
        already_applied,
        markers: points.len(),
        model_outputs_left: c.point_count() - points.len() - split.unlabelled.len(),
        unlabelled: unlabelled_brief(&unlabelled),
        samples_at_origin: at_origin(&trial, &in_scope),
        swaps_undone: count_action(&stage.briefs, SwapAction::Undone),
        jumps_to_gaps: count_action(&stage.briefs, SwapAction::Gap),
        swaps_note: stage.note.clone(),
        reclaimed: reclaim.samples_moved,
        ..Summary::default()
    };
    let (gaps, gap_list) = gap_summary(c, &report, &in_scope, &row_label, &mut s);
    let rows = Rows {
        points: &points,
        row_of: &row_of,
        in_scope: &in_scope,
    };
    let (spikes, segments) = spike_and_segment_rows(c, &report, &in_scope, &row_label, &mut s);
    let next = next_record(
        &record,
        Settings {
            fill: fill_settings,
            swaps: swap_settings,
            reclaim: reclaim_settings,
        },
        &stage,
        &reclaim,
        &report,
        &rows,
        &cfg,
        opts,
    );
    let c3d_error = |source| Error::C3d {
        path: name.to_path_buf(),
        source,
    };
    next.write(c).map_err(c3d_error)?;
    let wb = write_back(c, &trial, &points, &report.changes, only.as_deref()).map_err(c3d_error)?;
    s.samples_changed = wb.changed + stage.exchanged + reclaim.samples_moved;
    s.samples_clamped = wb.clamped;
    let (markers_changed, markers) = marker_changes(&rows, &report, &stage, &reclaim, &row_label);
    s.markers_changed = markers_changed;
    Ok(Repaired {
        swaps: stage.briefs,
        reclaim,
        summary: s,
        config: cfg,
        gaps,
        gap_list,
        spikes,
        spike_mode: report.spike_mode,
        segments,
        markers,
    })
}

/// Every gap of the markers in scope, into the summary's counts, as the report's gap rows
/// and in brief (each with its expected error in millimetres).
fn gap_summary(
    c: &c3d::C3d,
    report: &repair::RepairReport,
    in_scope: &dyn Fn(usize) -> bool,
    row_label: &dyn Fn(usize) -> String,
    s: &mut Summary,
) -> (Vec<GapRow>, Vec<GapBrief>) {
    let mut gaps = Vec::new();
    let mut list = Vec::new();
    let mm = mm_per_unit(&c.point_units());
    let mut expected = Vec::new();
    for g in report.gaps.iter().filter(|g| in_scope(g.gap.marker)) {
        s.gaps += 1;
        let mut brief = GapBrief {
            label: row_label(g.gap.marker),
            first_frame: c.frame_number(g.gap.first),
            last_frame: c.frame_number(g.gap.last),
            first_time: c.frame_time(g.gap.first),
            last_time: c.frame_time(g.gap.last),
            at_trial_end: g.gap.touches_edge(),
            method: None,
            reason: None,
            expected_error_mm: None,
        };
        match g.outcome {
            FillOutcome::Filled {
                method,
                expected_error,
                ..
            } => {
                s.filled += 1;
                s.filled_by.add(method, 1);
                brief.method = Some(method);
                brief.expected_error_mm = expected_error.map(|e| e * mm);
                expected.extend(brief.expected_error_mm);
            }
            FillOutcome::Skipped(reason) => {
                s.left += 1;
                s.left_because.add(reason.kind(), 1);
                brief.reason = Some(reason.kind());
                if let repair::SkipReason::Uncertain { expected_error, .. } = reason {
                    brief.expected_error_mm = Some(expected_error * mm);
                }
            }
        }
        gaps.push(GapRow {
            label: brief.label.clone(),
            marker: g.gap.marker,
            first: brief.first_frame,
            last: brief.last_frame,
            len: g.gap.len,
            at_start: g.gap.at_start,
            at_end: g.gap.at_end,
            outcome: g.outcome,
            expected_error_mm: brief.expected_error_mm,
        });
        list.push(brief);
    }
    if !expected.is_empty() {
        s.expected_error_mm_max = Some(expected.iter().copied().fold(0.0, f64::max));
        s.expected_error_mm_mean = Some(expected.iter().sum::<f64>() / expected.len() as f64);
    }
    (gaps, list)
}

/// This run's settings as the file's record writes them.
struct Settings {
    fill: String,
    swaps: Option<String>,
    reclaim: Option<String>,
}

/// The markers a repair works on: their points, each point's row, and which rows are in
/// this run's scope.
struct Rows<'a> {
    points: &'a [usize],
    row_of: &'a std::collections::HashMap<usize, usize>,
    in_scope: &'a dyn Fn(usize) -> bool,
}

/// The record this run leaves in the file (see [`crate::rerun`]).
#[allow(clippy::too_many_arguments)]
fn next_record(
    record: &rerun::Record,
    settings: Settings,
    stage: &swap_stage::Stage,
    reclaim: &Reclaim,
    report: &repair::RepairReport,
    rows: &Rows,
    cfg: &repair::RepairConfig,
    opts: &RepairOptions,
) -> rerun::Record {
    // The record this run leaves: every fill so far; the gaps left now (and those of
    // markers outside this run's --markers, as they were); the steps applied.
    let (points, row_of, in_scope) = (rows.points, rows.row_of, rows.in_scope);
    let in_scope_point = |p: usize| row_of.get(&p).is_some_and(|&r| in_scope(r));
    let mut next = rerun::Record {
        filled: record.filled.clone(),
        left: record
            .left
            .iter()
            .filter(|l| !in_scope_point(l.point))
            .copied()
            .collect(),
        fill: Some(settings.fill),
        filter: record.filter.clone(),
        spikes: record.spikes.clone(),
        swaps: record.swaps.clone().or(settings.swaps),
        undone: record.undone.iter().chain(&stage.undone).cloned().collect(),
        // Recorded only when something moved: a stage that moved nothing leaves the file as
        // it was, and judges the same again.
        reclaim: record
            .reclaim
            .clone()
            .or(settings.reclaim.filter(|_| !reclaim.moved.is_empty())),
        reclaimed: record
            .reclaimed
            .iter()
            .chain(&reclaim.moved)
            .copied()
            .collect(),
    };
    next.reclaimed.sort();
    next.reclaimed.dedup();
    next.undone.sort();
    next.undone.dedup();
    for g in report.gaps.iter().filter(|g| in_scope(g.gap.marker)) {
        let (p, a, b) = (points[g.gap.marker], g.gap.first, g.gap.last);
        match g.outcome {
            FillOutcome::Filled { .. } => next.filled.push((p, a, b)),
            FillOutcome::Skipped(reason) => next.left.push(rerun::Left {
                point: p,
                first_index: a,
                last_index: b,
                reason,
            }),
        }
    }
    next.filled.sort_unstable();
    next.filled.dedup();
    next.left
        .sort_by_key(|l| (l.point, l.first_index, l.last_index));
    if cfg.filter().is_some() {
        next.filter = opts.lowpass.map(|f| f.to_string());
    }
    if cfg.spikes().is_some() {
        next.spikes = rerun::spike_settings(opts);
    }
    next
}

/// The spikes and filtered segments of the markers in scope, counted into the summary and as
/// the report's rows.
fn spike_and_segment_rows(
    c: &c3d::C3d,
    report: &repair::RepairReport,
    in_scope: &dyn Fn(usize) -> bool,
    row_label: &dyn Fn(usize) -> String,
    s: &mut Summary,
) -> (Vec<SpikeRow>, Vec<SegmentRow>) {
    let spikes: Vec<SpikeRow> = report
        .spikes
        .iter()
        .filter(|sp| in_scope(sp.marker))
        .map(|sp| SpikeRow {
            label: row_label(sp.marker),
            marker: sp.marker,
            frame: c.frame_number(sp.frame),
            axes: sp.axes,
            median: sp.median,
        })
        .collect();
    s.spikes = spikes.len();
    let segments: Vec<SegmentRow> = report
        .segments
        .iter()
        .filter(|x| in_scope(x.marker))
        .map(|x| {
            if x.filtered {
                s.segments_filtered += 1;
            } else {
                s.segments_too_short += 1;
            }
            SegmentRow {
                label: row_label(x.marker),
                marker: x.marker,
                first: c.frame_number(x.first),
                last: c.frame_number(x.last),
                len: x.len,
                filtered: x.filtered,
                padlen: x.padlen,
            }
        })
        .collect();
    (spikes, segments)
}

/// How many markers in scope this repair changed (by fills, spikes, filters, swaps undone or
/// samples reclaimed), and per marker how many samples, as the report lists them.
fn marker_changes(
    rows: &Rows,
    report: &repair::RepairReport,
    stage: &swap_stage::Stage,
    reclaim: &Reclaim,
    row_label: &dyn Fn(usize) -> String,
) -> (usize, Vec<MarkerChange>) {
    let (points, in_scope) = (rows.points, rows.in_scope);
    let exchanged: Vec<usize> = stage
        .briefs
        .iter()
        .filter(|b| b.action == SwapAction::Undone)
        .flat_map(|b| b.find.points.iter().copied())
        .collect();
    let moved_into = |p: usize| reclaim.moved.iter().any(|m| m.point == p);
    let markers_changed = (0..points.len())
        .filter(|&r| {
            in_scope(r)
                && (report.changes[r].iter().any(|&x| x != 0)
                    || exchanged.contains(&points[r])
                    || moved_into(points[r]))
        })
        .count();
    let markers: Vec<MarkerChange> = (0..points.len())
        .filter(|&r| in_scope(r))
        .map(|r| {
            let swapped = stage
                .briefs
                .iter()
                .filter(|b| b.action == SwapAction::Undone && b.find.points.contains(&points[r]))
                .map(|b| b.find.last_index - b.find.first_index + 1)
                .sum::<usize>();
            let reclaimed = reclaim
                .settled
                .iter()
                .filter(|b| b.action == ReclaimAction::Moved && b.point == points[r])
                .map(|b| b.samples)
                .sum::<usize>();
            MarkerChange {
                label: row_label(r),
                samples_changed: report.changed_per_marker[r] + swapped + reclaimed,
            }
        })
        .collect();
    (markers_changed, markers)
}

/// The reclaim stage run on this trial: the labelled markers' own data judged, the
/// unlabelled points' samples moved where settled (see [`crate::reclaim_stage`]).
fn reclaim_now(
    c: &mut c3d::C3d,
    name: &Path,
    opts: &RepairOptions,
    points: &reclaim_stage::Points,
    (trial, unlabelled): (&mut repair::Trial, &mut Others),
    point_in_scope: &dyn Fn(usize) -> bool,
) -> Result<Reclaim> {
    let data = reclaim_stage::own_data(c, points.labelled, trial);
    let labelled = reclaim_stage::Points {
        data: &data,
        ..*points
    };
    reclaim_stage::run(
        c,
        name,
        opts.reclaim,
        &labelled,
        trial,
        unlabelled,
        point_in_scope,
    )
}

/// The points a repair works on: those `opts` names (`None`: every marker) and the trial's
/// markers split into labelled and unlabelled; refused for a file without points and for an
/// unlabelled point named as a marker.
fn markers_of(
    c: &c3d::C3d,
    opts: &RepairOptions,
    name: &Path,
) -> Result<(Option<Vec<usize>>, crate::markers::Split)> {
    if c.point_count() == 0 {
        return Err(Error::Trial {
            path: name.to_path_buf(),
            what: "the file has no points to repair".into(),
        });
    }
    let only = opts.markers.as_ref().map(|m| select(c, m)).transpose()?;
    let split = split_unlabelled(c, &opts.unlabelled_rule());
    if let Some(p) = only.iter().flatten().find(|p| split.unlabelled.contains(p)) {
        return Err(Error::options(format!(
            "{:?} is an unlabelled point, not a marker: a repair leaves it as recorded",
            c.point_labels()[*p].trim()
        )));
    }
    Ok((only, split))
}

/// Valid samples at exactly (0, 0, 0) among the rows in scope: a writer's stand-in for
/// missing points, which only `zero_invalid` reads as such.
fn at_origin(trial: &repair::Trial, in_scope: &dyn Fn(usize) -> bool) -> usize {
    (0..trial.xyz.len())
        .filter(|&r| in_scope(r))
        .map(|r| {
            trial.xyz[r]
                .iter()
                .zip(&trial.valid[r])
                .filter(|(p, &v)| v && **p == [0.0; 3])
                .count()
        })
        .sum()
}

/// `cfg` in the file's length unit, its fills held to the step rule as this file will store
/// them.
fn in_file_units(c: &c3d::C3d, cfg: repair::RepairConfig) -> repair::RepairConfig {
    let storage = match c.format() {
        c3d::NumberFormat::Integer => repair::Storage::Integer {
            scale: c.layout().point_scale,
        },
        c3d::NumberFormat::Float => repair::Storage::Float32,
    };
    cfg.in_units(mm_per_unit(&c.point_units()))
        .with_storage(storage)
}

/// `cfg` without the spikes and filter an earlier repair of this file applied (each named in
/// `already_applied`): a step is never done twice.
fn without_done_steps(
    cfg: repair::RepairConfig,
    record: &rerun::Record,
    name: &Path,
    already_applied: &mut Vec<String>,
) -> Result<repair::RepairConfig> {
    let mut spikes = cfg.spikes().copied();
    let mut filter = cfg.filter().copied();
    if let (Some(done), Some(_)) = (&record.spikes, spikes) {
        already_applied.push(format!("spikes ({done})"));
        spikes = None;
    }
    if let (Some(done), Some(_)) = (&record.filter, filter) {
        already_applied.push(format!("filter ({done})"));
        filter = None;
    }
    if already_applied.is_empty() {
        return Ok(cfg);
    }
    repair::RepairConfig::new(spikes, cfg.fill().clone(), filter).map_err(|source| Error::Repair {
        path: name.to_path_buf(),
        source,
    })
}

/// A settled jump's samples made a gap for the fill stage (unfilled, they are written
/// missing): the (row, frame) of each sample made invalid.
fn jumps_made_gaps(
    stage: &swap_stage::Stage,
    row_of: &std::collections::HashMap<usize, usize>,
    trial: &mut repair::Trial,
    frames: usize,
) -> Vec<(usize, usize)> {
    let mut jumped = Vec::new();
    for &(p, a, b) in &stage.gaps {
        if let Some(&r) = row_of.get(&p) {
            for f in a..=b.min(frames.saturating_sub(1)) {
                if trial.valid[r][f] {
                    trial.valid[r][f] = false;
                    jumped.push((r, f));
                }
            }
        }
    }
    jumped
}

/// What an earlier repair recorded, as the fill stage reads it: its fills are no data, and
/// the gaps it left under the same fill settings stay left.
fn earlier_of(
    record: &rerun::Record,
    row_of: &std::collections::HashMap<usize, usize>,
    frames: usize,
    rows: usize,
    fill_settings: &str,
) -> repair::Earlier {
    let mut earlier = repair::Earlier::default();
    if !record.filled.is_empty() {
        earlier.filled = vec![vec![false; frames]; rows];
        for &(p, a, b) in &record.filled {
            if let Some(&r) = row_of.get(&p) {
                earlier.filled[r][a..=b].fill(true);
            }
        }
    }
    if record.fill.as_deref() == Some(fill_settings) {
        earlier.left = record
            .left
            .iter()
            .filter_map(|l| {
                Some((
                    *row_of.get(&l.point)?,
                    l.first_index,
                    l.last_index,
                    l.reason,
                ))
            })
            .collect();
    }
    earlier
}

/// The unlabelled points for the summary (after the reclaim stage's moves), `None` when
/// there are none.
fn unlabelled_brief(unlabelled: &Others) -> Option<UnlabelledBrief> {
    if unlabelled.valid.is_empty() {
        return None;
    }
    Some(UnlabelledBrief {
        points: unlabelled.valid.len(),
        samples: unlabelled.samples(),
    })
}

fn count_action(briefs: &[SwapBrief], action: SwapAction) -> usize {
    briefs.iter().filter(|b| b.action == action).count()
}
