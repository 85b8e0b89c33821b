//! The trial as the finding reads it ([`Ctx`]): which samples are data, the links learned
//! from it, each marker's usual step, and what every question of the finding asks of them
//! (a marker's position with two markers exchanged, its links' errors and their verdict,
//! its steps and leaps), with the medians those answers take.

use rayon::prelude::*;
use std::collections::BTreeMap;

use crate::swaps::links::{dist, finite, Link};
use crate::Trial;

/// A swap's verdict at a frame from the pair's scores as labelled and exchanged, summed
/// over `n` markers ([`Ctx::pair_scores`]).
pub(super) fn verdict(before: f64, after: f64, n: f64) -> Verdict {
    if after <= n && before > n && after < 0.5 * before {
        Verdict::Yes
    } else if before <= n && after > before + 1.0 {
        Verdict::No
    } else {
        Verdict::Undecided
    }
}

/// Per-frame verdict for one hypothesis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Verdict {
    Yes,
    No,
    Undecided,
}

pub(super) struct Ctx<'a> {
    pub(super) t: &'a Trial,
    pub(super) links: Vec<Vec<Link>>,
    pub(super) ok: Vec<Vec<bool>>,
    /// Each marker's usual step out of its predicted path (median, mm).
    pub(super) usual: Vec<f64>,
    /// Every sample's [`Ctx::scores`] as labelled (frame-major, −1 for none: a score is
    /// never negative), made once:
    /// the verdicts ask for the same marker and frame many times over, each pair's frames
    /// and each run's edges, and this is what the stage spends most on. 16 bytes a sample,
    /// two thirds of what the trial's coordinates hold, so it is made only up to
    /// [`LABELLED_MAX_SAMPLES`]; empty otherwise (and until made), the scores then computed
    /// as asked.
    pub(super) labelled: Vec<[f64; 2]>,
}

/// The most samples (markers × frames) whose labelled scores are kept: 32 MB. A long trial
/// (the 100 000-frame one of the memory test, 10 million samples) computes them as asked
/// rather than hold 160 MB more than the repair's own arrays.
const LABELLED_MAX_SAMPLES: usize = 2_000_000;

