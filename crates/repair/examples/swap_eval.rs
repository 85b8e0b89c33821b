//! Swap and jump finding on the walking and full-body trials of the shared corpora (issue
//! 34): episodes injected one at a time into each trial, with the trial's own gaps left in:
//! swaps between two markers of one segment and between near markers of different
//! segments, 1, 5, 20 and 100 frames and to the end of the trial; jumps of 20–50 mm for
//! 5–40 frames. Reports recall per kind and length, precision, the share of swaps undone
//! exactly, the jumped samples' error once refilled by the fill stage, and every find on the
//! untouched trials (per 10 000 frames). Constants were chosen on the corpora `samples`,
//! `extra` and `fullbody` (the "tuned" labs); the labs of `c3d-more` other than CMU chose
//! nothing and are reported apart ("held apart").
//!
//! ```sh
//! cargo run --release -p repair --example swap_eval                        # a few minutes
//! cargo run --release -p repair --example swap_eval -- --per 2 --seed 35   # docs/swaps.md
//! ```
//! Options: `--per N` (episodes per kind, length and trial, jumps 4 × N; default 1), `--seed S`,
//! `--only TEXT` (files whose path contains TEXT), `--list` (every injected episode missed),
//! `--untouched` (the finds on the untouched trials alone, no episode injected: a quick look).

mod corpus;

use corpus::{load, load_recorded, FILES};
use repair::swaps::{find_swaps, undo, Find, FindKind, SwapOptions};
use repair::{repair_trial, FillOptions, RepairConfig, Trial};
use std::collections::BTreeMap;

/// The corpora every constant of the detector was chosen on.
const TUNED: [&str; 3] = ["samples", "extra", "fullbody"];

/// Swap lengths in frames; `usize::MAX` stands for "to the end of the trial".
const SWAP_LENGTHS: [usize; 5] = [1, 5, 20, 100, usize::MAX];

struct Args {
    per: usize,
    seed: u64,
    only: Option<String>,
    list: bool,
    untouched: bool,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        per: 1,
        seed: 34,
        only: None,
        list: false,
        untouched: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let mut val = || it.next().ok_or(format!("{k} needs a value"));
        match k.as_str() {
            "--per" => a.per = val()?.parse().map_err(|e| format!("--per: {e}"))?,
            "--seed" => a.seed = val()?.parse().map_err(|e| format!("--seed: {e}"))?,
            "--only" => a.only = Some(val()?),
            "--list" => a.list = true,
            "--untouched" => a.untouched = true,
            _ => return Err(format!("unknown option {k}")),
        }
    }
    Ok(a)
}

/// SplitMix64, as the crate's own generator (private there).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: usize, hi: usize) -> usize {
        if hi <= lo {
            lo
        } else {
            lo + (self.next() % (hi - lo) as u64) as usize
        }
    }
}

/// Marker labels in the order `corpus::load` keeps them (non-output points with a valid
/// sample off the origin; with `recorded`, residual-0 samples count as missing where the
/// file has recorded residuals).
fn labels(path: &std::path::Path, recorded: bool) -> Vec<String> {
    let Ok(c) = c3d::read_file(path) else {
        return Vec::new();
    };
    let outputs = c.model_output_labels();
    let p = c.points();
    let markers: Vec<usize> = (0..c.point_labels().len())
        .filter(|&i| !outputs.contains(&c.point_labels()[i]))
        .collect();
    let drop = recorded
        && markers.iter().any(|&i| {
            let r = p.residuals(i);
            (0..p.frames()).any(|f| p.is_valid(f, i) && r[f] > 0.0)
        });
    markers
        .into_iter()
        .filter(|&i| {
            let r = p.residuals(i);
            let t = p.trajectory(i);
            (0..p.frames()).any(|f| p.is_valid(f, i) && !(drop && r[f] == 0.0) && t[f] != [0.0; 3])
        })
        .map(|i| c.point_labels()[i].clone())
        .collect()
}

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Kind {
    /// Two markers keeping their distance (spread under 3 mm): one segment.
    SwapSegment,
    /// Two markers of changing distance that come within 150 mm: different segments,
    /// swapped around the frame they are closest.
    SwapNear,
    Jump,
}

