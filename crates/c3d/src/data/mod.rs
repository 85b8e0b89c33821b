//! The data section: frames of point samples followed by analog samples, decoded and encoded
//! through one codec chosen per file.

mod decode;
mod encode;
mod scan;
mod view;

pub(crate) use decode::{chunk_frames, DecodeAnalog, DecodePoints, PARALLEL_SCAN_BYTES};
pub(crate) use encode::{Encode, Patch};
pub(crate) use scan::{Scan, ScanNotes};
pub use view::PointsView;

use serde::Serialize;

/// How the data section is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Layout {
    /// Points per frame.
    pub points: usize,
    /// Analog channels.
    pub analog_channels: usize,
    /// Analog samples per channel per 3D frame.
    pub analog_samples_per_frame: usize,
    pub frames: usize,
    /// Floating-point (true) or scaled int16 (false) samples.
    pub float: bool,
    /// Analog integers are unsigned (ANALOG:FORMAT = UNSIGNED).
    pub unsigned_analog: bool,
    /// |POINT:SCALE|: integer coordinates are multiplied by it; residuals always are.
    pub point_scale: f32,
}

impl Layout {
    pub fn word_bytes(&self) -> usize {
        if self.float {
            4
        } else {
            2
        }
    }

    // Counts come from the file: products saturate, so an absurd layout compares as larger
    // than any file instead of wrapping around.

    pub fn analog_words(&self) -> usize {
        self.analog_channels
            .saturating_mul(self.analog_samples_per_frame)
    }

    /// Bytes of one 3D frame with its analog samples.
    pub fn frame_bytes(&self) -> usize {
        (4 * self.points)
            .saturating_add(self.analog_words())
            .saturating_mul(self.word_bytes())
    }

    /// Bytes of the whole data section.
    pub fn data_bytes(&self) -> usize {
        self.frames.saturating_mul(self.frame_bytes())
    }
}
