//! Swap and jump finding on the walking and full-body trials of the shared corpora (issue
//! 34): episodes injected one at a time into each trial, with the trial's own gaps left in:
//! swaps between two markers of one segment and between near markers of different
//! segments, 1, 5, 20 and 100 frames and to the end of the trial; jumps of 20–50 mm for
//! 5–40 frames; and jumps onto recorded points: a marker's samples over 5–40 frames
//! replaced whole (coordinates, residual, camera mask) by those of a marker 15–60 mm away,
//! which keeps its own or is missing there. Reports recall per kind and length, precision, the share of swaps undone
//! exactly, the jumped samples' error once refilled by the fill stage, and every find on the
//! untouched trials (per 10 000 frames), and, apart, the hits that are jumps of markers
//! with 2–3 links found by their leaps and steady offset alone. Constants were chosen on the corpora `samples`,
//! `extra` and `fullbody` (the "tuned" labs); the labs of `c3d-more` other than CMU chose
//! nothing and are reported apart ("held apart"), and `c3d-labs`' labs, which came after every
//! rule, apart again.
//!
//! ```sh
//! cargo run --release -p evals --bin swap_eval                        # a few minutes
//! cargo run --release -p evals --bin swap_eval -- --per 2 --seed 35   # docs/swaps.md
//! ```
//! Options: `--per N` (episodes per kind, length and trial, jumps 4 × N; default 1), `--seed S`,
//! `--only TEXT` (files whose path contains TEXT), `--corpus NAME` (one corpus's trials), `--list` (every injected episode missed),
//! `--untouched` (the finds on the untouched trials alone, no episode injected: a quick look),
//! `--explain` (with each untouched find, and each missed jump onto a recorded point under
//! `--list`, the samples it rests on), `--residual res|cam|both FLOOR` (the residual-witness
//! experiment of docs/swaps.md, not the detector's rule).

use clap::Parser;
use evals::corpus::{self, load, load_recorded, FILES};
use evals::stats::{median, rank, sorted};
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
    /// Only the trials of this corpus (its short name in `corpus::roots`).
    corpus: Option<String>,
    list: bool,
    untouched: bool,
    /// With the untouched finds, each one's samples: its links inside and around it.
    explain: bool,
    /// The residual experiment: which word witnesses a jump, and from what confidence.
    residual: Option<(Witness, f64)>,
}

/// The recorded word a jump's residual witness reads (`--residual res|cam|both FLOOR`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Witness {
    Residual,
    Cameras,
    Both,
}

/// Swap and jump finding on the corpora's trials (see the module's documentation).
#[derive(Parser)]
#[command(name = "swap_eval")]
struct Cli {
    /// Episodes per kind, length and trial (jumps 4 × N).
    #[arg(long, value_name = "N", default_value_t = 1)]
    per: usize,
    /// The episodes' random seed.
    #[arg(long, default_value_t = 34)]
    seed: u64,
    /// Only files whose path contains TEXT.
    #[arg(long, value_name = "TEXT")]
    only: Option<String>,
    /// Only the trials of this corpus (samples, extra, fullbody, more, labs).
    #[arg(long)]
    corpus: Option<String>,
    /// Every injected episode missed.
    #[arg(long)]
    list: bool,
    /// The finds on the untouched trials alone, no episode injected.
    #[arg(long)]
    untouched: bool,
    /// With each untouched find (and each missed jump onto a recorded point under --list),
    /// the samples it rests on.
    #[arg(long)]
    explain: bool,
    /// The residual-witness experiment: the word read (res, cam or both) and its floor.
    #[arg(long, num_args = 2, value_names = ["WORD", "FLOOR"])]
    residual: Option<Vec<String>>,
}

