//! `auto`'s expected error: the evidence a choice leaves ([`Diag`]), the features made of it
//! and the model that turns them into an expected error (fitted by `evals::fit` on
//! `fill_eval`'s gaps; its coefficients are generated into `model/coefficients.rs`).

use serde::{Deserialize, Serialize};

mod coefficients;
mod donors;

pub use donors::{gap_donors, GapDonors};

use super::super::anchor::Raw;
use super::super::{dist, linear, FillMethod, Span, Target};
use coefficients::{BETA, C0, C1, GAMMA};

/// The evidence behind an expected error: the choice's mean error on the artificial gaps
/// (`scored`), and how far the two best-scored candidates' fills of the real gap are apart
/// (`spread`: their mean distance; 0 with one candidate). Both in the data's units.
///
/// The rest says how much harder the real gap is than the holes that scored it, from what
/// is known there: how far the best and the third-best fills are apart (`spread3`, data
/// units); how far the two best candidates' predictions were apart on the holes
/// (`spread_holes`, data units: where they agreed there but not on the real gap, the gap is
/// unlike the holes); how far the fill strays from the straight line between its anchors
/// relative to how far the truth strayed from it in the holes (`bend`: what polynomial
/// errors scale with); and how far the donor methods' residuals drift from one anchor to
/// the other relative to the holes (`drift`, geometric mean over the donor methods: the
/// linear tie to the anchors assumes a steady drift, so a large one means an error the
/// anchors only partly correct).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Diag {
    pub scored: f64,
    pub spread: f64,
    pub len: usize,
    pub spread3: Option<f64>,
    pub spread_holes: Option<f64>,
    pub bend: Option<f64>,
    pub drift: Option<f64>,
    /// Whether the gap was filled again in the second pass (see `fill_gaps`) with a
    /// neighbour's first-pass fill as a donor; the evidence above is the first pass's.
    pub refilled: bool,
    /// For a refilled gap: the second pass's score on its artificial gaps over the first's.
    pub rescored: Option<f64>,
    /// For a refilled gap: the largest first-pass score among its nearest donors' fills
    /// that overlap it, over `scored` (a refill is no better than what it leans on).
    pub donor_err: Option<f64>,
    /// For a refilled gap: the largest share of its frames where one of its nearest donors
    /// is a fill rather than a recording.
    pub share: Option<f64>,
    /// For a refilled gap: the second pass's spread (see above) over the first's.
    pub respread: Option<f64>,
    /// The fill's largest step (joins to the anchors included) over the marker's largest
    /// recorded step. The step rule holds it at 1.5 by slowing the fill; a fill that needed
    /// that, or came near it, moves unlike the marker ever did.
    #[serde(default)]
    pub step: Option<f64>,
    /// Where the step rule had to slow the chosen fill (or the candidates blended into it):
    /// how far it moved them (mean distance, weighted as the blend, data units). The fill
    /// is then not what its methods predicted, and what the artificial gaps scored does
    /// not vouch for it: the method's prediction moved the marker faster than it ever
    /// moves, so the real gap is unlike the holes, and the fill written is that prediction
    /// pulled part of the way to the straight line. The truth cannot be near both, so the
    /// distance floors the expected error (see [`calibrated`]).
    #[serde(default)]
    pub slowed: Option<f64>,
    /// How hard the marker accelerates beside the gap against its whole recording: its
    /// mean acceleration (second difference) over the recorded frames within the gap's
    /// length (at least 10 frames) either side, over its mean acceleration over every
    /// recorded frame ([`accel_ratio`]). The artificial gaps are spread over the marker's
    /// recording, so a gap next to a landing, a push-off or a lift's swing is harder than
    /// the holes that scored it; a gap in a quiet stretch is easier.
    #[serde(default)]
    pub accel: Option<f64>,
    /// How fast the marker moves beside the gap against its whole recording: its mean step
    /// over the recorded frames within the gap's length (at least 10 frames) either side,
    /// over its mean step over every recorded frame ([`speed_ratio`]). Beside `accel`: a
    /// gap in the fast part of a run, a jump's flight or a lift's swing is harder than the
    /// holes that scored it, which lie mostly where the marker moves at its usual pace.
    #[serde(default)]
    pub speed: Option<f64>,
    /// The method that leads the fill (the choice, or the blend's first method; for a
    /// refilled gap, the second pass's). The methods err in their own ways beyond what
    /// their scores say: a quintic through the anchors' samples scores well on holes in
    /// smooth stretches and misses by far more where the marker turns, the published PCA
    /// and the Kalman smoother stay close to their scores (see [`features`]).
    #[serde(default)]
    pub lead: Option<FillMethod>,
}

