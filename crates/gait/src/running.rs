//! Running: a gait with flight, where both feet are off the floor between one foot's off
//! and the other's strike (walking has double support instead: the other foot lands before
//! this one leaves). The definition is the physics' (a duty factor under one half), read
//! from the events themselves, so no speed or cadence threshold is chosen.
//!
//! Why it matters for the markers: Zeni's off, the toe's backward extreme relative to the
//! pelvis, comes while the hip still extends after the foot has left; in walking that is a
//! few milliseconds, in running the leg keeps swinging back through the flight, and the
//! extreme came 39 to 103 ms after the plates' off on the corpora's runs (c3d-more's
//! JA1Gait35, c3d-labs' RBDS001runT35 and sprint_1; docs/events.md, "Running"). The toe
//! leaving its stance level ([`crate::kinematic::refine_off`]) is the lift-off itself.

use crate::Side;

/// Longest flight (s) read as one: an other foot's strike this soon after an off. A
/// sprinter's flight lasts about 0.13 s, a jogger's 0.05 s; walking's next strike of the
/// other foot comes a swing later (0.35 s or more).
pub const MAX_FLIGHT_S: f64 = 0.2;

/// Longest double support (s) read as one: an other foot's strike this long before an off.
/// A slow pathological walk holds both feet down for up to about 0.4 s.
pub const MAX_DOUBLE_SUPPORT_S: f64 = 0.5;

/// Whether the trial is a run: of the offs (frame indices per foot, `offs[0]` left) whose
/// other foot strikes within [`MAX_FLIGHT_S`] after or [`MAX_DOUBLE_SUPPORT_S`] before
/// them, the nearest such strike comes after the off (a flight) for more than half.
/// `strikes` and `offs` are each foot's, in frames at `rate`.
pub fn is_running(strikes: &[Vec<f64>; 2], offs: &[Vec<f64>; 2], rate: f64) -> bool {
    let (mut flights, mut supports) = (0usize, 0usize);
    for side in Side::BOTH {
        let (me, other) = match side {
            Side::Left => (0, 1),
            Side::Right => (1, 0),
        };
        for &off in &offs[me] {
            let nearest = strikes[other]
                .iter()
                .map(|&s| (s - off) / rate)
                .filter(|&d| (-MAX_DOUBLE_SUPPORT_S..=MAX_FLIGHT_S).contains(&d))
                .min_by(|a, b| a.abs().total_cmp(&b.abs()));
            match nearest {
                Some(d) if d > 0.0 => flights += 1,
                Some(_) => supports += 1,
                None => {}
            }
        }
    }
    flights > supports
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flights_make_a_run_and_double_supports_a_walk() {
        let rate = 100.0;
        // Running, 0.7 s stride: left strikes at 0, 70, 140; left offs 25 frames later;
        // right strikes half a stride on (35, 105): 10 frames of flight after each off.
        let run = [vec![0.0, 70.0, 140.0], vec![35.0, 105.0]];
        let run_offs = [vec![25.0, 95.0], vec![60.0, 130.0]];
        assert!(is_running(&run, &run_offs, rate));
        // Walking, 1.1 s stride, 62 % stance: each off comes 12 frames after the other
        // foot's strike.
        let walk = [vec![0.0, 110.0, 220.0], vec![55.0, 165.0]];
        let walk_offs = [vec![67.0, 177.0], vec![12.0, 122.0]];
        assert!(!is_running(&walk, &walk_offs, rate));
        // Nothing to judge by: no run.
        assert!(!is_running(&[vec![], vec![]], &[vec![10.0], vec![]], rate));
    }
}