fn args() -> Result<Args, String> {
    let c = Cli::parse();
    let residual = match c.residual.as_deref() {
        None => None,
        Some([word, floor]) => {
            let w = match word.as_str() {
                "res" => Witness::Residual,
                "cam" => Witness::Cameras,
                "both" => Witness::Both,
                o => return Err(format!("--residual: res, cam or both, not {o}")),
            };
            let floor = floor
                .parse()
                .map_err(|e| format!("--residual floor: {e}"))?;
            Some((w, floor))
        }
        Some(_) => return Err("--residual needs a word and a floor".into()),
    };
    Ok(Args {
        per: c.per,
        seed: c.seed,
        only: c.only,
        corpus: c.corpus,
        list: c.list,
        untouched: c.untouched,
        explain: c.explain,
        residual,
    })
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

/// What `corpus::load` leaves out of a trial, per marker in its order: the labels, the
/// residuals (−1 missing) and the camera masks as recorded, so that an episode can move a
/// sample whole (coordinates, residual word and camera mask from the same frame).
#[derive(Clone, Default)]
struct Side {
    labels: Vec<String>,
    residual: Vec<Vec<f32>>,
    mask: Vec<Vec<u8>>,
    /// Whether the file carries measured residuals (some valid sample above 0).
    measured: bool,
}

/// [`Side`] of the markers `corpus::load` keeps (non-output points with a valid sample off
/// the origin; with `recorded`, residual-0 samples count as missing where the file has
/// recorded residuals).
fn side(path: &std::path::Path, recorded: bool) -> Side {
    let Ok(c) = c3d::read_file(path) else {
        return Side::default();
    };
    let p = c.points();
    let markers = corpus::markers_of(&c);
    let measured = markers.iter().any(|&i| {
        let r = p.residuals(i);
        (0..p.frames()).any(|f| p.is_valid(f, i) && r[f] > 0.0)
    });
    let drop = recorded && measured;
    let kept: Vec<usize> = markers
        .into_iter()
        .filter(|&i| {
            let r = p.residuals(i);
            let t = p.trajectory(i);
            (0..p.frames()).any(|f| p.is_valid(f, i) && !(drop && r[f] == 0.0) && t[f] != [0.0; 3])
        })
        .collect();
    Side {
        labels: kept.iter().map(|&i| c.point_labels()[i].clone()).collect(),
        residual: kept.iter().map(|&i| p.residuals(i)).collect(),
        mask: kept
            .iter()
            .map(|&i| {
                (0..p.frames())
                    .map(|f| p.camera_mask[p.index(f, i)])
                    .collect()
            })
            .collect(),
        measured,
    }
}

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Kind {
    /// Two markers keeping their distance (spread under 3 mm): one segment.
    SwapSegment,
    /// Two markers of changing distance that come within 150 mm: different segments,
    /// swapped around the frame they are closest.
    SwapNear,
    Jump,
    /// A label on a near marker's recorded point, that marker keeping its own: the point
    /// twice in the frame (coordinates, residual and cameras of one sample).
    JumpOntoKept,
    /// A label on a near marker's recorded point, that marker missing over the span: the
    /// point's label left it for the other's.
    JumpOntoTaken,
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
    /// For a jump onto a recorded point, the marker whose samples the label takes.
    onto: Option<usize>,
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
                        onto: None,
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
                onto: None,
            });
            break;
        }
    }
    out
}

/// For each marker, the markers whose median distance to it (over up to 400 evenly spaced
/// frames where both are seen, at least 20) is 15–60 mm, the issue's "typically 15–60 mm
/// away"; a marker with none takes its nearest if that is within 60 mm.
fn near_points(t: &Trial) -> Vec<Vec<usize>> {
    let (nm, nf) = (t.markers(), t.frames());
    let step = nf.div_ceil(400).max(1);
    let median = |a: usize, b: usize| {
        let ds: Vec<f64> = (0..nf)
            .step_by(step)
            .filter(|&f| a != b && t.valid[a][f] && t.valid[b][f])
            .map(|f| dist(&t.xyz[a][f], &t.xyz[b][f]))
            .collect();
        if ds.len() < 20 {
            return f64::INFINITY;
        }
        median(ds).unwrap_or(f64::INFINITY)
    };
    let med: Vec<Vec<f64>> = (0..nm)
        .map(|a| (0..nm).map(|b| median(a, b)).collect())
        .collect();
    (0..nm)
        .map(|a| {
            let within: Vec<usize> = (0..nm)
                .filter(|&b| (15.0..=60.0).contains(&med[a][b]))
                .collect();
            if !within.is_empty() {
                return within;
            }
            (0..nm)
                .filter(|&b| b != a && med[a][b] < 60.0)
                .min_by(|&x, &y| med[a][x].total_cmp(&med[a][y]))
                .into_iter()
                .collect()
        })
        .collect()
}

