//! The repair pipeline: spikes → fill → filter, with a report of everything done or not.

use rayon::prelude::*;
use serde::Serialize;

use crate::error::Result;
use crate::fill::{fill_gaps, max_steps, FillOptions, FillOutcome, SkipReason, Vetting};
use crate::filter::{FilterSpec, Iir};
use crate::gaps::{find_gaps, valid_segments, Gap};
use crate::spikes::{detect, Spike, SpikeMode, SpikeOptions};
use crate::Trial;

/// Bits of the per-sample change mask ([`RepairReport::changes`]).
pub mod change {
    /// Was invalid, now holds a fill.
    pub const FILLED: u8 = 1;
    /// Spike coordinates replaced by the window median.
    pub const DESPIKED: u8 = 2;
    /// Was valid, judged a spike and made invalid (then possibly `FILLED`).
    pub const INVALIDATED: u8 = 4;
    /// Smoothed by the low-pass filter.
    pub const FILTERED: u8 = 8;
}

/// Validated settings, built once and applied to any number of trials.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RepairConfig {
    spikes: Option<SpikeOptions>,
    fill: FillOptions,
    filter: Option<FilterSpec>,
}

impl RepairConfig {
    /// Checks every option now, so applying the config can only fail on the trial's shape
    /// or on a cutoff above the trial's Nyquist frequency.
    pub fn new(
        spikes: Option<SpikeOptions>,
        fill: FillOptions,
        filter: Option<FilterSpec>,
    ) -> Result<RepairConfig> {
        if let Some(s) = &spikes {
            s.validate()?;
        }
        fill.validate()?;
        if let Some(f) = &filter {
            f.validate()?;
        }
        Ok(RepairConfig {
            spikes,
            fill,
            filter,
        })
    }

    pub fn spikes(&self) -> Option<&SpikeOptions> {
        self.spikes.as_ref()
    }

    /// This configuration for a file that stores coordinates as `storage` says: fills are
    /// held to the step rule as stored (see [`FillOptions::storage`]).
    pub fn with_storage(mut self, storage: crate::fill::Storage) -> Self {
        self.fill.storage = storage;
        self
    }

    /// This configuration, given in millimetres, for data whose unit is `mm_per_unit` mm:
    /// the spike detector's smallest deviation and the fill's expected-error limit are
    /// divided by it (the fill also keeps it, to judge speeds in mm). Options are checked
    /// once, in millimetres, before any file's unit is known; dividing by a positive finite
    /// number keeps them valid.
    pub fn in_units(mut self, mm_per_unit: f64) -> Self {
        if let Some(s) = &mut self.spikes {
            s.min_deviation /= mm_per_unit;
        }
        self.fill.max_expected_error = self.fill.max_expected_error.map(|e| e / mm_per_unit);
        self.fill.mm_per_unit = mm_per_unit;
        self
    }

    pub fn fill(&self) -> &FillOptions {
        &self.fill
    }

    pub fn filter(&self) -> Option<&FilterSpec> {
        self.filter.as_ref()
    }
}

/// One gap and what was done with it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GapRecord {
    #[serde(flatten)]
    pub gap: Gap,
    pub outcome: FillOutcome,
}

/// One continuous valid segment at the filter step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SegmentRecord {
    pub marker: usize,
    pub first: usize,
    pub last: usize,
    pub len: usize,
    pub filtered: bool,
    /// Set when skipped: filtfilt needs more than `padlen` samples.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub padlen: Option<usize>,
}

/// Everything the repair did, per marker and sample.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RepairReport {
    pub markers: usize,
    pub frames: usize,
    pub spikes: Vec<Spike>,
    /// What happened to spikes: `gap` (refilled by the fill step) or `median`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spike_mode: Option<SpikeMode>,
    /// Every gap after spike removal, in marker then frame order.
    pub gaps: Vec<GapRecord>,
    pub segments: Vec<SegmentRecord>,
    /// Samples with any change bit set, per marker.
    pub changed_per_marker: Vec<usize>,
    /// `changes[marker][frame]`: [`change`] bits. Not serialized (one byte per sample).
    #[serde(skip)]
    pub changes: Vec<Vec<u8>>,
}

impl RepairReport {
    /// Per-sample "modified" mask: any change at all.
    pub fn modified(&self) -> Vec<Vec<bool>> {
        self.changes
            .iter()
            .map(|m| m.iter().map(|&c| c != 0).collect())
            .collect()
    }

