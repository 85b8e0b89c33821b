//! Treadmill trials: the pelvis stays in the volume while the feet cycle under it, so the
//! walking direction cannot come from the pelvis' travel. Zeni et al. (2008) defined their
//! method on the feet *relative to the pelvis*, on a treadmill first: the heel's forward
//! extreme at foot strike, the toe's backward extreme at foot off. The direction they need is
//! the one along which the feet swing back and forth relative to the pelvis, pointing the
//! way the feet move while they are off the floor (forward in swing; the belt carries them
//! back in stance).

use crate::axes::Vertical;
use crate::signal;

/// Least range (mm, 5th to 95th percentile) of a foot's horizontal position relative to the
/// pelvis along its main axis for the feet to be cycling: well under half the shortest
/// stride of slow treadmill walking (about 0.8 m at 0.5 m/s), well over the sway of a
/// person standing or lifting (feet still, the pelvis moving a few centimetres).
pub const MIN_SWING_MM: f64 = 250.0;

/// Least range (mm, 5th to 95th percentile) of a foot's height for it to be lifting off
/// the floor in swing (a standing or stooping person's feet stay within a few millimetres).
pub const MIN_LIFT_MM: f64 = 30.0;

/// Whether the pelvis stays in place: it is seen at both ends of `window_s` (about a
/// stride, over which its sway and bounce cancel) and its median horizontal speed over such
/// spans is under `min_speed_mm_s`. A walkway trial whose pelvis is seen for less than that
/// (MOtoNMS' walks and runs, 52 to 85 % missing) has no walking direction from the pelvis,
/// but no sign that it stays either: no treadmill.
pub fn pelvis_stays(
    pelvis: &[[f64; 3]],
    vertical: Vertical,
    rate: f64,
    window_s: f64,
    min_speed_mm_s: f64,
) -> bool {
    let lag = ((window_s * rate).round() as usize).max(1);
    let speeds: Vec<f64> = pelvis
        .iter()
        .zip(pelvis.iter().skip(lag))
        .filter_map(|(a, b)| {
            let d = vertical.horizontal([b[0] - a[0], b[1] - a[1], b[2] - a[2]]);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            len.is_finite().then_some(len * rate / lag as f64)
        })
        .collect();
    signal::quantile(&speeds, 0.5).is_some_and(|s| s < min_speed_mm_s)
}

/// The treadmill's walking direction (unit, horizontal) from the pelvis and the foot
/// markers (each NaN where missing), or `None` when the feet do not cycle relative to the
/// pelvis: no foot swings [`MIN_SWING_MM`] along the feet's main horizontal axis while
/// lifting [`MIN_LIFT_MM`], or fewer than two frames have a foot with the pelvis. The
/// caller checks first that the pelvis stays ([`pelvis_stays`]).
///
/// The axis is the principal axis of the feet's horizontal positions relative to the
/// pelvis (each foot about its own mean); its sign is that of the feet's velocity along it
/// while they are higher than their median (swing), so it points the way the person faces.
pub fn direction(
    pelvis: &[[f64; 3]],
    feet: &[&[[f64; 3]]],
    vertical: Vertical,
    rate: f64,
) -> Option<[f64; 3]> {
    let rel: Vec<Vec<Option<[f64; 3]>>> = feet
        .iter()
        .map(|f| {
            f.iter()
                .zip(pelvis)
                .map(|(m, p)| {
                    let d = vertical.horizontal([m[0] - p[0], m[1] - p[1], m[2] - p[2]]);
                    d.iter().all(|v| v.is_finite()).then_some(d)
                })
                .collect()
        })
        .collect();
    // Pooled covariance of the horizontal offsets, each foot about its own mean.
    let mut cov = [[0.0; 3]; 3];
    let mut count = 0usize;
    for r in &rel {
        let known: Vec<[f64; 3]> = r.iter().flatten().copied().collect();
        if known.len() < 2 {
            continue;
        }
        let mut mean = [0.0; 3];
        for d in &known {
            for k in 0..3 {
                mean[k] += d[k] / known.len() as f64;
            }
        }
        for d in &known {
            for a in 0..3 {
                for b in 0..3 {
                    cov[a][b] += (d[a] - mean[a]) * (d[b] - mean[b]);
                }
            }
        }
        count += known.len();
    }
    if count < 2 {
        return None;
    }
    let axis = principal_axis(&cov, vertical)?;
    let along = |d: &[f64; 3]| (0..3).map(|k| d[k] * axis[k]).sum::<f64>();
    let mut cycling = false;
    let mut sign = 0.0;
    for (r, f) in rel.iter().zip(feet) {
        let x: Vec<f64> = r
            .iter()
            .map(|d| d.as_ref().map_or(f64::NAN, along))
            .collect();
        let h: Vec<f64> = f.iter().map(|p| vertical.height(*p)).collect();
        let spread = |v: &[f64]| {
            let k: Vec<f64> = v.iter().copied().filter(|v| v.is_finite()).collect();
            Some(signal::quantile(&k, 0.95)? - signal::quantile(&k, 0.05)?)
        };
        let (Some(swing), Some(lift)) = (spread(&x), spread(&h)) else {
            continue;
        };
        cycling |= swing >= MIN_SWING_MM && lift >= MIN_LIFT_MM;
        let known_h: Vec<f64> = h.iter().copied().filter(|v| v.is_finite()).collect();
        let Some(mid) = signal::quantile(&known_h, 0.5) else {
            continue;
        };
        let v = signal::derivative(&x, rate);
        sign += v
            .iter()
            .zip(&h)
            .filter(|(v, h)| v.is_finite() && h.is_finite())
            .map(|(v, h)| v * (h - mid))
            .sum::<f64>();
    }
    if !cycling || sign == 0.0 || !sign.is_finite() {
        return None;
    }
    let s = sign.signum();
    Some([s * axis[0], s * axis[1], s * axis[2]])
}

