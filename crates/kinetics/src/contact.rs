//! Contact intervals: where a foot pushes on the plate, as gait labs read foot-strike and
//! foot-off from the vertical force.
//!
//! The series judged is the push (see [`crate::plate::PlateOutput::push`]), never |Fz|: a
//! plate whose unloaded reading sits at a pull of 15 N is no contact, and a pull is nothing
//! a standing or walking foot can exert.
//!
//! A force hovering at the threshold crosses it back and forth on noise alone, which would
//! cut one footfall into many or add contacts of a few samples. So runs closer than
//! [`MIN_CONTACT_S`] are joined, and runs shorter than it are dropped. The value is no fit
//! to any trial: it is a fifth of the shortest ground contact of human locomotion (about
//! 0.1 s in sprinting), so no real footfall is dropped or joined to the next one (a flight
//! phase lasts longer than that too).

/// The shortest contact, and the shortest break between two, in seconds.
pub const MIN_CONTACT_S: f64 = 0.02;

/// Inclusive sample ranges where `push` is at or above `threshold` (N), sampled at
/// `rate` Hz, joined across breaks shorter than [`MIN_CONTACT_S`] and keeping those at
/// least that long. A NaN counts as no load: an unknown force is not a contact.
pub fn contacts(push: &[f64], threshold: f64, rate: f64) -> Vec<[usize; 2]> {
    let min = if rate.is_finite() && rate > 0.0 {
        (MIN_CONTACT_S * rate).ceil() as usize
    } else {
        1
    }
    .max(1);
    let mut runs: Vec<[usize; 2]> = Vec::new();
    let mut start = None;
    for (i, v) in push.iter().enumerate() {
        // NaN compares false: no contact.
        let on = *v >= threshold;
        match (on, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                runs.push([s, i - 1]);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        runs.push([s, push.len() - 1]);
    }
    let mut joined: Vec<[usize; 2]> = Vec::new();
    for r in runs {
        match joined.last_mut() {
            Some(last) if r[0] - last[1] - 1 < min => last[1] = r[1],
            _ => joined.push(r),
        }
    }
    joined.retain(|r| r[1] - r[0] + 1 >= min);
    joined
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_above_the_threshold() {
        let push = [0.0, 5.0, 20.0, 30.0, 8.0, 12.0, f64::NAN, 15.0, -40.0];
        // At 1 Hz every run and break is long enough to stand alone.
        assert_eq!(contacts(&push, 10.0, 1.0), vec![[2, 3], [5, 5], [7, 7]]);
        // A pull, however strong, is no contact.
        assert!(contacts(&[-50.0; 10], 10.0, 1.0).is_empty());
        assert!(contacts(&[], 10.0, 1000.0).is_empty());
    }

    #[test]
    fn noise_at_the_threshold_is_one_contact_or_none() {
        // 1000 Hz: a 5-sample blip is dropped; a 300-sample stance with a 3-sample dip
        // below the threshold is one contact.
        let mut fz = vec![0.0; 1000];
        fz[100..105].iter_mut().for_each(|v| *v = 11.0);
        fz[400..700].iter_mut().for_each(|v| *v = 600.0);
        fz[500..503].iter_mut().for_each(|v| *v = 9.0);
        assert_eq!(contacts(&fz, 10.0, 1000.0), vec![[400, 699]]);
    }
}
