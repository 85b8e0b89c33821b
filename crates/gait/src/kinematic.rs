//! Foot strike and foot off from the markers. Three methods share the walking direction
//! and the checks here; each event kind uses the method [`KinematicOptions`] names
//! ([`Method`]), chosen by measurement (`events_eval`, docs/events.md):
//!
//! - [`Method::Zeni`] (here): Zeni, Richards & Higginson (2008), "Two simple methods for
//!   determining gait events during treadmill and overground walking using kinematic
//!   data", Gait & Posture 27(4): 710–714, with strikes refined by the feet's heights;
//! - [`Method::OConnor`] ([`crate::oconnor`]): the foot centre's vertical velocity;
//! - [`Method::Desailly`] ([`crate::desailly`]): high-pass filtered forward positions.
//!
//! Zeni's method: along the walking direction, relative to the sacrum, the heel reaches its most forward
//! position at foot strike and the toe its most backward position at foot off. Here the
//! walking direction is the pelvis' horizontal displacement over a window of about one
//! step either side of each frame ([`KinematicOptions::direction_window_s`]), so it follows
//! curved paths and turns and either direction of travel; frames where the pelvis moves
//! slower than [`KinematicOptions::min_speed_mm_s`] are no walking and get no events.
//! Gaps: a heel's or toe's gap up to [`KinematicOptions::bridge_s`] is bridged by a cubic
//! first; an extremum needs known neighbours, and on a side that a gap cuts short only a
//! tenth of the fall the other side needs ([`KinematicOptions::cut_min_fall`]), on a side
//! the trial's edge cuts short a fall above marker noise
//! ([`KinematicOptions::edge_min_fall`]): a foot that lands just after the capture starts
//! or just before its markers drop out is found, a marker's last sample before a gap is
//! not. An extreme just beyond the trial's ends, or one sample inside, is seen from the
//! parabola through the last three samples ([`KinematicOptions::edge_beyond_s`]). A
//! pelvis seen for less than the direction's window gets a window it fills.

use crate::axes::Vertical;
use crate::error::{Error, Result};
pub use crate::kinematic_options::{Estimate, KinematicOptions, Method, Prepared};
use crate::signal::{self, lowest};
use crate::{Event, Feet, Kind, Side, Source};

/// The fewest frames a trial needs: three, to see an extremum between two samples.
pub const MIN_FRAMES: usize = 3;

/// The walking direction per frame (unit, horizontal; NaN where the pelvis is unknown or
/// slower than walking, except next to walking: see [`hold_direction`]).
pub fn walking_direction(
    pelvis: &[[f64; 3]],
    vertical: Vertical,
    rate: f64,
    opts: &KinematicOptions,
) -> Vec<[f64; 3]> {
    let h = ((opts.direction_window_s * rate).round() as usize).max(1);
    let dir = direction_over(pelvis, vertical, rate, opts, h);
    if dir.iter().any(|d| d[0].is_finite()) {
        return dir;
    }
    // A pelvis seen for less than the window (MOtoNMS' run: its sacrum seen for 0.5 s
    // while the feet cross the plates) gets the window its longest seen run allows, down
    // to 0.2 s: the speed test still decides whether it travels.
    let seen = longest_run(pelvis);
    let short = seen.saturating_sub(1) / 2;
    if short < h && short as f64 >= 0.1 * rate {
        return direction_over(pelvis, vertical, rate, opts, short);
    }
    dir
}

/// The length of the longest run of frames where every coordinate of `x` is known.
fn longest_run(x: &[[f64; 3]]) -> usize {
    let (mut best, mut run) = (0, 0);
    for p in x {
        run = if p.iter().all(|v| v.is_finite()) {
            run + 1
        } else {
            0
        };
        best = best.max(run);
    }
    best
}

/// [`walking_direction`] over a window of `h` frames either side.
fn direction_over(
    pelvis: &[[f64; 3]],
    vertical: Vertical,
    rate: f64,
    opts: &KinematicOptions,
    h: usize,
) -> Vec<[f64; 3]> {
    let n = pelvis.len();
    let mut dir: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(h), (i + h).min(n - 1));
            let d = vertical.horizontal([
                pelvis[b][0] - pelvis[a][0],
                pelvis[b][1] - pelvis[a][1],
                pelvis[b][2] - pelvis[a][2],
            ]);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let speed = len / ((b - a) as f64 / rate);
            if len.is_finite() && b > a && speed >= opts.min_speed_mm_s {
                [d[0] / len, d[1] / len, d[2] / len]
            } else {
                [f64::NAN; 3]
            }
        })
        .collect();
    hold_direction(&mut dir, pelvis, 2 * h);
    dir
}

/// The walking direction per frame as [`walking_direction`] finds it from the pelvis'
/// travel or, where the pelvis never travels at walking speed and the feet cycle under it
/// (a treadmill: [`crate::treadmill::pelvis_stays`], and [`crate::treadmill::direction`]
/// from `feet`), the treadmill's direction
/// at every frame with the pelvis; the flag says which.
pub fn travel_direction(
    pelvis: &[[f64; 3]],
    feet: &[&[[f64; 3]]],
    vertical: Vertical,
    rate: f64,
    opts: &KinematicOptions,
) -> (Vec<[f64; 3]>, bool) {
    let dir = walking_direction(pelvis, vertical, rate, opts);
    if dir.iter().any(|d| d[0].is_finite())
        || !crate::treadmill::pelvis_stays(
            pelvis,
            vertical,
            rate,
            2.0 * opts.direction_window_s,
            opts.min_speed_mm_s,
        )
    {
        return (dir, false);
    }
    match crate::treadmill::direction(pelvis, feet, vertical, rate) {
        Some(d) => (
            pelvis
                .iter()
                .map(|p| {
                    if p.iter().all(|v| v.is_finite()) {
                        d
                    } else {
                        [f64::NAN; 3]
                    }
                })
                .collect(),
            true,
        ),
        None => (dir, false),
    }
}