/// Jumps onto recorded points, both variants, `per * 4` of each for one trial: marker A's
/// samples over 5–40 frames replaced by a near marker B's recorded samples of the same
/// frames, A and B both seen at the span's first and last frames. Drawn from their own
/// generator, so that the other episodes stay as they were.
fn episodes_onto(t: &Trial, per: usize, rng: &mut Rng) -> Vec<Episode> {
    let nf = t.frames();
    let near = near_points(t);
    let from: Vec<usize> = (0..t.markers()).filter(|&a| !near[a].is_empty()).collect();
    let mut out = Vec::new();
    if from.is_empty() {
        return out;
    }
    for kind in [Kind::JumpOntoKept, Kind::JumpOntoTaken] {
        for _ in 0..per * 4 {
            for _ in 0..20 {
                let a = from[rng.range(0, from.len())];
                let b = near[a][rng.range(0, near[a].len())];
                let l = rng.range(5, 41);
                if l + 40 > nf {
                    break;
                }
                let first = rng.range(10, nf - l - 10);
                let last = first + l - 1;
                let seen = |m: usize| t.valid[m][first] && t.valid[m][last];
                if !seen(a) || !seen(b) {
                    continue;
                }
                out.push(Episode {
                    kind,
                    markers: vec![a],
                    first,
                    last,
                    len: l,
                    counted: true,
                    onto: Some(b),
                });
                break;
            }
        }
    }
    out
}

/// Inject a jump onto a recorded point: A takes B's samples whole over the span (B's
/// coordinates, validity, residual and camera mask); for [`Kind::JumpOntoTaken`] B is
/// missing there (residual −1, no cameras).
fn inject_onto(t: &mut Trial, w: &mut Side, e: &Episode) {
    let (a, Some(b)) = (e.markers[0], e.onto) else {
        return;
    };
    let words = w.residual.len() > a.max(b);
    for f in e.first..=e.last {
        t.xyz[a][f] = t.xyz[b][f];
        t.valid[a][f] = t.valid[b][f];
        if words {
            w.residual[a][f] = w.residual[b][f];
            w.mask[a][f] = w.mask[b][f];
        }
        if e.kind == Kind::JumpOntoTaken {
            t.valid[b][f] = false;
            if words {
                w.residual[b][f] = -1.0;
                w.mask[b][f] = 0;
            }
        }
    }
}

fn overlaps(x: &Find, e: &Episode) -> bool {
    x.first <= e.last && e.first <= x.last
}

/// The find that answers `e`: same kind and markers, overlapping its frames. A label that
/// left its point for another's is answered by a jump of that label, and by a swap of the
/// two (undone, the point goes back to its label and the other becomes a gap, as a jump).
fn answers(x: &Find, e: &Episode) -> bool {
    if !overlaps(x, e) {
        return false;
    }
    match (e.kind, e.onto) {
        (Kind::Jump | Kind::JumpOntoKept, _) => x.kind == FindKind::Jump && x.markers == e.markers,
        (Kind::JumpOntoTaken, Some(b)) => {
            let a = e.markers[0];
            (x.kind == FindKind::Jump && x.markers == e.markers)
                || (x.kind == FindKind::Swap && x.markers == [a.min(b), a.max(b)])
        }
        _ => x.kind == FindKind::Swap && x.markers == e.markers,
    }
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
    /// Jumps onto recorded points: settled finds after whose undoing the other marker
    /// holds its recorded samples (kept, or given back by a swap).
    given_back: usize,
}

