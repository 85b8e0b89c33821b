//! One piece against the evidence: its samples against the marker's segment distances,
//! frame by frame, and its ends against the marker's own path.

use super::finds::{Fit, Piece, ReclaimOptions, Verdict};
use crate::swaps::Link;
use crate::Trial;

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The piece `p` judged for its marker, with that marker's `links`; `m` and `u` in mm.
/// The links are asked for only when the piece passes the path, so that a trial none of
/// whose pieces does is judged without learning them.
pub(super) fn score<'l>(
    p: &Piece,
    m: &Trial,
    u: &Trial,
    links: impl FnOnce() -> &'l [Link],
    opts: &ReclaimOptions,
) -> Fit {
    // The path first: it is cheap, and most pieces (another point's samples) fail it.
    let (path_ok, path_mm, ends) = path(p, m, u, opts);
    let off = |checks, fails| Fit {
        verdict: Verdict::Off,
        cost: f64::NAN,
        rms_mm: f64::NAN,
        checked_frames: 0,
        checks,
        fails,
        path_mm,
    };
    if !path_ok || ends < opts.min_ends {
        return off(0, 0);
    }
    let links = links();
    let (mut sum, mut sq, mut checks, mut fails) = (0.0, 0.0, 0, 0);
    // Frames checked by `min_links` links, and by at least one.
    let (mut checked, mut touched) = (0, 0);
    // More fails than this share of every check the piece could have is Off whatever the
    // rest says: most pieces are another point and stop within a few frames.
    let most = opts.max_fail * (p.len() * links.len()) as f64;
    for f in p.first..=p.last {
        let q = &u.xyz[p.source][f];
        let mut here = 0;
        for l in links.iter().filter(|l| m.valid[l.other][f]) {
            let r = (dist(q, &m.xyz[l.other][f]) - l.d0_mm).abs();
            let x = (r / l.tol_mm).min(10.0);
            sum += x * x;
            sq += r * r;
            checks += 1;
            fails += usize::from(x > 1.0);
            here += 1;
        }
        if fails as f64 > most {
            return off(checks, fails);
        }
        checked += usize::from(here >= opts.min_links);
        touched += usize::from(here >= 1);
    }
    let cost = if checks > 0 { sum / checks as f64 } else { 0.0 };
    let links_off =
        checks > 0 && (fails as f64 > opts.max_fail * checks as f64 || cost > opts.max_cost);
    let share = |k: usize| k >= 1 && k as f64 >= opts.min_checked * p.len() as f64;
    // A piece that reaches both ends of the gap, on the marker's path at both, needs one
    // link per frame; one that floats inside the gap needs `min_links`.
    let whole = p.first > 0
        && p.last + 1 < m.frames()
        && m.valid[p.marker][p.first - 1]
        && m.valid[p.marker][p.last + 1];
    let enough = share(checked) || (ends == 2 && (share(touched) || (opts.path_alone && whole)));
    let verdict = if links_off {
        Verdict::Off
    } else if !enough {
        if path_mm.is_some() {
            Verdict::FewLinks
        } else {
            Verdict::Off
        }
    } else {
        Verdict::Fits
    };
    Fit {
        verdict,
        cost,
        rms_mm: if checks > 0 {
            (sq / checks as f64).sqrt()
        } else {
            0.0
        },
        checked_frames: checked,
        checks,
        fails,
        path_mm,
    }
}

/// The piece's ends against the marker's path: whether they agree, and the largest
/// distance found (mm), if any end could be judged, and how many of the piece's two ends
/// were judged by the marker's path.
///
/// At an end that lies within [`ReclaimOptions::path_frames`] of the gap's edge, the
/// marker's last position before the gap (first after it), moved on by its velocity there,
/// must reach the piece's sample within `path_mm` per frame carried. Where the unlabelled
/// trajectory goes on past the gap, over up to 5 frames there it must sit on the marker
/// (within `path_mm`): a second reconstruction of it, not another point.
fn path(p: &Piece, m: &Trial, u: &Trial, opts: &ReclaimOptions) -> (bool, Option<f64>, usize) {
    let mv = &m.valid[p.marker];
    let (mx, ux, uv) = (&m.xyz[p.marker], &u.xyz[p.source], &u.valid[p.source]);
    let n = mv.len();
    let mut worst: Option<f64> = None;
    let mut ok = true;
    let mut ends = 0;
    let mut note = |e: f64, limit: f64| {
        worst = Some(worst.map_or(e, |w: f64| w.max(e)));
        ok &= e <= limit;
    };
    // Before: the marker's last sample before the piece, if the gap is that near.
    let before = (0..p.first).rev().take(opts.path_frames).find(|&f| mv[f]);
    if let Some(a) = before {
        let k = (p.first - a) as f64;
        let v = if a > 0 && mv[a - 1] {
            sub(&mx[a], &mx[a - 1])
        } else {
            [0.0; 3]
        };
        let pred = [
            mx[a][0] + v[0] * k,
            mx[a][1] + v[1] * k,
            mx[a][2] + v[2] * k,
        ];
        note(
            dist(&ux[p.first], &pred),
            (opts.path_mm + 0.5 * norm(&v)) * k,
        );
        ends += 1;
    }
    let after = (p.last + 1..n).take(opts.path_frames).find(|&f| mv[f]);
    if let Some(b) = after {
        let k = (b - p.last) as f64;
        let v = if b + 1 < n && mv[b + 1] {
            sub(&mx[b], &mx[b + 1])
        } else {
            [0.0; 3]
        };
        let pred = [
            mx[b][0] + v[0] * k,
            mx[b][1] + v[1] * k,
            mx[b][2] + v[2] * k,
        ];
        note(
            dist(&ux[p.last], &pred),
            (opts.path_mm + 0.5 * norm(&v)) * k,
        );
        ends += 1;
    }
    // The unlabelled trajectory past the gap, where the marker is recorded too.
    let outside = (0..p.first)
        .rev()
        .take_while(|&f| uv[f])
        .take(5)
        .chain((p.last + 1..n).take_while(|&f| uv[f]).take(5));
    for f in outside {
        if mv[f] {
            note(dist(&ux[f], &mx[f]), opts.path_mm);
        }
    }
    (ok, worst, ends)
}

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
