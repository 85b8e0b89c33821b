//! A trial's trajectories cut into fragments: runs of recorded samples, cut again where a
//! trajectory leaps further in one frame than a marker moves (a capture system that joined
//! two points into one trajectory).

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

/// The fragments of every row of `t` (in mm, missing samples already not valid); a step of
/// more than `max_step_mm` between consecutive frames starts a new fragment.
pub(crate) fn fragments(t: &Trial, max_step_mm: f64) -> Vec<Fragment> {
    let mut out = Vec::new();
    for (row, (xyz, valid)) in t.xyz.iter().zip(&t.valid).enumerate() {
        let mut f = 0;
        let n = valid.len();
        while f < n {
            if !valid[f] {
                f += 1;
                continue;
            }
            let first = f;
            f += 1;
            while f < n && valid[f] && super::options::dist(&xyz[f], &xyz[f - 1]) <= max_step_mm {
                f += 1;
            }
            out.push(Fragment {
                row,
                first,
                last: f - 1,
            });
        }
    }
    out
}

/// For each frame, the fragments recorded there (indices into `frags`, in order).
pub(crate) fn by_frame(frags: &[Fragment], frames: usize) -> Vec<Vec<u32>> {
    let mut at = vec![Vec::new(); frames];
    for (i, g) in frags.iter().enumerate() {
        for a in &mut at[g.first..=g.last] {
            a.push(i as u32);
        }
    }
    at
}