/// New finds (not in the untouched trial) that answer an episode / that do not, and the
/// refilled jumped samples' errors.
#[derive(Default)]
struct Prec {
    true_finds: usize,
    false_finds: usize,
    true_settled: usize,
    false_settled: usize,
    refill_err: Vec<f64>,
    /// Hits that are jumps of a marker with two or three links found by its leaps alone
    /// (no frame its links decide): found, settled, and their refilled samples' errors.
    leaps_found: usize,
    leaps_settled: usize,
    leaps_refill_err: Vec<f64>,
}

#[derive(Default)]
struct Tally {
    cells: BTreeMap<(Kind, usize), Cell>,
    /// The injected swaps and offset jumps; the jumps onto recorded points apart.
    prec: [Prec; 2],
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
    // The jumps onto recorded points draw from their own generator: the other episodes
    // are the ones drawn before they were added.
    let mut rngs = (Rng(a.seed), Rng(a.seed ^ 0x6f6e_746f));
    let t0 = std::time::Instant::now();
    println!("## finds on the untouched trials\n");
    for &(_set, lab, corpus, rel) in FILES {
        if a.only.as_deref().is_some_and(|o| !rel.contains(o))
            || a.corpus.as_deref().is_some_and(|c| c != corpus)
        {
            continue;
        }
        let Some(Some(root)) = roots.get(corpus) else {
            continue;
        };
        let group = if TUNED.contains(&corpus) {
            "tuned"
        } else if tuned_labs.contains(&lab) {
            "cmu (c3d-more)"
        } else if corpus == "labs" {
            // `c3d-labs` came after every rule: its labs are held apart from all of them.
            "held apart: c3d-labs"
        } else {
            "held apart"
        };
        let path = root.join(rel);
        let recorded = corpus::holds_fills(corpus);
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
        let words = side(&path, recorded);
        eprintln!(
            "{rel}: residuals {}, camera masks {}",
            if words.measured { "measured" } else { "all 0" },
            if words.mask.iter().flatten().any(|&m| m != 0) {
                "recorded"
            } else {
                "all 0"
            }
        );
        let tally = tallies.entry(group).or_default();
        if let Err(e) = trial(&a, &opts, &clean, &words, (group, rel), tally, &mut rngs) {
            eprintln!("{rel}: {e}");
            continue;
        }
        // Untouched alone, a trial is quick: no progress line.
        if a.untouched {
            continue;
        }
        eprintln!("{rel}: done at {:.0} s", t0.elapsed().as_secs_f64());
    }
    for (group, t) in &tallies {
        report(group, t);
    }
}

/// Trial `clean` (of `group` and file `rel`): its finds untouched (printed, and explained
/// with `--explain`), then each injected episode judged, into `tally`. `rngs` draw the
/// episodes and the jumps onto recorded points, each from its own generator.
fn trial(
    a: &Args,
    opts: &SwapOptions,
    clean: &Trial,
    words: &Side,
    (group, rel): (&str, &str),
    tally: &mut Tally,
    rngs: &mut (Rng, Rng),
) -> Result<(), repair::RepairError> {
    let (rng, rng_onto) = (&mut rngs.0, &mut rngs.1);
    let name = |m: usize| {
        words
            .labels
            .get(m)
            .cloned()
            .unwrap_or_else(|| format!("#{m}"))
    };
    let base = finds_of(clean, words, opts, a)?;
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
        if a.explain {
            explain(clean, words, x, opts);
        }
    }
    if a.untouched {
        return Ok(());
    }
    for e in episodes(clean, a.per, rng) {
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
        let mut w = words.clone();
        if let [m, n] = e.markers[..] {
            if w.residual.len() > m.max(n) {
                for f in e.first..=e.last {
                    let (r, k) = (w.residual[m][f], w.mask[m][f]);
                    w.residual[m][f] = w.residual[n][f];
                    w.mask[m][f] = w.mask[n][f];
                    w.residual[n][f] = r;
                    w.mask[n][f] = k;
                }
            }
        }
        judge(&t, &w, clean, &base, &e, opts, tally, a, group, rel);
    }
    for e in episodes_onto(clean, a.per, rng_onto) {
        let (mut t, mut w) = (clean.clone(), words.clone());
        inject_onto(&mut t, &mut w, &e);
        judge(&t, &w, clean, &base, &e, opts, tally, a, group, rel);
    }
    Ok(())
}