/// The expected error of a choice from its mean error on the artificial gaps.
///
/// Artificial gaps nearby miss what happens in the real gap's own frames, and the choice
/// that scored best on them flatters itself, so the score alone was over-confident on 14 %
/// of real trials' gaps. Where the candidates disagree on the real gap, its error is larger
/// than their scores say, the more so the further they disagree; longer gaps are scored on
/// fewer, shorter stand-ins; and what can be seen of the real gap says how much harder it
/// is than the holes that scored it (see [`Diag`]). So ln(expected / scored) =
/// β · x + c₁ · exp(γ · x) + c₀ over the features x of `features`: β by median regression
/// of ln(real / scored) on the real trials of the evaluation (`cargo run --release -p
/// evals --bin fill_eval`, which also checks the model fitted leave-one-lab-out); γ by
/// least squares of the log of the fitted residuals' size, so exp(γ · x) says how far a gap
/// like this one strays from its median; c₁ widens the margin of such gaps (the value that
/// puts most gaps within 2×) and c₀ leaves 5 % of the gaps above twice their estimate: the
/// estimate is meant to vouch for a fill. One shared margin instead sets every gap's by the
/// least predictable ones, and left 17.5 % of gaps below half their estimate.
///
/// A gap filled again in the second pass keeps the first pass's evidence, with `refilled`
/// set, `rescored` and `respread` (the second pass's score and spread over the first's),
/// and what the refill leans on (`donor_err`, `share`): the second pass's own scores come
/// from artificial gaps with recorded donors where the real gap has filled ones, and alone
/// were over-confident on 10–16 % of gaps; a second pass that scores far better than the
/// first is believed only down to a ratio of about e⁻¹ (the hinge).
///
/// The weights are fitted (`evals::fit`) on every lab of `fill_eval`'s corpora (tuned and
/// held apart alike), every lab weighing the same, and the margin (c₁, c₀) on gaps of labs
/// the β and γ judging them never saw, set so that a new set of six labs' over-confidence
/// rates average at most 5 % by a one-sided 90 % prediction bound over labs: a new lab is
/// one more draw from labs, and a margin set on the pooled gaps left the held-apart labs of
/// `c3d-more` at 6.0 % instead of 5 % (a bound on the 26 labs' mean alone, 5.1 % on the
/// last run). They live in the generated `model/coefficients.rs`, the fit of the committed
/// `crates/evals/data/expected_error_gaps.txt` (36 228 gaps of 36 labs, 30 per length, group
/// and trial, from the records of 2ccb416 over every corpus, `c3d-labs` included), which
/// `evals`' `coefficients` test fits again. Before `c3d-labs` and `accel`, each lab judged by
/// the model fitted to the other 25 (nested: margin included): Spearman 0.955, 81.8 % of
/// gaps within 2× of their estimate, 3.9 % above twice it; lab by lab 2.3–8.3 % above (the
/// most in `art`, whose points are nearly all computed from 6-DOF targets).
///
/// Per activity (`fill_eval --replay --activities`, each lab judged by the fit to the other
/// 35): walking 81.0 % within 2× and 3.2 % above, sports 83.1 % and 3.1 %, the other
/// full-body sequences 79.5 % and 3.9 %, running 77.8 % and 5.0 %, the drop jumps 71.8 %
/// and 5.9 %, lifting 75.7 % and 6.2 %: the activities beyond walking spread wider around
/// their estimates than walking does, and the goal (≥ 80 % and ≤ 5 % on every activity of
/// two labs or more) is met on walking and sports only (docs/fill-evaluation.md, "Issue 45
/// item 7, third round"). `accel`, the marker's acceleration beside the gap against its
/// whole recording, was chosen among eight measures of the marker's own motion on the older
/// corpora's labs (`fill_eval --replay --motion`) and moved `c3d-labs`' trials (11 labs,
/// each judged apart) from 73.3 % to 74.0 % within 2× (5.4 % above twice, both); `speed`
/// and `lead` were chosen the same way among twelve measures and the lead's indicators
/// alone and with measures beside them (the older labs' five activities 393.8 → 396.4
/// points of within-2×), and moved every lab apart from 79.0 % to 79.5 % within 2× (3.8 %
/// above twice, both), the labs nothing was chosen on from 76.7 % and 4.5 % to 77.1 % and
/// 4.6 %, at the same sharpness (median estimate over median error 1.22 → 1.21).
/// Left out one at a time and judged on the tuned labs left out in turn
/// (`fill_eval --replay --ablate`), the fill's distance-range violation against the
/// skeleton and whether a polynomial made the fill did not pay and are gone. Earlier
/// features that did not help: the marker's pace at the anchors and across the gap against
/// the holes', the error of the holes most like the real gap in bend, the spread, median
/// and geometric mean of the holes' errors, their number, and twice as many holes (+0.4
/// points at 1.4× the cost); a gradient-boosted model did no better. Nor did the donors'
/// evidence (`fill_eval --replay RECORDS --donors`, see docs/fill-evaluation.md): how
/// rigid the donors stay with the target beside the gap, how fast they move in it against
/// beside it, their roughness (at most 0.1 point within 2× on the tuned labs left out in
/// turn).
///
/// A fill the step rule had to slow is floored at how far it was moved (`Diag::slowed`):
/// its artificial gaps scored the method's prediction, which moved the marker faster than
/// it ever moves, and the fill written is not that prediction. Of the held-apart fills off
/// by more than 20 mm, 59 of 60 are now expected above 10 mm (54 of 69 before the floor,
/// the runner-up's spread, see `holes::score`, and blends of any size).
pub fn calibrated(d: &Diag) -> f64 {
    let e = d.scored.max(1e-12) * log_ratio(&features(d), &BETA, &GAMMA, C1, C0).exp();
    e.max(d.slowed.unwrap_or(0.0))
}

