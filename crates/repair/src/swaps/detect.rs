//! Finding swaps and jumps: every frame's markers checked against their links, the
//! exchange of two markers tried where links break, episodes built from the frames and
//! their boundaries placed by trajectory continuity.

use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

use super::links::{dist, finite, learn_links, Link};
use crate::error::{RepairError, Result};
use crate::Trial;

mod offset;

/// What the detector looks for and when a find counts as settled. Build with
/// [`SwapOptions::default`] and change fields; [`SwapOptions::validate`] checks them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SwapOptions {
    /// A pair is a link only if its distance's robust spread is at most this (mm).
    pub max_link_spread_mm: f64,
    /// Share of the sampled frames a link's distance must keep (a majority, so that a
    /// swap over part of the trial cannot move the learned distance).
    pub min_link_support: f64,
    /// Links kept per marker (the most rigid first).
    pub max_links: usize,
    /// Markers farther apart than this are not tried as a swap (mm).
    pub partner_radius_mm: f64,
    /// Frames of undecided evidence (a marker missing, both markers passing close) that
    /// may sit inside an episode or at its edges.
    pub max_hole: usize,
    /// Jumps shorter than this are left to the spike stage.
    pub min_jump_frames: usize,
    /// Finds below this confidence are dropped: evidence this weak is what a trial's
    /// own noise gives.
    pub min_report: f64,
    /// Finds at or above this confidence are settled: [`super::undo()`] acts on them; the
    /// others are only reported.
    pub min_confidence: f64,
}

impl Default for SwapOptions {
    fn default() -> Self {
        SwapOptions {
            max_link_spread_mm: 2.5,
            min_link_support: 0.5,
            max_links: 8,
            partner_radius_mm: 500.0,
            max_hole: 10,
            min_jump_frames: 5,
            min_report: 0.6,
            min_confidence: 0.7,
        }
    }
}

impl SwapOptions {
    /// Every field in its range.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: &str| Err(RepairError::Option(format!("swaps: {what}")));
        if !(self.max_link_spread_mm > 0.0 && self.max_link_spread_mm.is_finite()) {
            return bad("max_link_spread_mm must be a positive number");
        }
        if !(self.min_link_support >= 0.5 && self.min_link_support <= 1.0) {
            return bad("min_link_support must be from 0.5 to 1");
        }
        if self.max_links == 0 {
            return bad("max_links must be at least 1");
        }
        if self.partner_radius_mm.is_nan() || self.partner_radius_mm <= 0.0 {
            return bad("partner_radius_mm must be above 0");
        }
        if !(0.0..=1.0).contains(&self.min_confidence) || !(0.0..=1.0).contains(&self.min_report) {
            return bad("min_confidence and min_report must be from 0 to 1");
        }
        Ok(())
    }
}

/// A swap (two markers holding each other's samples) or a jump (one marker's label on
/// another point).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FindKind {
    Swap,
    Jump,
}

/// What a find rests on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evidence {
    /// Links of the find's markers (learned from the trial).
    pub links: usize,
    /// Frames of the episode where the links decided (the rest were bridged).
    pub frames_decided: usize,
    /// Median link error of the markers as labelled over the decided frames, in units of
    /// each link's tolerance (above 1: broken), summed over the markers (a jump found by
    /// its leaps alone: over the span's frames where its one link is seen).
    pub link_error: f64,
    /// The same with the swap exchanged back (for a jump: the error once the marker sits
    /// where its links put it, 0).
    pub link_error_undone: f64,
    /// At the episode's edges, the continuity of the trajectories as labelled against as
    /// undone: how many edges the undone version is smoother at, and how many edges could
    /// be checked.
    pub edges_smoother: usize,
    pub edges_checked: usize,
    /// Largest step out of the predicted path (mm) at the episode's edges as labelled.
    pub edge_step_mm: f64,
    /// A jump's steady-offset witness, 0 to 1: its two edge leaps cancel, both break the
    /// marker's path, and between them the marker holds that offset from its link
    /// partners; `None` where it could not be measured (and for swaps).
    pub offset_share: Option<f64>,
}

