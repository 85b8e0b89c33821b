//! One pass of votes: in each frame read, every recorded fragment is matched to the marker
//! whose pairs it keeps best, given where the fragments labelled so far place the other
//! markers; one marker per fragment and one fragment per marker in a frame (the lowest
//! costs first). Each frame's match is a vote for the fragment's label.

use super::cost::Around;
use super::fragments::Pieces;
use super::model::Model;
use super::options::LabelOptions;
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
    pc: &Pieces,
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
            (i, frame_votes(model, pc, labels, f, opts))
        })
        .collect();
    for (i, v) in fresh {
        cache.per[i] = Some(v);
    }
    let n = pc.frags.len();
    let mut votes: Vec<Vec<(usize, u32)>> = vec![Vec::new(); n];
    let mut checked = vec![0u32; n];
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

/// One frame's votes. Each marker's placed pairs are gathered once for the frame; a
/// fragment that itself holds one of them is costed without it (a point is not its own
/// neighbour).
fn frame_votes(
    model: &Model,
    pc: &Pieces,
    labels: &[Option<usize>],
    f: usize,
    opts: &LabelOptions,
) -> FrameVotes {
    let k = model.markers;
    let here = &pc.active[f];
    // Which fragment holds each marker here (the first, should two claim it).
    let mut holder: Vec<Option<u32>> = vec![None; k];
    for &g in here {
        if let Some(m) = labels[g as usize] {
            holder[m].get_or_insert(g);
        }
    }
    let pos = |g: u32| pc.at(g as usize, f);
    let mut cands: Vec<(f64, u32, u16)> = Vec::new();
    let mut judged = vec![false; here.len()];
    let (mut shared, mut own) = (Around::default(), Around::default());
    let mut involved: Vec<u32> = Vec::new();
    for m in 0..k {
        if !model.present[m] {
            continue;
        }
        shared.gather(model, m, |n| holder[n].map(pos));
        involved.clear();
        involved.extend(model.nb[m].iter().filter_map(|n| holder[n.other]));
        for c in &model.chiral[m] {
            involved.extend([c.a, c.b, c.c].iter().filter_map(|&x| holder[x]));
        }
        // A mean above `accept` over every pair the marker has is sure once the sum
        // passes this: no need to add the rest.
        let limit = opts.accept * model.nb[m].len() as f64;
        for (j, &g) in here.iter().enumerate() {
            let around = if involved.contains(&g) {
                own.gather(model, m, |n| holder[n].filter(|&h| h != g).map(pos));
                &own
            } else {
                &shared
            };
            let terms = around.terms();
            if terms < opts.min_neighbours {
                continue;
            }
            judged[j] = true;
            if let Some(sum) = around.cost(pos(g), opts.cap, limit) {
                let c = sum / terms as f64;
                if c <= opts.accept {
                    cands.push((c, g, m as u16));
                }
            }
        }
    }
    let judged = here
        .iter()
        .zip(&judged)
        .filter_map(|(&g, &j)| j.then_some(g))
        .collect();
    cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut taken_m = vec![false; k];
    let mut out = Vec::new();
    let mut done: Vec<u32> = Vec::new();
    for &(c, g, m) in &cands {
        if taken_m[m as usize] || done.contains(&g) {
            continue;
        }
        taken_m[m as usize] = true;
        done.push(g);
        // A fragment that fits another marker nearly as well is judged here but votes
        // for neither: two markers the frame cannot tell apart (a mirror pair, two
        // markers of one segment placed alike) would otherwise vote for whichever
        // labelling the neighbours hold, right or exchanged.
        let clear = opts.vote_margin <= 0.0 || {
            let rival = cands
                .iter()
                .filter(|r| r.1 == g && r.2 != m)
                .map(|r| r.0)
                .fold(f64::INFINITY, f64::min);
            rival - c >= opts.vote_margin
        };
        if clear {
            out.push((g, m));
        }
    }
    (out, judged)
}