/// ln(expected / scored) for features `x` under `auto`'s expected-error model (shared with the
/// evaluation that fits it, which may try more features than `auto` computes).
pub fn log_ratio<const N: usize>(
    x: &[f64; N],
    beta: &[f64; N],
    gamma: &[f64; N],
    c1: f64,
    c0: f64,
) -> f64 {
    let dot = |w: &[f64; N]| w.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
    dot(beta) + c1 * dot(gamma).clamp(-20.0, 20.0).exp() + c0
}

/// Number of the expected-error model's features.
pub const FEATURES: usize = 24;

/// The methods whose lead gets a term of its own in the expected-error model (see
/// [`features`]), beside the PCA fill, the one most often chosen.
pub const LEADS: [FillMethod; 6] = [
    FillMethod::Rigid,
    FillMethod::Lagrange5,
    FillMethod::Pattern,
    FillMethod::Spline,
    FillMethod::Kalman,
    FillMethod::Gloersen,
];

/// The expected-error model's features (see [`calibrated`]), shared with the evaluation
/// that fits it: 1, ln q, ln(len), (ln q)², ln q₃, ln h, ln bend, ln drift, refilled,
/// ln rescored, min(ln rescored + 1, 0), ln donor_err, share, ln respread, max(step − 1,
/// 0), one candidate, ln accel, ln speed and one indicator per method of [`LEADS`] leading the fill;
/// with q = spread / scored, q₃ = spread3 / scored, h = spread_holes / scored, every ratio
/// clamped to [0.05, 20] and taken as 1 where it is unknown (fewer than three or two
/// candidates, holes without bend, no donor method, not refilled), and share and the step
/// excess 0 where unknown. The square lets the estimate grow faster when the candidates
/// disagree far beyond their scores. A lone candidate's spread of 0 is no agreement: q is
/// unknown there, and the indicator lets the model widen such gaps' margin (alone, they
/// were read as the closest agreement and 10 % of them came out above twice their
/// estimate). The step excess is how far the fill's largest step goes beyond the marker's
/// largest recorded one: fills the step rule had to slow, or nearly, were above twice their
/// estimate 45–55 % of the time. The lead's indicators move the estimate (β) and its
/// margin (γ) by method: on every lab's artificial gaps, each lab judged by the model
/// without them fitted to the other labs, the fills the quintic led were 66.8 % within 2×
/// of their estimate and 28.3 % below half it, the published PCA's 86.1 % and 12.4 %, the
/// Kalman smoother's 88.6 % and 8.3 % (fills led by another method, or none known, read as
/// the PCA fill's).
pub fn features(d: &Diag) -> [f64; FEATURES] {
    let s = d.scored.max(1e-12);
    let ln = |r: Option<f64>| r.map_or(0.0, |r| r.clamp(0.05, 20.0).ln());
    // One candidate: no disagreement to read (its spread is 0 by convention).
    let single = d.spread == 0.0 && d.spread3.is_none();
    let q = if single { 0.0 } else { ln(Some(d.spread / s)) };
    let rescored = ln(d.rescored);
    [
        1.0,
        q,
        (d.len as f64).ln(),
        q * q,
        ln(d.spread3.map(|v| v / s)),
        ln(d.spread_holes.map(|v| v / s)),
        ln(d.bend),
        ln(d.drift),
        f64::from(u8::from(d.refilled)),
        rescored,
        (rescored + 1.0).min(0.0),
        ln(d.donor_err),
        d.share.unwrap_or(0.0),
        ln(d.respread),
        d.step.map_or(0.0, |r| (r - 1.0).max(0.0)),
        f64::from(u8::from(single)),
        ln(d.accel),
        ln(d.speed),
        lead(d, 0),
        lead(d, 1),
        lead(d, 2),
        lead(d, 3),
        lead(d, 4),
        lead(d, 5),
    ]
}

