//! Marker label swaps and label jumps (issue 34): found from the trial's own evidence and
//! undone.
//!
//! Two markers that trade labels for some frames, or one label that lands on a stray point,
//! break the distances the markers of one body segment keep. [`links`] learns those
//! distances from the trial itself (pairs whose distance is nearly constant over most
//! frames; no marker set is written into the code), [`detect`] checks every frame against
//! them and tries the exchange of two markers' samples, and uses the continuity of each
//! trajectory to place an episode's boundaries. [`undo()`] exchanges a settled swap's samples
//! back and marks a settled jump's samples missing, for the fill stage.
//!
//! Frames are 0-based here; a C3D caller converts them to the file's numbering.

pub mod detect;
pub mod links;
pub mod undo;

pub use detect::{find_swaps, find_swaps_learned, Evidence, Find, FindKind, SwapOptions};
pub use links::{learn_links, LearnedLinks, Link, LinksOnDemand, Relearned};
pub use undo::undo;
