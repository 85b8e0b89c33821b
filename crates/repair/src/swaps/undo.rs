//! Undoing settled finds on the arrays: a swap's samples exchanged back, a jump's samples
//! marked missing for the fill stage.

use super::detect::{Find, FindKind};
use crate::Trial;

/// Apply the settled finds to `trial` (unsettled ones are left as they are) and return how
/// many samples changed. A swap exchanges coordinates and validity of its two markers over
/// its frames, so the undone samples are bit for bit the recorded ones; a jump marks its
/// marker's samples missing. Finds outside the trial's shape are skipped.
pub fn undo(trial: &mut Trial, finds: &[Find]) -> usize {
    let nf = trial.frames();
    let nm = trial.markers();
    let mut changed = 0;
    for x in finds.iter().filter(|x| x.settled) {
        if x.last >= nf || x.first > x.last || x.markers.iter().any(|&m| m >= nm) {
            continue;
        }
        match (x.kind, x.markers.as_slice()) {
            (FindKind::Swap, &[a, b]) if a != b => {
                for f in x.first..=x.last {
                    let (pa, pb) = (trial.xyz[a][f], trial.xyz[b][f]);
                    trial.xyz[a][f] = pb;
                    trial.xyz[b][f] = pa;
                    let (va, vb) = (trial.valid[a][f], trial.valid[b][f]);
                    trial.valid[a][f] = vb;
                    trial.valid[b][f] = va;
                    changed += 2;
                }
            }
            (FindKind::Jump, &[a]) => {
                for f in x.first..=x.last {
                    if trial.valid[a][f] {
                        trial.valid[a][f] = false;
                        changed += 1;
                    }
                }
            }
            _ => {}
        }
    }
    changed
}
