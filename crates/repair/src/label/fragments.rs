//! A trial's trajectories cut into fragments: runs of recorded samples, cut again where a
//! trajectory leaps further in one frame than a marker moves (a capture system that joined
//! two points into one trajectory). The samples are kept fragment by fragment in one
//! array ([`Pieces`]): the labelling reads a frame's points across every fragment, and a
//! trial's rows are mostly empty frames.

use crate::Trial;
use serde::Serialize;

/// One run of samples of one trajectory: the unit that gets a label.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Fragment {
    /// Row of the trial.
    pub row: usize,
    /// First and last frame, inclusive (0-based).
    pub first: usize,
    pub last: usize,
}

impl Fragment {
    pub fn len(&self) -> usize {
        self.last - self.first + 1
    }

    pub fn is_empty(&self) -> bool {
        false
    }

    pub fn overlaps(&self, o: &Fragment) -> bool {
        self.first <= o.last && o.first <= self.last
    }
}

/// The fragments of a trial with their samples in mm, and which are recorded in each frame.
pub(crate) struct Pieces {
    pub frags: Vec<Fragment>,
    /// Where each fragment's first sample sits in `xyz`.
    start: Vec<usize>,
    xyz: Vec<[f64; 3]>,
    /// For each frame, the fragments recorded there (indices into `frags`, in order).
    pub active: Vec<Vec<u32>>,
    pub rate_hz: f64,
}

impl Pieces {
    /// The fragments of every row of `t`, its coordinates times `mm_per_unit`; a sample
    /// with a coordinate that is not finite is missing, and a step of more than
    /// `max_step_mm` between consecutive frames starts a new fragment.
    pub fn cut(t: &Trial, mm_per_unit: f64, max_step_mm: f64) -> Pieces {
        let mut frags = Vec::new();
        let mut start = Vec::new();
        let mut xyz: Vec<[f64; 3]> = Vec::new();
        let n = t.frames();
        for (row, (raw, valid)) in t.xyz.iter().zip(&t.valid).enumerate() {
            let at = |f: usize| {
                if !valid[f] {
                    return None;
                }
                let p = raw[f].map(|v| v * mm_per_unit);
                p.iter().all(|c| c.is_finite()).then_some(p)
            };
            let mut f = 0;
            while f < n {
                let Some(mut prev) = at(f) else {
                    f += 1;
                    continue;
                };
                let first = f;
                start.push(xyz.len());
                xyz.push(prev);
                f += 1;
                while let Some(p) = (f < n).then(|| at(f)).flatten() {
                    if super::options::dist(&p, &prev) > max_step_mm {
                        break;
                    }
                    xyz.push(p);
                    prev = p;
                    f += 1;
                }
                frags.push(Fragment {
                    row,
                    first,
                    last: f - 1,
                });
            }
        }
        let mut active = vec![Vec::new(); n];
        for (i, g) in frags.iter().enumerate() {
            for a in &mut active[g.first..=g.last] {
                a.push(i as u32);
            }
        }
        Pieces {
            frags,
            start,
            xyz,
            active,
            rate_hz: t.rate_hz,
        }
    }

    /// Frames of the trial.
    pub fn frames(&self) -> usize {
        self.active.len()
    }

    /// Fragment `g`'s position at frame `f` (which it must cover).
    pub fn at(&self, g: usize, f: usize) -> &[f64; 3] {
        &self.xyz[self.start[g] + f - self.frags[g].first]
    }
}