/// Give frames without a direction, where the pelvis is known, the direction of the
/// nearest frame that has one, when it lies within `hold` frames. The first steps of a
/// trial that starts from standing (gait initiation) and the last ones of a trial that
/// stops come while the pelvis, averaged over the window, is still slower than walking;
/// the labs mark their strikes and offs all the same (HansUniVie, BTK's 561xxa01 and
/// c3d-samples' 2198928 lost their first events to this). Standing farther from walking
/// keeps no direction, and a still foot shows no extreme, so no event is made up there.
pub fn hold_direction(dir: &mut [[f64; 3]], pelvis: &[[f64; 3]], hold: usize) {
    let n = dir.len();
    let known: Vec<usize> = (0..n).filter(|&i| dir[i][0].is_finite()).collect();
    if known.is_empty() {
        return;
    }
    let mut next = 0;
    for i in 0..n {
        if dir[i][0].is_finite() || !pelvis[i].iter().all(|v| v.is_finite()) {
            continue;
        }
        while next < known.len() && known[next] < i {
            next += 1;
        }
        let after = known.get(next).map(|&k| (k - i, k));
        let before = next.checked_sub(1).map(|j| (i - known[j], known[j]));
        let nearest = match (before, after) {
            (Some(b), Some(a)) => Some(if b.0 <= a.0 { b } else { a }),
            (b, a) => b.or(a),
        };
        if let Some((d, k)) = nearest {
            if d <= hold {
                dir[i] = dir[k];
            }
        }
    }
}

/// `marker − pelvis` along the walking direction, per frame (NaN where unknown).
fn along(marker: &[[f64; 3]], pelvis: &[[f64; 3]], dir: &[[f64; 3]]) -> Vec<f64> {
    marker
        .iter()
        .zip(pelvis)
        .zip(dir)
        .map(|((m, p), d)| (0..3).map(|k| (m[k] - p[k]) * d[k]).sum())
        .collect()
}

fn all_missing(t: &[[f64; 3]]) -> bool {
    !t.iter().any(|p| p.iter().all(|v| v.is_finite()))
}

/// Check the input and find what the methods share.
pub fn prepare(feet: &Feet, rate: f64, opts: &KinematicOptions) -> Result<Prepared> {
    feet.check()?;
    if !(rate.is_finite() && rate > 0.0) {
        return Err(Error::Input(format!(
            "point rate {rate}: expected a positive number of frames per second"
        )));
    }
    let n = feet.frames();
    if n < MIN_FRAMES {
        return Err(Error::TooShort {
            frames: n,
            needed: MIN_FRAMES,
        });
    }
    if all_missing(&feet.pelvis) {
        return Err(Error::AllMissing("pelvis".into()));
    }
    if [
        &feet.left_heel,
        &feet.left_toe,
        &feet.right_heel,
        &feet.right_toe,
    ]
    .iter()
    .all(|t| all_missing(t))
    {
        return Err(Error::AllMissing("foot".into()));
    }
    let vertical = feet
        .vertical()
        .ok_or_else(|| Error::AllMissing("foot (in frames with the pelvis)".into()))?;
    let mut pelvis = feet.pelvis.clone();
    signal::fill_short(&mut pelvis, (0.5 * rate).round() as usize);
    signal::extend_ends(
        &mut pelvis,
        (opts.pelvis_extend_s * rate).round() as usize,
        ((0.1 * rate).round() as usize).max(1),
    );
    let (dir, treadmill) = travel_direction(
        &pelvis,
        &[
            &feet.left_heel,
            &feet.left_toe,
            &feet.right_heel,
            &feet.right_toe,
        ],
        vertical,
        rate,
        opts,
    );
    if dir.iter().all(|d| d[0].is_nan()) {
        return Err(Error::NoWalking {
            min_speed_m_s: opts.min_speed_mm_s / 1000.0,
            window_s: 2.0 * opts.direction_window_s,
        });
    }
    let half = ((opts.min_half_stride_s * rate).round() as usize).max(1);
    Ok(Prepared {
        vertical,
        pelvis,
        dir,
        treadmill,
        rate,
        half,
        reach: 2 * half,
    })
}

/// Foot strikes and foot offs of both feet (sorted by time), each kind by the estimates
/// [`KinematicOptions`] names for it; on a run ([`crate::running::is_running`], judged with
/// the walking offs) the offs are [`KinematicOptions::running_off`]'s.
pub fn kinematic_events(feet: &Feet, rate: f64, opts: &KinematicOptions) -> Result<Vec<Event>> {
    Ok(kinematic_gait(feet, rate, opts)?.0)
}

