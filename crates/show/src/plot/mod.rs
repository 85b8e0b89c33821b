//! The plots (`c3dfix plot`): marker coordinates (and optionally an analog channel) against time, drawn
//! as SVG or PNG with `plotters`.
//!
//! This is presentation, so it lives here rather than beside the algorithms. What is drawn is gathered first (plain arrays; testable without drawing) by `gather`, then
//! `draw` turns it into bytes. The keyframe error curves of `c3dfix keyframes --plot` follow
//! the same split.

pub mod decimate;
mod draw;
mod file_plot;
mod forces;
mod gather;

pub use draw::{render, render_keyframe_curves, Format};
pub use file_plot::{drawn_events, forces_picture, markers_picture};
pub use forces::render_forces;
pub use gather::{marker_index, KeyframeCurves, Plot};
