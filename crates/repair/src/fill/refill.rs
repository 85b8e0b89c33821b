//! The two passes over a trial's gaps: every gap filled from the data as recorded, then
//! the gaps whose nearest donors were filled near them filled again with those fills as
//! samples.

use rayon::prelude::*;

use super::auto;
use super::data::{Data, Span, Target};
use super::dispatch::{fill_gap_diag, fill_planned, refused, GapFill, Vetting};
use super::gloersen;
use super::method::FillMethod;
use super::options::FillOptions;
use super::outcome::{FillOutcome, SkipReason};
use super::plan::Plan;
use crate::gaps::Gap;

/// A gap is filled again when one of its this many nearest PCA neighbours is a marker
/// filled near it. On the corpus evaluation 2 kept the gains of refilling whenever any donor
/// was filled (2–3 markers missing together, every rate within 2 %; 1 lost up to 30 % of
/// them), and on the pipeline bench (independent random gaps) it refills a sixth of the
/// gaps instead of most: the nearest markers carry most of the weight, and many far donors
/// are filled somewhere near a gap.
const REFILL_NEAREST: usize = 2;

/// Fills `gaps` (of any markers; each gap one of its marker's) in two passes, each pass's
/// fills read from the data as the pass found it, and writes every fill into `xyz` (the
/// samples are also returned; `valid` is left to the caller, who knows what it means).
/// Occlusions often hide several neighbouring markers over overlapping frames, and each
/// then loses its nearest donors to the others for the whole gap, though they are missing
/// only part of it. So after the first pass every gap is planned again with the other
/// markers' first-pass fills counted as samples (the target's own samples stay as
/// recorded, so `auto` still scores on recorded truth only), and filled again when one of
/// its nearest donors now is a marker filled near it. On the corpus evaluation
/// (`fill_eval`) this took 10–25 % off `auto`'s errors on 2–3 neighbouring markers missing
/// together. The first pass's fills are written into `xyz` rather than into a copy, so the
/// second pass costs no second copy of the trial.
pub(crate) fn fill_gaps(
    xyz: &mut [Vec<[f64; 3]>],
    valid: &[Vec<bool>],
    max_step: &[f64],
    gaps: &[Gap],
    opts: &FillOptions,
    vetting: Vetting,
) -> Vec<GapFill> {
    let write = |xyz: &mut [Vec<[f64; 3]>], fills: &[GapFill]| {
        for (g, r) in gaps.iter().zip(fills) {
            if let Some(v) = &r.0 {
                xyz[g.marker][g.first..=g.last].copy_from_slice(v);
            }
        }
    };
    // Each pass's data has its own published-PCA models (see `gloersen::Cache`).
    let (cache1, cache2) = (gloersen::Cache::default(), gloersen::Cache::default());
    let data = Data::new(xyz, valid, max_step).with_gloersen(&cache1);
    let first: Vec<GapFill> = gaps
        .par_iter()
        .map(|g| {
            let _time = crate::profile::gap(g.len);
            fill_gap_diag(data, g, opts, vetting)
        })
        .collect();
    write(xyz, &first);
    if !(opts.method.is_donor() || opts.method == FillMethod::Auto) {
        return first;
    }
    // Per marker, the frames the first pass filled and the fills' scores on their artificial
    // gaps (the raw evidence, not the calibrated estimate, which is fitted with it).
    let mut filled: Vec<Vec<(usize, usize, Option<f64>)>> = vec![Vec::new(); xyz.len()];
    for (g, r) in gaps.iter().zip(&first) {
        if r.0.is_some() {
            filled[g.marker].push((g.first, g.last, r.2.map(|d| d.scored)));
        }
    }
    if filled.iter().all(Vec::is_empty) {
        return first;
    }
    // Whether one of the gap's nearest donors now is a marker filled near it and recorded
    // on some frame of the gap (a neighbour missing all through the gap adds only its fill,
    // made without the target: on the corpus evaluation, refilling for it changed no cell
    // by more than 1.5 %, and it is a sixth of the refills on the pipeline bench).
    let near_filled = |plan: &Plan, span: Span| {
        let (lo, hi) = span.outer();
        plan.pca.iter().take(REFILL_NEAREST).any(|&(j, _)| {
            filled[j].iter().any(|&(a, b, _)| a <= hi && b >= lo)
                && valid[j][span.first..=span.last].contains(&true)
        })
    };
    let mut valid2 = valid.to_vec();
    for (m, ranges) in filled.iter().enumerate() {
        for &(a, b, _) in ranges {
            valid2[m][a..=b].fill(true);
        }
    }
    let second = Data::new(xyz, &valid2, max_step).with_gloersen(&cache2);
    let out: Vec<GapFill> = gaps
        .par_iter()
        .zip(first)
        .map(|(g, r)| {
            // A gap too uncertain to fill stays so: its estimate is the first pass's.
            let uncertain = matches!(r.1, FillOutcome::Skipped(SkipReason::Uncertain { .. }));
            if uncertain || refused(g, opts).is_some() {
                return r;
            }
            let _time = crate::profile::gap(g.len);
            let t = Target {
                m: g.marker,
                data: second.with_own(g.marker, &valid[g.marker]),
                hole: None,
            };
            let span = Span::of(g, second.frames);
            let plan = Plan::build(&t, span, opts);
            if !near_filled(&plan, span) {
                return r;
            }
            let again = fill_planned(&t, span, &plan, opts, vetting);
            refill_kept(again, r, (&plan, g), &filled, valid, opts)
        })
        .collect();
    write(xyz, &out);
    out
}