/// [`kinematic_events`] and whether the trial was read as a run.
pub fn kinematic_gait(
    feet: &Feet,
    rate: f64,
    opts: &KinematicOptions,
) -> Result<(Vec<Event>, bool)> {
    let prep = prepare(feet, rate, opts)?;
    let n = feet.frames();
    let mut found = [Found::default(), Found::default()];
    // The trial's stride, both feet's intervals pooled: one shift for every off of the
    // trial, so a calibration on the trial's own plates (one median shift) undoes it exactly.
    let off_shift = if opts.off_stride_slope != 0.0 {
        let [l, r] = &mut found;
        let strikes = [
            l.get(
                Method::Zeni,
                Kind::FootStrike,
                feet,
                Side::Left,
                &prep,
                opts,
            ),
            r.get(
                Method::Zeni,
                Kind::FootStrike,
                feet,
                Side::Right,
                &prep,
                opts,
            ),
        ];
        let stride = trial_stride_s(&strikes, rate).unwrap_or(opts.off_stride_ref_s);
        opts.off_stride_slope * (stride - opts.off_stride_ref_s) * rate
    } else {
        0.0
    };
    let combined = |found: &mut [Found; 2], estimates: &[Estimate], kind: Kind, shift: f64| {
        let [l, r] = found;
        [(l, Side::Left), (r, Side::Right)]
            .map(|(f, side)| combine(f, estimates, kind, feet, side, &prep, opts, shift))
    };
    let strikes = combined(&mut found, &opts.strike, Kind::FootStrike, 0.0);
    let walking_offs = combined(&mut found, &opts.off, Kind::FootOff, off_shift);
    // A flight both offs show: the walking offs come late on a run (so a flight they show
    // is there), and a walking toe marker that rises early in the roll-over cannot make one
    // alone; the running offs must show it too (the synthetic walk of sample_c3d, whose toe
    // rises 150 ms after Zeni's off, shows it in Zeni's alone).
    let running_offs = (!opts.running_off.is_empty()
        && crate::running::is_running(&strikes, &walking_offs, rate))
    .then(|| combined(&mut found, &opts.running_off, Kind::FootOff, 0.0))
    .filter(|offs| crate::running::is_running(&strikes, offs, rate));
    let running = running_offs.is_some();
    let mut offs = running_offs.unwrap_or(walking_offs);
    if running {
        for (s, side) in Side::BOTH.into_iter().enumerate() {
            if let Some(off) =
                running_off_at_the_end(feet, side, &prep, &strikes[s], &offs[s], opts)
            {
                offs[s].push(off);
            }
        }
    }
    let mut out = Vec::new();
    for (s, side) in Side::BOTH.into_iter().enumerate() {
        for (kind, times) in [(Kind::FootStrike, &strikes[s]), (Kind::FootOff, &offs[s])] {
            for &index in times {
                if index >= 0.0 && index <= (n - 1) as f64 {
                    out.push(Event {
                        side,
                        kind,
                        index,
                        source: Source::Kinematics,
                        plate: None,
                    });
                }
            }
        }
    }
    crate::sort_events(&mut out);
    Ok((out, running))
}

/// On a run, the off of a foot whose last strike has no off after it: the running off's
/// method ([`Method::ZeniLift`], the toe's last rise through its stance level) anchored on
/// the trial's last frame instead of Zeni's off, which a run's flight carries 40–100 ms past
/// the lift-off (docs/events.md, "Running"), so past the end of a trial that stops within
/// that of a foot leaving the floor (pyorerun's run, the treadmill run's last step). Kept
/// only where the toe is seen rising after that strike; none where the trial ends with the
/// foot still down.
fn running_off_at_the_end(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    strikes: &[f64],
    offs: &[f64],
    opts: &KinematicOptions,
) -> Option<f64> {
    let last = *strikes.last()?;
    let est = opts.running_off.first()?;
    if est.method != Method::ZeniLift || offs.iter().any(|&o| o > last) {
        return None;
    }
    let end = (feet.frames() - 1) as f64;
    let lift = refine_off(feet, side, prep.vertical, end, prep.rate, opts.lift_mm);
    (lift < end && lift > last).then_some(lift + est.offset_s * prep.rate)
}

/// One foot's events of one kind from `estimates`: the first decides which events exist;
/// each event's index is the mean of the estimates (offsets added) that have an event
/// within [`KinematicOptions::combine_window_s`] of it, plus `shift` (frames).
#[allow(clippy::too_many_arguments)]
fn combine(
    found: &mut Found,
    estimates: &[Estimate],
    kind: Kind,
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    opts: &KinematicOptions,
    shift: f64,
) -> Vec<f64> {
    let window = opts.combine_window_s * prep.rate;
    let mut each = estimates.iter().map(|e| {
        let offset = e.offset_s * prep.rate;
        let v: Vec<f64> = found
            .get(e.method, kind, feet, side, prep, opts)
            .iter()
            .map(|i| i + offset)
            .collect();
        v
    });
    let Some(primary) = each.next() else {
        return Vec::new();
    };
    let others: Vec<Vec<f64>> = each.collect();
    primary
        .into_iter()
        .map(|i| {
            let mut sum = i;
            let mut count = 1.0;
            for o in &others {
                if let Some(j) = o
                    .iter()
                    .copied()
                    .filter(|j| (j - i).abs() <= window)
                    .min_by(|a, b| (a - i).abs().total_cmp(&(b - i).abs()))
                {
                    sum += j;
                    count += 1.0;
                }
            }
            sum / count + shift
        })
        .collect()
}

/// Each method's (strikes, offs) of one foot, computed once when first asked for.
#[derive(Default)]
struct Found {
    zeni: Option<(Vec<f64>, Vec<f64>)>,
    zeni_landing: Option<Vec<f64>>,
    oconnor: Option<(Vec<f64>, Vec<f64>)>,
    desailly: Option<(Vec<f64>, Vec<f64>)>,
    velocity: Option<(Vec<f64>, Vec<f64>)>,
    lift: Option<Vec<f64>>,
    impact: Option<Vec<f64>>,
    landing: Option<(Vec<f64>, Vec<f64>)>,
    touchdown: Option<(Vec<f64>, Vec<f64>)>,
}

