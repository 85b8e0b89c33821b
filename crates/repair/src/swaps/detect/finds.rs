//! What the finding is asked and what it answers: the options ([`SwapOptions`]), and each
//! find ([`Find`]: a swap or a jump, its frames, its confidence and the evidence behind it).

use serde::Serialize;

use crate::error::{RepairError, Result};

/// What the detector looks for and when a find counts as settled. Build with
/// [`SwapOptions::default`] and change fields; [`SwapOptions::validate`] checks them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SwapOptions {
    /// A pair is a link only if its distance's robust spread is at most this (mm).
    pub max_link_spread_mm: f64,
    /// Share of the sampled frames a link's distance must keep (a majority, so that a
    /// swap over part of the trial cannot move the learned distance).
    pub min_link_support: f64,
    /// Links kept per marker (the most rigid first).
    pub max_links: usize,
    /// Markers farther apart than this are not tried as a swap (mm).
    pub partner_radius_mm: f64,
    /// Frames of undecided evidence (a marker missing, both markers passing close) that
    /// may sit inside an episode or at its edges.
    pub max_hole: usize,
    /// Jumps shorter than this are left to the spike stage.
    pub min_jump_frames: usize,
    /// Finds below this confidence are dropped: evidence this weak is what a trial's
    /// own noise gives.
    pub min_report: f64,
    /// Finds at or above this confidence are settled: [`crate::swaps::undo()`] acts on them; the
    /// others are only reported.
    pub min_confidence: f64,
}

impl Default for SwapOptions {
    fn default() -> Self {
        SwapOptions {
            max_link_spread_mm: 2.5,
            min_link_support: 0.5,
            max_links: 8,
            partner_radius_mm: 500.0,
            max_hole: 10,
            min_jump_frames: 5,
            min_report: 0.6,
            min_confidence: 0.7,
        }
    }
}

impl SwapOptions {
    /// Every field in its range.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: &str| Err(RepairError::Option(format!("swaps: {what}")));
        if !(self.max_link_spread_mm > 0.0 && self.max_link_spread_mm.is_finite()) {
            return bad("max_link_spread_mm must be a positive number");
        }
        if !(self.min_link_support >= 0.5 && self.min_link_support <= 1.0) {
            return bad("min_link_support must be from 0.5 to 1");
        }
        if self.max_links == 0 {
            return bad("max_links must be at least 1");
        }
        if self.partner_radius_mm.is_nan() || self.partner_radius_mm <= 0.0 {
            return bad("partner_radius_mm must be above 0");
        }
        if !(0.0..=1.0).contains(&self.min_confidence) || !(0.0..=1.0).contains(&self.min_report) {
            return bad("min_confidence and min_report must be from 0 to 1");
        }
        Ok(())
    }
}

/// A swap (two markers holding each other's samples) or a jump (one marker's label on
/// another point).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FindKind {
    Swap,
    Jump,
}

/// What a find rests on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evidence {
    /// Links of the find's markers (learned from the trial).
    pub links: usize,
    /// Frames of the episode where the links decided (the rest were bridged).
    pub frames_decided: usize,
    /// Median link error of the markers as labelled over the decided frames, in units of
    /// each link's tolerance (above 1: broken), summed over the markers (a jump found by
    /// its leaps alone: over the span's frames where its one link is seen).
    pub link_error: f64,
    /// The same with the swap exchanged back (for a jump: the error once the marker sits
    /// where its links put it, 0).
    pub link_error_undone: f64,
    /// At the episode's edges, the continuity of the trajectories as labelled against as
    /// undone: how many edges the undone version is smoother at, and how many edges could
    /// be checked.
    pub edges_smoother: usize,
    pub edges_checked: usize,
    /// Largest step out of the predicted path (mm) at the episode's edges as labelled.
    pub edge_step_mm: f64,
    /// A jump's steady-offset witness, 0 to 1: its two edge leaps cancel, both break the
    /// marker's path, and between them the marker holds that offset from its link
    /// partners; `None` where it could not be measured (and for swaps).
    pub offset_share: Option<f64>,
}

/// One swap or jump, frames 0-based and inclusive.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Find {
    pub kind: FindKind,
    /// Two markers (swap, lower index first) or one (jump).
    pub markers: Vec<usize>,
    pub first: usize,
    pub last: usize,
    /// 0 to 1: how strongly the links and the continuity agree.
    pub confidence: f64,
    /// Confidence at least [`SwapOptions::min_confidence`]: undone, not only reported.
    pub settled: bool,
    pub evidence: Evidence,
}
