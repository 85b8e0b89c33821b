//! What reclaiming is asked and what it finds: its thresholds ([`ReclaimOptions`]), the
//! pieces of unlabelled trajectories inside a marker's gaps ([`Piece`]), the pieces settled
//! ([`Move`]) and those that fit but are not ([`Unsettled`], [`Why`]), together
//! ([`Reclaims`]), and how a piece fits its marker ([`Fit`], [`Verdict`]).

use serde::Serialize;

/// The thresholds of the evidence, in mm. The defaults were chosen on the corpora
/// `c3d-samples`, `c3d-extra` and `c3d-fullbody` with the `reclaim_eval` example
/// (docs/reclaim.md); `c3d-more` and `c3d-labs` chose nothing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ReclaimOptions {
    /// Links (segment distances) must be checked in a frame for it to count as checked.
    pub min_links: usize,
    /// Share of a piece's frames that must be checked by `min_links` links.
    pub min_checked: f64,
    /// Share of a piece's link checks that may stray beyond the link's tolerance.
    pub max_fail: f64,
    /// Largest mean squared link residual, in tolerances.
    pub max_cost: f64,
    /// How far the piece's first or last sample may sit from where the marker's path
    /// carries it across one frame (mm); grows with the frames it is carried over.
    pub path_mm: f64,
    /// Frames over which the marker's path is carried into a gap to judge a piece that
    /// starts (ends) inside it; further in, only the links judge.
    pub path_frames: usize,
    /// Links whose distance departs more than this (mm, 95th percentile over the trial) are
    /// not used: they span a joint.
    pub max_link_tol_mm: f64,
    /// Ends of a piece (0, 1 or 2) that must be judged by the marker's path: a piece that
    /// floats inside a long gap, away from both its ends, rests on the links alone.
    pub min_ends: usize,
    /// A piece that fills a whole gap, on the marker's path at both ends, is a candidate
    /// without links (a marker with no segment to check, or none recorded there).
    pub path_alone: bool,
    /// A rival fitting with a cost below `margin` times the best's (plus 0.02) leaves both
    /// unsettled.
    pub margin: f64,
}

impl Default for ReclaimOptions {
    fn default() -> Self {
        ReclaimOptions {
            min_links: 2,
            min_checked: 0.5,
            max_fail: 0.5,
            max_cost: 3.0,
            path_mm: 20.0,
            path_frames: 5,
            margin: 4.0,
            path_alone: true,
            min_ends: 1,
            max_link_tol_mm: 15.0,
        }
    }
}

/// One stretch of an unlabelled trajectory's samples inside a marker's gap.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Piece {
    /// The labelled marker (row of the markers' trial).
    pub marker: usize,
    /// The unlabelled trajectory (row of the candidates' trial).
    pub source: usize,
    /// First and last frame, inclusive.
    pub first: usize,
    pub last: usize,
}

impl Piece {
    pub fn len(&self) -> usize {
        self.last - self.first + 1
    }

    pub fn is_empty(&self) -> bool {
        false
    }

    pub(super) fn overlaps(&self, o: &Piece) -> bool {
        self.first <= o.last && o.first <= self.last
    }
}

/// A settled piece: its samples belong to the marker.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Move {
    #[serde(flatten)]
    pub piece: Piece,
    pub fit: Fit,
}

/// Why a piece that fits was not moved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "why", rename_all = "snake_case")]
pub enum Why {
    /// Another piece fits as well: the same marker's gap from another unlabelled
    /// trajectory, or the same unlabelled samples in another marker's gap.
    Ambiguous { rival: Piece, rival_cost: f64 },
    /// The marker's path fits, but too few of its segment's distances could be checked to
    /// tell it from another point.
    FewLinks { checked_frames: usize },
}

/// A piece the evidence does not settle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Unsettled {
    #[serde(flatten)]
    pub piece: Piece,
    #[serde(flatten)]
    pub why: Why,
    pub fit: Fit,
}

/// What [`super::find_reclaims`] found.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Reclaims {
    /// Settled pieces, by marker and frame.
    pub moves: Vec<Move>,
    /// Pieces that fit and were not settled, by marker and frame.
    pub unsettled: Vec<Unsettled>,
    /// Pieces judged (unlabelled stretches inside labelled gaps).
    pub pieces: usize,
    /// The pairs of markers whose links were learned here, of all: fewer when an earlier
    /// stage's learning was handed on ([`super::find_reclaims_sharing`]), none when no piece
    /// passed the path (no link was asked for). The same links either way; this says only
    /// what they cost.
    #[serde(skip)]
    pub link_pairs: crate::swaps::Relearned,
}

/// How a piece fits the marker it is judged for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Fit {
    /// What the evidence says.
    pub verdict: Verdict,
    /// Mean squared link residual, in tolerances (each residual counted up to 10).
    pub cost: f64,
    /// Root mean square of the link residuals, mm.
    pub rms_mm: f64,
    /// Frames checked by at least [`ReclaimOptions::min_links`] links.
    pub checked_frames: usize,
    /// Link checks made, and those beyond the link's tolerance.
    pub checks: usize,
    pub fails: usize,
    /// The largest distance of the piece's end samples from the marker's path, mm, where
    /// the path could be carried to them (`None`: at neither end).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_mm: Option<f64>,
}

/// The evidence's word on a piece.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The links and the path agree: a candidate.
    Fits,
    /// The path fits, too few frames could be checked against the segment.
    FewLinks,
    /// Something says it is another point.
    Off,
}