/// One swap or jump, frames 0-based and inclusive.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Find {
    pub kind: FindKind,
    /// Two markers (swap, lower index first) or one (jump).
    pub markers: Vec<usize>,
    pub first: usize,
    pub last: usize,
    /// 0 to 1: how strongly the links and the continuity agree.
    pub confidence: f64,
    /// Confidence at least [`SwapOptions::min_confidence`]: undone, not only reported.
    pub settled: bool,
    pub evidence: Evidence,
}

/// A swap's verdict at a frame from the pair's scores as labelled and exchanged, summed
/// over `n` markers ([`Ctx::pair_scores`]).
fn verdict(before: f64, after: f64, n: f64) -> Verdict {
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
enum Verdict {
    Yes,
    No,
    Undecided,
}

struct Ctx<'a> {
    t: &'a Trial,
    links: Vec<Vec<Link>>,
    ok: Vec<Vec<bool>>,
    /// Each marker's usual step out of its predicted path (median, mm).
    usual: Vec<f64>,
    /// Every sample's [`Ctx::scores`] as labelled (frame-major, −1 for none: a score is
    /// never negative), made once:
    /// the verdicts ask for the same marker and frame many times over, each pair's frames
    /// and each run's edges, and this is what the stage spends most on. 16 bytes a sample,
    /// two thirds of what the trial's coordinates hold, so it is made only up to
    /// [`LABELLED_MAX_SAMPLES`]; empty otherwise (and until made), the scores then computed
    /// as asked.
    labelled: Vec<[f64; 2]>,
}

/// The most samples (markers × frames) whose labelled scores are kept: 32 MB. A long trial
/// (the 100 000-frame one of the memory test, 10 million samples) computes them as asked
/// rather than hold 160 MB more than the repair's own arrays.
const LABELLED_MAX_SAMPLES: usize = 2_000_000;