/// The fill a refilled gap keeps: the second pass's (`again`), with the first pass's
/// (`r`) evidence as its expected error, unless that estimate is above
/// `max_expected_error`; the first pass's fill when the second could not fill the gap.
fn refill_kept(
    again: GapFill,
    r: GapFill,
    (plan, g): (&Plan, &Gap),
    filled: &[Vec<(usize, usize, Option<f64>)>],
    valid: &[Vec<bool>],
    opts: &FillOptions,
) -> GapFill {
    match (again, r) {
        // The expected error is the first pass's evidence, marked as refilled (the
        // calibration learns how much better a refill does than that evidence
        // says): the second pass's own artificial gaps are scored with recorded
        // donors where the real gap has filled ones, so its own estimate is
        // over-confident (on the corpus evaluation, 10 % of gaps above twice
        // their estimate instead of 5 %).
        // A refill whose estimate is above `max_expected_error` (it leans on fills
        // less sure than the recorded donors of the first pass) gives way to the
        // first pass's fill, which its estimate vouched for.
        // A gap the first pass could not fill keeps the second pass's own.
        ((Some(v), again, own), (v1, first, diag)) => match (&first, diag) {
            (FillOutcome::Filled { .. }, Some(d1)) => {
                let (donor_err, share) = filled_donors(plan, g, filled, valid);
                let d = auto::Diag {
                    refilled: true,
                    donor_err: donor_err.map(|e| e / d1.scored.max(1e-12)),
                    share,
                    rescored: own.map(|o| o.scored / d1.scored.max(1e-12)),
                    respread: own.map(|o| o.spread / d1.spread.max(1e-12)),
                    // The fill written is the second pass's.
                    slowed: own.map_or(d1.slowed, |o| o.slowed),
                    lead: match &again {
                        FillOutcome::Filled { method, .. } => Some(*method),
                        _ => d1.lead,
                    },
                    ..d1
                };
                let e = auto::calibrated(&d);
                if opts.max_expected_error.is_some_and(|max| e > max) {
                    (v1, first, Some(d1))
                } else {
                    (Some(v), again.with_expected_error(Some(e)), Some(d))
                }
            }
            (FillOutcome::Filled { expected_error, .. }, None) => {
                (Some(v), again.with_expected_error(*expected_error), None)
            }
            _ => (Some(v), again, own),
        },
        (_, r) => r,
    }
}

