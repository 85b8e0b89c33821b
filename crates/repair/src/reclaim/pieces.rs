//! The pieces: every stretch of an unlabelled trajectory recorded inside a gap of a marker,
//! and the unlabelled trajectories indexed by their recorded runs so that a gap's pieces
//! near its ends are found without walking its frames.

use super::finds::{Piece, ReclaimOptions};
use crate::Trial;

/// Every stretch of an unlabelled trajectory recorded inside a gap of a marker, in order of
/// marker, gap, unlabelled trajectory and frame.
pub(super) fn all(m: &Trial, u: &Trial) -> Vec<Piece> {
    let runs = Runs::of(u);
    let mut out = Vec::new();
    for (marker, mv) in m.valid.iter().enumerate() {
        for g in crate::gaps::find_gaps(mv, marker) {
            for source in 0..runs.by_source.len() {
                let (lo, hi) = runs.within(source, g.first, g.last);
                out.extend((lo..hi).map(|i| runs.piece(marker, source, i, g.first, g.last)));
            }
        }
    }
    out
}

/// Each unlabelled trajectory's runs of recorded samples, `(first, last)` in order.
pub(super) struct Runs {
    by_source: Vec<Vec<(usize, usize)>>,
}

impl Runs {
    pub(super) fn of(u: &Trial) -> Runs {
        let by_source = u
            .valid
            .iter()
            .map(|v| {
                let mut runs = Vec::new();
                let mut f = 0;
                while f < v.len() {
                    if !v[f] {
                        f += 1;
                        continue;
                    }
                    let first = f;
                    while f < v.len() && v[f] {
                        f += 1;
                    }
                    runs.push((first, f - 1));
                }
                runs
            })
            .collect();
        Runs { by_source }
    }

    /// The runs of `source` that meet frames `first..=last`: indices `lo..hi`.
    fn within(&self, source: usize, first: usize, last: usize) -> (usize, usize) {
        let runs = &self.by_source[source];
        let lo = runs.partition_point(|r| r.1 < first);
        let hi = runs.partition_point(|r| r.0 <= last);
        (lo, hi.max(lo))
    }

    /// Run `i` of `source` cut to the gap `first..=last` of `marker`.
    fn piece(&self, marker: usize, source: usize, i: usize, first: usize, last: usize) -> Piece {
        let r = self.by_source[source][i];
        Piece {
            marker,
            source,
            first: r.0.max(first),
            last: r.1.min(last),
        }
    }

    /// Call `each` on every piece (in the order of [`all`]) that the marker's path can
    /// judge at one end at least, when [`ReclaimOptions::min_ends`] asks for one: a piece
    /// that starts within [`ReclaimOptions::path_frames`] of its gap's first frame or ends
    /// as near its last. The others are scored off for want of an end (the path is carried
    /// that far into a gap, no further), so they are only counted. Returns how many pieces
    /// there are in all.
    pub(super) fn each_near_end(
        &self,
        m: &Trial,
        opts: &ReclaimOptions,
        mut each: impl FnMut(Piece),
    ) -> usize {
        let reach = if opts.min_ends == 0 {
            usize::MAX
        } else {
            opts.path_frames
        };
        let mut total = 0;
        for (marker, mv) in m.valid.iter().enumerate() {
            for g in crate::gaps::find_gaps(mv, marker) {
                for source in 0..self.by_source.len() {
                    let (lo, hi) = self.within(source, g.first, g.last);
                    total += hi - lo;
                    let piece = |i| self.piece(marker, source, i, g.first, g.last);
                    // Pieces near the start are a prefix of the gap's pieces, those near
                    // the end a suffix.
                    let near_start = |i| piece(i).first - g.first < reach;
                    let near_end = |i| g.last - piece(i).last < reach;
                    let mut head = lo;
                    while head < hi && near_start(head) {
                        head += 1;
                    }
                    let mut tail = hi;
                    while tail > head && near_end(tail - 1) {
                        tail -= 1;
                    }
                    (lo..head).chain(tail..hi).for_each(|i| each(piece(i)));
                }
            }
        }
        total
    }
}