/// One injected episode.
#[derive(Clone, Debug)]
struct Episode {
    kind: Kind,
    markers: Vec<usize>,
    first: usize,
    last: usize,
    /// The cell: swap length (`usize::MAX`: to the end) or the jump's length.
    len: usize,
    /// Whether the episode is injected and counted (an episode too long for its pair is
    /// drawn and left out).
    counted: bool,
}

fn dist(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// Pairs by how their distance behaves over the trial: (segment pairs, near pairs with the
/// frame they are closest at).
/// Markers `a` and `b`, and for near pairs the frame they are closest at.
type Pairs = (Vec<(usize, usize)>, Vec<(usize, usize, usize)>);

fn pairs(t: &Trial) -> Pairs {
    let (nm, nf) = (t.markers(), t.frames());
    let step = nf.div_ceil(400).max(1);
    let (mut seg, mut near) = (Vec::new(), Vec::new());
    for a in 0..nm {
        for b in a + 1..nm {
            let ds: Vec<(f64, usize)> = (0..nf)
                .step_by(step)
                .filter(|&f| t.valid[a][f] && t.valid[b][f])
                .map(|f| (dist(&t.xyz[a][f], &t.xyz[b][f]), f))
                .collect();
            if ds.len() < 20 {
                continue;
            }
            let mean = ds.iter().map(|d| d.0).sum::<f64>() / ds.len() as f64;
            let sd =
                (ds.iter().map(|d| (d.0 - mean).powi(2)).sum::<f64>() / ds.len() as f64).sqrt();
            let &(dmin, fmin) = ds
                .iter()
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .unwrap_or(&(f64::MAX, 0));
            if sd < 3.0 && mean > 20.0 {
                seg.push((a, b));
            } else if sd > 15.0 && dmin < 150.0 && dmin > 20.0 {
                near.push((a, b, fmin));
            }
        }
    }
    (seg, near)
}

/// Inject `e` into `t` (swap: exchange coordinates and masks; jump: offset `off` added to
/// the valid samples).
fn inject(t: &mut Trial, e: &Episode, off: [f64; 3]) {
    for f in e.first..=e.last {
        match e.markers[..] {
            [a, b] => {
                let (p, q) = (t.xyz[a][f], t.xyz[b][f]);
                t.xyz[a][f] = q;
                t.xyz[b][f] = p;
                let (v, w) = (t.valid[a][f], t.valid[b][f]);
                t.valid[a][f] = w;
                t.valid[b][f] = v;
            }
            [a] => {
                let p = t.xyz[a][f];
                t.xyz[a][f] = [p[0] + off[0], p[1] + off[1], p[2] + off[2]];
            }
            _ => {}
        }
    }
}

/// Episodes of every cell for one trial.
fn episodes(t: &Trial, per: usize, rng: &mut Rng) -> Vec<Episode> {
    let nf = t.frames();
    let (seg, near) = pairs(t);
    let both = |a: usize, b: usize, f: usize| t.valid[a][f] && t.valid[b][f];
    let mut out = Vec::new();
    for &len in &SWAP_LENGTHS {
        for (kind, cands) in [
            (
                Kind::SwapSegment,
                seg.iter().map(|&(a, b)| (a, b, None)).collect::<Vec<_>>(),
            ),
            (
                Kind::SwapNear,
                near.iter().map(|&(a, b, f)| (a, b, Some(f))).collect(),
            ),
        ] {
            if cands.is_empty() {
                continue;
            }
            for _ in 0..per {
                // A few tries for a start where both markers are seen.
                for _ in 0..20 {
                    let (a, b, at) = cands[rng.range(0, cands.len())];
                    let l = if len == usize::MAX {
                        // From somewhere in the second half: the labels of the first
                        // half are the majority the links are learned from.
                        nf - rng.range(nf * 11 / 20, nf.saturating_sub(10).max(nf * 11 / 20 + 1))
                    } else {
                        len
                    };
                    // Under half the trial: beyond that the swapped labels are the
                    // majority, and the other frames are the swap.
                    if l + 20 > nf || l * 20 > nf * 9 {
                        break;
                    }
                    let first = match at {
                        Some(f) if len != usize::MAX => {
                            f.saturating_sub(rng.range(0, l)).clamp(10, nf - l - 5)
                        }
                        _ if len == usize::MAX => nf - l,
                        _ => rng.range(10, nf - l - 5),
                    };
                    if !both(a, b, first) || (len != usize::MAX && !both(a, b, first + l - 1)) {
                        continue;
                    }
                    // Under half the frames where both markers are seen, too: the links
                    // are learned there, and a pair seen together in few frames can hold
                    // its labels swapped in most of them (the untouched frames are then
                    // the swap). Such an episode is drawn but not counted, so that the
                    // random draws, and every other episode, stay as they were.
                    let seen = (0..nf).filter(|&f| both(a, b, f)).count();
                    let swapped = (first..=first + l - 1).filter(|&f| both(a, b, f)).count();
                    out.push(Episode {
                        kind,
                        markers: vec![a, b],
                        first,
                        last: first + l - 1,
                        len,
                        counted: swapped * 20 <= seen * 9,
                    });
                    break;
                }
            }
        }
    }
    for _ in 0..per * 4 {
        for _ in 0..20 {
            let a = rng.range(0, t.markers());
            let l = rng.range(5, 41);
            if l + 40 > nf {
                break;
            }
            let first = rng.range(10, nf - l - 10);
            if !t.valid[a][first] {
                continue;
            }
            out.push(Episode {
                kind: Kind::Jump,
                markers: vec![a],
                first,
                last: first + l - 1,
                len: l,
                counted: true,
            });
            break;
        }
    }
    out
}

fn overlaps(x: &Find, e: &Episode) -> bool {
    x.first <= e.last && e.first <= x.last
}

/// The find that answers `e`: same kind and markers, overlapping its frames.
fn answers(x: &Find, e: &Episode) -> bool {
    let kind = match e.kind {
        Kind::Jump => FindKind::Jump,
        _ => FindKind::Swap,
    };
    x.kind == kind && x.markers == e.markers && overlaps(x, e)
}

/// A find of the injected trial that the untouched trial had too (same kind, markers and
/// overlapping frames): not the injection's doing.
fn known(x: &Find, base: &[Find]) -> bool {
    base.iter().any(|b| {
        b.kind == x.kind && b.markers == x.markers && b.first <= x.last && x.first <= b.last
    })
}

#[derive(Default, Clone)]
struct Cell {
    n: usize,
    found: usize,
    settled: usize,
    exact: usize,
}

#[derive(Default)]
struct Tally {
    cells: BTreeMap<(Kind, usize), Cell>,
    /// New finds (not in the untouched trial) that answer an episode / that do not.
    true_finds: usize,
    false_finds: usize,
    true_settled: usize,
    false_settled: usize,
    refill_err: Vec<f64>,
    frames_untouched: usize,
    untouched_finds: usize,
    untouched_settled: usize,
    /// Swap episodes drawn and left out: over half the frames where both markers are seen.
    uncounted: usize,
}

fn jump_bin(l: usize) -> usize {
    match l {
        0..=10 => 10,
        11..=20 => 20,
        _ => 40,
    }
}

/// Median error (mm) of the jumped samples once marked missing and refilled by the fill
/// stage (auto), on a window of ±400 frames around the episode.
fn refill(t: &Trial, clean: &Trial, e: &Episode) -> Option<Vec<f64>> {
    let lo = e.first.saturating_sub(400);
    let hi = (e.last + 400).min(t.frames() - 1);
    let crop = |x: &Trial| Trial {
        rate_hz: x.rate_hz,
        xyz: x.xyz.iter().map(|v| v[lo..=hi].to_vec()).collect(),
        valid: x.valid.iter().map(|v| v[lo..=hi].to_vec()).collect(),
    };
    let mut w = crop(t);
    let before = w.valid[e.markers[0]].clone();
    let cfg = RepairConfig::new(None, FillOptions::default(), None).ok()?;
    repair_trial(&mut w, &cfg).ok()?;
    let a = e.markers[0];
    let errs: Vec<f64> = (e.first..=e.last)
        .filter(|&f| clean.valid[a][f] && !before[f - lo] && w.valid[a][f - lo])
        .map(|f| dist(&w.xyz[a][f - lo], &clean.xyz[a][f]))
        .collect();
    Some(errs)
}

fn main() {
    let a = match args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("swap_eval: {e}");
            std::process::exit(2);
        }
    };
    let roots = corpus::roots();
    let tuned_labs: Vec<&str> = FILES
        .iter()
        .filter(|f| TUNED.contains(&f.2))
        .map(|f| f.1)
        .collect();
    let opts = SwapOptions::default();
    let mut tallies: BTreeMap<&str, Tally> = BTreeMap::new();
    let mut rng = Rng(a.seed);
    let t0 = std::time::Instant::now();
    println!("## finds on the untouched trials\n");
    for &(_set, lab, corpus, rel) in FILES {
        if a.only.as_deref().is_some_and(|o| !rel.contains(o)) {
            continue;
        }
        let Some(Some(root)) = roots.get(corpus) else {
            continue;
        };
        let group = if TUNED.contains(&corpus) {
            "tuned"
        } else if tuned_labs.contains(&lab) {
            "cmu (c3d-more)"
        } else {
            "held apart"
        };
        let path = root.join(rel);
        let recorded = corpus == "more";
        let loaded = if recorded {
            load_recorded(&path)
        } else {
            load(&path)
        };
        let clean = match loaded {
            Ok(t) if t.markers() >= 4 && t.frames() >= 60 => t,
            Ok(_) => continue,
            Err(e) => {
                eprintln!("{rel}: {e}");
                continue;
            }
        };
        let names = labels(&path, recorded);
        let name = |m: usize| names.get(m).cloned().unwrap_or_else(|| format!("#{m}"));
        let tally = tallies.entry(group).or_default();
        let base = match find_swaps(&clean, &opts) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("{rel}: {e}");
                continue;
            }
        };
        tally.frames_untouched += clean.frames();
        tally.untouched_finds += base.len();
        tally.untouched_settled += base.iter().filter(|x| x.settled).count();
        for x in &base {
            let ms: Vec<String> = x.markers.iter().map(|&m| name(m)).collect();
            println!(
                "- [{group}] {rel}: {:?} {} frames {}–{} (0-based), confidence {:.2}{}",
                x.kind,
                ms.join("/"),
                x.first,
                x.last,
                x.confidence,
                if x.settled { ", settled" } else { "" }
            );
        }
        if a.untouched {
            continue;
        }
        for e in episodes(&clean, a.per, &mut rng) {
            let mut t = clean.clone();
            let off = {
                let (u, v) = (
                    rng.uniform() * 2.0 - 1.0,
                    rng.uniform() * std::f64::consts::TAU,
                );
                let r = 20.0 + 30.0 * rng.uniform();
                let s = (1.0 - u * u).sqrt();
                [r * s * v.cos(), r * s * v.sin(), r * u]
            };
            if !e.counted {
                tally.uncounted += 1;
                continue;
            }
            inject(&mut t, &e, off);
            let finds = match find_swaps(&t, &opts) {
                Ok(f) => f,
                Err(err) => {
                    eprintln!("{rel}: {err}");
                    continue;
                }
            };
            let new: Vec<&Find> = finds.iter().filter(|x| !known(x, &base)).collect();
            let hit = new.iter().find(|x| answers(x, &e));
            let key = (
                e.kind,
                if e.kind == Kind::Jump {
                    jump_bin(e.len)
                } else {
                    e.len
                },
            );
            let cell = tally.cells.entry(key).or_default();
            cell.n += 1;
            for x in &new {
                let ok = answers(x, &e);
                match (ok, x.settled) {
                    (true, s) => {
                        tally.true_finds += 1;
                        tally.true_settled += s as usize;
                    }
                    (false, s) => {
                        tally.false_finds += 1;
                        tally.false_settled += s as usize;
                        if a.list {
                            println!(
                                "  false find [{group}] {rel}: {:?} {:?} {}–{} conf {:.2} (episode {:?} {:?} {}–{})",
                                x.kind, x.markers, x.first, x.last, x.confidence, e.kind, e.markers, e.first, e.last
                            );
                        }
                    }
                }
            }
            match hit {
                Some(x) => {
                    cell.found += 1;
                    if x.settled {
                        cell.settled += 1;
                        let mut u = t.clone();
                        let settled: Vec<Find> = new
                            .iter()
                            .filter(|y| answers(y, &e))
                            .map(|y| (*y).clone())
                            .collect();
                        undo(&mut u, &settled);
                        if e.kind == Kind::Jump {
                            if let Some(errs) = refill(&u, &clean, &e) {
                                tally.refill_err.extend(errs);
                            }
                            cell.exact += 1;
                        } else if e
                            .markers
                            .iter()
                            .all(|&m| u.xyz[m] == clean.xyz[m] && u.valid[m] == clean.valid[m])
                        {
                            cell.exact += 1;
                        } else if a.list {
                            println!(
                                "  inexact [{group}] {rel}: {:?} {:?} {}–{} found {}–{}",
                                e.kind, e.markers, e.first, e.last, x.first, x.last
                            );
                        }
                    }
                }
                None => {
                    if a.list {
                        let links = repair::swaps::learn_links(
                            &t,
                            opts.max_link_spread_mm,
                            opts.min_link_support,
                            opts.max_links,
                        );
                        let weak = SwapOptions {
                            min_report: 0.0,
                            ..opts.clone()
                        };
                        let all = find_swaps(&t, &weak).unwrap_or_default();
                        let near: Vec<String> = all
                            .iter()
                            .filter(|x| {
                                overlaps(x, &e) && x.markers.iter().any(|m| e.markers.contains(m))
                            })
                            .map(|x| {
                                format!(
                                    "{:?}{:?} {}–{} {:.2} {:?}",
                                    x.kind, x.markers, x.first, x.last, x.confidence, x.evidence
                                )
                            })
                            .collect();
                        println!(
                            "  missed [{group}] {rel}: {:?} {:?} {}–{} links {:?} weak finds {near:?}",
                            e.kind,
                            e.markers,
                            e.first,
                            e.last,
                            e.markers.iter().map(|&m| links[m].len()).collect::<Vec<_>>()
                        );
                    }
                }
            }
        }
        eprintln!("{rel}: done at {:.0} s", t0.elapsed().as_secs_f64());
    }
    for (group, t) in &tallies {
        report(group, t);
    }
}

