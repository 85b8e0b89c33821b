//! A pair's runs of exchanged frames: the cheapest sequence of states (labelled or
//! exchanged) over the trial, and the episodes a marker's broken frames make.

use super::context::{Ctx, Verdict};

/// Cost of switching between labelled and exchanged, in units of link tolerance: a swap
/// must mend more than this at its two edges together to be worth a run.
const SWITCH_COST: f64 = 2.5;
/// A frame's link error counts up to this many tolerances per marker, so that one wild
/// frame cannot carry a run.
const CLIP: f64 = 5.0;
/// The continuity term of a change of state counts up to this many units either way.
const CONT_CLIP: f64 = 6.0;

/// The frames where `a` and `b` hold each other's samples, by the cheapest sequence of
/// states (labelled or exchanged) over the whole trial: each frame costs its link error in
/// that state, each change of state [`SWITCH_COST`]. Frames without evidence cost nothing
/// either way, so runs pass through them. Returns (first, last, frames decided) of each
/// run of exchanged frames that holds a decided frame, its edges widened over undecided
/// frames for [`swap_find`] to place by continuity.
pub(super) fn swap_runs(
    cx: &Ctx,
    a: usize,
    b: usize,
    hole: usize,
) -> Vec<(usize, usize, Vec<usize>)> {
    let nf = cx.t.frames();
    let cost: Vec<(f64, f64)> = (0..nf)
        .map(|f| match cx.pair_scores(a, b, f) {
            Some((x, y, n)) => (x.min(n * CLIP), y.min(n * CLIP)),
            None => (0.0, 0.0),
        })
        .collect();
    // Changing state where the two trajectories leap into each other's places is cheap,
    // where they run smoothly dear: the continuity difference in units of the pair's
    // usual steps.
    let scale = (3.0 * (cx.usual[a] + cx.usual[b])).max(2.0);
    let switch: Vec<f64> = (0..nf)
        .map(|f| match cx.switch_gain(a, b, f) {
            Some((l, u)) => SWITCH_COST + ((u - l) / scale).clamp(-CONT_CLIP, CONT_CLIP),
            None => SWITCH_COST,
        })
        .collect();
    // Viterbi over two states, either free at the first frame.
    let mut acc = [cost[0].0, cost[0].1];
    let mut from: Vec<[u8; 2]> = Vec::with_capacity(nf);
    from.push([0, 1]);
    for (c, &sw) in cost[1..].iter().zip(&switch[1..]) {
        let mut next = [0.0; 2];
        let mut back = [0u8; 2];
        for (st, own) in [(0usize, c.0), (1usize, c.1)] {
            let stay = acc[st];
            let switch = acc[1 - st] + sw;
            if stay <= switch {
                next[st] = stay + own;
                back[st] = st as u8;
            } else {
                next[st] = switch + own;
                back[st] = (1 - st) as u8;
            }
        }
        acc = next;
        from.push(back);
    }
    let mut state = vec![0u8; nf];
    let mut st = if acc[1] < acc[0] { 1u8 } else { 0u8 };
    for f in (0..nf).rev() {
        state[f] = st;
        st = from[f][st as usize];
    }
    let mut out = Vec::new();
    let mut f = 0;
    while f < nf {
        if state[f] == 0 {
            f += 1;
            continue;
        }
        let s = f;
        while f < nf && state[f] == 1 {
            f += 1;
        }
        let e = f - 1;
        let decided: Vec<usize> = (s..=e)
            .filter(|&g| cx.swap_verdict(a, b, g) == Verdict::Yes)
            .collect();
        let (Some(&d0), Some(&d1)) = (decided.first(), decided.last()) else {
            // No link decides: kept when continuity alone calls both edges (or the one
            // edge of a run to the end) a leap into each other's places.
            let leap = |f: usize| switch[f] < 0.0;
            if leap(s) && (e + 1 == nf || leap(e + 1)) {
                out.push((s, e, Vec::new()));
            }
            continue;
        };
        let undecided = |g: usize| cx.swap_verdict(a, b, g) == Verdict::Undecided;
        let mut lo = d0;
        while lo > 0 && d0 - lo < hole && undecided(lo - 1) {
            lo -= 1;
        }
        let mut hi = d1;
        while hi + 1 < nf && hi - d1 < hole && undecided(hi + 1) {
            hi += 1;
        }
        // The run's own edges, where the cheapest sequence put them (links and continuity
        // together), when no frame between them and the decided frames says the pair is
        // as labelled: a marker strained in its own place leaves the exchange not quite
        // mended for a while (undecided, not labelled), and a swap to the trial's end has
        // no second edge (frames that cannot tell, a marker missing or no link seen, are
        // the swap's as much as its decided ones: exchanging them back is what restores
        // the recorded labels).
        let no = |g: usize| cx.swap_verdict(a, b, g) == Verdict::No;
        if e > hi && !(hi + 1..=e).any(no) {
            hi = e;
        }
        if s < lo && !(s..lo).any(no) {
            lo = s;
        }
        out.push((lo, hi, decided));
    }
    out
}

/// Runs of `frames` (sorted) joined across at most `hole` frames whose verdict is not
/// `No`, and widened over such frames at both ends: (first, last, decided frames).
pub(super) fn episodes(
    frames: &[usize],
    hole: usize,
    nf: usize,
    verdict: impl Fn(usize) -> Verdict,
) -> Vec<(usize, usize, Vec<usize>)> {
    let mut out: Vec<(usize, usize, Vec<usize>)> = Vec::new();
    for &f in frames {
        if let Some(last) = out.last_mut() {
            let gap = f - last.1 - 1;
            if gap <= hole && (last.1 + 1..f).all(|g| verdict(g) != Verdict::No) {
                last.1 = f;
                last.2.push(f);
                continue;
            }
        }
        out.push((f, f, vec![f]));
    }
    for ep in &mut out {
        let mut k = 0;
        while k < hole && ep.0 > 0 && verdict(ep.0 - 1) == Verdict::Undecided {
            ep.0 -= 1;
            k += 1;
        }
        let mut k = 0;
        while k < hole && ep.1 + 1 < nf && verdict(ep.1 + 1) == Verdict::Undecided {
            ep.1 += 1;
            k += 1;
        }
    }
    out
}