/// What a refilled gap leans on: the largest first-pass score (mean error on artificial
/// gaps) among the fills of its nearest donors that overlap it, and the largest share of
/// its frames where one of those donors is not recorded (so is a fill).
fn filled_donors(
    plan: &Plan,
    g: &Gap,
    filled: &[Vec<(usize, usize, Option<f64>)>],
    valid: &[Vec<bool>],
) -> (Option<f64>, Option<f64>) {
    let (mut err, mut share) = (None::<f64>, None::<f64>);
    let n = (g.last - g.first + 1) as f64;
    for &(j, _) in plan.pca.iter().take(REFILL_NEAREST) {
        for &(a, b, e) in &filled[j] {
            if let (true, Some(e)) = (a <= g.last && b >= g.first, e) {
                err = Some(err.map_or(e, |x| x.max(e)));
            }
        }
        let missing = valid[j][g.first..=g.last].iter().filter(|v| !**v).count() as f64 / n;
        share = Some(share.map_or(missing, |x| x.max(missing)));
    }
    (err, share)
}

#[cfg(test)]
mod tests {
    use super::super::data::dist;
    use super::super::step::max_steps;
    use super::*;

    /// Two neighbouring markers missing over overlapping frames: the second pass fills each
    /// with the other's first-pass fill as a donor, closer to the truth than the first
    /// pass (which had to do without its nearest marker), and its expected error comes from
    /// the first pass's evidence, marked as refilled.
    #[test]
    fn second_pass_uses_a_co_missing_neighbour() {
        let trial = crate::synth::gait_like(24, 8, 2000, 100.0, 0.3, 7);
        // The marker nearest marker 0 (the synthetic segments are round-robin: 8 apart).
        let mean_dist = |j: usize| {
            (0..2000)
                .map(|f| dist(trial.xyz[0][f], trial.xyz[j][f]))
                .sum::<f64>()
        };
        let near = (1..24)
            .min_by(|&a, &b| mean_dist(a).total_cmp(&mean_dist(b)))
            .unwrap();
        // Gaps of 20 frames, overlapping by 10. On this clean synthetic trial the published
        // PCA and (from 40 frames) the Kalman smoother bridge the co-missing neighbour in the
        // first pass already from 30 frames (30 frames: 0.583 mm first, 0.586 mm refilled;
        // 20 frames: 0.574 and 0.528 mm first, 0.568 and 0.513 refilled).
        let mut valid = trial.valid.clone();
        let gaps = [(0, 1000), (near, 1010)].map(|(m, a)| {
            valid[m][a..a + 20].fill(false);
            Gap {
                marker: m,
                first: a,
                last: a + 19,
                len: 20,
                at_start: false,
                at_end: false,
            }
        });
        let steps = max_steps(&trial.xyz, &valid);
        let data = Data::new(&trial.xyz, &valid, &steps);
        let opts = FillOptions::default();
        let mut xyz = trial.xyz.clone();
        let err = |g: &Gap, v: &[[f64; 3]]| {
            v.iter()
                .enumerate()
                .map(|(i, p)| dist(*p, trial.xyz[g.marker][g.first + i]))
                .sum::<f64>()
                / v.len() as f64
        };
        let both = fill_gaps(&mut xyz, &valid, &steps, &gaps, &opts, Vetting::Checked);
        for (g, (v, outcome, diag)) in gaps.iter().zip(&both) {
            let v = v.as_ref().unwrap();
            assert_eq!(&xyz[g.marker][g.first..=g.last], &v[..]);
            let (alone, first, _) = fill_gap_diag(data, g, &opts, Vetting::Checked);
            let (a, b) = (err(g, &alone.unwrap()), err(g, v));
            assert!(b < a, "marker {}: {b} not below {a}", g.marker);
            let expected = |o: &FillOutcome| match o {
                FillOutcome::Filled { expected_error, .. } => *expected_error,
                FillOutcome::Skipped(_) => None,
            };
            // The first pass's evidence, marked as refilled, with the second pass's score.
            let diag = diag.expect("auto's evidence");
            assert!(diag.refilled && diag.rescored.is_some());
            assert!(expected(&first).is_some());
            assert_eq!(expected(outcome), Some(auto::calibrated(&diag)));
        }
    }
}
