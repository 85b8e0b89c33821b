//! Whether the lab's own events are a truth: the foot's state at each of them, and the lab
//! strikes the trial's plates contradict (`--truth-check`, `--without-contradicted`).

use super::Timed;
use gait::Kind;

/// A foot's state at time `t` (s): how far its heel and its toe stand above their stance
/// level and how fast they move up (mm, mm/s: heel height, heel speed, toe height, toe
/// speed). The stance level is the lowest height over the next 0.5 s for a strike, over the
/// 0.5 s before for an off. `None` at the trial's edges or where the lab has no vertical.
fn foot_state(
    c: &c3d::C3d,
    feet: &gait::Feet,
    rate: f64,
    (side, kind, t): Timed,
) -> Option<[f64; 4]> {
    let v = gait::axes::vertical(
        &feet.pelvis,
        &[
            &feet.left_heel,
            &feet.right_heel,
            &feet.left_toe,
            &feet.right_toe,
        ],
    )?;
    let n = feet.frames();
    let i = ((t - c.frame_time(0)) * rate).round();
    if i < 1.0 || i as usize + 1 >= n {
        return None;
    }
    let i = i as usize;
    let (heel, toe) = feet.foot(side);
    let half = (0.5 * rate) as usize;
    let state = |x: &[[f64; 3]]| {
        let h = |j: usize| v.height(x[j]);
        let (a, b) = if kind == Kind::FootStrike {
            (i, (i + half).min(n))
        } else {
            (i.saturating_sub(half), i + 1)
        };
        let level = (a..b)
            .map(h)
            .filter(|v| v.is_finite())
            .fold(f64::NAN, f64::min);
        (h(i) - level, (h(i + 1) - h(i - 1)) * rate / 2.0)
    };
    let (hh, hs) = state(heel);
    let (th, ts) = state(toe);
    Some([hh, hs, th, ts])
}

/// How much higher (mm) than at every plate strike of the trial the landing part must stand
/// for a lab strike to be contradicted. Over one trial's plate strikes that part's height
/// spreads by 0–5 mm on most corpus trials, more at 60 Hz where the heel descends 3–7 mm
/// a frame (sample_04: 8.6 and 16.1 mm; sample_11: 9.9–22.6 mm); what counts is the
/// excess over the highest (RBWH's two free strikes: 7.2 and 9.5 mm, at 100 Hz with the
/// heel descending under 1 mm a frame). `--truth-check` prints every plate strike's
/// heights.
const CONTRADICTED_MM: f64 = 5.0;

/// The lab's strikes away from the plates whose foot, by the trial's own plate strikes, has
/// not landed yet. The landing part is the heel or the toe, whichever stands lower above its
/// stance level at the trial's plate strikes (the heel for a heel striker); a lab strike
/// where that part stands more than [`CONTRADICTED_MM`] higher than at every plate strike
/// is contradicted. A strike set by hand (or carried over from the markers by the lab's
/// software) can be early or late; where the plates show what a contact looks like in this
/// trial, such a strike is no truth to score against.
pub fn contradicted(
    c: &c3d::C3d,
    feet: &gait::Feet,
    rate: f64,
    lab_events: &[Timed],
    plates: &[Timed],
) -> Vec<Timed> {
    let at_plates: Vec<[f64; 4]> = plates
        .iter()
        .filter(|p| p.1 == Kind::FootStrike)
        .filter_map(|&p| foot_state(c, feet, rate, p))
        .collect();
    let highest = |k: usize| at_plates.iter().map(|s| s[k]).fold(f64::NAN, f64::max);
    let (heel, toe) = (highest(0), highest(2));
    if !(heel.is_finite() && toe.is_finite()) {
        return Vec::new();
    }
    let (part, level) = if heel <= toe { (0, heel) } else { (2, toe) };
    lab_events
        .iter()
        .filter(|e| e.1 == Kind::FootStrike)
        .filter(|e| {
            !plates
                .iter()
                .any(|p| p.0 == e.0 && p.1 == e.1 && (p.2 - e.2).abs() <= 0.02)
        })
        .filter(|&&e| {
            foot_state(c, feet, rate, e).is_some_and(|s| s[part] > level + CONTRADICTED_MM)
        })
        .copied()
        .collect()
}

/// `--truth-check`: each lab event with the foot's state at it ([`foot_state`]), marked
/// `plate` when a plate event of its foot and kind lies within 20 ms (the lab's event is
/// then the plate's), `free` otherwise, and `CONTRADICTED` as [`contradicted`] finds.
pub fn truth_state(
    name: &str,
    lab: &str,
    c: &c3d::C3d,
    feet: &gait::Feet,
    lab_events: &[Timed],
    plates: &[Timed],
    rate: f64,
) {
    let bad = contradicted(c, feet, rate, lab_events, plates);
    let short = name.rsplit('/').next().unwrap_or(name);
    for &p in plates.iter().filter(|p| p.1 == Kind::FootStrike) {
        if let Some([hh, _, th, _]) = foot_state(c, feet, rate, p) {
            println!(
                "plate {lab:<28} {short:<40} {:?} FootStrike {:7.3} heel {hh:5.1} mm toe {th:5.1} mm",
                p.0, p.2
            );
        }
    }
    for &e in lab_events {
        let Some([hh, hs, th, ts]) = foot_state(c, feet, rate, e) else {
            continue;
        };
        let (side, kind, t) = e;
        let on_plate = plates
            .iter()
            .any(|p| p.0 == side && p.1 == kind && (p.2 - t).abs() <= 0.02);
        println!(
            "truth {lab:<28} {short:<40} {side:?} {kind:?} {t:7.3} {:<5} heel {hh:5.1} mm {hs:+6.0} mm/s  toe {th:5.1} mm {ts:+6.0} mm/s{}",
            if on_plate { "plate" } else { "free" },
            if bad.contains(&e) { "  CONTRADICTED by the trial's plate strikes" } else { "" }
        );
    }
}
