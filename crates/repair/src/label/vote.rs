//! One pass of votes: in each frame read, every recorded fragment is matched to the marker
//! whose pairs it keeps best, given where the fragments labelled so far place the other
//! markers; one marker per fragment and one fragment per marker in a frame (the lowest
//! costs first). Each frame's match is a vote for the fragment's label.

use super::cost::marker_cost;
use super::model::Model;
use super::options::LabelOptions;
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

/// Each frame's votes, kept between passes: a pass re-reads only the frames where a
/// fragment's label changed (the others would vote as before), so the passes after the
/// first cost what changed, not the trial.
pub(crate) struct Cache {
    frames: Vec<usize>,
    per: Vec<Option<FrameVotes>>,
}

impl Cache {
    /// Every `step`-th frame of `n`, none read yet.
    pub fn new(n: usize, step: usize) -> Cache {
        let frames: Vec<usize> = (0..n).step_by(step.max(1)).collect();
        let per = vec![None; frames.len()];
        Cache { frames, per }
    }

    /// Forget the frames any of `changed` fragments is recorded in (all with `None`).
    pub fn forget(&mut self, frags: &[super::fragments::Fragment], changed: Option<&[usize]>) {
        let Some(changed) = changed else {
            self.per.iter_mut().for_each(|p| *p = None);
            return;
        };
        for &g in changed {
            let (a, b) = (frags[g].first, frags[g].last);
            let lo = self.frames.partition_point(|&f| f < a);
            let hi = self.frames.partition_point(|&f| f <= b);
            self.per[lo..hi].iter_mut().for_each(|p| *p = None);
        }
    }
}

/// Votes over the cache's frames, given the current `labels` of the fragments: the frames
/// forgotten are read again.
pub(crate) fn vote(
    model: &Model,
    t: &Trial,
    frags: &[super::fragments::Fragment],
    active: &[Vec<u32>],
    labels: &[Option<usize>],
    cache: &mut Cache,
    opts: &LabelOptions,
) -> Votes {
    let frames = &cache.frames;
    let fresh: Vec<(usize, FrameVotes)> = (0..frames.len())
        .filter(|&i| cache.per[i].is_none())
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|i| {
            let f = frames[i];
            (i, frame_votes(model, t, frags, &active[f], labels, f, opts))
        })
        .collect();
    for (i, v) in fresh {
        cache.per[i] = Some(v);
    }
    let mut votes: Vec<Vec<(usize, u32)>> = vec![Vec::new(); frags.len()];
    let mut checked = vec![0u32; frags.len()];
    for (fv, judged) in cache.per.iter().flatten() {
        for &g in judged {
            checked[g as usize] += 1;
        }
        for &(g, m) in fv {
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
    frags: &[super::fragments::Fragment],
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
            // A mean above `accept` over every pair the marker has is sure once the sum
            // passes this: no need to add the rest.
            let limit = opts.accept * model.nb[m].len() as f64;
            let (sum, terms) = marker_cost(model, m, p, at, opts, limit);
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