/// 1 where the method of [`LEADS`]`[k]` leads the fill, else 0.
fn lead(d: &Diag, k: usize) -> f64 {
    f64::from(u8::from(d.lead == Some(LEADS[k])))
}

/// The marker's mean acceleration beside a gap over its mean acceleration over its whole
/// recording (see [`Diag::accel`]): `xyz` the marker's samples, `ok` whether a frame is
/// recorded (the gap's frames are not), the gap over `first..first + len`. The
/// acceleration at a frame is the length of its second difference, read where the frame
/// and both neighbours are recorded; "beside" is `max(len, 10)` frames either side. `None`
/// where either mean has no frame or the whole recording's is 0.
///
/// One function for `auto` and for the evaluation that fits the model on records made
/// before the feature existed (`fill_eval` reads it from each record's trial), so both
/// read the same number.
pub fn accel_ratio(
    xyz: &[[f64; 3]],
    ok: impl Fn(usize) -> bool,
    first: usize,
    len: usize,
) -> Option<f64> {
    let n = xyz.len();
    let acc = |f: usize| {
        (f >= 1 && f + 1 < n && ok(f - 1) && ok(f) && ok(f + 1)).then(|| {
            let (a, b, c) = (xyz[f - 1], xyz[f], xyz[f + 1]);
            dist(
                [c[0] - b[0], c[1] - b[1], c[2] - b[2]],
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
            )
        })
    };
    beside_over_whole(n, first, len, acc)
}

