//! The labelling's constants ([`LabelOptions`]) and the one distance every part measures:
//! the words the labelling's parts share, apart from the labelling itself.

use serde::Serialize;

/// The constants of the labelling, in mm where they are lengths. Chosen on the corpora
/// named in docs/label.md with the `label_eval` benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LabelOptions {
    /// A pair's tolerance is its spread over the template plus `floor_mm` plus
    /// `floor_share` of its distance (the trial's skin moves more than the template shows).
    pub floor_mm: f64,
    pub floor_share: f64,
    /// Pairs used per marker (its most closely kept).
    pub neighbours: usize,
    /// Largest squared departure one pair adds (in tolerances²).
    pub cap: f64,
    /// Largest mean squared departure of a match (in tolerances²).
    pub accept: f64,
    /// Cost of leaving a marker out of a seed, per placed pair.
    pub absent: f64,
    /// Pairs that must be checked for a match to count.
    pub min_neighbours: usize,
    /// States kept by the seed's beam search.
    pub beam: usize,
    /// Most frames matched from nothing when the trial labels nothing.
    pub seed_frames: usize,
    /// One frame matched from nothing per this many seconds (the one with the most points).
    pub seed_every_s: f64,
    /// Seed every `seed_every_s` from the start (true), or 8 frames first and then only
    /// where the labels have not reached (false: fewer beam searches, but on label_eval
    /// 90.08 % right and 0.61 % wrong on the labs held apart instead of 90.63 % and
    /// 0.56 %).
    pub seed_all: bool,
    /// Seed frames in runs of this many: the first of a run is matched from nothing, each
    /// next one keeps the fragments the one before placed and searches only the rest (1:
    /// every seed frame from nothing).
    pub seed_chain: usize,
    /// Frames read per pass: every `step`-th (0: chosen from the trial's length).
    pub step: usize,
    /// Frames a fragment must be read in to get a label.
    pub min_checked: usize,
    /// Share of its frames that must vote for a fragment's label.
    pub min_share: f64,
    /// The label's votes must be this many times a rival's.
    pub margin: f64,
    /// Share of its frames that must vote for another marker to change a label the trial
    /// gave (and at most a tenth for its own).
    pub relabel_share: f64,
    /// Fastest a marker moves (mm/s): a longer step in one frame starts a new fragment.
    pub max_speed_mm_s: f64,
    /// Largest number of vote passes.
    pub passes: usize,
    /// Times the geometry is learned again from the template and the trial as labelled.
    pub relearn: usize,
    /// Fit the template's size to the trial's body before matching (a template of another
    /// subject); false: the template's distances as recorded.
    pub fit_scale: bool,
    /// The ladder of sizes tried when nothing is labelled: `scale_ratio` to the powers
    /// `-scale_steps..=scale_steps` (1.05 and 5: 0.78–1.28 times the template, each size
    /// within 2.5 % of the next, inside a pair's floor of 2 %, 3 mm).
    pub scale_steps: usize,
    pub scale_ratio: f64,
    /// `floor_share` of the first round, before the geometry is learned again from the
    /// trial as labelled (at least `floor_share`).
    pub first_floor_share: f64,
    /// Learn the geometry again from the template's frames and the trial's (true), or
    /// from the trial's alone.
    pub relearn_template: bool,
    /// A frame's match votes only when the fragment's cost for any other marker is at
    /// least this much more (mean squared departure, in tolerances²; 0: always).
    pub vote_margin: f64,
    /// Two newly labelled fragments of neighbouring markers keep their labels only if
    /// exchanging them costs at least this much more (mean squared departure over their
    /// pairs, in tolerances²; 0: not checked).
    pub exchange_margin: f64,
}

impl Default for LabelOptions {
    fn default() -> Self {
        LabelOptions {
            floor_mm: 3.0,
            floor_share: 0.02,
            neighbours: 8,
            cap: 16.0,
            accept: 4.0,
            absent: 6.0,
            min_neighbours: 2,
            beam: 200,
            seed_frames: 400,
            seed_every_s: 0.5,
            seed_all: true,
            seed_chain: 1,
            step: 0,
            min_checked: 3,
            min_share: 0.5,
            margin: 3.0,
            relabel_share: 0.8,
            max_speed_mm_s: 20_000.0,
            passes: 30,
            relearn: 1,
            fit_scale: false,
            scale_steps: 5,
            scale_ratio: 1.05,
            first_floor_share: 0.02,
            relearn_template: true,
            vote_margin: 0.0,
            exchange_margin: 0.5,
        }
    }
}

/// The distance of two points, in their units.
pub(crate) fn dist(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}