/// The detector's finds; under `--residual W FLOOR`, a jump found with a confidence from
/// FLOOR up takes the recorded words' step at its edges as a second witness beside its
/// links (as a swap's edges do): c' = 1 − (1 − c)(1 − g / 2), g the share of the span's
/// samples whose word lies outside the range of the 10 samples either side.
fn finds_of(
    t: &Trial,
    w: &Side,
    opts: &SwapOptions,
    a: &Args,
) -> Result<Vec<Find>, repair::RepairError> {
    let Some((witness, floor)) = a.residual else {
        return find_swaps(t, opts);
    };
    let low = SwapOptions {
        min_report: floor.min(opts.min_report),
        ..opts.clone()
    };
    let mut out = Vec::new();
    for mut x in find_swaps(t, &low)? {
        if x.kind == FindKind::Jump && x.confidence < opts.min_confidence {
            let g = word_step(t, w, x.markers[0], x.first, x.last, witness);
            x.confidence = 1.0 - (1.0 - x.confidence) * (1.0 - g / 2.0);
            x.settled = x.confidence >= opts.min_confidence;
        }
        if x.confidence >= opts.min_report {
            out.push(x);
        }
    }
    Ok(out)
}

/// The share of marker `m`'s valid samples in `first..=last` whose residual (or camera
/// count) lies outside the range of its valid samples in the 10 frames either side; 0
/// with fewer than 3 inside or 6 outside, or when the file records no such word.
fn word_step(t: &Trial, w: &Side, m: usize, first: usize, last: usize, which: Witness) -> f64 {
    if w.residual.len() <= m {
        return 0.0;
    }
    let nf = t.frames();
    let share = |word: &dyn Fn(usize) -> f64| {
        let inside: Vec<f64> = (first..=last)
            .filter(|&f| t.valid[m][f])
            .map(word)
            .collect();
        let outside: Vec<f64> = (first.saturating_sub(10)..first)
            .chain(last + 1..(last + 11).min(nf))
            .filter(|&f| t.valid[m][f])
            .map(word)
            .collect();
        if inside.len() < 3 || outside.len() < 6 {
            return 0.0;
        }
        let lo = outside.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = outside.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        inside.iter().filter(|&&v| v < lo || v > hi).count() as f64 / inside.len() as f64
    };
    let res = || {
        if w.measured {
            share(&|f| w.residual[m][f] as f64)
        } else {
            0.0
        }
    };
    let cam = || share(&|f| w.mask[m][f].count_ones() as f64);
    match which {
        Witness::Residual => res(),
        Witness::Cameras => cam(),
        Witness::Both => res().max(cam()),
    }
}

