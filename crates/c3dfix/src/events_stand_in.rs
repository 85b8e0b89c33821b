//! A heel or toe marker's missing frames filled from another marker of the same foot
//! ([`stand_in`]): first the markers named for the same part, then any marker that moves
//! rigidly with the chosen one ([`rigid_with`]).

use crate::error::Result;
use crate::events_tracks::{marker_labels, tracks};
use gait::{Feet, MarkerChoice};
use std::path::Path;

/// How far either side of a gap (s) the chosen marker's offset from a stand-in is taken:
/// about a stride, over which the foot turns through every angle it takes in a step.
const STAND_IN_WINDOW_S: f64 = 1.0;

/// The fewest frames with both markers seen near a gap that give the offset.
const STAND_IN_MIN_FRAMES: usize = 5;

/// Each heel and toe role of one marker found by its name (no cluster, no ankle) whose
/// marker is missing in some frames gets, in those frames, the first other marker of its
/// side named for the same part ([`gait::markers::candidates`]) that is seen there, moved by
/// the median offset between the two over the frames both are seen within
/// [`STAND_IN_WINDOW_S`] of the gap: two metatarsal heads or two heel markers keep their
/// spacing on the rigid foot. Then, where frames are still missing, any marker of the
/// trial that keeps one offset from the chosen marker ([`rigid_with`]): an anatomical set
/// may mark the forefoot with names no list holds (MOtoNMS' `RIIT`, 50 mm from `RIMH`,
/// seen where both metatarsal heads are lost at the foot off). Recorded in
/// [`MarkerChoice::stand_ins`].
pub(crate) fn stand_in(
    c: &c3d::C3d,
    choice: &mut MarkerChoice,
    f: &mut Feet,
    path: &Path,
) -> Result<()> {
    let labels = marker_labels(c);
    let rate = c.point_rate() as f64;
    let reach = (STAND_IN_WINDOW_S * rate).round().max(1.0) as usize;
    let roles: [(&'static str, char, bool, usize); 4] = [
        ("lheel", 'l', true, 0),
        ("ltoe", 'l', false, 0),
        ("rheel", 'r', true, 1),
        ("rtoe", 'r', false, 1),
    ];
    for (role, side, heel, k) in roles {
        let chosen = match role {
            "lheel" => &choice.left_heel,
            "ltoe" => &choice.left_toe,
            "rheel" => &choice.right_heel,
            _ => &choice.right_toe,
        };
        if chosen.len() != 1
            || !choice.by_position[k].is_empty()
            || (heel && choice.heel_is_ankle[k])
        {
            continue;
        }
        let chosen = chosen[0];
        let track = match role {
            "lheel" => &mut f.left_heel,
            "ltoe" => &mut f.left_toe,
            "rheel" => &mut f.right_heel,
            _ => &mut f.right_toe,
        };
        if track.iter().all(|p| p[0].is_finite()) {
            continue;
        }
        let named: Vec<usize> = gait::markers::candidates(&labels, side, heel)
            .into_iter()
            .filter(|&i| i != chosen)
            .collect();
        // The chosen marker's own samples judge which markers move rigidly with it.
        let own = track.clone();
        let mut fill = |track: &mut Vec<[f64; 3]>, marker: usize, alt: &[[f64; 3]], rigid| {
            let frames = fill_gaps(track, alt, reach);
            if frames > 0 {
                choice.stand_ins.push(gait::markers::StandIn {
                    role,
                    chosen,
                    marker,
                    frames,
                    rigid,
                });
            }
        };
        for (marker, alt) in named.iter().copied().zip(tracks(c, &named, path)?) {
            fill(track, marker, &alt, false);
        }
        if track.iter().all(|p| p[0].is_finite()) {
            continue;
        }
        let exclude: Vec<usize> = named.iter().copied().chain([chosen]).collect();
        for (marker, alt) in rigid_with(c, &labels, &own, &exclude, rate, path)? {
            fill(track, marker, &alt, true);
        }
    }
    Ok(())
}

/// `track`'s missing frames filled from `alt` plus the median offset of `track` from `alt`
/// over the frames both are seen within `reach` frames of each gap; the frames filled.
fn fill_gaps(track: &mut [[f64; 3]], alt: &[[f64; 3]], reach: usize) -> usize {
    let n = track.len();
    let seen = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    let mut filled = 0;
    let mut i = 0;
    while i < n {
        if seen(&track[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < n && !seen(&track[i]) {
            i += 1;
        }
        let (lo, hi) = (start.saturating_sub(reach), (i + reach).min(n));
        let diffs: Vec<[f64; 3]> = (lo..hi)
            .filter(|&j| seen(&track[j]) && seen(&alt[j]))
            .map(|j| [0, 1, 2].map(|k| track[j][k] - alt[j][k]))
            .collect();
        if diffs.len() < STAND_IN_MIN_FRAMES {
            continue;
        }
        let offset = [0, 1, 2].map(|k| {
            let mut v: Vec<f64> = diffs.iter().map(|d| d[k]).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        });
        for j in start..i {
            if seen(&alt[j]) {
                track[j] = [0, 1, 2].map(|k| alt[j][k] + offset[k]);
                filled += 1;
            }
        }
    }
    filled
}

/// The least time (s) both markers must be seen together while the foot moves to judge that
/// one moves rigidly with the other: a quarter of a second holds a good part of a swing's
/// turn of the foot.
const RIGID_MIN_S: f64 = 0.25;

/// How far (mm) a marker's offset from the chosen one may stray from its median in 90 % of
/// the frames both are seen, for the one to stand in for the other: what a marker's
/// position is known to (a few millimetres) plus what the foot's turn through a step does
/// to an offset of a few centimetres. Markers 10 cm or more apart on the foot stray by
/// 80–120 mm as it turns (MOtoNMS' malleoli and calcaneus from `RIMH`); two metatarsal
/// heads 10 cm apart by 17–21 mm; a marker 5 cm away by 7–9 mm.
const RIGID_MM: f64 = 10.0;

/// The markers of `c` (model outputs apart, `exclude` apart) whose offset from `track`
/// stays within [`RIGID_MM`] of its median in 90 % of the frames where `track` moves
/// ([`moving_frames`]) and both are seen, at least [`RIGID_MIN_S`] of them, with their
/// trajectories, steadiest first: markers on the same rigid part of the foot, close to the
/// chosen one, whatever their names. Only frames where the foot moves judge: standing
/// still, every marker keeps its offset from every other.
fn rigid_with(
    c: &c3d::C3d,
    labels: &[String],
    track: &[[f64; 3]],
    exclude: &[usize],
    rate: f64,
    path: &Path,
) -> Result<Vec<(usize, Vec<[f64; 3]>)>> {
    let least = ((RIGID_MIN_S * rate).round() as usize).max(STAND_IN_MIN_FRAMES);
    let points: Vec<usize> = (0..labels.len())
        .filter(|i| !labels[*i].trim().is_empty() && !exclude.contains(i))
        .collect();
    let all = tracks(c, &points, path)?;
    let seen = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    let moving = moving_frames(track, rate);
    let mut found: Vec<(f64, usize, Vec<[f64; 3]>)> = Vec::new();
    for (i, alt) in points.into_iter().zip(all) {
        let diffs: Vec<[f64; 3]> = moving
            .iter()
            .filter(|&&f| seen(&alt[f]))
            .map(|&f| [0, 1, 2].map(|k| track[f][k] - alt[f][k]))
            .collect();
        if diffs.len() < least {
            continue;
        }
        let median = [0, 1, 2].map(|k| {
            let mut v: Vec<f64> = diffs.iter().map(|d| d[k]).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        });
        let mut stray: Vec<f64> = diffs
            .iter()
            .map(|d| {
                (0..3)
                    .map(|k| (d[k] - median[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        stray.sort_by(f64::total_cmp);
        let p90 = stray[((stray.len() - 1) as f64 * 0.9).round() as usize];
        if p90 <= RIGID_MM {
            found.push((p90, i, alt));
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(found.into_iter().map(|(_, i, t)| (i, t)).collect())
}

/// How fast (mm/s) a marker moves in the frames that judge rigidity ([`rigid_with`]): a
/// foot in swing moves at several metres per second, a standing one at a few millimetres;
/// half a metre per second is well clear of both (and of a marker's jitter).
const MOVING_MM_S: f64 = 500.0;

/// The frames where `track` is seen with both neighbours and moves faster than
/// [`MOVING_MM_S`] (central difference at `rate`).
fn moving_frames(track: &[[f64; 3]], rate: f64) -> Vec<usize> {
    let seen = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    (1..track.len().saturating_sub(1))
        .filter(|&f| {
            let (a, b) = (&track[f - 1], &track[f + 1]);
            seen(&track[f]) && seen(a) && seen(b) && {
                let d2: f64 = (0..3).map(|k| (b[k] - a[k]).powi(2)).sum();
                d2.sqrt() * rate / 2.0 > MOVING_MM_S
            }
        })
        .collect()
}