/// The unit eigenvector of the largest eigenvalue of the symmetric `cov`, within the
/// horizontal plane (power iteration from the horizontal axis of largest variance).
fn principal_axis(cov: &[[f64; 3]; 3], vertical: Vertical) -> Option<[f64; 3]> {
    let start = (0..3)
        .filter(|&k| k != vertical.axis)
        .max_by(|&a, &b| cov[a][a].total_cmp(&cov[b][b]))?;
    let mut v = [0.0; 3];
    v[start] = 1.0;
    for _ in 0..100 {
        let mut w = [0.0; 3];
        for a in 0..3 {
            for b in 0..3 {
                w[a] += cov[a][b] * v[b];
            }
        }
        let w = vertical.horizontal(w);
        let len = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        if !(len.is_finite() && len > 0.0) {
            return None;
        }
        v = [w[0] / len, w[1] / len, w[2] / len];
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feet cycling along −y relative to a still pelvis (Z up): each foot moves forward
    /// (−y) while raised and back while down.
    fn cycling(phase: f64, frames: usize, rate: f64) -> Vec<[f64; 3]> {
        (0..frames)
            .map(|f| {
                let t = f as f64 / rate * std::f64::consts::TAU + phase;
                // Forward position −300·sin t: moving forward (−y) where cos t > 0.
                let y = -300.0 * t.sin();
                let z = 60.0 + 50.0 * t.cos().max(0.0);
                [100.0, y, z]
            })
            .collect()
    }

    #[test]
    fn the_feet_swing_forward_while_raised() {
        let (frames, rate) = (400, 100.0);
        let pelvis = vec![[0.0, 0.0, 950.0]; frames];
        let l = cycling(0.0, frames, rate);
        let r = cycling(std::f64::consts::PI, frames, rate);
        let v = Vertical { axis: 2, sign: 1.0 };
        let d = direction(&pelvis, &[&l, &r], v, rate).unwrap();
        assert!(d[1] < -0.99 && d[2] == 0.0, "{d:?}");
        // Standing: feet still under the pelvis.
        let still = vec![[100.0, 50.0, 60.0]; frames];
        assert_eq!(direction(&pelvis, &[&still, &still], v, rate), None);
        assert!(pelvis_stays(&pelvis, v, rate, 1.0, 200.0));
        // A walkway's pelvis seen for 0.5 s at 1.5 m/s: no sign that it stays.
        let glimpse: Vec<[f64; 3]> = (0..frames)
            .map(|f| {
                if (100..150).contains(&f) {
                    [0.0, 15.0 * f as f64, 950.0]
                } else {
                    [f64::NAN; 3]
                }
            })
            .collect();
        assert!(!pelvis_stays(&glimpse, v, rate, 1.0, 200.0));
    }
}