impl Found {
    fn get(
        &mut self,
        method: Method,
        kind: Kind,
        feet: &Feet,
        side: Side,
        prep: &Prepared,
        opts: &KinematicOptions,
    ) -> Vec<f64> {
        let strike = kind == Kind::FootStrike;
        let pick = |p: &(Vec<f64>, Vec<f64>)| if strike { p.0.clone() } else { p.1.clone() };
        let zeni = self
            .zeni
            .get_or_insert_with(|| zeni(feet, side, prep, opts))
            .clone();
        match method {
            Method::Zeni => pick(&zeni),
            Method::ZeniLift if !strike => self
                .lift
                .get_or_insert_with(|| {
                    zeni.1
                        .iter()
                        .map(|&j| refine_off(feet, side, prep.vertical, j, prep.rate, opts.lift_mm))
                        .collect()
                })
                .clone(),
            Method::ZeniLanding if !strike => zeni.1,
            Method::ZeniLanding | Method::ZeniLift => self
                .zeni_landing
                .get_or_insert_with(|| {
                    zeni.0
                        .iter()
                        .map(|&i| {
                            if feet.heel_is_ankle(side) {
                                i + opts.ankle_strike_offset_s * prep.rate
                            } else {
                                refine_strike(
                                    feet,
                                    side,
                                    prep.vertical,
                                    i,
                                    prep.rate,
                                    opts.touch_mm,
                                )
                            }
                        })
                        .collect()
                })
                .clone(),
            Method::Impact if !strike => zeni.1,
            Method::Impact => self
                .impact
                .get_or_insert_with(|| crate::impact::strikes(feet, side, prep, &zeni.0, opts))
                .clone(),
            Method::Landing => pick(self.landing.get_or_insert_with(|| {
                (
                    crate::landing::strikes(feet, side, prep, &zeni.0, opts),
                    crate::landing::offs(feet, side, prep, &zeni.1, opts),
                )
            })),
            Method::Touchdown => pick(self.touchdown.get_or_insert_with(|| {
                (
                    crate::touchdown::strikes(feet, side, prep, &zeni.0, opts),
                    crate::touchdown::offs(feet, side, prep, &zeni.1, opts),
                )
            })),
            Method::OConnor => pick(
                self.oconnor
                    .get_or_insert_with(|| crate::oconnor::events(feet, side, prep, opts)),
            ),
            Method::Velocity => pick(self.velocity.get_or_insert_with(|| {
                crate::velocity::events(feet, side, prep, &zeni.0, &zeni.1, opts)
            })),
            Method::Desailly => {
                let stride_hz = stride_frequency(&zeni.0, prep.rate);
                pick(self.desailly.get_or_insert_with(|| {
                    crate::desailly::events(feet, side, prep, stride_hz, opts)
                }))
            }
        }
    }
}

/// The trial's stride (s): the median interval between successive strikes of each foot
/// (frame indices at `rate`), both feet pooled; `None` where no foot has two strikes.
pub fn trial_stride_s(feet_strikes: &[Vec<f64>], rate: f64) -> Option<f64> {
    let gaps: Vec<f64> = feet_strikes
        .iter()
        .flat_map(|s| s.windows(2).map(|w| w[1] - w[0]))
        .collect();
    signal::quantile(&gaps, 0.5)
        .filter(|g| g.is_finite() && *g > 0.0)
        .map(|g| g / rate)
}

/// The stride frequency (Hz) from one foot's successive strikes: the median interval's
/// inverse, 1 Hz (a typical walk) when fewer than two strikes are seen.
pub fn stride_frequency(strikes: &[f64], rate: f64) -> f64 {
    let gaps: Vec<f64> = strikes.windows(2).map(|w| w[1] - w[0]).collect();
    match signal::quantile(&gaps, 0.5) {
        Some(g) if g > 0.0 => rate / g,
        _ => 1.0,
    }
}

/// Zeni's strikes (the heel's forward extremes) and offs (the toe's backward extremes) of
/// one foot, as fractional frame indices before any offset.
pub fn zeni(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    opts: &KinematicOptions,
) -> (Vec<f64>, Vec<f64>) {
    let smooth = ((opts.smooth_s * prep.rate / 2.0).round()) as usize;
    let (heel, toe) = feet.foot(side);
    let bridge = (opts.bridge_s * prep.rate).round() as usize;
    let bridged = |m: &[[f64; 3]]| {
        let mut x = along(m, &prep.pelvis, &prep.dir);
        signal::bridge_short(&mut x, bridge);
        x
    };
    let heel = signal::smooth(&bridged(heel), smooth);
    let toe: Vec<f64> = signal::smooth(&bridged(toe), smooth)
        .into_iter()
        .map(|v| -v)
        .collect();
    // The prominence is measured over at least a third of the stride either side: a slow
    // pathological walk (c3d-samples' Eb015: 0.2 m/s, 2.3 s stances) moves the heel back
    // by too little within the default half second for its forward extreme to stand out.
    let rate = prep.rate;
    // At most 8 of the longest strides looked for (about 30 s), from the trial's middle:
    // the autocorrelation costs frames × lags, and a long trial repeats its stride anyway.
    let (lo, hi) = ((0.6 * rate) as usize, (4.0 * rate) as usize);
    let keep = (8 * hi).min(heel.len());
    let start = (heel.len() - keep) / 2;
    let stride = signal::period(&heel[start..start + keep], lo, hi);
    let reach = stride.map_or(prep.reach, |t| prep.reach.max(t / 3));
    let extremes = |x: &[f64]| match (signal::quantile(x, 0.05), signal::quantile(x, 0.95)) {
        (Some(a), Some(b)) => {
            let prominence = (0.25 * (b - a)).max(40.0);
            let mut found = signal::maxima_cut(
                x,
                prep.half,
                reach,
                prominence,
                Some(signal::Cut {
                    min_samples: 2,
                    min_fall: opts.cut_min_fall,
                    edge_min_fall: opts.edge_min_fall,
                }),
            );
            found.extend(signal::edge_maxima(
                x,
                prep.half,
                reach,
                prominence,
                opts.edge_beyond_s * rate,
            ));
            found.sort_by(f64::total_cmp);
            found
        }
        _ => Vec::new(),
    };
    (extremes(&heel), extremes(&toe))
}