impl Ctx<'_> {
    /// Position of marker `i` at `f`, with markers `sw` exchanged.
    #[inline(always)]
    fn pos(&self, i: usize, f: usize, sw: Option<(usize, usize)>) -> Option<[f64; 3]> {
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
    fn score(&self, m: usize, f: usize, sw: Option<(usize, usize)>) -> Option<f64> {
        self.scores(m, f, sw).map(|s| s.0)
    }

    /// The upper median, above 1 when half the links broke: two markers of one segment
    /// that trade places keep their own link, so each keeps one unbroken link more.
    #[inline]
    fn loose(&self, m: usize, f: usize, sw: Option<(usize, usize)>) -> Option<f64> {
        self.scores(m, f, sw).map(|s| s.1)
    }

    #[inline(always)]
    fn scores(&self, m: usize, f: usize, sw: Option<(usize, usize)>) -> Option<(f64, f64)> {
        if sw.is_none() {
            if let Some(&[lo, hi]) = self.labelled.get(f * self.links.len() + m) {
                return (lo >= 0.0 || lo.is_nan()).then_some((lo, hi));
            }
        }
        self.link_scores(m, f, sw)
    }

    /// [`Ctx::scores`] computed from the links.
    fn link_scores(&self, m: usize, f: usize, sw: Option<(usize, usize)>) -> Option<(f64, f64)> {
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
    fn labelled_scores(&self) -> Vec<[f64; 2]> {
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
    fn link_change(
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
    fn seen_links(&self, m: usize, f: usize) -> usize {
        if !self.ok[m][f] {
            return 0;
        }
        self.links[m].iter().filter(|l| self.ok[l.other][f]).count()
    }

    fn has_links(&self, m: usize) -> bool {
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
    fn pair_scores(&self, a: usize, b: usize, f: usize) -> Option<(f64, f64, f64)> {
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

    fn swap_verdict(&self, a: usize, b: usize, f: usize) -> Verdict {
        let Some((before, after, n)) = self.pair_scores(a, b, f) else {
            return Verdict::Undecided;
        };
        verdict(before, after, n)
    }

    /// The exchanged score where [`Ctx::swap_verdict`] says `Yes`, `None` elsewhere.
    fn mends(&self, a: usize, b: usize, f: usize) -> Option<f64> {
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
    fn past_mending(&self, a: usize, b: usize, f: usize) -> bool {
        let sw = Some((a, b));
        let over = |m: usize| {
            self.loose(m, f, None).is_some() && self.loose(m, f, sw).is_some_and(|t| t > 2.0)
        };
        over(a) || over(b)
    }

    fn jump_verdict(&self, a: usize, f: usize) -> Verdict {
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
    fn break_mm(&self, m: usize) -> f64 {
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
    fn switch_gain(&self, a: usize, b: usize, f: usize) -> Option<(f64, f64)> {
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
    fn leap(&self, m: usize, f: usize) -> Option<f64> {
        self.leap_vec(m, f).map(|d| norm(&d))
    }

    /// [`Ctx::leap`] as a vector: a jump's two leaps, going and coming back, are opposite.
    #[inline]
    fn leap_vec(&self, m: usize, f: usize) -> Option<[f64; 3]> {
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
    fn leap_pairs(&self, m: usize, min_len: usize) -> Vec<(usize, usize)> {
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
    fn step(
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

/// All swaps and jumps in `trial`, in order of first frame. Coordinates that are not
/// finite count as missing.
pub fn find_swaps(trial: &Trial, opts: &SwapOptions) -> Result<Vec<Find>> {
    trial.check()?;
    opts.validate()?;
    let (nm, nf) = (trial.markers(), trial.frames());
    if nm < 2 || nf < 3 {
        return Ok(Vec::new());
    }
    let cx = Ctx::learned(trial, opts);
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
    Ok(finds)
}

impl<'a> Ctx<'a> {
    /// What the finding reads of `trial`: which samples are data, the links learned from
    /// it, each marker's usual step, and (on trials small enough) the labelled scores.
    fn learned(trial: &'a Trial, opts: &SwapOptions) -> Ctx<'a> {
        let (nm, nf) = (trial.markers(), trial.frames());
        let ok: Vec<Vec<bool>> = (0..nm)
            .map(|m| {
                (0..nf)
                    .map(|f| trial.valid[m][f] && finite(&trial.xyz[m][f]))
                    .collect()
            })
            .collect();
        let links = learn_links(
            trial,
            opts.max_link_spread_mm,
            opts.min_link_support,
            opts.max_links,
        );
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

/// Confidence of a jump found by continuity alone whose second leap takes back the first
/// exactly.
const LEAP_ONLY_CONFIDENCE: f64 = 0.75;

/// A jump found by continuity alone is noise when the median leap inside it is above this
/// share of its smaller edge leap ...
const QUIET_SHARE: f64 = 0.25;
/// ... and its confidence is then multiplied by this (as when its leaps are small).
const NOISY: f64 = 0.5;

/// Longest span between a jump's two leaps looked for, frames.
const MAX_LEAP_SPAN: usize = 120;

/// Frames either side of a jump's edge over which its links' change across the edge is
/// measured ([`Ctx::link_change`]).
const EDGE_WINDOW: usize = 3;

/// A jump's links must change across its edges by at least twice this (in tolerances, the
/// lower median over its links) to count in full; below this, not at all.
const LINK_CHANGE_FLOOR: f64 = 0.5;

/// Frames either side of a jump's edge searched for its leap.
const EDGE_SEARCH: usize = 3;

/// Longest range of candidate frames for a swap's start over which the steps are summed
/// alike for every candidate ([`swap_find`]).
const EDGE_RANGE: usize = 64;

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
fn swap_runs(cx: &Ctx, a: usize, b: usize, hole: usize) -> Vec<(usize, usize, Vec<usize>)> {
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
fn episodes(
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

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The upper median (the element at half the length once sorted), 0 for none.
fn median(mut v: Vec<f64>) -> f64 {
    signal::order::upper_median(&mut v).unwrap_or(0.0)
}

fn swap_find(
    cx: &Ctx,
    a: usize,
    b: usize,
    s0: usize,
    e0: usize,
    decided: Vec<usize>,
    opts: &SwapOptions,
) -> Find {
    // Undecided frames at the edges (both markers missing or passing close): the edge is
    // placed where the exchanged trajectories run smoothest.
    let (first_dec, last_dec) = match (decided.first(), decided.last()) {
        (Some(&x), Some(&y)) => (x, y),
        _ => (s0, e0),
    };
    // The steps of both markers, the exchange applied over `s..=e`, summed over the
    // frames around `lo..=hi` (for the start, every candidate's range alike, so that a
    // leap the start leaves unexplained counts wherever it falls: a label that took the
    // other marker's point over that marker's gap has one step each way at the edge, and
    // a window around each candidate alone placed the start where least was seen, not
    // where the trajectories run smoothest). Ranges longer than [`EDGE_RANGE`] keep a
    // window of 2 frames around each candidate, so that the cost stays linear.
    let nf = cx.t.frames();
    let cost = |s: usize, e: usize, around: usize, lo: usize, hi: usize| -> f64 {
        let (lo, hi) = if hi - lo > EDGE_RANGE {
            (around, around)
        } else {
            (lo, hi)
        };
        (lo.saturating_sub(2)..=(hi + 2).min(nf - 1))
            .flat_map(|f| [a, b].map(|m| cx.step(m, f, (a, b), (s, e), true)))
            .flatten()
            .sum()
    };
    let starts = |x: usize| cost(x, e0, x, s0, first_dec);
    let s = (s0..=first_dec)
        .min_by(|&x, &y| starts(x).total_cmp(&starts(y)))
        .unwrap_or(first_dec);
    // Ties (no continuity to tell, as where the markers are missing) go to the trial's
    // end for a run that reaches it, to the last decided frame otherwise.
    let ends = last_dec..=e0;
    // The end is placed as the start where both markers are seen in the frame after the
    // run (a label leaving a missing marker's point as that marker reappears). A run that
    // ends at the trial's end or in a gap keeps a window around each candidate: summed
    // alike, runs to the trial's end ended short (tuned labs: near markers to the end
    // undone exactly 92.2 -> 78.4 %), and so did `nick_freeform_001.c3d`'s swap up to a
    // gap both markers share (frames 0-197 for 0-199, 0-based).
    let to_end = e0 + 1 == nf;
    let seen_after = !to_end && cx.ok[a][e0 + 1] && cx.ok[b][e0 + 1];
    let end_cost = |x: usize| {
        if seen_after {
            cost(s, x, x + 1, last_dec + 1, e0 + 1)
        } else {
            cost(s, x, x + 1, x + 1, x + 1)
        }
    };
    let by_cost = |x: &usize, y: &usize| end_cost(*x).total_cmp(&end_cost(*y));
    let e = if to_end {
        ends.rev().min_by(by_cost)
    } else {
        ends.min_by(by_cost)
    }
    .unwrap_or(last_dec);

    // Frames where one marker is missing weigh as both (the sums are of two markers').
    let full = if cx.has_links(a) && cx.has_links(b) {
        2.0
    } else {
        1.0
    };
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for &f in &decided {
        if let Some((x, y, n)) = cx.pair_scores(a, b, f) {
            before.push(x * full / n);
            after.push(y * full / n);
        }
    }
    let (before, after) = (median(before), median(after));
    // Continuity at each edge: labelled against undone.
    let (mut smoother, mut checked, mut edge_step) = (0, 0, 0.0f64);
    // The least share of the labelled steps that undoing removes at an edge, where both
    // markers leap there (the labelled steps above both breaks); 0 otherwise.
    let mut leap_gain = 1.0f64;
    for f in [s, e + 1] {
        if f == 0 || f >= nf || (f == e + 1 && e + 1 >= nf) {
            continue;
        }
        // Both markers' steps; where one marker is missing at the edge (a label that took
        // the other's point over its gap), the one step each way that spans it.
        let steps = |apply: bool| [a, b].map(|m| cx.step(m, f, (a, b), (s, e), apply));
        let (lab, und) = (steps(false), steps(true));
        let n = |v: &[Option<f64>; 2]| v.iter().flatten().count();
        let both = n(&lab) == 2 && n(&und) == 2;
        let one = n(&lab) == 1 && n(&und) == 1;
        let sum = |v: &[Option<f64>; 2]| v.iter().flatten().sum::<f64>();
        if both || one {
            let (l, u) = (sum(&lab), sum(&und));
            checked += 1;
            edge_step = edge_step.max(l);
            if u < l {
                smoother += 1;
            }
            // The breaks of the markers whose labelled steps were measured.
            let brk: f64 = [a, b]
                .iter()
                .zip(&lab)
                .filter(|(_, st)| st.is_some())
                .map(|(&m, _)| cx.break_mm(m))
                .sum();
            let leaps = l > brk;
            leap_gain = leap_gain.min(if leaps { 1.0 - u / l } else { 0.0 });
        }
    }
    if checked == 0 {
        leap_gain = 0.0;
    }
    let strength = (before - after).max(0.0);
    let p_link = 1.0 - (-strength / 2.0).exp();
    // The share of the frames the links could judge (both markers, or one, seen with a
    // link) that they decided: frames where nothing can be judged (both markers missing,
    // as often near a trial's end) neither confirm a swap nor weaken it.
    let judged = (s..=e)
        .filter(|&f| cx.pair_scores(a, b, f).is_some())
        .count();
    let share = (decided.len() as f64 / judged.max(1) as f64)
        .min(1.0)
        .sqrt();
    let confidence = if decided.is_empty() {
        // Continuity alone: two trajectories leaping into each other's places at every
        // edge is a swap a person would call, but one with no link to confirm it.
        if checked > 0 && smoother == checked {
            0.6
        } else {
            0.3
        }
    } else {
        let p_cont = if checked == 0 || smoother == checked {
            1.0
        } else if smoother == 0 {
            0.5
        } else {
            0.8
        };
        // The two trajectories leaping into each other's places at every edge is evidence
        // of its own, beside the links: a long swap of two markers of one segment keeps
        // their own link whole and mends the others only in the frames where they are
        // seen, and the edges then say what the links say weakly.
        let p_edges = EDGE_WEIGHT * leap_gain.max(0.0);
        1.0 - (1.0 - p_link * share * p_cont) * (1.0 - p_edges)
    }
    .clamp(0.0, 1.0);
    Find {
        kind: FindKind::Swap,
        markers: vec![a, b],
        first: s,
        last: e,
        confidence,
        settled: confidence >= opts.min_confidence,
        evidence: Evidence {
            links: cx.links[a].len() + cx.links[b].len(),
            frames_decided: decided.len(),
            link_error: before,
            link_error_undone: after,
            edges_smoother: smoother,
            edges_checked: checked,
            edge_step_mm: edge_step,
            offset_share: None,
        },
    }
}

fn jump_find(
    cx: &Ctx,
    a: usize,
    s: usize,
    e: usize,
    decided: Vec<usize>,
    opts: &SwapOptions,
) -> Find {
    let before = median(
        decided
            .iter()
            .filter_map(|&f| cx.score(a, f, None))
            .collect(),
    );
    // The steps at the edges against the marker's usual steps.
    let nf = cx.t.frames();
    // Each edge moved to the largest leap within a few frames, when that is a break: the
    // frames a link decides can stop short of the edge (an offset along a link changes its
    // length little), and the jump's samples are the ones between the two leaps.
    let near = |edge: usize, lo: usize, hi: usize| -> usize {
        (edge.saturating_sub(EDGE_SEARCH).max(lo)..=(edge + EDGE_SEARCH).min(hi))
            .filter_map(|f| Some((cx.leap(a, f)?, f)))
            .filter(|&(l, _)| l > cx.break_mm(a))
            .max_by(|x, y| x.0.total_cmp(&y.0))
            .map_or(edge, |(_, f)| f)
    };
    let s = near(s, 1, e);
    let e = if e + 1 < nf {
        near(e + 1, s + 1, nf - 1) - 1
    } else {
        e
    };

    let (mut smoother, mut checked, mut edge_step) = (0, 0, 0.0f64);
    for f in [s, e + 1] {
        if f >= nf {
            continue;
        }
        if let Some(st) = cx.step(a, f, (a, a), (0, 0), false) {
            checked += 1;
            edge_step = edge_step.max(st);
            if st > cx.break_mm(a) {
                smoother += 1;
            }
        }
    }
    // The links' change across the edges (the larger of the two that can be measured):
    // the links must break at the edge, not only be broken, for the break to be the
    // jump's ([`Ctx::link_change`]).
    let w = EDGE_WINDOW;
    let change = [
        (s > 0).then(|| cx.link_change(a, s..(s + w).min(e + 1), s.saturating_sub(w)..s)),
        (e + 1 < nf).then(|| {
            cx.link_change(
                a,
                (e + 1).saturating_sub(w).max(s)..e + 1,
                e + 1..(e + 1 + w).min(nf),
            )
        }),
    ]
    .into_iter()
    .flatten()
    .flatten()
    .fold(None, |acc: Option<f64>, c| {
        Some(acc.map_or(c, |x| x.max(c)))
    });
    let at_edge = change.map_or(1.0, |c| {
        ((c - LINK_CHANGE_FLOOR) / LINK_CHANGE_FLOOR).clamp(0.0, 1.0)
    });
    let p_link = (1.0 - (-2.0 * (before - 1.0).max(0.0)).exp()) * at_edge;
    let inside = decided.iter().filter(|&&f| f >= s && f <= e).count();
    let share = (inside as f64 / (e + 1 - s) as f64).sqrt();
    // A label that lands on another point leaves its path twice, going and coming back;
    // skin moving or a marker wobbling does neither.
    // No edge to check (the episode runs from a gap or the trial's end to another): the
    // links alone, which a marker set that bends slowly (a trunk at the trial's ends) also
    // breaks, and no report.
    let p_cont = match (smoother, checked) {
        (0, 0) => 0.3,
        (b, c) if b == c => 1.0,
        (1, _) => 0.4,
        _ => 0.1,
    };
    // Both edges breaking is not enough alone: the links must say the marker left its
    // place over the episode's frames.
    let links_say = (p_cont * (0.3 + 0.7 * p_link * share)).clamp(0.0, 1.0);
    // The steady offset between two cancelling leaps is a second witness beside the
    // links, as a swap's edges are (an offset across the links changes their lengths
    // little, and a long jump's links then break barely past their tolerance).
    // Measured only where it could lift the find to a report: a witness is at most 1, and
    // most spans of jump frames (a strained pose, a marker settling after a gap) stay
    // under the report with a full one; they are dropped, and measuring the offset (every
    // frame of the span carried by the link partners' motion) was most of their cost.
    let most = (1.0 - (1.0 - links_say) * (1.0 - OFFSET_WEIGHT)).clamp(0.0, 1.0);
    let witness = if most < opts.min_report {
        None
    } else {
        cx.offset_witness(a, s, e).map(|o| o.share())
    };
    let g = witness.unwrap_or(0.0);
    let confidence = (1.0 - (1.0 - links_say) * (1.0 - OFFSET_WEIGHT * g)).clamp(0.0, 1.0);
    Find {
        kind: FindKind::Jump,
        markers: vec![a],
        first: s,
        last: e,
        confidence,
        settled: confidence >= opts.min_confidence,
        evidence: Evidence {
            links: cx.links[a].len(),
            frames_decided: inside,
            link_error: before,
            link_error_undone: 0.0,
            edges_smoother: smoother,
            edges_checked: checked,
            edge_step_mm: edge_step,
            offset_share: witness,
        },
    }
}

/// Most links a marker whose links decide no frame of a span between two opposite leaps
/// may have to be found by the leaps and the steady offset ([`leap_jump_find`]): with four
/// or more, links that stay whole over a jump say it is none, as far as links can.
const SPARSE_LINKS: usize = 3;

/// Most the steady-offset witness adds to a jump's link evidence (as the probability of an
/// independent witness): half, as a swap's edges ([`EDGE_WEIGHT`]), so that it cannot
/// settle a jump alone (0.3 from the links and edges, as a jump whose links barely break,
/// becomes 0.65 with a full witness: reported, not settled).
const OFFSET_WEIGHT: f64 = 0.5;

/// Most the continuity at a swap's edges adds to its link evidence (as the probability of
/// an independent witness): half, so that it cannot settle a swap whose links say little.
const EDGE_WEIGHT: f64 = 0.5;

/// A jump of a marker with fewer than two links, found by continuity alone between two
/// opposite leaps ([`Ctx::leap_pairs`]): how nearly the second leap takes back the first
/// (a label on another point and back: exactly; a foot striking the ground and leaving it:
/// seldom) is the confidence, at most [`LEAP_ONLY_CONFIDENCE`].
fn leap_jump_find(cx: &Ctx, a: usize, s: usize, e: usize, opts: &SwapOptions) -> Find {
    let (v1, v2) = (cx.leap_vec(a, s), cx.leap_vec(a, e + 1));
    let closure = match (v1, v2) {
        (Some(v1), Some(v2)) => {
            let sum: [f64; 3] = std::array::from_fn(|c| v1[c] + v2[c]);
            1.0 - norm(&sum) / norm(&v1).min(norm(&v2)).max(f64::MIN_POSITIVE)
        }
        _ => 0.0,
    };
    let steps: Vec<f64> = [s, e + 1]
        .iter()
        .filter_map(|&f| cx.step(a, f, (a, a), (0, 0), false))
        .collect();
    let smoother = steps.iter().filter(|&&x| x > cx.break_mm(a)).count();
    // A label on another point follows that point, as smooth as any marker: its two leaps
    // stand out of a quiet span. Leaps amid leaps as large are a noisy trajectory (a fast
    // arm seen by few cameras), which closes on itself as often as not.
    let inner: Vec<f64> = (s + 2..e).filter_map(|f| cx.leap(a, f)).collect();
    let edge = match (v1, v2) {
        (Some(v1), Some(v2)) => norm(&v1).min(norm(&v2)),
        _ => 0.0,
    };
    let quiet = if !inner.is_empty() && median(inner) > QUIET_SHARE * edge {
        NOISY
    } else {
        1.0
    };
    // With no link to confirm it, a leap just past a break is as likely a glitch of the
    // cameras (two of them, opposite by chance, frames apart) as a label on another point:
    // continuity alone calls a jump whose leaps are both at least twice a break.
    let plain = if edge >= 2.0 * cx.break_mm(a) {
        1.0
    } else {
        NOISY
    };
    // A marker with links (two or three, none deciding): the span must also hold a steady
    // offset from the link partners, the leaps' own (none measured: no find).
    let witness = (cx.links[a].len() >= 2).then(|| cx.offset_witness(a, s, e));
    let steady = match witness {
        None => 1.0,
        Some(w) => w.map_or(0.0, |o| o.steady),
    };
    let confidence =
        (LEAP_ONLY_CONFIDENCE * closure.max(0.0) * quiet * plain * steady).clamp(0.0, 1.0);
    Find {
        kind: FindKind::Jump,
        markers: vec![a],
        first: s,
        last: e,
        confidence,
        settled: confidence >= opts.min_confidence,
        evidence: Evidence {
            links: cx.links[a].len(),
            frames_decided: 0,
            // The error of the one link, if any (one link cannot say which of its two
            // markers strayed), for a find that is reported: most spans between opposite
            // leaps are not, and this is the costliest part of their evidence.
            link_error: if confidence >= opts.min_report {
                median((s..=e).filter_map(|f| cx.score(a, f, None)).collect())
            } else {
                0.0
            },
            link_error_undone: 0.0,
            edges_smoother: smoother,
            edges_checked: steps.len(),
            edge_step_mm: steps.iter().copied().fold(0.0, f64::max),
            offset_share: witness.flatten().map(|o| o.share()),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::{learn_links, medians, sort8, Ctx};
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
