//! OpenSim's ground reaction motion file, the `.mot` its ExternalLoads read.

use super::header_label;
use crate::axes::Axes;
use crate::error::{Error, Result};
use crate::ForcePlatforms;
use std::fmt::Write as _;
use std::path::Path;

/// The MOT of the plates `fp` computed from `c` (`path` names the file in errors, its stem
/// the table): `time`, then per plate K (numbered as FORCE_PLATFORM numbers it)
/// `ground_force_K_v{x,y,z}` in N, `ground_force_K_p{x,y,z}` (the COP) in m and
/// `ground_torque_K_{x,y,z}` (the free moment) in N·m, one row per analog sample, timed on
/// the file's base ([`c3d::C3d::analog_time`]) so that it lines up with the TRC's frames.
///
/// OpenSim takes no NaN: where a plate carries less than the threshold the COP is undefined,
/// and the row says "no load" — force and torque 0, the point at the plate's centre, so that
/// a force applied there is nothing. Rows outside every contact of the plate say so too: a
/// run above the threshold shorter than a footfall can be ([`kinetics::contact::MIN_CONTACT_S`]) is
/// noise crossing it, no foot (`sub_labels.c3d` has 15 N for a few samples between steps),
/// and an ExternalLoads would apply it as a push.
pub fn mot(c: &c3d::C3d, fp: &ForcePlatforms, path: &Path, axes: &Axes) -> Result<String> {
    let trial = |what: String| Error::Trial {
        path: path.to_path_buf(),
        what,
    };
    let Some(first) = fp.platforms.first() else {
        return Err(trial(format!(
            "no force platforms{}: nothing to write as MOT",
            if fp.warnings.is_empty() {
                ""
            } else {
                " could be computed (see the warnings)"
            }
        )));
    };
    let rate = first.rate;
    if !(rate > 0.0 && rate.is_finite()) {
        return Err(trial(format!(
            "ANALOG:RATE is {rate}: MOT needs a time for each sample"
        )));
    }
    let mut scales = Vec::new();
    for p in &fp.platforms {
        let m = crate::units::metres_per(&p.units.position).map_err(|source| Error::Unit {
            path: path.to_path_buf(),
            parameter: "POINT:UNITS".into(),
            source,
        })?;
        scales.push(m);
    }
    let rows = fp.samples();
    let columns = 1 + 9 * fp.platforms.len();
    let stem = path
        .file_stem()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut s = format!(
        "name {}\nversion=1\nnRows={rows}\nnColumns={columns}\ninDegrees=yes\nendheader\ntime",
        header_label(&stem).0
    );
    for p in &fp.platforms {
        let k = p.index;
        for q in ["vx", "vy", "vz", "px", "py", "pz"] {
            let _ = write!(s, "\tground_force_{k}_{q}");
        }
        for q in ["x", "y", "z"] {
            let _ = write!(s, "\tground_torque_{k}_{q}");
        }
    }
    s.push('\n');
    // Per plate, the samples inside one of its contacts.
    let inside: Vec<Vec<bool>> = fp
        .platforms
        .iter()
        .map(|p| {
            let mut v = vec![false; rows];
            for k in &p.contacts {
                if k.first_sample < rows {
                    v[k.first_sample..=k.last_sample.min(rows - 1)].fill(true);
                }
            }
            v
        })
        .collect();
    for i in 0..rows {
        let _ = write!(s, "{:.6}", c.analog_time(i));
        for ((p, &m), inside) in fp.platforms.iter().zip(&scales).zip(&inside) {
            let at = |v: &[[f64; 3]]| v.get(i).copied().unwrap_or([f64::NAN; 3]);
            let (force, cop, torque) = (at(&p.force), at(&p.cop), at(&p.free_moment));
            let loaded = inside[i] && [force, cop, torque].iter().flatten().all(|x| x.is_finite());
            let (force, point, torque) = if loaded {
                (force, cop.map(|x| x * m), torque.map(|x| x * m))
            } else {
                ([0.0; 3], p.centre.map(|x| x * m), [0.0; 3])
            };
            for v in [force, point, torque] {
                for x in axes.apply(v) {
                    // A rotated 0 may be a negative zero: written as 0.
                    let _ = write!(s, "\t{:.6}", x + 0.0);
                }
            }
        }
        s.push('\n');
    }
    Ok(s)
}