/// Heights of a foot's heel and toe per frame (NaN where missing).
fn heights(feet: &Feet, side: Side, v: Vertical) -> (Vec<f64>, Vec<f64>) {
    let (heel, toe) = feet.foot(side);
    (
        heel.iter().map(|p| v.height(*p)).collect(),
        toe.iter().map(|p| v.height(*p)).collect(),
    )
}

/// Foot strike refined from Zeni's heel extremum at `i0`: the first local minimum of the
/// heel's or the toe's height in the 0.25 s after `i0` (whichever part lands first) that
/// lies within `touch` mm of that part's lowest height in the 0.5 s after `i0` (its stance
/// level, taken after the event so stairs and slopes follow). The heel's forward extreme
/// comes while the foot still descends; the landing stops the descent, and the marker
/// rises again as the foot rolls over. Falls back to `i0` when no such minimum exists.
pub fn refine_strike(feet: &Feet, side: Side, v: Vertical, i0: f64, rate: f64, touch: f64) -> f64 {
    let (heel, toe) = heights(feet, side, v);
    let n = heel.len();
    let first_min = |x: &[f64]| -> Option<f64> {
        let base = lowest(x, i0, i0 + 0.5 * rate);
        // Two samples either side must be known: the edge of a gap is no landing.
        let (a, b) = (
            i0.floor().max(2.0) as usize,
            ((i0 + 0.25 * rate) as usize).min(n.saturating_sub(2)),
        );
        (a..b).find_map(|k| {
            let (y0, y1, y2) = (x[k - 1], x[k], x[k + 1]);
            let known = x[k - 2..=k + 2].iter().all(|v| v.is_finite());
            (known && y1 < y0 && y1 <= y2 && y1 - base <= touch)
                .then(|| k as f64 + signal::parabolic(y0, y1, y2))
        })
    };
    match (first_min(&heel), first_min(&toe)) {
        (Some(h), Some(t)) => h.min(t),
        (Some(h), None) => h,
        (None, Some(t)) => t,
        (None, None) => i0,
    }
}

