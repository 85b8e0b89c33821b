//! One light pass over the stored samples for what the reader notes about a file, without
//! decoding it into memory.

use super::decode::{chunk_frames, decode_sample, PARALLEL_SCAN_BYTES};
use super::Layout;
use crate::points::{float_word, is_missing};
use crate::processor::{Codec, CodecFn};

/// What decoding found besides the samples.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct DecodeNotes {
    /// Float fourth words that are not 16-bit words (see [`float_word`]).
    pub odd_fourth_words: usize,
    /// The first of them, as a sample index (frame × points + point).
    pub first_odd: Option<usize>,
}

impl DecodeNotes {
    pub(crate) fn merge(self, other: DecodeNotes) -> DecodeNotes {
        DecodeNotes {
            odd_fourth_words: self.odd_fourth_words + other.odd_fourth_words,
            first_odd: match (self.first_odd, other.first_odd) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
        }
    }
}

/// What the reader notes about a file's samples without decoding them into memory.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct ScanNotes {
    pub notes: DecodeNotes,
    /// Some sample is valid.
    pub any_valid: bool,
    /// Some missing sample stores coordinates other than (0, 0, 0) (looked for only until a
    /// valid sample turns up).
    pub any_stored: bool,
}

/// One pass over the stored samples for [`ScanNotes`]: float fourth words that are not
/// 16-bit words (every sample), and whether any sample is valid (until one is).
pub(crate) struct Scan<'a> {
    pub bytes: &'a [u8],
    pub layout: Layout,
}

impl CodecFn<ScanNotes> for Scan<'_> {
    fn call<C: Codec>(self) -> ScanNotes {
        use rayon::prelude::*;
        let l = self.layout;
        let fb = l.frame_bytes();
        let sb = 4 * l.word_bytes();
        let pb = sb * l.points;
        if fb == 0 || l.points == 0 {
            return ScanNotes::default();
        }
        let chunk = chunk_frames(&l);
        let scan = |(i, b): (usize, &[u8])| {
            let mut n = ScanNotes::default();
            for (f, frame) in b.chunks_exact(fb).enumerate() {
                for (j, c) in frame[..pb].chunks_exact(sb).enumerate() {
                    if l.float {
                        let w = C::read_f32([c[12], c[13], c[14], c[15]]);
                        if float_word(w).is_none() {
                            n.notes.odd_fourth_words += 1;
                            n.notes
                                .first_odd
                                .get_or_insert((i * chunk + f) * l.points + j);
                        }
                    } else if n.any_valid {
                        // Integer files have nothing more to note.
                        return n;
                    }
                    if !n.any_valid {
                        let (p, r, _) = decode_sample::<C>(c, &l);
                        n.any_valid = !is_missing(p, r);
                        n.any_stored |= p != [0.0; 3];
                    }
                }
            }
            n
        };
        let merge = |a: ScanNotes, b: ScanNotes| ScanNotes {
            notes: a.notes.merge(b.notes),
            any_valid: a.any_valid || b.any_valid,
            any_stored: a.any_stored || b.any_stored,
        };
        let data = &self.bytes[..l.frames * fb];
        if data.len() > PARALLEL_SCAN_BYTES {
            forkpool::install(|| {
                data.par_chunks(chunk * fb)
                    .enumerate()
                    .map(scan)
                    .reduce(ScanNotes::default, merge)
            })
        } else {
            data.chunks(chunk * fb)
                .enumerate()
                .map(scan)
                .fold(ScanNotes::default(), merge)
        }
    }
}
