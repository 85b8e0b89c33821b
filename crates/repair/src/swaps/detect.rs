//! Finding swaps and jumps: every frame's markers checked against their links, the
//! exchange of two markers tried where links break, episodes built from the frames and
//! their boundaries placed by trajectory continuity.
//!
//! The rooms: what is asked and answered (`finds.rs`), the trial as the finding reads it
//! (`context.rs`), a pair's runs of exchanged frames (`runs.rs`), one swap (`swap.rs`), one
//! jump (`jump.rs`, with its steady-offset witness in `offset.rs`); this file runs them in
//! order over a trial.

use rayon::prelude::*;
use std::collections::BTreeMap;

use crate::error::Result;
use crate::swaps::links::{dist, LearnedLinks};
use crate::Trial;
use context::{Ctx, Verdict};
use jump::{jump_find, leap_jump_find};
use runs::{episodes, swap_runs};
use swap::swap_find;

mod context;
mod finds;
mod jump;
mod offset;
mod runs;
mod swap;

pub use finds::{Evidence, Find, FindKind, SwapOptions};

/// All swaps and jumps in `trial`, in order of first frame. Coordinates that are not
/// finite count as missing.
pub fn find_swaps(trial: &Trial, opts: &SwapOptions) -> Result<Vec<Find>> {
    Ok(find_swaps_learned(trial, opts)?.0)
}

/// [`find_swaps`], with the links it learned from `trial` (`None` when the trial has too
/// little to learn from: fewer than 2 markers or 3 frames), for a later stage on the same
/// markers that would learn them again ([`LearnedLinks::learn_again`]).
pub fn find_swaps_learned(
    trial: &Trial,
    opts: &SwapOptions,
) -> Result<(Vec<Find>, Option<LearnedLinks>)> {
    trial.check()?;
    opts.validate()?;
    let (nm, nf) = (trial.markers(), trial.frames());
    if nm < 2 || nf < 3 {
        return Ok((Vec::new(), None));
    }
    let learned = LearnedLinks::learn(
        trial,
        opts.max_link_spread_mm,
        opts.min_link_support,
        opts.max_links,
    );
    let cx = Ctx::learned(trial, learned.links.clone());
    let (mut swap_frames, jump_frames) = broken_link_frames(&cx, opts);
    leaps_into_places(&cx, &mut swap_frames);
    let mut finds = Vec::new();
    for &(a, b) in swap_frames.keys() {
        for (s, e, decided) in swap_runs(&cx, a, b, opts.max_hole) {
            finds.push(swap_find(&cx, a, b, s, e, decided, opts));
        }
    }
    let jumps = jump_finds(&cx, jump_frames, &finds, opts);
    finds.extend(jumps);
    finds.retain(|x| x.confidence >= opts.min_report);
    finds.sort_by_key(|x| (x.first, x.markers.clone()));
    Ok((finds, Some(learned)))
}

/// Swap frames per pair, jump frames per marker: frames where a marker's links break, and
/// the exchange that mends them if any.
#[allow(clippy::type_complexity)]
fn broken_link_frames(
    cx: &Ctx,
    opts: &SwapOptions,
) -> (
    BTreeMap<(usize, usize), Vec<usize>>,
    BTreeMap<usize, Vec<usize>>,
) {
    let (trial, nm, nf) = (cx.t, cx.t.markers(), cx.t.frames());
    let mut swap_frames: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    let mut jump_frames: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    // Each frame's markers whose links are half broken as labelled.
    let offs: Vec<Vec<usize>> = (0..nf)
        .into_par_iter()
        .map(|f| {
            (0..nm)
                .filter(|&m| cx.scores(m, f, None).is_some_and(|s| s.1 > 1.0))
                .collect()
        })
        .collect();
    // A marker with links that holds another's samples breaks its own links too: partners
    // are markers off at that frame, or markers without links to break.
    let linkless: Vec<usize> = (0..nm).filter(|&m| !cx.has_links(m)).collect();
    for (f, off) in offs.iter().enumerate() {
        let mut taken: Vec<usize> = Vec::new();
        for (i, &a) in off.iter().enumerate() {
            if taken.contains(&a) {
                continue;
            }
            let pa = trial.xyz[a][f];
            let mut best: Option<(f64, usize)> = None;
            // The off markers before `a` that are not taken were tried against `a` in their
            // own turn and did not mend with it (a pair's verdict is the same either way
            // round): only those after it are tried.
            for &b in off[i + 1..].iter().chain(&linkless) {
                if b == a
                    || taken.contains(&b)
                    || !cx.ok[b][f]
                    || dist(&pa, &trial.xyz[b][f]) > opts.partner_radius_mm
                {
                    continue;
                }
                // A marker without links is a partner only for one with two or more.
                if !cx.has_links(b) && cx.links[a].len() < 2 {
                    continue;
                }
                if cx.past_mending(a, b, f) {
                    continue;
                }
                if let Some(after) = cx.mends(a, b, f) {
                    if best.is_none_or(|(s, _)| after < s) {
                        best = Some((after, b));
                    }
                }
            }
            match best {
                Some((_, b)) => {
                    taken.extend([a, b]);
                    swap_frames.entry((a.min(b), a.max(b))).or_default().push(f);
                }
                None if cx.jump_verdict(a, f) == Verdict::Yes => {
                    jump_frames.entry(a).or_default().push(f)
                }
                None => {}
            }
        }
    }
    (swap_frames, jump_frames)
}