/// Foot off refined from Zeni's toe extremum at `j0`: where the toe last rises through
/// `lift` mm above its stance level (its lowest height in the 0.5 s before `j0`), searched
/// from 0.15 s after `j0` back to 0.3 s before it. The toe's backward extreme relative to
/// the pelvis depends on where the marker sits on the forefoot; the toe leaving its stance
/// height is the lift-off itself. Falls back to `j0` when no such rise is seen with known
/// samples on both sides.
pub fn refine_off(feet: &Feet, side: Side, v: Vertical, j0: f64, rate: f64, lift: f64) -> f64 {
    let (_, toe) = heights(feet, side, v);
    let n = toe.len();
    if n < 2 {
        return j0;
    }
    let base = lowest(&toe, j0 - 0.5 * rate, j0 + 1.0);
    if !base.is_finite() {
        return j0;
    }
    let thr = base + lift;
    let hi = ((j0 + 0.15 * rate) as usize).min(n - 2);
    let lo = (j0 - 0.3 * rate).max(0.0) as usize;
    (lo..=hi)
        .rev()
        .find(|&k| {
            toe[k].is_finite() && toe[k + 1].is_finite() && toe[k] <= thr && toe[k + 1] > thr
        })
        .map_or(j0, |k| {
            let (a, b) = (toe[k], toe[k + 1]);
            k as f64 + ((thr - a) / (b - a)).clamp(0.0, 1.0)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One method for both kinds, no offsets.
    fn only(method: Method) -> KinematicOptions {
        let e = Estimate {
            method,
            offset_s: 0.0,
        };
        KinematicOptions {
            strike: vec![e],
            off: vec![e],
            ..KinematicOptions::default()
        }
    }

    /// A synthetic walk along −x at 1.2 m/s, Z up, 100 Hz: each heel swings ±300 mm about
    /// the pelvis with a 1 s stride, the sides half a stride apart.
    fn walk(frames: usize) -> Feet {
        let rate = 100.0;
        let mut f = Feet::default();
        for i in 0..frames {
            let t = i as f64 / rate;
            let x = -1200.0 * t;
            f.pelvis.push([x, 0.0, 950.0]);
            for (phase, heel, toe) in [
                (0.0, &mut f.left_heel, &mut f.left_toe),
                (0.5, &mut f.right_heel, &mut f.right_toe),
            ] {
                let s = (2.0 * std::f64::consts::PI * (t - phase)).cos();
                heel.push([x - 300.0 * s, 0.0, 60.0]);
                toe.push([
                    x - 300.0 * (2.0 * std::f64::consts::PI * (t - phase - 0.4)).cos() - 150.0,
                    0.0,
                    40.0,
                ]);
            }
        }
        f
    }

    #[test]
    fn strikes_at_the_heels_forward_extreme() {
        let f = walk(400);
        let ev = kinematic_events(&f, 100.0, &only(Method::Zeni)).unwrap();
        let strikes: Vec<f64> = ev
            .iter()
            .filter(|e| e.side == Side::Left && e.kind == Kind::FootStrike)
            .map(|e| e.index)
            .collect();
        // Left heel forward (towards −x) when cos = 1: t = 1, 2, 3 s (t = 0 is the edge).
        assert_eq!(strikes.len(), 3, "{ev:?}");
        for (s, want) in strikes.iter().zip([100.0, 200.0, 300.0]) {
            assert!((s - want).abs() < 0.05, "{strikes:?}");
        }
        let offs = ev
            .iter()
            .filter(|e| e.side == Side::Right && e.kind == Kind::FootOff)
            .count();
        assert!(offs >= 3, "{ev:?}");
    }

    /// Position and heading (horizontal x, z) after `s` mm along a path: 3.6 m straight along
    /// +z, a half circle of radius 1.5 m, 3.6 m back along −z.
    fn u_turn(s: f64) -> ([f64; 2], [f64; 2]) {
        let (l1, r) = (3600.0, 1500.0);
        let arc = std::f64::consts::PI * r;
        if s < l1 {
            ([0.0, s], [0.0, 1.0])
        } else if s < l1 + arc {
            let th = (s - l1) / r;
            ([r - r * th.cos(), l1 + r * th.sin()], [th.sin(), th.cos()])
        } else {
            ([2.0 * r, l1 - (s - l1 - arc)], [0.0, -1.0])
        }
    }

    #[test]
    fn a_u_turn_in_a_y_up_lab() {
        let rate = 100.0;
        let frames = 990;
        let mut f = Feet::default();
        let tau = 2.0 * std::f64::consts::PI;
        for i in 0..frames {
            let t = i as f64 / rate;
            let (p, d) = u_turn(1200.0 * t);
            f.pelvis.push([p[0], 950.0, p[1]]);
            for (phase, heel, toe) in [
                (0.0, &mut f.left_heel, &mut f.left_toe),
                (0.5, &mut f.right_heel, &mut f.right_toe),
            ] {
                let h = 300.0 * (tau * (t - phase)).cos();
                let o = 300.0 * (tau * (t - phase - 0.4)).cos() + 150.0;
                heel.push([p[0] + d[0] * h, 60.0, p[1] + d[1] * h]);
                toe.push([p[0] + d[0] * o, 40.0, p[1] + d[1] * o]);
            }
        }
        let ev = kinematic_events(&f, rate, &only(Method::Zeni)).unwrap();
        // The left heel is forward at t = 1, 2, … 9 s: one strike each, straight, on the
        // curve and after the turn, and nothing else.
        let strikes: Vec<f64> = ev
            .iter()
            .filter(|e| e.side == Side::Left && e.kind == Kind::FootStrike)
            .map(|e| e.index / rate)
            .collect();
        assert_eq!(strikes.len(), 9, "{strikes:?}");
        for (k, s) in strikes.iter().enumerate() {
            assert!((s - (k + 1) as f64).abs() < 0.02, "{strikes:?}");
        }
        let offs = ev
            .iter()
            .filter(|e| e.side == Side::Right && e.kind == Kind::FootOff)
            .count();
        // The right toe is farthest back at t = 0.4, 1.4, … 9.4 s.
        assert_eq!(offs, 10, "{ev:?}");
    }

    /// A walk along +x at 1.2 m/s, Z up, 100 Hz, 1 s strides; each foot (heel and toe
    /// together) stands still from its strike at t = k + `phase` to its off 0.6 s later, then
    /// swings 1.2 m forward in 0.4 s (forward speed peaking mid-swing) while its height
    /// rises and falls as sin² (fastest rise 0.1 s after the off, fastest fall 0.1 s before
    /// the strike).
    fn stepping(frames: usize) -> Feet {
        let rate = 100.0;
        let tau = 2.0 * std::f64::consts::PI;
        let mut f = Feet::default();
        for i in 0..frames {
            let t = i as f64 / rate;
            f.pelvis.push([1200.0 * t, 0.0, 950.0]);
            for (phase, heel, toe) in [
                (0.0, &mut f.left_heel, &mut f.left_toe),
                (0.5, &mut f.right_heel, &mut f.right_toe),
            ] {
                let c = t - phase + 0.4; // cycles since the first swing began
                let (k, u) = (c.floor(), c - c.floor());
                let (x, z) = if u < 0.4 {
                    let s = u / 0.4;
                    (
                        k + s - (tau * s).sin() / tau,
                        80.0 * (std::f64::consts::PI * s).sin().powi(2),
                    )
                } else {
                    (k + 1.0, 0.0)
                };
                let x = 1200.0 * x + 1200.0 * phase - 600.0;
                heel.push([x - 100.0, 0.0, 60.0 + z]);
                toe.push([x + 100.0, 0.0, 40.0 + z]);
            }
        }
        f
    }

    fn times(ev: &[Event], side: Side, kind: Kind) -> Vec<f64> {
        ev.iter()
            .filter(|e| e.side == side && e.kind == kind)
            .map(|e| e.index / 100.0)
            .collect()
    }

    #[test]
    fn oconnor_strikes_at_the_fall_and_offs_at_the_rise_of_the_foot_centre() {
        let ev = kinematic_events(&stepping(500), 100.0, &only(Method::OConnor)).unwrap();
        // Left strikes at t = 1, 2, 3, 4, 5: the fastest fall 0.1 s before each.
        let s = times(&ev, Side::Left, Kind::FootStrike);
        assert_eq!(s.len(), 5, "{s:?}");
        for (got, want) in s.iter().zip([0.9, 1.9, 2.9, 3.9, 4.9]) {
            assert!((got - want).abs() < 0.02, "{s:?}");
        }
        // Left offs at t = 0.6, 1.6, …: the fastest rise 0.1 s after each.
        let o = times(&ev, Side::Left, Kind::FootOff);
        assert!(o.len() >= 3, "{o:?}");
        for got in &o {
            assert!((got - 0.7 - (got - 0.7).round()).abs() < 0.02, "{o:?}");
        }
    }

    #[test]
    fn velocity_strikes_where_the_foot_stops_and_offs_where_the_toe_starts() {
        // The stepping walk: each foot stands still from its strike (t = k + phase) to its
        // off 0.6 s later. Its swing is short (0.4 s at 3 m/s on average, over a 1.2 m/s
        // walk), so the thresholds (0.5 and 0.8 × the walking speed) are crossed while the
        // foot still slows down: within 60 ms before the strike and after the off, never on
        // the wrong side of either.
        let ev = kinematic_events(&stepping(500), 100.0, &only(Method::Velocity)).unwrap();
        let s = times(&ev, Side::Left, Kind::FootStrike);
        assert!(s.len() >= 3, "{s:?}");
        for got in &s {
            let d = got - got.round();
            assert!((-0.06..=0.0).contains(&d), "{s:?}");
        }
        let o = times(&ev, Side::Left, Kind::FootOff);
        assert!(o.len() >= 3, "{o:?}");
        for got in &o {
            let d = got - 0.6 - (got - 0.6).round();
            assert!((0.0..=0.06).contains(&d), "{o:?}");
        }
    }

    #[test]
    fn impact_strikes_where_the_heels_descent_is_stopped() {
        // The stepping walk's heel comes down as 80 sin²(π s) mm and stands still from the
        // strike (t = k for the left foot): its upward acceleration is largest at the
        // landing and zero after it; low-passed at 10 Hz, that edge spreads and the peak
        // comes 32 ms before the landing (a real landing's stop is sharper: on the corpora
        // the method's median lag is +11 ms, docs/events.md).
        // The strike at the trial's last frame (t = 5 s) is left out: its search is cut.
        let ev = kinematic_events(&stepping(500), 100.0, &only(Method::Impact)).unwrap();
        let mut s = times(&ev, Side::Left, Kind::FootStrike);
        s.retain(|t| *t < 4.9);
        assert!(s.len() >= 3, "{s:?}");
        for got in &s {
            let d = got - got.round();
            assert!((-0.035..=-0.03).contains(&d), "{s:?}");
        }
    }

    #[test]
    fn zeni_lift_offs_where_the_toe_rises_from_its_stance_level() {
        // The stepping walk's toe leaves the floor at t = k + 0.6 (left) and rises as
        // 80 sin²(π u / 0.4) mm: 10 mm after 46 ms.
        let ev = kinematic_events(&stepping(500), 100.0, &only(Method::ZeniLift)).unwrap();
        let o = times(&ev, Side::Left, Kind::FootOff);
        assert!(o.len() >= 3, "{o:?}");
        for got in &o {
            let d = got - 0.6 - (got - 0.6).round();
            assert!((d - 0.046).abs() < 0.01, "{o:?}");
        }
    }

    #[test]
    fn landing_strikes_and_offs_at_a_fraction_of_the_swing_height() {
        // The stepping walk's heel comes down as 80 sin²(π s) mm over the last half of a
        // 0.4 s swing: within 10 % (8 mm) of its stance level 41 ms before the strike;
        // its toe leaves likewise, 41 ms after the off.
        let ev = kinematic_events(&stepping(500), 100.0, &only(Method::Landing)).unwrap();
        let s = times(&ev, Side::Left, Kind::FootStrike);
        assert!(s.len() >= 3, "{s:?}");
        for got in &s {
            let d = got - got.round();
            assert!((d + 0.041).abs() < 0.005, "{s:?}");
        }
        let o = times(&ev, Side::Left, Kind::FootOff);
        assert!(o.len() >= 3, "{o:?}");
        for got in &o {
            let d = got - 0.6 - (got - 0.6).round();
            assert!((d - 0.041).abs() < 0.005, "{o:?}");
        }
    }

    #[test]
    fn touchdown_strikes_where_the_foot_is_down_and_still_and_offs_where_the_toe_leaves() {
        // The stepping walk's heel comes down as 80 sin²(π s) mm and stands still from the
        // strike (t = k for the left foot): within 5 mm of its level 32 ms before it, but
        // still descending at over 100 mm/s there; low-passed at 10 Hz, the stop spreads
        // and its speed falls under 30 mm/s 8 ms after the landing. The toe leaves at t = k + 0.6 and, with a
        // 5 mm and 200 mm/s lift-off, rises by 5 mm after 32 ms (30 ms interpolated between
        // 100 Hz frames; its forward speed passes 200 mm/s after 23 ms, so the height
        // decides).
        let opts = KinematicOptions {
            liftoff_mm: 5.0,
            liftoff_speed_mm_s: 200.0,
            ..only(Method::Touchdown)
        };
        let ev = kinematic_events(&stepping(500), 100.0, &opts).unwrap();
        let mut s = times(&ev, Side::Left, Kind::FootStrike);
        s.retain(|t| *t < 4.9);
        assert!(s.len() >= 3, "{s:?}");
        for got in &s {
            let d = got - got.round();
            assert!((0.006..=0.010).contains(&d), "{s:?}");
        }
        let o = times(&ev, Side::Left, Kind::FootOff);
        assert!(o.len() >= 3, "{o:?}");
        for got in &o {
            let d = got - 0.6 - (got - 0.6).round();
            assert!((d - 0.030).abs() < 0.003, "{o:?}");
        }
        // Where an ankle marker stands in for the heel, its height says nothing of the
        // landing: no touchdown strike (the landing refinement gives Zeni's + 20 ms there).
        let mut ankle = stepping(500);
        ankle.heel_is_ankle = [true, false];
        let ev = kinematic_events(&ankle, 100.0, &opts).unwrap();
        assert!(times(&ev, Side::Left, Kind::FootStrike).is_empty());
        assert!(times(&ev, Side::Right, Kind::FootStrike).len() >= 3);
    }

    #[test]
    fn desailly_strikes_at_the_filtered_heels_forward_extreme() {
        let ev = kinematic_events(&walk(500), 100.0, &only(Method::Desailly)).unwrap();
        // The heel's forward swing about the progression peaks at t = 1, 2, 3, 4 s: the
        // zero-lag filter keeps the instants.
        let s = times(&ev, Side::Left, Kind::FootStrike);
        assert!(s.len() >= 3, "{s:?}");
        for got in &s {
            assert!((got - got.round()).abs() < 0.03, "{s:?}");
        }
        let o = times(&ev, Side::Right, Kind::FootOff);
        assert!(o.len() >= 3, "{o:?}");
    }

    #[test]
    fn estimates_are_averaged_and_the_first_decides_which_events_exist() {
        let f = walk(400);
        let e = |method, offset_s| Estimate { method, offset_s };
        let opts = KinematicOptions {
            // Zeni's strikes at t = 0, 1, 2, 3 s, once as is and once 40 ms later; Desailly's
            // shifted 0.5 s away from every one of them, so it joins none.
            strike: vec![
                e(Method::Zeni, 0.0),
                e(Method::Zeni, 0.04),
                e(Method::Desailly, 0.5),
            ],
            off: vec![],
            ..KinematicOptions::default()
        };
        let ev = kinematic_events(&f, 100.0, &opts).unwrap();
        assert!(ev.iter().all(|e| e.kind == Kind::FootStrike), "{ev:?}");
        let s = times(&ev, Side::Left, Kind::FootStrike);
        // The walk's heel also peaks at its first frame (t = 0: an extreme at the edge).
        assert_eq!(s.len(), 4, "{s:?}");
        for (got, want) in s.iter().zip([0.02, 1.02, 2.02, 3.02]) {
            assert!((got - want).abs() < 0.001, "{s:?}");
        }
    }

    #[test]
    fn offs_move_with_the_trials_stride_and_strikes_do_not() {
        // The synthetic walk's stride is 1 s: 0.17 s shorter than the reference, so every
        // off comes 0.0124 × 0.17 s = 2.1 ms earlier than with a constant offset.
        let f = walk(400);
        let zeni = Estimate {
            method: Method::Zeni,
            offset_s: 0.0,
        };
        let with = |slope| KinematicOptions {
            strike: vec![zeni],
            off: vec![zeni],
            off_stride_slope: slope,
            ..KinematicOptions::default()
        };
        let a = kinematic_events(&f, 100.0, &with(0.0)).unwrap();
        let b = kinematic_events(&f, 100.0, &with(0.0124)).unwrap();
        assert_eq!(a.len(), b.len());
        assert!(a.iter().any(|e| e.kind == Kind::FootOff), "{a:?}");
        for (x, y) in a.iter().zip(&b) {
            let want = if x.kind == Kind::FootOff {
                0.0124 * (1.0 - 1.17) * 100.0
            } else {
                0.0
            };
            assert!((y.index - x.index - want).abs() < 1e-3, "{x:?} {y:?}");
        }
        assert_eq!(
            trial_stride_s(&[vec![100.0, 200.0, 300.0], vec![150.0, 252.0]], 100.0),
            Some(1.0)
        );
        assert_eq!(trial_stride_s(&[vec![100.0], vec![]], 100.0), None);
    }

    #[test]
    fn the_direction_is_held_into_the_first_slow_frames() {
        // Standing 0.5 s, then walking: frames of the first second have a direction
        // (held from the first frame walking), frames beyond the hold do not.
        let rate = 100.0;
        let pelvis: Vec<[f64; 3]> = (0..600)
            .map(|i| {
                let t = (i as f64 / rate - 3.0).max(0.0);
                [1200.0 * t, 0.0, 950.0]
            })
            .collect();
        let v = Vertical { axis: 2, sign: 1.0 };
        let dir = walking_direction(&pelvis, v, rate, &KinematicOptions::default());
        assert!(dir[0][0].is_nan());
        assert!((dir[250][0] - 1.0).abs() < 1e-9, "{:?}", dir[250]);
        assert!((dir[400][0] - 1.0).abs() < 1e-9);
    }

    #[test]
    fn bad_input_is_an_error() {
        let f = walk(2);
        assert!(matches!(
            kinematic_events(&f, 100.0, &KinematicOptions::default()),
            Err(Error::TooShort { .. })
        ));
        let mut f = walk(200);
        for p in f
            .left_heel
            .iter_mut()
            .chain(f.right_heel.iter_mut())
            .chain(f.left_toe.iter_mut())
            .chain(f.right_toe.iter_mut())
        {
            *p = [f64::NAN; 3];
        }
        assert!(matches!(
            kinematic_events(&f, 100.0, &KinematicOptions::default()),
            Err(Error::AllMissing(_))
        ));
        let mut f = walk(200);
        for p in f.pelvis.iter_mut() {
            p[0] = 0.0;
        }
        assert!(matches!(
            kinematic_events(&f, 100.0, &KinematicOptions::default()),
            Err(Error::NoWalking { .. })
        ));
        assert!(kinematic_events(&walk(200), f64::NAN, &KinematicOptions::default()).is_err());
    }
}