/// The marker's mean step beside a gap over its mean step over its whole recording (see
/// [`Diag::speed`]); arguments and "beside" as [`accel_ratio`]'s, the step at a frame read
/// where it and the frame before are recorded. `None` where either mean has no frame or the
/// whole recording's is 0.
pub fn speed_ratio(
    xyz: &[[f64; 3]],
    ok: impl Fn(usize) -> bool,
    first: usize,
    len: usize,
) -> Option<f64> {
    let n = xyz.len();
    let step = |f: usize| (f >= 1 && f < n && ok(f - 1) && ok(f)).then(|| dist(xyz[f], xyz[f - 1]));
    beside_over_whole(n, first, len, step)
}

/// The mean of `at` over the recorded frames within `max(len, 10)` frames either side of
/// the gap `first..first + len`, over its mean over every frame (`at` is `None` where it
/// has nothing to read).
fn beside_over_whole(
    n: usize,
    first: usize,
    len: usize,
    at: impl Fn(usize) -> Option<f64>,
) -> Option<f64> {
    let mean = |it: &mut dyn Iterator<Item = f64>| {
        let (s, k) = it.fold((0.0, 0usize), |(s, k), x| (s + x, k + 1));
        (k > 0).then(|| s / k as f64)
    };
    let w = len.max(10);
    let end = (first + len).min(n);
    let beside = mean(
        &mut (first.saturating_sub(w)..first)
            .chain(end..(end + w).min(n))
            .filter_map(&at),
    )?;
    let whole = mean(&mut (0..n).filter_map(&at))?;
    (whole > 0.0).then(|| beside / whole)
}

/// Expected error without any artificial gap to score on: a quarter of the distance the
/// marker travels over the gap's length at its mean recorded speed (a coarse, cautious
/// guess, used only when the marker has no room for even a shorter trial gap).
pub(super) fn prior(t: &Target, len: usize) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for f in 1..t.data.frames {
        if t.ok(f) && t.ok(f - 1) {
            sum += dist(t.at(f), t.at(f - 1));
            n += 1;
        }
    }
    let mean = if n > 0 { sum / n as f64 } else { 0.0 };
    0.25 * mean * (len + 1) as f64
}

/// Mean distance of `v` (samples over `span`'s frames) from the straight line between the
/// target's anchors (from the held anchor at the trial's edges): how far the marker bends
/// away from what the simplest fill assumes.
pub(super) fn deviation(t: &Target, span: Span, v: &[[f64; 3]]) -> Option<f64> {
    let line = match (span.before, span.after) {
        (Some(_), Some(_)) => linear::fill(t, span).ok()?,
        _ => linear::hold(t, span).ok()?,
    };
    Some(line.iter().zip(v).map(|(a, b)| dist(*a, *b)).sum::<f64>() / v.len().max(1) as f64)
}

/// The slot of a donor method in per-method tallies. The Kalman smoother has none: its
/// residuals are its own smoothed estimate's, near zero at the anchors whatever the gap.
pub(super) fn donor_index(m: FillMethod) -> Option<usize> {
    match m {
        FillMethod::Rigid => Some(0),
        FillMethod::Pattern => Some(1),
        FillMethod::Pca => Some(2),
        _ => None,
    }
}

/// How far a donor prediction's residual moves from one anchor to the other (at the
/// trial's edges: the one anchor's residual, which the fill keeps throughout).
pub(super) fn drift(r: &Raw) -> Option<f64> {
    match (r.before.first(), r.after.first()) {
        (Some(b), Some(a)) => Some(dist(b.1, a.1)),
        (Some((_, e)), None) | (None, Some((_, e))) => Some(dist(*e, [0.0; 3])),
        _ => None,
    }
}