impl Ctx<'_> {
    /// Position of marker `i` at `f`, with markers `sw` exchanged.
    #[inline(always)]
    pub(super) fn pos(&self, i: usize, f: usize, sw: Option<(usize, usize)>) -> Option<[f64; 3]> {
        let j = match sw {
            Some((a, b)) if i == a => b,
            Some((a, b)) if i == b => a,
            _ => i,
        };
        self.ok[j][f].then(|| self.t.xyz[j][f])
    }

    /// Median over `m`'s links of |distance − learned| / tolerance at frame `f`, with
    /// markers `sw` exchanged; `None` without a position or a valid link. The lower
    /// median: above 1 only when a strict majority of the links broke (both of two), so
    /// one marker that strays does not drag its partners along.
    #[inline]
    pub(super) fn score(&self, m: usize, f: usize, sw: Option<(usize, usize)>) -> Option<f64> {
        self.scores(m, f, sw).map(|s| s.0)
    }

    /// The upper median, above 1 when half the links broke: two markers of one segment
    /// that trade places keep their own link, so each keeps one unbroken link more.
    #[inline]
    pub(super) fn loose(&self, m: usize, f: usize, sw: Option<(usize, usize)>) -> Option<f64> {
        self.scores(m, f, sw).map(|s| s.1)
    }

    #[inline(always)]
    pub(super) fn scores(
        &self,
        m: usize,
        f: usize,
        sw: Option<(usize, usize)>,
    ) -> Option<(f64, f64)> {
        if sw.is_none() {
            if let Some(&[lo, hi]) = self.labelled.get(f * self.links.len() + m) {
                return (lo >= 0.0 || lo.is_nan()).then_some((lo, hi));
            }
        }
        self.link_scores(m, f, sw)
    }

    /// [`Ctx::scores`] computed from the links.
    pub(super) fn link_scores(
        &self,
        m: usize,
        f: usize,
        sw: Option<(usize, usize)>,
    ) -> Option<(f64, f64)> {
        let p = self.pos(m, f, sw)?;
        let mut z = [0.0f64; 32];
        let mut k = 0;
        for l in &self.links[m] {
            if let Some(q) = self.pos(l.other, f, sw) {
                if k < z.len() {
                    z[k] = (dist(&p, &q) - l.d0_mm).abs() / l.tol_mm;
                    k += 1;
                }
            }
        }
        medians(&z[..k])
    }

    /// Every sample's [`Ctx::link_scores`] as labelled, frame-major, `[-1, -1]` for none.
    ///
    /// Each link's error is computed once per frame and read by both its markers (a link
    /// is in both markers' lists, with the same length and tolerance, and the distance
    /// from either end is the same number), and the frames go in blocks so that each link
    /// reads its two markers' rows in order: marker by marker at every frame, the rows of
    /// all the markers were read at once, a cache miss apiece. The same numbers as
    /// [`Ctx::link_scores`] sample by sample.
    pub(super) fn labelled_scores(&self) -> Vec<[f64; 2]> {
        const BLOCK: usize = 256;
        let (nm, nf) = (self.links.len(), self.t.frames());
        // Each link once, and each marker's links (in order) as indices into that list.
        let mut pairs: Vec<(usize, usize, f64, f64)> = Vec::new();
        let mut index: BTreeMap<(usize, usize), usize> = BTreeMap::new();
        let ids: Vec<Vec<usize>> = (0..nm)
            .map(|m| {
                self.links[m]
                    .iter()
                    .map(|l| {
                        *index
                            .entry((m.min(l.other), m.max(l.other)))
                            .or_insert_with(|| {
                                pairs.push((m, l.other, l.d0_mm, l.tol_mm));
                                pairs.len() - 1
                            })
                    })
                    .collect()
            })
            .collect();
        let mut out = vec![[-1.0f64; 2]; nm * nf];
        out.par_chunks_mut(BLOCK * nm)
            .enumerate()
            .for_each(|(block, chunk)| {
                let f0 = block * BLOCK;
                let len = chunk.len() / nm;
                // Each link's error at each frame of the block, −1 where an end is missing.
                let mut err = vec![-1.0f64; pairs.len() * len];
                for (row, &(a, b, d0, tol)) in err.chunks_mut(len).zip(&pairs) {
                    let (oa, ob) = (&self.ok[a][f0..f0 + len], &self.ok[b][f0..f0 + len]);
                    let (xa, xb) = (&self.t.xyz[a][f0..f0 + len], &self.t.xyz[b][f0..f0 + len]);
                    for (k, e) in row.iter_mut().enumerate() {
                        if oa[k] && ob[k] {
                            *e = (dist(&xa[k], &xb[k]) - d0).abs() / tol;
                        }
                    }
                }
                // Frame by frame, each marker in turn: the block's output is written in
                // order, and the errors one frame reads are one column of the block's
                // rows, the same cache lines for the next frames.
                let few = ids.iter().all(|ids| ids.len() <= 8);
                for (k, out) in chunk.chunks_mut(nm).enumerate() {
                    for (m, (ids, slot)) in ids.iter().zip(out.iter_mut()).enumerate() {
                        if !self.ok[m][f0 + k] {
                            continue;
                        }
                        if few {
                            // Up to 8 links (the default's most): each link's error goes
                            // into the network as its bits, as it stands. An error's sign
                            // bit is clear and the mark for a missing end (−1) has it set,
                            // so as integers the missing ones order after every error and
                            // before the padding: the errors come out first, in the order
                            // [`medians`] gives them, and their count is the entries with
                            // the sign bit clear. No copy of the seen errors is made first.
                            let mut v = [u64::MAX; 8];
                            for (x, &id) in v.iter_mut().zip(ids) {
                                *x = err[id * len + k].to_bits();
                            }
                            sort8(&mut v);
                            let n = v.iter().filter(|&&b| b >> 63 == 0).count();
                            if n > 0 {
                                *slot = [f64::from_bits(v[(n - 1) / 2]), f64::from_bits(v[n / 2])];
                            }
                            continue;
                        }
                        let mut z = [0.0f64; 32];
                        let mut n = 0;
                        for &id in ids {
                            let e = err[id * len + k];
                            // An error's sign bit is clear (an absolute value over a
                            // positive tolerance, NaN included); the mark for a missing
                            // end is −1.
                            if e.is_sign_positive() && n < z.len() {
                                z[n] = e;
                                n += 1;
                            }
                        }
                        if let Some((lo, hi)) = medians(&z[..n]) {
                            *slot = [lo, hi];
                        }
                    }
                }
            });
        out
    }

    /// How much `m`'s links change across an edge between `inside` and `outside` frames:
    /// per link, its mean signed length error over the seen frames of each side, the
    /// difference in units of its tolerance; the lower median over the links seen on both
    /// sides (above 1 only when a strict majority changed, as [`Ctx::score`]). `None`
    /// when fewer than two links are seen on both sides.
    ///
    /// A label that lands on another point moves the marker by an offset at once, and
    /// the lengths of its links change at the edge by that offset along each link. A
    /// strained pose (a bent knee the links, learned from the trial's majority, do not
    /// keep) breaks the links as much just outside an episode as inside, and a
    /// reconstruction settling after a gap has come back by the edge: neither changes
    /// the links across it.
    pub(super) fn link_change(
        &self,
        m: usize,
        inside: std::ops::Range<usize>,
        outside: std::ops::Range<usize>,
    ) -> Option<f64> {
        let mean_err = |l: &Link, frames: std::ops::Range<usize>| -> Option<f64> {
            let (mut sum, mut n) = (0.0, 0usize);
            for f in frames {
                if let (Some(p), Some(q)) = (self.pos(m, f, None), self.pos(l.other, f, None)) {
                    sum += dist(&p, &q) - l.d0_mm;
                    n += 1;
                }
            }
            (n > 0).then(|| sum / n as f64)
        };
        let mut z: Vec<f64> = self.links[m]
            .iter()
            .filter_map(|l| {
                let a = mean_err(l, inside.clone())?;
                let b = mean_err(l, outside.clone())?;
                Some((a - b).abs() / l.tol_mm)
            })
            .collect();
        if z.len() < 2 {
            return None;
        }
        signal::order::lower_median(&mut z)
    }

    /// Links of `m` with both ends seen at `f`.
    pub(super) fn seen_links(&self, m: usize, f: usize) -> usize {
        if !self.ok[m][f] {
            return 0;
        }
        self.links[m].iter().filter(|l| self.ok[l.other][f]).count()
    }

    pub(super) fn has_links(&self, m: usize) -> bool {
        !self.links[m].is_empty()
    }

    /// Swap of `a` and `b` at `f`: the sum of their scores as labelled and exchanged, and
    /// how many markers the sums hold.
    ///
    /// Each marker's links judge the samples its label holds as labelled and exchanged.
    /// Where one marker's links cannot (a link partner hidden), the other's judge alone;
    /// where one marker is missing, the other's sample is judged as its own label and as
    /// the missing one's (through that marker's links). So a swap is followed while one
    /// of its markers, or a partner of it, is hidden, as near a trial's end. Both only when
    /// both markers have two links or more: one link cannot say which of its two markers
    /// strayed.
    pub(super) fn pair_scores(&self, a: usize, b: usize, f: usize) -> Option<(f64, f64, f64)> {
        let sw = Some((a, b));
        let own = |m: usize| Some((self.loose(m, f, None)?, self.loose(m, f, sw)?));
        // A marker without links is judged through its partner's links alone, whichever
        // of the two it is (pairs are kept lower index first, so either can be).
        if !self.has_links(b) {
            return own(a).map(|(x, y)| (x, y, 1.0));
        }
        if !self.has_links(a) {
            return own(b).map(|(x, y)| (x, y, 1.0));
        }
        let alone = self.links[a].len() >= 2 && self.links[b].len() >= 2;
        match (own(a), own(b)) {
            (Some((sa, ta)), Some((sb, tb))) => Some((sa + sb, ta + tb, 2.0)),
            (Some((x, y)), None) | (None, Some((x, y))) if alone => Some((x, y, 1.0)),
            _ if !alone => None,
            // One marker missing: its partner's sample as its own label and as the other.
            _ => match (self.ok[a][f], self.ok[b][f]) {
                (true, false) => Some((self.loose(a, f, None)?, self.loose(b, f, sw)?, 1.0)),
                (false, true) => Some((self.loose(b, f, None)?, self.loose(a, f, sw)?, 1.0)),
                _ => None,
            },
        }
    }

    pub(super) fn swap_verdict(&self, a: usize, b: usize, f: usize) -> Verdict {
        let Some((before, after, n)) = self.pair_scores(a, b, f) else {
            return Verdict::Undecided;
        };
        verdict(before, after, n)
    }

    /// The exchanged score where [`Ctx::swap_verdict`] says `Yes`, `None` elsewhere.
    pub(super) fn mends(&self, a: usize, b: usize, f: usize) -> Option<f64> {
        let (before, after, n) = self.pair_scores(a, b, f)?;
        (verdict(before, after, n) == Verdict::Yes).then_some(after)
    }

    /// True where the exchange of `a` and `b` at `f` cannot mend ([`Ctx::swap_verdict`]
    /// is not `Yes`), told from one marker's exchanged score, the other's left uncomputed:
    /// wherever a marker's own scores enter [`Ctx::pair_scores`], its exchanged score is
    /// a term of the exchanged sum, the other term not negative, and a `Yes` needs that
    /// sum at most the markers counted (2 at most). Most exchanges tried between the
    /// markers off at a frame are this far from mending, and the second marker's score
    /// then need not be computed.
    pub(super) fn past_mending(&self, a: usize, b: usize, f: usize) -> bool {
        let sw = Some((a, b));
        let over = |m: usize| {
            self.loose(m, f, None).is_some() && self.loose(m, f, sw).is_some_and(|t| t > 2.0)
        };
        over(a) || over(b)
    }

    pub(super) fn jump_verdict(&self, a: usize, f: usize) -> Verdict {
        // One link cannot say which of its two markers strayed.
        if self.seen_links(a, f) < 2 {
            return Verdict::Undecided;
        }
        match self.score(a, f, None) {
            Some(s) if s > 1.0 => Verdict::Yes,
            Some(s) if s <= 0.7 => Verdict::No,
            _ => Verdict::Undecided,
        }
    }

    /// A step out of the predicted path this large breaks `m`'s continuity: well beyond
    /// its usual steps, and at least 8 mm.
    pub(super) fn break_mm(&self, m: usize) -> f64 {
        (6.0 * self.usual[m]).max(8.0)
    }

    /// Continuity of `a` and `b` at `f` as labelled (l) and with their labels changing
    /// between `f − 1` and `f` (u): the summed steps out of the paths predicted from the
    /// two frames before. Entering and leaving a swap give the same u.
    ///
    /// One marker missing on one side of the change (a label that took the other's point
    /// while that marker's own label is missing: its gap starts at `f` or ends at `f − 1`)
    /// leaves one step each way: the seen sample against both paths (entering), or the
    /// one path against both samples (leaving). That is the continuity a person reads in
    /// a label that leaps onto where another marker's trajectory, hidden over exactly
    /// those frames, would be.
    pub(super) fn switch_gain(&self, a: usize, b: usize, f: usize) -> Option<(f64, f64)> {
        if f < 2 {
            return None;
        }
        let pred = |m: usize| -> Option<[f64; 3]> {
            let (p0, p1) = (self.pos(m, f - 2, None)?, self.pos(m, f - 1, None)?);
            Some([
                2.0 * p1[0] - p0[0],
                2.0 * p1[1] - p0[1],
                2.0 * p1[2] - p0[2],
            ])
        };
        let (pa, pb) = (pred(a), pred(b));
        let (xa, xb) = (self.pos(a, f, None), self.pos(b, f, None));
        let d = |x: Option<[f64; 3]>, p: Option<[f64; 3]>| Some(dist(&x?, &p?));
        let (l, u) = ([d(xa, pa), d(xb, pb)], [d(xb, pa), d(xa, pb)]);
        let sum = |v: [Option<f64>; 2]| v.iter().flatten().sum::<f64>();
        let n = |v: [Option<f64>; 2]| v.iter().flatten().count();
        // As many steps each way: both markers, or the one sample or path that spans the
        // change.
        (n(l) > 0 && n(l) == n(u)).then(|| (sum(l), sum(u)))
    }

    /// How far `m` leaps between `f − 1` and `f`: that step against the mean of the steps
    /// either side (a centred second difference). A label that lands on another point
    /// leaps once by the offset; the frames beside the edge show half of it, so the edge is
    /// where this is largest.
    pub(super) fn leap(&self, m: usize, f: usize) -> Option<f64> {
        self.leap_vec(m, f).map(|d| norm(&d))
    }

    /// [`Ctx::leap`] as a vector: a jump's two leaps, going and coming back, are opposite.
    #[inline]
    pub(super) fn leap_vec(&self, m: usize, f: usize) -> Option<[f64; 3]> {
        if f < 2 || f + 1 >= self.t.frames() {
            return None;
        }
        let p = |g: usize| self.pos(m, g, None);
        let (p0, p1, p2, p3) = (p(f - 2)?, p(f - 1)?, p(f)?, p(f + 1)?);
        Some(std::array::from_fn(|c| {
            (p2[c] - p1[c]) - 0.5 * ((p1[c] - p0[c]) + (p3[c] - p2[c]))
        }))
    }

    /// Spans `(first, last)` of `m` that open with a leap and close with the opposite leap
    /// (a label that landed on another point and came back: the offset the first leap
    /// adds, the second takes away), each leap a break and the largest of its neighbours,
    /// `min_len` to [`MAX_LEAP_SPAN`] frames apart.
    pub(super) fn leap_pairs(&self, m: usize, min_len: usize) -> Vec<(usize, usize)> {
        let nf = self.t.frames();
        let size: Vec<f64> = (0..nf).map(|f| self.leap(m, f).unwrap_or(0.0)).collect();
        let br = self.break_mm(m);
        let leaps: Vec<(usize, [f64; 3])> = (2..nf.saturating_sub(1))
            .filter(|&f| size[f] > br && size[f] >= size[f - 1] && size[f] >= size[f + 1])
            .filter_map(|f| Some((f, self.leap_vec(m, f)?)))
            .collect();
        let mut out = Vec::new();
        let mut i = 0;
        while i < leaps.len() {
            let (f1, v1) = leaps[i];
            let back = leaps[i + 1..]
                .iter()
                .enumerate()
                .take_while(|(_, (f2, _))| f2 - f1 <= MAX_LEAP_SPAN)
                .find(|(_, (f2, v2))| {
                    let sum: [f64; 3] = std::array::from_fn(|c| v1[c] + v2[c]);
                    f2 - f1 >= min_len && norm(&sum) < 0.5 * norm(&v1).min(norm(v2))
                });
            match back {
                Some((k, &(f2, _))) => {
                    out.push((f1, f2 - 1));
                    i += k + 2;
                }
                None => i += 1,
            }
        }
        out
    }

    /// Size of marker `m`'s step out of its predicted path (constant velocity) at `f`,
    /// with `sw` exchanged on the frames `span` holds.
    #[inline]
    pub(super) fn step(
        &self,
        m: usize,
        f: usize,
        sw: (usize, usize),
        span: (usize, usize),
        apply: bool,
    ) -> Option<f64> {
        if f < 2 {
            return None;
        }
        let at = |g: usize| {
            let s = (apply && g >= span.0 && g <= span.1).then_some(sw);
            self.pos(m, g, s)
        };
        let (p0, p1, p2) = (at(f - 2)?, at(f - 1)?, at(f)?);
        let pred = [
            2.0 * p1[0] - p0[0],
            2.0 * p1[1] - p0[1],
            2.0 * p1[2] - p0[2],
        ];
        Some(dist(&p2, &pred))
    }
}