/// Print what a find rests on, to read it: for each of its markers and each link, the
/// median distance over the 20 frames before, the find's frames and the 20 after (mm, and
/// the learned distance ± tolerance); the marker's median step (mm per frame) there and
/// the largest step at each edge; its residuals and camera counts (medians) there.
fn explain(t: &Trial, w: &Side, x: &Find, opts: &SwapOptions) {
    let links = repair::swaps::learn_links(
        t,
        opts.max_link_spread_mm,
        opts.min_link_support,
        opts.max_links,
    );
    println!("    {:?}", x.evidence);
    let nf = t.frames();
    let name = |m: usize| w.labels.get(m).cloned().unwrap_or_else(|| format!("#{m}"));
    let med = |v: Vec<f64>| -> String { median(v).map_or("–".into(), |m| format!("{m:.1}")) };
    let spans = [
        (x.first.saturating_sub(20), x.first),
        (x.first, x.last + 1),
        (x.last + 1, (x.last + 21).min(nf)),
    ];
    for &m in &x.markers {
        println!("    {} ({} links):", name(m), links[m].len());
        for l in &links[m] {
            let d: Vec<String> = spans
                .iter()
                .map(|&(lo, hi)| {
                    med((lo..hi)
                        .filter(|&f| t.valid[m][f] && t.valid[l.other][f])
                        .map(|f| dist(&t.xyz[m][f], &t.xyz[l.other][f]))
                        .collect())
                })
                .collect();
            println!(
                "      to {:<24} {:.1} ± {:.1} mm: before {}, inside {}, after {}",
                name(l.other),
                l.d0_mm,
                l.tol_mm,
                d[0],
                d[1],
                d[2]
            );
            // Frame by frame over 5 frames either side of each edge ('|' at the edge).
            let series = |lo: usize, at: usize, hi: usize| {
                (lo..hi.min(nf))
                    .map(|f| {
                        let v = if t.valid[m][f] && t.valid[l.other][f] {
                            format!("{:.0}", dist(&t.xyz[m][f], &t.xyz[l.other][f]))
                        } else {
                            "–".into()
                        };
                        if f == at {
                            format!("| {v}")
                        } else {
                            v
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            println!(
                "        first edge: {}; last edge: {}",
                series(x.first.saturating_sub(5), x.first, x.first + 5),
                series(x.last.saturating_sub(4), x.last + 1, x.last + 6)
            );
        }
        nearest_line(t, m, &spans, &name);
        let step = |f: usize| {
            (f > 0 && t.valid[m][f] && t.valid[m][f - 1])
                .then(|| dist(&t.xyz[m][f], &t.xyz[m][f - 1]))
        };
        let steps: Vec<String> = spans
            .iter()
            .map(|&(lo, hi)| med((lo.max(1)..hi).filter_map(step).collect()))
            .collect();
        let edge = |f: usize| {
            (f.saturating_sub(2)..(f + 3).min(nf))
                .filter_map(step)
                .fold(0.0f64, f64::max)
        };
        println!(
            "      step before {}, inside {}, after {} mm/frame; largest at the edges {:.1} and {:.1}",
            steps[0],
            steps[1],
            steps[2],
            edge(x.first),
            edge(x.last + 1)
        );
        if w.residual.len() > m {
            let words: Vec<String> = spans
                .iter()
                .map(|&(lo, hi)| {
                    let ok: Vec<usize> = (lo..hi).filter(|&f| t.valid[m][f]).collect();
                    format!(
                        "{} / {}",
                        med(ok.iter().map(|&f| w.residual[m][f] as f64).collect()),
                        med(ok
                            .iter()
                            .map(|&f| w.mask[m][f].count_ones() as f64)
                            .collect())
                    )
                })
                .collect();
            println!(
                "      residual / cameras before {}, inside {}, after {}",
                words[0], words[1], words[2]
            );
        }
    }
}

/// `--explain`: the nearest other marker to marker `m` (median over each of `spans`, before,
/// inside and after a find): a label on another labelled point sits on it.
fn nearest_line(t: &Trial, m: usize, spans: &[(usize, usize); 3], name: &dyn Fn(usize) -> String) {
    let nearest = |f: usize| {
        (0..t.markers())
            .filter(|&o| o != m && t.valid[o][f] && t.valid[m][f])
            .map(|o| (dist(&t.xyz[m][f], &t.xyz[o][f]), o))
            .min_by(|p, q| p.0.total_cmp(&q.0))
    };
    let near: Vec<String> = spans
        .iter()
        .map(|&(lo, hi)| {
            let mut v: Vec<(f64, usize)> = (lo..hi).filter_map(nearest).collect();
            v.sort_by(|p, q| p.0.total_cmp(&q.0));
            v.get(v.len() / 2)
                .map(|&(d, o)| format!("{d:.1} mm ({})", name(o)))
                .unwrap_or_else(|| "–".into())
        })
        .collect();
    println!(
        "      nearest marker (median) before {}, inside {}, after {}",
        near[0], near[1], near[2]
    );
}

/// Find swaps in the injected trial `t` and score the finds against episode `e`.
#[allow(clippy::too_many_arguments)]
fn judge(
    t: &Trial,
    w: &Side,
    clean: &Trial,
    base: &[Find],
    e: &Episode,
    opts: &SwapOptions,
    tally: &mut Tally,
    a: &Args,
    group: &str,
    rel: &str,
) {
    let finds = match finds_of(t, w, opts, a) {
        Ok(f) => f,
        Err(err) => {
            eprintln!("{rel}: {err}");
            return;
        }
    };
    let new: Vec<&Find> = finds.iter().filter(|x| !known(x, base)).collect();
    let hit = new.iter().find(|x| answers(x, e));
    let onto = e.onto.is_some();
    let key = (
        e.kind,
        if e.kind == Kind::Jump || onto {
            jump_bin(e.len)
        } else {
            e.len
        },
    );
    let cell = tally.cells.entry(key).or_default();
    cell.n += 1;
    let prec = &mut tally.prec[onto as usize];
    for x in &new {
        let ok = answers(x, e);
        match (ok, x.settled) {
            (true, s) => {
                prec.true_finds += 1;
                prec.true_settled += s as usize;
            }
            (false, s) => {
                prec.false_finds += 1;
                prec.false_settled += s as usize;
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
            let leaps_only =
                x.kind == FindKind::Jump && x.evidence.frames_decided == 0 && x.evidence.links >= 2;
            if leaps_only {
                prec.leaps_found += 1;
                prec.leaps_settled += x.settled as usize;
            }
            if x.settled {
                cell.settled += 1;
                let mut u = t.clone();
                let settled: Vec<Find> = new
                    .iter()
                    .filter(|y| answers(y, e))
                    .map(|y| (*y).clone())
                    .collect();
                undo(&mut u, &settled);
                if let (true, Some(b)) = (onto, e.onto) {
                    // Undone when the label is off the other's point over the whole span
                    // (a gap for the fill stage); the other marker holding its recorded
                    // samples again (a swap found where it was missing) is counted apart.
                    let m = e.markers[0];
                    if u.xyz[b] == clean.xyz[b] && u.valid[b] == clean.valid[b] {
                        cell.given_back += 1;
                    }
                    if (e.first..=e.last).all(|f| !u.valid[m][f]) {
                        cell.exact += 1;
                    } else if a.list {
                        println!(
                            "  inexact [{group}] {rel}: {:?} {:?} onto {b} {}–{} found {:?} {}–{}",
                            e.kind, e.markers, e.first, e.last, x.kind, x.first, x.last
                        );
                    }
                    if let Some(errs) = refill(&u, clean, e) {
                        if leaps_only {
                            prec.leaps_refill_err.extend(errs.iter().copied());
                        }
                        prec.refill_err.extend(errs);
                    }
                } else if e.kind == Kind::Jump {
                    if let Some(errs) = refill(&u, clean, e) {
                        if leaps_only {
                            prec.leaps_refill_err.extend(errs.iter().copied());
                        }
                        prec.refill_err.extend(errs);
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
        None if a.list => missed(t, w, e, opts, a, (group, rel)),
        None => {}
    }
}

/// `--list`: an episode no find answered, with its markers' links and the finds below the
/// report's confidence around it (with `--explain`, a jump onto a recorded point's
/// samples, as a find would have shown them).
fn missed(
    t: &Trial,
    w: &Side,
    e: &Episode,
    opts: &SwapOptions,
    a: &Args,
    (group, rel): (&str, &str),
) {
    let links = repair::swaps::learn_links(
        t,
        opts.max_link_spread_mm,
        opts.min_link_support,
        opts.max_links,
    );
    let weak = SwapOptions {
        min_report: 0.0,
        ..opts.clone()
    };
    let all = find_swaps(t, &weak).unwrap_or_default();
    let near: Vec<String> = all
        .iter()
        .filter(|x| overlaps(x, e) && x.markers.iter().any(|m| e.markers.contains(m)))
        .map(|x| {
            format!(
                "{:?}{:?} {}–{} {:.2} {:?}",
                x.kind, x.markers, x.first, x.last, x.confidence, x.evidence
            )
        })
        .collect();
    println!(
        "  missed [{group}] {rel}: {:?} {:?}{} {}–{} links {:?} weak finds {near:?}",
        e.kind,
        e.markers,
        e.onto
            .map(|b| {
                let n = |m: usize| w.labels.get(m).cloned().unwrap_or_default();
                format!(" ({}) onto {b} ({})", n(e.markers[0]), n(b))
            })
            .unwrap_or_default(),
        e.first,
        e.last,
        e.markers
            .iter()
            .map(|&m| links[m].len())
            .collect::<Vec<_>>()
    );
    if a.explain && e.onto.is_some() {
        let as_found = Find {
            kind: FindKind::Jump,
            markers: e.markers.clone(),
            first: e.first,
            last: e.last,
            confidence: 0.0,
            settled: false,
            evidence: repair::swaps::Evidence {
                links: 0,
                frames_decided: 0,
                link_error: 0.0,
                link_error_undone: 0.0,
                edges_smoother: 0,
                offset_share: None,
                edges_checked: 0,
                edge_step_mm: 0.0,
            },
        };
        explain(t, w, &as_found, opts);
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
            (Kind::Jump | Kind::JumpOntoKept | Kind::JumpOntoTaken, 10) => "5–10".into(),
            (Kind::Jump | Kind::JumpOntoKept | Kind::JumpOntoTaken, 20) => "11–20".into(),
            (Kind::Jump | Kind::JumpOntoKept | Kind::JumpOntoTaken, _) => "21–40".into(),
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
    let (mut back, mut settled) = (0, 0);
    for (_, c) in t.cells.range((Kind::JumpOntoTaken, 0)..) {
        back += c.given_back;
        settled += c.settled;
    }
    if settled > 0 {
        println!(
            "\nJumpOntoTaken: undone exactly = the label made a gap over the whole span; the \
             other marker's point given back to it (a swap of the two found) in {back} of {settled} settled"
        );
    }
    for (p, what) in t
        .prec
        .iter()
        .zip(["swaps and offset jumps", "jumps onto recorded points"])
    {
        if p.true_finds + p.false_finds == 0 {
            continue;
        }
        println!(
            "\n{what}: precision {} of finds ({} true, {} false), {} of settled finds ({} true, {} false)",
            pct(p.true_finds, p.true_finds + p.false_finds),
            p.true_finds,
            p.false_finds,
            pct(p.true_settled, p.true_settled + p.false_settled),
            p.true_settled,
            p.false_settled
        );
        let e = sorted(p.refill_err.iter().copied());
        if let (Some(m), Some(p90)) = (rank(&e, 1, 2), rank(&e, 9, 10)) {
            println!(
                "jumped samples refilled (auto fill): median {m:.2} mm, 90th percentile {p90:.2} mm, {} samples",
                e.len()
            );
        }
        let e = sorted(p.leaps_refill_err.iter().copied());
        println!(
            "of the hits, jumps of markers with 2-3 links by their leaps alone: {} found, {} settled; refilled: median {:.2} mm, 90th percentile {:.2} mm, {} samples",
            p.leaps_found,
            p.leaps_settled,
            rank(&e, 1, 2).unwrap_or(f64::NAN),
            rank(&e, 9, 10).unwrap_or(f64::NAN),
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
