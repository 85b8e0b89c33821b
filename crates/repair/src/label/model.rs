//! What a template says about its markers: which pairs keep their distance and how
//! closely (the segments, found from the template's own frames, no marker set in the
//! code), which quadruples keep their handedness (what tells left from right, which no
//! distance can), and an order in which a marker set is best matched from nothing.

use super::options::LabelOptions;
use crate::Trial;

/// A pair of template markers and the distance it keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Neighbour {
    pub other: usize,
    /// The distance's median over the template's frames (mm).
    pub d0: f64,
    /// Its robust spread plus a floor for the trial's own skin motion (mm).
    pub sigma: f64,
    /// The robust spread alone (mm): what a scaled copy of the template scales.
    pub spread: f64,
}

/// Three neighbours whose tetrahedron with the marker keeps its sign: a mirror labelling
/// (left for right) keeps every distance and flips every such sign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Chiral {
    pub a: usize,
    pub b: usize,
    pub c: usize,
    pub sign: f64,
}

/// The template's geometry.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Model {
    pub markers: usize,
    /// Whether the template records the marker at all.
    pub present: Vec<bool>,
    /// Each marker's closest-kept pairs, best first.
    pub nb: Vec<Vec<Neighbour>>,
    pub chiral: Vec<Vec<Chiral>>,
    /// Markers in the order a frame is matched from nothing: each next one the best tied
    /// to those before it.
    pub order: Vec<usize>,
}

/// Frames of the template read to learn its geometry (evenly spaced).
const LEARN_FRAMES: usize = 400;

fn dist(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// Signed volume of the tetrahedron (m, a, b, c), over the product of its edges from m:
/// its sign is the handedness, its size how far from flat it is (at most 1).
pub(crate) fn handedness(m: &[f64; 3], a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let u = [a[0] - m[0], a[1] - m[1], a[2] - m[2]];
    let v = [b[0] - m[0], b[1] - m[1], b[2] - m[2]];
    let w = [c[0] - m[0], c[1] - m[1], c[2] - m[2]];
    let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]);
    let l = dist(m, a) * dist(m, b) * dist(m, c);
    if l > 0.0 {
        det / l
    } else {
        0.0
    }
}

fn median(v: &mut [f64]) -> f64 {
    let k = v.len() / 2;
    *v.select_nth_unstable_by(k, f64::total_cmp).1
}

impl Model {
    /// Learn the geometry of `t` (in mm).
    pub fn learn(t: &Trial, opts: &LabelOptions) -> Model {
        let k = t.markers();
        let n = t.frames();
        let step = n.div_ceil(LEARN_FRAMES).max(1);
        let frames: Vec<usize> = (0..n).step_by(step).collect();
        let present: Vec<bool> = (0..k)
            .map(|m| frames.iter().any(|&f| t.valid[m][f]))
            .collect();
        let mut pairs: Vec<Vec<Neighbour>> = vec![Vec::new(); k];
        let mut ds = Vec::with_capacity(frames.len());
        for i in 0..k {
            for j in i + 1..k {
                ds.clear();
                ds.extend(
                    frames
                        .iter()
                        .filter(|&&f| t.valid[i][f] && t.valid[j][f])
                        .map(|&f| dist(&t.xyz[i][f], &t.xyz[j][f])),
                );
                if ds.is_empty() {
                    continue;
                }
                let d0 = median(&mut ds);
                let mut dev: Vec<f64> = ds.iter().map(|d| (d - d0).abs()).collect();
                let spread = 1.4826 * median(&mut dev);
                if d0 < 5.0 {
                    continue;
                }
                let sigma = spread + opts.floor_mm + opts.floor_share * d0;
                pairs[i].push(Neighbour {
                    other: j,
                    d0,
                    sigma,
                    spread,
                });
                pairs[j].push(Neighbour {
                    other: i,
                    d0,
                    sigma,
                    spread,
                });
            }
        }
        for p in &mut pairs {
            // Closest kept first: a small spread, then a short distance (a static template
            // keeps every pair; the near ones also keep it in motion).
            p.sort_by(|a, b| a.sigma.total_cmp(&b.sigma).then(a.other.cmp(&b.other)));
            p.truncate(opts.neighbours);
        }
        let chiral = (0..k).map(|m| chirals(t, &frames, m, &pairs[m])).collect();
        let order = order(&pairs, &present);
        Model {
            markers: k,
            present,
            nb: pairs,
            chiral,
            order,
        }
    }
}

impl Model {
    /// The same geometry on a body `s` times as large: every distance and spread times
    /// `s`, the floors as they are (the trial's skin moves as much on any body); the
    /// pairs, hands and order stay (a handedness does not change with size).
    pub fn scaled(&self, s: f64, opts: &LabelOptions) -> Model {
        let mut m = self.clone();
        for n in m.nb.iter_mut().flatten() {
            n.d0 *= s;
            n.spread *= s;
            n.sigma = n.spread + opts.floor_mm + opts.floor_share * n.d0;
        }
        m
    }
}

/// Up to three triples of `m`'s nearest-kept neighbours whose tetrahedron with `m` keeps one
/// sign in at least 95 % of the template's frames and is far from flat.
fn chirals(t: &Trial, frames: &[usize], m: usize, nb: &[Neighbour]) -> Vec<Chiral> {
    let cand: Vec<usize> = nb.iter().take(6).map(|n| n.other).collect();
    let mut found = Vec::new();
    for x in 0..cand.len() {
        for y in x + 1..cand.len() {
            for z in y + 1..cand.len() {
                let (a, b, c) = (cand[x], cand[y], cand[z]);
                let mut hs: Vec<f64> = frames
                    .iter()
                    .filter(|&&f| t.valid[m][f] && t.valid[a][f] && t.valid[b][f] && t.valid[c][f])
                    .map(|&f| handedness(&t.xyz[m][f], &t.xyz[a][f], &t.xyz[b][f], &t.xyz[c][f]))
                    .collect();
                if hs.is_empty() {
                    continue;
                }
                let med = median(&mut hs);
                let same = hs.iter().filter(|h| h.signum() == med.signum()).count();
                if med.abs() >= 0.15 && same as f64 >= 0.95 * hs.len() as f64 {
                    found.push((
                        med.abs(),
                        Chiral {
                            a,
                            b,
                            c,
                            sign: med.signum(),
                        },
                    ));
                }
            }
        }
    }
    found.sort_by(|p, q| q.0.total_cmp(&p.0));
    found.into_iter().take(3).map(|(_, c)| c).collect()
}

/// The matching order: the marker whose pairs are kept most closely first, then always the
/// one most tied (by 1/σ of its pairs) to those already ordered.
fn order(nb: &[Vec<Neighbour>], present: &[bool]) -> Vec<usize> {
    let k = nb.len();
    let mut tie = vec![0.0f64; k];
    let mut done = vec![false; k];
    let mut out = Vec::with_capacity(k);
    let own = |m: usize| -> f64 { nb[m].iter().take(4).map(|n| 1.0 / n.sigma).sum() };
    while out.len() < present.iter().filter(|&&p| p).count() {
        let next = (0..k).filter(|&m| present[m] && !done[m]).max_by(|&a, &b| {
            tie[a]
                .total_cmp(&tie[b])
                .then(own(a).total_cmp(&own(b)))
                .then(b.cmp(&a))
        });
        let Some(m) = next else { break };
        done[m] = true;
        out.push(m);
        for (x, l) in nb.iter().enumerate() {
            for n in l {
                if n.other == m {
                    tie[x] += 1.0 / n.sigma;
                }
            }
        }
    }
    out
}