/// Longest span between a jump's two leaps looked for, frames.
const MAX_LEAP_SPAN: usize = 120;

impl<'a> Ctx<'a> {
    /// What the finding reads of `trial`: which samples are data, the links learned from
    /// it, each marker's usual step, and (on trials small enough) the labelled scores.
    /// The links are `links`, learned from `trial` ([`crate::swaps::LearnedLinks`]).
    pub(super) fn learned(trial: &'a Trial, links: Vec<Vec<Link>>) -> Ctx<'a> {
        let (nm, nf) = (trial.markers(), trial.frames());
        let ok: Vec<Vec<bool>> = (0..nm)
            .map(|m| {
                (0..nf)
                    .map(|f| trial.valid[m][f] && finite(&trial.xyz[m][f]))
                    .collect()
            })
            .collect();
        let mut cx = Ctx {
            t: trial,
            links,
            ok,
            usual: Vec::new(),
            labelled: Vec::new(),
        };
        cx.usual = (0..nm)
            .map(|m| {
                median(
                    (2..nf)
                        .step_by((nf / 2000).max(1))
                        .filter_map(|f| cx.step(m, f, (m, m), (0, 0), false))
                        .collect(),
                )
            })
            .collect();
        if nm * nf <= LABELLED_MAX_SAMPLES {
            cx.labelled = cx.labelled_scores();
        }
        cx
    }
}

/// The lower and upper medians of a marker's link errors (`None` for none).
///
/// The errors are ordered by their bits: each is an absolute value over a positive
/// tolerance, its sign bit clear, and numbers with the sign bit clear order by their bits
/// as [`f64::total_cmp`] orders them (which spent most of the sort turning the bits of each
/// number into that order). Up to 8 errors (the default number of links) go through a
/// sorting network of 19 exchanges without a branch, the unused places filled with the
/// largest key so that they sort last; this runs for every marker at every frame. More go
/// through an insertion sort. Either way the sorted keys, and so the medians, are the
/// ones [`f64::total_cmp`] gives.
fn medians(z: &[f64]) -> Option<(f64, f64)> {
    let k = z.len();
    if k == 0 {
        return None;
    }
    debug_assert!(z.iter().all(|x| x.is_sign_positive()));
    let (lo, hi) = ((k - 1) / 2, k / 2);
    if k <= 8 {
        // Element by element over all 8 places (a copy of `k` would be a call to copy
        // memory, which cost more than the sort).
        let v: [u64; 8] = std::array::from_fn(|i| z.get(i).map_or(u64::MAX, |e| e.to_bits()));
        let mut v = v;
        sort8(&mut v);
        return Some((f64::from_bits(v[lo]), f64::from_bits(v[hi])));
    }
    let mut v: Vec<u64> = z.iter().map(|e| e.to_bits()).collect();
    for i in 1..k {
        let mut j = i;
        while j > 0 && v[j - 1] > v[j] {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
    Some((f64::from_bits(v[lo]), f64::from_bits(v[hi])))
}

/// Sort 8 keys by a sorting network (19 exchanges, 6 layers: Knuth, TAOCP 5.3.4), written
/// out exchange by exchange so that the keys stay in registers: looped over a table of the
/// exchanges, each read and wrote the array in memory, waiting on the one before.
#[inline(always)]
fn sort8(v: &mut [u64; 8]) {
    let [mut a0, mut a1, mut a2, mut a3, mut a4, mut a5, mut a6, mut a7] = *v;
    macro_rules! x {
        ($p:ident, $q:ident) => {{
            let (lo, hi) = ($p.min($q), $p.max($q));
            $p = lo;
            $q = hi;
        }};
    }
    x!(a0, a2);
    x!(a1, a3);
    x!(a4, a6);
    x!(a5, a7);
    x!(a0, a4);
    x!(a1, a5);
    x!(a2, a6);
    x!(a3, a7);
    x!(a0, a1);
    x!(a2, a3);
    x!(a4, a5);
    x!(a6, a7);
    x!(a2, a4);
    x!(a3, a5);
    x!(a1, a4);
    x!(a3, a6);
    x!(a1, a2);
    x!(a3, a4);
    x!(a5, a6);
    *v = [a0, a1, a2, a3, a4, a5, a6, a7];
}

pub(super) fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The upper median (the element at half the length once sorted), 0 for none.
pub(super) fn median(mut v: Vec<f64>) -> f64 {
    signal::order::upper_median(&mut v).unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::{medians, sort8, Ctx};
    use crate::swaps::links::learn_links;
    use crate::Trial;

    /// Each sample's kept scores as labelled are those [`Ctx::link_scores`] computes for it,
    /// bit for bit, with up to 8 links a marker (the network on the errors as they stand)
    /// and with more (the general path): two rigid clusters of 12 moving and turning, noise,
    /// samples missing, a swap and a jump inside.
    #[test]
    fn labelled_scores_as_computed() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let (nm, nf) = (24, 700);
        let offsets: Vec<[f64; 3]> = (0..nm)
            .map(|_| [0.0, 0.0, 0.0].map(|_: f64| 200.0 * next() - 100.0))
            .collect();
        let mut xyz = vec![vec![[0.0; 3]; nf]; nm];
        let mut valid = vec![vec![true; nf]; nm];
        for f in 0..nf {
            let t = f as f64 / 100.0;
            for m in 0..nm {
                let g = m % 2;
                let a = t * (1.0 + g as f64) * 0.7;
                let o = offsets[m];
                let c = [400.0 * g as f64 + 50.0 * t, 30.0 * (t * 2.0).sin(), 900.0];
                xyz[m][f] = [
                    c[0] + o[0] * a.cos() - o[1] * a.sin() + next() - 0.5,
                    c[1] + o[0] * a.sin() + o[1] * a.cos() + next() - 0.5,
                    c[2] + o[2] + next() - 0.5,
                ];
                valid[m][f] = next() > 0.08;
            }
        }
        let (first, rest) = xyz.split_at_mut(1);
        first[0][200..260].swap_with_slice(&mut rest[1][200..260]);
        for p in &mut xyz[4][400..430] {
            p[0] += 30.0;
        }
        let trial = Trial::new(100.0, xyz, valid).expect("a trial");
        for max_links in [8, 12] {
            let links = learn_links(&trial, 2.5, 0.5, max_links);
            assert!(links.iter().all(|l| l.len() >= 2), "{links:?}");
            let most = links.iter().map(|l| l.len()).max().unwrap_or(0);
            assert_eq!(most > 8, max_links > 8, "{most} links");
            let ok = (0..nm)
                .map(|m| (0..nf).map(|f| trial.valid[m][f]).collect())
                .collect();
            let cx = Ctx {
                t: &trial,
                links,
                ok,
                usual: Vec::new(),
                labelled: Vec::new(),
            };
            let kept = cx.labelled_scores();
            let mut seen = 0;
            for f in 0..nf {
                for m in 0..nm {
                    let want = cx
                        .link_scores(m, f, None)
                        .map_or([-1.0; 2], |(a, b)| [a, b]);
                    let got = kept[f * nm + m];
                    assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{m} at {f}");
                    seen += usize::from(got[0] >= 0.0);
                }
            }
            assert!(seen > nm * nf / 2, "{seen}");
        }
    }

    /// The network sorts every input of 0s and 1s (so, by the 0-1 principle, every input).
    #[test]
    fn sort8_sorts() {
        for bits in 0u32..256 {
            let mut v: [u64; 8] = std::array::from_fn(|i| u64::from((bits >> i) & 1));
            sort8(&mut v);
            assert!(v.windows(2).all(|w| w[0] <= w[1]), "{bits:08b}: {v:?}");
        }
    }

    /// The medians are those of the sorted errors, for every count of links up to 12.
    #[test]
    fn medians_as_sorted() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for k in 1..=12 {
            for _ in 0..200 {
                let z: Vec<f64> = (0..k)
                    .map(|_| {
                        x ^= x << 13;
                        x ^= x >> 7;
                        x ^= x << 17;
                        // Ties too: a few values only.
                        (x % 7) as f64 * 0.25
                    })
                    .collect();
                let mut s = z.clone();
                s.sort_by(f64::total_cmp);
                assert_eq!(medians(&z), Some((s[(k - 1) / 2], s[k / 2])));
            }
        }
        assert_eq!(medians(&[]), None);
    }
}
