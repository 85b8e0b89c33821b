//! One pass of votes: in each frame read, every recorded fragment is matched to the marker
//! whose pairs it keeps best, given where the fragments labelled so far place the other
//! markers; one marker per fragment and one fragment per marker in a frame (the lowest
//! costs first). Each frame's match is a vote for the fragment's label.

use super::cost::marker_cost;
use super::model::Model;
use super::LabelOptions;
use crate::Trial;
use rayon::prelude::*;

/// Votes of one pass: `votes[fragment]` as `(marker, frames)` pairs, and the frames each
/// fragment was judged in (where the fragments labelled so far placed enough of some
/// marker's pairs to judge it: a frame without such evidence neither confirms nor denies).
pub(crate) struct Votes {
    pub votes: Vec<Vec<(usize, u32)>>,
    pub checked: Vec<u32>,
}

/// One frame's matches `(fragment, marker)` and the fragments it judged.
type FrameVotes = (Vec<(u32, u16)>, Vec<u32>);

/// Votes over every `step`-th frame, given the current `labels` of the fragments.
pub(crate) fn vote(
    model: &Model,
    t: &Trial,
    frags: &[super::Fragment],
    active: &[Vec<u32>],
    labels: &[Option<usize>],
    step: usize,
    opts: &LabelOptions,
) -> Votes {
    let frames: Vec<usize> = (0..active.len()).step_by(step.max(1)).collect();
    let per_frame: Vec<FrameVotes> = frames
        .par_iter()
        .map(|&f| frame_votes(model, t, frags, &active[f], labels, f, opts))
        .collect();
    let mut votes: Vec<Vec<(usize, u32)>> = vec![Vec::new(); frags.len()];
    let mut checked = vec![0u32; frags.len()];
    for (fv, judged) in per_frame {
        for g in judged {
            checked[g as usize] += 1;
        }
        for (g, m) in fv {
            let v = &mut votes[g as usize];
            match v.iter_mut().find(|(x, _)| *x == m as usize) {
                Some(e) => e.1 += 1,
                None => v.push((m as usize, 1)),
            }
        }
    }
    Votes { votes, checked }
}

fn frame_votes(
    model: &Model,
    t: &Trial,
    frags: &[super::Fragment],
    here: &[u32],
    labels: &[Option<usize>],
    f: usize,
    opts: &LabelOptions,
) -> FrameVotes {
    let k = model.markers;
    // Which fragment holds each marker here (the first, should two claim it).
    let mut holder: Vec<Option<u32>> = vec![None; k];
    for &g in here {
        if let Some(m) = labels[g as usize] {
            holder[m].get_or_insert(g);
        }
    }
    let pos = |g: u32| &t.xyz[frags[g as usize].row][f];
    let mut cands: Vec<(f64, u32, u16)> = Vec::new();
    let mut judged = Vec::new();
    for &g in here {
        let p = pos(g);
        let mut any = false;
        let at = |n: usize| holder[n].filter(|&h| h != g).map(pos);
        for m in 0..k {
            if !model.present[m] {
                continue;
            }
            let (sum, terms) = marker_cost(model, m, p, at, opts);
            if terms >= opts.min_neighbours {
                any = true;
                let c = sum / terms as f64;
                if c <= opts.accept {
                    cands.push((c, g, m as u16));
                }
            }
        }
        if any {
            judged.push(g);
        }
    }
    cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut taken_m = vec![false; k];
    let mut out = Vec::new();
    for (_, g, m) in cands {
        if taken_m[m as usize] || out.iter().any(|&(h, _)| h == g) {
            continue;
        }
        taken_m[m as usize] = true;
        out.push((g, m));
    }
    (out, judged)
}