/// Pairs that leap into each other's places at one frame, links or not, added to
/// `swap_frames`.
fn leaps_into_places(cx: &Ctx, swap_frames: &mut BTreeMap<(usize, usize), Vec<usize>>) {
    let (nm, nf) = (cx.t.markers(), cx.t.frames());
    for f in 2..nf {
        let broke: Vec<usize> = (0..nm)
            .filter(|&m| {
                cx.step(m, f, (m, m), (0, 0), false)
                    .is_some_and(|st| st > cx.break_mm(m))
            })
            .collect();
        for (i, &a) in broke.iter().enumerate() {
            for &b in &broke[i + 1..] {
                if cx.switch_gain(a, b, f).is_some_and(|(l, u)| u < 0.25 * l) {
                    swap_frames.entry((a, b)).or_default().push(f);
                }
            }
            // A label that leaps onto where a marker whose gap starts here would be, or
            // from which a marker whose gap ends here goes on: the label took that
            // marker's point over its gap.
            for b in 0..nm {
                let gap_edge = (!cx.ok[b][f] && cx.ok[b][f - 1] && cx.ok[b][f - 2])
                    || (cx.ok[b][f] && !cx.ok[b][f - 1]);
                if b == a || !gap_edge {
                    continue;
                }
                if cx.switch_gain(a, b, f).is_some_and(|(l, u)| u < 0.25 * l) {
                    swap_frames.entry((a.min(b), a.max(b))).or_default().push(f);
                }
            }
        }
    }
}

/// The jumps: each marker's jump frames (those a swap in `swaps` explains left out) made
/// episodes, joined across the leaps that bound them; markers with fewer than two links by
/// continuity alone.
fn jump_finds(
    cx: &Ctx,
    mut jump_frames: BTreeMap<usize, Vec<usize>>,
    swaps: &[Find],
    opts: &SwapOptions,
) -> Vec<Find> {
    let (nm, nf) = (cx.t.markers(), cx.t.frames());
    let mut out = Vec::new();
    // Frames a swap explains are no jump of either marker.
    for x in swaps {
        for m in &x.markers {
            if let Some(v) = jump_frames.get_mut(m) {
                v.retain(|&f| f < x.first || f > x.last);
            }
        }
    }
    // Markers with fewer than two links never have jump frames (one link cannot say which
    // of its markers strayed): their jumps are found by continuity alone, below.
    let few_links: Vec<usize> = (0..nm).filter(|&m| cx.links[m].len() < 2).collect();
    for &a in &few_links {
        jump_frames.entry(a).or_default();
    }
    let swapped: Vec<(usize, usize, usize)> = swaps
        .iter()
        .flat_map(|x| x.markers.iter().map(move |&m| (m, x.first, x.last)))
        .collect();
    for (&a, frames) in &jump_frames {
        let mut eps = episodes(frames, opts.max_hole, nf, |f| cx.jump_verdict(a, f));
        let few = cx.links[a].len() < 2;
        // A span between two opposite leaps that holds jump frames is one jump, its edges
        // the leaps: the episodes inside it (a link can stay whole for a few frames of the
        // jump, splitting it) are joined into it.
        for (s, e) in cx.leap_pairs(a, opts.min_jump_frames) {
            let inside: Vec<usize> = frames
                .iter()
                .copied()
                .filter(|&f| f >= s && f <= e)
                .collect();
            // A swap leaves the same two leaps on both its markers.
            let in_swap = swapped.iter().any(|&(m, x, y)| m == a && s <= y && x <= e);
            // Markers with two or three links whose links decide no frame of the span
            // (an offset across them changes their lengths little): the leaps alone, with
            // the steady offset from the link partners required ([`leap_jump_find`]).
            let sparse = (2..=SPARSE_LINKS).contains(&cx.links[a].len());
            if in_swap || (inside.is_empty() && !few && !sparse) {
                continue;
            }
            eps.retain(|ep| ep.1 < s || ep.0 > e);
            eps.push((s, e, inside));
        }
        eps.sort_by_key(|ep| ep.0);
        for (s, e, decided) in eps {
            if e + 1 - s >= opts.min_jump_frames {
                let x = if decided.is_empty() {
                    leap_jump_find(cx, a, s, e, opts)
                } else {
                    jump_find(cx, a, s, e, decided, opts)
                };
                if x.last + 1 - x.first >= opts.min_jump_frames {
                    out.push(x);
                }
            }
        }
    }
    out
}

/// Most links a marker whose links decide no frame of a span between two opposite leaps
/// may have to be found by the leaps and the steady offset ([`leap_jump_find`]): with four
/// or more, links that stay whole over a jump say it is none, as far as links can.
const SPARSE_LINKS: usize = 3;