    /// Gaps left unfilled.
    pub fn unfilled(&self) -> impl Iterator<Item = &GapRecord> {
        self.gaps
            .iter()
            .filter(|g| matches!(g.outcome, FillOutcome::Skipped(_)))
    }
}

/// What an earlier repair of the same trial did, as the file records it: so that repairing
/// a repaired trial again changes nothing (a rerun must not fill what the first run
/// refused because the first run's fills now look like data).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Earlier {
    /// `filled[marker][frame]`: samples an earlier repair filled (empty: none). They are
    /// kept as they are and are no data to this run: no donor, no context, no step limit,
    /// never judged a spike. A filter this run applies still smooths them with their segment.
    pub filled: Vec<Vec<bool>>,
    /// Gaps an earlier repair left under the same fill settings, `(marker, first, last)`
    /// with its reason: a gap of exactly these frames is left again, not judged again.
    pub left: Vec<(usize, usize, usize, SkipReason)>,
}

impl Earlier {
    fn filled(&self, m: usize, f: usize) -> bool {
        self.filled
            .get(m)
            .and_then(|row| row.get(f))
            .copied()
            .unwrap_or(false)
    }
}

/// Repairs `trial` in place: spikes, then gap fill, then zero-phase filtering of each
/// continuous valid segment. Markers are processed in parallel; gaps are filled from the
/// data as it stood before any fill, then those next to a filled neighbour once more with
/// the neighbour's first fill as a donor (see `fill_gaps`), so the result does not depend
/// on marker order.
pub fn repair_trial(trial: &mut Trial, cfg: &RepairConfig) -> Result<RepairReport> {
    repair_trial_after(trial, cfg, &Earlier::default())
}

/// [`repair_trial`] on a trial an earlier repair already worked on (see [`Earlier`]).
pub fn repair_trial_after(
    trial: &mut Trial,
    cfg: &RepairConfig,
    earlier: &Earlier,
) -> Result<RepairReport> {
    trial.check()?;
    // Earlier fills are hidden from this run until the filter step: every stage reads the
    // trial as recorded, as the first run did.
    let hidden = hide_earlier_fills(trial, earlier);
    let iir = cfg.filter.map(|s| s.design(trial.rate_hz)).transpose()?;
    let (markers, frames) = (trial.markers(), trial.frames());
    let mut changes = vec![vec![0u8; frames]; markers];

    // 1. Spikes.
    let mut spikes = Vec::new();
    if let Some(opts) = &cfg.spikes {
        spikes = remove_spikes(trial, &mut changes, opts);
    }

    // 2. Fill, reading the spike-free data.
    let gaps = fill_stage(trial, &mut changes, &cfg.fill, earlier);
    for (m, f) in hidden {
        trial.valid[m][f] = true;
    }

    // 3. Filter each continuous valid segment.
    let mut segments = Vec::new();
    if let Some(iir) = &iir {
        segments = filter_segments(trial, &mut changes, iir);
    }

    let changed_per_marker = changes
        .iter()
        .map(|m| m.iter().filter(|&&c| c != 0).count())
        .collect();
    Ok(RepairReport {
        markers,
        frames,
        spikes,
        spike_mode: cfg.spikes.map(|s| s.mode),
        gaps,
        segments,
        changed_per_marker,
        changes,
    })
}

/// Marks an earlier repair's fills missing, returning them (marker, frame) to be shown
/// again before the filter.
fn hide_earlier_fills(trial: &mut Trial, earlier: &Earlier) -> Vec<(usize, usize)> {
    let mut hidden = Vec::new();
    for (m, row) in trial.valid.iter_mut().enumerate() {
        for (f, v) in row.iter_mut().enumerate() {
            if *v && earlier.filled(m, f) {
                *v = false;
                hidden.push((m, f));
            }
        }
    }
    hidden
}