fn pct(a: usize, b: usize) -> String {
    if b == 0 {
        "–".into()
    } else {
        format!("{:.1} %", 100.0 * a as f64 / b as f64)
    }
}

fn report(group: &str, t: &Tally) {
    println!("\n## {group}\n");
    println!("| kind | length | episodes | found | settled | undone exactly (of settled) |");
    println!("|---|---|---|---|---|---|");
    for (&(k, len), c) in &t.cells {
        let l = match (k, len) {
            (_, usize::MAX) => "to end".to_string(),
            (Kind::Jump, 10) => "5–10".into(),
            (Kind::Jump, 20) => "11–20".into(),
            (Kind::Jump, _) => "21–40".into(),
            _ => len.to_string(),
        };
        println!(
            "| {k:?} | {l} | {} | {} | {} | {} |",
            c.n,
            pct(c.found, c.n),
            pct(c.settled, c.n),
            if k == Kind::Jump {
                "–".into()
            } else {
                pct(c.exact, c.settled)
            }
        );
    }
    println!(
        "\nprecision: {} of finds ({} true, {} false), {} of settled finds ({} true, {} false)",
        pct(t.true_finds, t.true_finds + t.false_finds),
        t.true_finds,
        t.false_finds,
        pct(t.true_settled, t.true_settled + t.false_settled),
        t.true_settled,
        t.false_settled
    );
    let mut e = t.refill_err.clone();
    e.sort_by(f64::total_cmp);
    if !e.is_empty() {
        println!(
            "jumped samples refilled (auto fill): median {:.2} mm, 90th percentile {:.2} mm, {} samples",
            e[e.len() / 2],
            e[e.len() * 9 / 10],
            e.len()
        );
    }
    println!(
        "swap episodes left out (over half the frames where both markers are seen): {}",
        t.uncounted
    );
    let per = |k: usize| 1e4 * k as f64 / t.frames_untouched.max(1) as f64;
    println!(
        "untouched trials: {} frames, {} finds ({:.2} per 10 000 frames), {} settled ({:.2} per 10 000 frames)",
        t.frames_untouched,
        t.untouched_finds,
        per(t.untouched_finds),
        t.untouched_settled,
        per(t.untouched_settled)
    );
}
