//! Gap fill methods. Each method fills one span of one marker from data that is only read,
//! so markers can be filled in parallel and a method can be tried on artificial gaps
//! (see `FillMethod::Auto`) without copying the trial.
//!
//! The modules stand in layers, each importing only from those below it:
//! - the vocabulary: `method` (the methods), `options` (the settings), `outcome` (what
//!   happened to a gap), `data` (the trial as fills read it), `step` (the step rule);
//! - the methods: `linear`, `poly`, `spline`, `anchor` (tying a prediction to the samples),
//!   `donors` (the donor choice), `rigid`, `pattern`, `skeleton`, `subspace` (the rows
//!   PCA and the Kalman smoother share), `pca`, `kalman`, `gloersen`, and `plan` (the
//!   donors with the models trained on them);
//! - `apply`: one concrete method by name; `auto`: the choice among them per gap;
//! - `dispatch`: one gap with the configured method; `refill`: the two passes over a
//!   trial's gaps.
//!
//! This file only declares the modules and says what the rest of the crate sees.

mod anchor;
mod apply;
mod auto;
mod data;
mod dispatch;
mod donors;
mod gloersen;
mod kalman;
mod linear;
mod method;
mod options;
mod outcome;
mod pattern;
mod pca;
mod plan;
mod poly;
mod refill;
mod rigid;
mod skeleton;
mod spline;
mod step;
mod subspace;
#[cfg(test)]
pub(crate) mod test_util;

pub(crate) use apply::{fill_raw, fill_with};
pub use auto::{
    accel_ratio, calibrated, features, gap_donors, log_ratio, speed_ratio, Diag, GapDonors,
    FEATURES, LEADS,
};
pub(crate) use data::{dist, Data, Span, Target};
pub(crate) use dispatch::Vetting;
pub use method::FillMethod;
pub use options::{FillOptions, Storage};
pub use outcome::{FillOutcome, SkipKind, SkipReason};
pub(crate) use plan::Plan;
pub(crate) use refill::fill_gaps;
pub use step::STEP_FACTOR;
pub(crate) use step::{max_steps, step_ratio};