/// The spikes of every marker, in parallel: each made a gap or replaced by its window's
/// median, as `opts.mode` says, and marked in `changes`.
fn remove_spikes(trial: &mut Trial, changes: &mut [Vec<u8>], opts: &SpikeOptions) -> Vec<Spike> {
    let found: Vec<Vec<Spike>> = trial
        .xyz
        .par_iter_mut()
        .zip(trial.valid.par_iter_mut())
        .zip(changes.par_iter_mut())
        .enumerate()
        .map(|(m, ((xyz, valid), ch))| {
            let s = detect(xyz, valid, m, opts);
            for sp in &s {
                match opts.mode {
                    SpikeMode::Gap => {
                        valid[sp.frame] = false;
                        ch[sp.frame] |= change::INVALIDATED;
                    }
                    SpikeMode::Median => {
                        for (c, &out) in sp.axes.iter().enumerate() {
                            if out {
                                xyz[sp.frame][c] = sp.median[c];
                            }
                        }
                        ch[sp.frame] |= change::DESPIKED;
                    }
                }
            }
            s
        })
        .collect();
    found.into_iter().flatten().collect()
}

/// The fill stage: `fill_gaps` writes the samples, the masks and `changes` are set here.
/// The gaps are the runs of samples missing in the file (earlier fills are no gap); those
/// an earlier repair left under the same settings are left again as they were. The records
/// come sorted by marker and first frame.
fn fill_stage(
    trial: &mut Trial,
    changes: &mut [Vec<u8>],
    fill: &FillOptions,
    earlier: &Earlier,
) -> Vec<GapRecord> {
    let (markers, frames) = (trial.markers(), trial.frames());
    let steps = max_steps(&trial.xyz, &trial.valid);
    let found: Vec<Gap> = (0..markers)
        .into_par_iter()
        .map(|m| {
            let mask: Vec<bool> = (0..frames)
                .map(|f| trial.valid[m][f] || earlier.filled(m, f))
                .collect();
            find_gaps(&mask, m)
        })
        .flatten()
        .collect();
    let (again, found): (Vec<Gap>, Vec<Gap>) = found.into_iter().partition(|g| {
        earlier
            .left
            .iter()
            .any(|&(m, a, b, _)| (m, a, b) == (g.marker, g.first, g.last))
    });
    let filled = fill_gaps(
        &mut trial.xyz,
        &trial.valid,
        &steps,
        &found,
        fill,
        Vetting::Checked,
    );
    let mut gaps = Vec::with_capacity(found.len() + again.len());
    for (gap, (v, outcome, _)) in found.into_iter().zip(filled) {
        let m = gap.marker;
        if v.is_some() {
            trial.valid[m][gap.first..=gap.last].fill(true);
            for c in &mut changes[m][gap.first..=gap.last] {
                *c |= change::FILLED;
            }
        }
        gaps.push(GapRecord { gap, outcome });
    }
    for gap in again {
        let reason = earlier
            .left
            .iter()
            .find(|&&(m, a, b, _)| (m, a, b) == (gap.marker, gap.first, gap.last))
            .map_or(SkipReason::NoContext, |l| l.3);
        gaps.push(GapRecord {
            gap,
            outcome: FillOutcome::Skipped(reason),
        });
    }
    gaps.sort_by_key(|g| (g.gap.marker, g.gap.first));
    gaps
}

/// Zero-phase filtering of each continuous valid segment longer than the filter's padding
/// (shorter ones are recorded as left), marked in `changes`.
fn filter_segments(trial: &mut Trial, changes: &mut [Vec<u8>], iir: &Iir) -> Vec<SegmentRecord> {
    let padlen = iir.padlen();
    let recs: Vec<Vec<SegmentRecord>> = trial
        .xyz
        .par_iter_mut()
        .zip(trial.valid.par_iter())
        .zip(changes.par_iter_mut())
        .enumerate()
        .map(|(m, ((xyz, valid), ch))| {
            let mut buf = Vec::new();
            valid_segments(valid)
                .into_iter()
                .map(|(first, last)| {
                    let len = last - first + 1;
                    let ok = len > padlen;
                    if ok {
                        for c in 0..3 {
                            buf.clear();
                            buf.extend(xyz[first..=last].iter().map(|p| p[c]));
                            // Length checked above, so filtfilt cannot refuse.
                            if iir.filtfilt(&mut buf).is_ok() {
                                for (p, v) in xyz[first..=last].iter_mut().zip(&buf) {
                                    p[c] = *v;
                                }
                            }
                        }
                        for c in &mut ch[first..=last] {
                            *c |= change::FILTERED;
                        }
                    }
                    SegmentRecord {
                        marker: m,
                        first,
                        last,
                        len,
                        filtered: ok,
                        padlen: (!ok).then_some(padlen),
                    }
                })
                .collect()
        })
        .collect();
    recs.into_iter().flatten().collect()
}
