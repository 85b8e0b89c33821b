//! A chunk of a trial's point samples, decoded as they are asked for.

use super::decode::decode_sample;
use super::Layout;
use crate::points::{is_missing, Points};
use crate::processor::{Dec, Intel, Processor, Sgi};

/// The point samples of a run of whole frames: a chunk of a trial's point data (see
/// [`C3d::map_point_chunks`](crate::C3d::map_point_chunks)). Samples are decoded as they are
/// asked for, straight from the stored bytes when the trial's arrays have not been decoded,
/// with the same decoding as [`C3d::points`](crate::C3d::points).
#[derive(Debug, Clone, Copy)]
pub struct PointsView<'a> {
    /// Index (0-based) of the chunk's first frame in the trial.
    pub first_frame: usize,
    /// Frames in the chunk.
    pub frames: usize,
    /// Points per frame.
    pub count: usize,
    data: ViewData<'a>,
}

#[derive(Debug, Clone, Copy)]
enum ViewData<'a> {
    /// Slices of decoded arrays.
    Decoded {
        xyz: &'a [[f32; 3]],
        residual: &'a [f32],
        camera_mask: &'a [u8],
    },
    /// Whole frames of the stored data section.
    Stored {
        bytes: &'a [u8],
        layout: Layout,
        processor: Processor,
    },
}

impl<'a> PointsView<'a> {
    /// Frames `first_frame..` of decoded points: samples `range` of the arrays.
    pub(crate) fn decoded(
        first_frame: usize,
        p: &'a Points,
        range: std::ops::Range<usize>,
    ) -> Self {
        PointsView {
            first_frame,
            frames: range.len() / p.count.max(1),
            count: p.count,
            data: ViewData::Decoded {
                xyz: &p.xyz[range.clone()],
                residual: &p.residual[range.clone()],
                camera_mask: &p.camera_mask[range],
            },
        }
    }

    /// Frames `first_frame..` as stored: `bytes` holds whole frames of the data section.
    pub(crate) fn stored(
        first_frame: usize,
        bytes: &'a [u8],
        layout: Layout,
        processor: Processor,
    ) -> Self {
        PointsView {
            first_frame,
            frames: bytes.len() / layout.frame_bytes().max(1),
            count: layout.points,
            data: ViewData::Stored {
                bytes,
                layout,
                processor,
            },
        }
    }

    /// Sample `(frame, point)` of the chunk (`frame` counted from the chunk's first):
    /// coordinates, residual (−1 when missing) and camera mask, as in [`Points`].
    #[inline]
    pub fn sample(&self, frame: usize, point: usize) -> ([f32; 3], f32, u8) {
        match self.data {
            ViewData::Decoded {
                xyz,
                residual,
                camera_mask,
            } => {
                let k = frame * self.count + point;
                (xyz[k], residual[k], camera_mask[k])
            }
            ViewData::Stored {
                bytes,
                layout,
                processor,
            } => {
                let sb = 4 * layout.word_bytes();
                let at = frame * layout.frame_bytes() + point * sb;
                let c = &bytes[at..at + sb];
                match processor {
                    Processor::Intel => decode_sample::<Intel>(c, &layout),
                    Processor::Dec => decode_sample::<Dec>(c, &layout),
                    Processor::Sgi => decode_sample::<Sgi>(c, &layout),
                }
            }
        }
    }

    /// Whether sample `(frame, point)` of the chunk is valid, by
    /// [`is_missing`](crate::is_missing).
    #[inline]
    pub fn is_valid(&self, frame: usize, point: usize) -> bool {
        let (p, r, _) = self.sample(frame, point);
        !is_missing(p, r)
    }
}
