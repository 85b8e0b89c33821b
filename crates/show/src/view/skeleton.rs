//! BVH skeletons in the viewer: forward kinematics gives every joint and End Site a position
//! in every frame, and the hierarchy gives the sticks, so no marker-set guessing is needed.

use super::{render, Style, Trial};
use crate::{Error, Result};
use bvh::fk::{all_positions, Positions};
use c3d::Points;

/// BVH files carry no unit; the page says so rather than guess centimetres or inches.
const UNITS: &str = "units of the file";

/// The positions as viewer points: every sample valid unless FK gave a non-finite value.
fn to_points(p: &Positions, frames: usize) -> Points {
    let mut points = Points::new(frames, p.labels.len());
    for ((xyz, r), v) in points
        .xyz
        .iter_mut()
        .zip(points.residual.iter_mut())
        .zip(&p.xyz)
    {
        if v.iter().all(|c| c.is_finite()) {
            *xyz = [v[0] as f32, v[1] as f32, v[2] as f32];
            *r = 1.0;
        }
    }
    points
}

/// Names in `a` but not in `b`, for saying how two skeletons differ.
fn missing<'a>(a: &'a [String], b: &[String]) -> Vec<&'a str> {
    a.iter()
        .filter(|l| !b.contains(l))
        .map(String::as_str)
        .collect()
}

/// The page for a BVH file; with `against`, a BVH file of the same skeleton (same joint and
/// End Site names) drawn as the original, with error vectors between matching points.
pub fn page(file: (&bvh::Bvh, &str), against: Option<(&bvh::Bvh, &str)>) -> Result<String> {
    let (b, name) = file;
    let pos = all_positions(b);
    let frames = b.motion.frames();
    let points = to_points(&pos, frames);
    let rate = b.motion.rate().unwrap_or(0.0) as f32;
    let other = against.map(|(o, oname)| (all_positions(o), o.motion.frames(), oname));
    let orig_points = other.as_ref().map(|(p, f, _)| to_points(p, *f));
    let original = match (&other, &orig_points) {
        (Some((opos, _, oname)), Some(opoints)) => {
            let only_here = missing(&pos.labels, &opos.labels);
            let only_there = missing(&opos.labels, &pos.labels);
            if !only_here.is_empty() || !only_there.is_empty() {
                return Err(Error::DifferentSkeletons {
                    file: name.into(),
                    original: oname.to_string(),
                    only_in_file: only_here.iter().map(|s| s.to_string()).collect(),
                    only_in_original: only_there.iter().map(|s| s.to_string()).collect(),
                });
            }
            let order = pos
                .labels
                .iter()
                .map(|l| opos.labels.iter().position(|o| o == l))
                .collect();
            let trial = Trial {
                name: oname,
                points: opoints,
                labels: opos.labels.clone(),
                units: UNITS.into(),
                rate,
                first_frame: 0,
            };
            Some((trial, order))
        }
        _ => None,
    };
    let style = Style {
        kind: "bvh",
        sticks: pos.bones.clone(),
        traced: pos.end_sites.clone(),
        shadow: true,
        plates: None,
        // The lab's rule for markers, over the joints; BVH files state no unit, so the
        // floor's band (in mm) reads the numbers as they are.
        up: c3dfix::axes::points_up(&points, c3d::mm_per_unit(UNITS) as f32),
        fills_marked: false,
        events: Vec::new(),
    };
    let trial = Trial {
        name,
        points: &points,
        labels: pos.labels,
        units: UNITS.into(),
        rate,
        // Frames are numbered from 0, as `keyframes` reports them.
        first_frame: 0,
    };
    render(trial, original, style)
}
