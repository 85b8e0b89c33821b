//! Reclaiming on the labelled trials of the shared corpora (issue 47): fragments of 5–200
//! frames cut out of labelled markers into new unlabelled trajectories, each with three
//! distractors over its frames: a ghost 15–60 mm off a marker near the cut one, a still
//! reflection 10–40 mm off the cut marker's path, and a copy of a marker near the cut one
//! shifted by 20–80 mm. Reclaim runs on the labelled markers and all the unlabelled
//! trajectories (the trial's own unlabelled points too); a cut sample is *right* when it is
//! moved back into its marker with its recorded value (bit for bit), *wrong* when moved into
//! another; a distractor sample moved into any marker is a *false move*.
//!
//! Constants were chosen on `samples`, `extra` and `fullbody`; `more` and `labs` are
//! reported apart and chose nothing. Then, apart, the corpora's own unlabelled points: the
//! labelled markers' missing samples, how many reclaiming fills with recorded samples, and
//! the moved samples' segment distances against the trial's own.
//!
//! ```sh
//! cargo run --release -p evals --bin reclaim_eval                   # about a minute
//! cargo run --release -p evals --bin reclaim_eval -- --rounds 4 --seed 7
//! ```
//! Options: `--rounds N` (rounds of cuts per trial, default 2), `--cuts K` (fragments per
//! round, default 6), `--seed S`, `--only TEXT` (files whose path contains TEXT), `--list`
//! (every fragment not put back, and every wrong or false move).

use clap::Parser;
use evals::corpus::{self, FILES};
use evals::dice::Dice;
use repair::reclaim::{find_reclaims, judge, segment_links, ReclaimOptions, Reclaims};
use repair::{Trial, Unlabelled};
use std::collections::BTreeMap;

/// The corpora every constant was chosen on.
const TUNED: [&str; 3] = ["samples", "extra", "fullbody"];

struct Args {
    rounds: usize,
    cuts: usize,
    seed: u64,
    only: Option<String>,
    list: bool,
    opts: ReclaimOptions,
}

/// The benchmark's options.
#[derive(Parser)]
#[command(
    about = "Reclaiming on the corpora's labelled trials: cut fragments put back, distractors left"
)]
struct Cli {
    /// Rounds of cuts per trial.
    #[arg(long, value_name = "N", default_value_t = 2)]
    rounds: usize,
    /// Fragments cut per round.
    #[arg(long, value_name = "K", default_value_t = 6)]
    cuts: usize,
    #[arg(long, default_value_t = 47)]
    seed: u64,
    /// Only the files whose path contains TEXT.
    #[arg(long, value_name = "TEXT")]
    only: Option<String>,
    /// Every fragment not put back, and every wrong or false move.
    #[arg(long)]
    list: bool,
    /// A reclaim constant set for this run: min_links, min_checked, max_fail, max_cost,
    /// path_mm, path_frames, margin, path_alone, min_ends or max_link_tol_mm.
    #[arg(long = "set", value_name = "FIELD=VALUE")]
    set: Vec<String>,
}

fn args() -> Result<Args, String> {
    let cli = Cli::try_parse().map_err(|e| e.to_string())?;
    let mut a = Args {
        rounds: cli.rounds,
        cuts: cli.cuts,
        seed: cli.seed,
        only: cli.only,
        list: cli.list,
        opts: ReclaimOptions::default(),
    };
    for kv in &cli.set {
        let (k, v) = kv.split_once('=').ok_or("--set FIELD=VALUE")?;
        let x: f64 = v.parse().map_err(|e| format!("--set {k}: {e}"))?;
        let o = &mut a.opts;
        match k {
            "min_links" => o.min_links = x as usize,
            "min_checked" => o.min_checked = x,
            "max_fail" => o.max_fail = x,
            "max_cost" => o.max_cost = x,
            "path_mm" => o.path_mm = x,
            "path_frames" => o.path_frames = x as usize,
            "margin" => o.margin = x,
            "path_alone" => o.path_alone = x != 0.0,
            "min_ends" => o.min_ends = x as usize,
            "max_link_tol_mm" => o.max_link_tol_mm = x,
            _ => return Err(format!("no option {k}")),
        }
    }
    Ok(a)
}

/// A trial's labelled markers and its own unlabelled trajectories, in mm.
struct Loaded {
    labelled: Trial,
    unlabelled: Trial,
}

fn load(path: &std::path::Path) -> Result<Loaded, String> {
    let c = c3d::read_file(path).map_err(|e| e.to_string())?;
    let outputs = c.model_output_labels();
    let labels = c.point_labels();
    let rule = Unlabelled::common();
    let markers: Vec<usize> = (0..labels.len())
        .filter(|&i| !outputs.contains(&labels[i]))
        .collect();
    let (u, l): (Vec<usize>, Vec<usize>) = markers
        .into_iter()
        .partition(|&i| rule.is_unlabelled(&labels[i]));
    Ok(Loaded {
        labelled: corpus::trial_of(&c, &l, false)?,
        unlabelled: corpus::trial_of(&c, &u, false)?,
    })
}

/// One cut fragment: the marker, the unlabelled row it went to, its frames.
struct Cut {
    marker: usize,
    row: usize,
    first: usize,
    last: usize,
}

#[derive(Default, Clone, Copy)]
struct Tally {
    cut: usize,
    right: usize,
    wrong: usize,
    false_moves: usize,
    fragments: usize,
    fragments_back: usize,
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.cut += o.cut;
        self.right += o.right;
        self.wrong += o.wrong;
        self.false_moves += o.false_moves;
        self.fragments += o.fragments;
        self.fragments_back += o.fragments_back;
    }
    fn line(&self, name: &str) -> String {
        let pct = |a: usize| 100.0 * a as f64 / self.cut.max(1) as f64;
        format!(
            "{name:<28} {:>4} fragments {:>7} samples: right {:>6.2} %  wrong {:>5.3} %  false moves {:>5.3} %  fragments back {:>5.1} %",
            self.fragments,
            self.cut,
            pct(self.right),
            pct(self.wrong),
            pct(self.false_moves),
            100.0 * self.fragments_back as f64 / self.fragments.max(1) as f64
        )
    }
}

/// Append a trajectory valid over `first..=last` to `u`.
fn push(u: &mut Trial, n: usize, first: usize, last: usize, at: impl Fn(usize) -> [f64; 3]) {
    let mut xyz = vec![[0.0; 3]; n];
    let mut valid = vec![false; n];
    for f in first..=last {
        xyz[f] = at(f);
        valid[f] = true;
    }
    u.xyz.push(xyz);
    u.valid.push(valid);
}

/// The marker nearest `m` at frame `f` other than itself, valid there.
fn nearest(t: &Trial, m: usize, f: usize) -> Option<usize> {
    let d = |a: &[f64; 3], b: &[f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    (0..t.markers())
        .filter(|&o| o != m && t.valid[o][f])
        .min_by(|&a, &b| d(&t.xyz[a][f], &t.xyz[m][f]).total_cmp(&d(&t.xyz[b][f], &t.xyz[m][f])))
}

/// One round on one trial: cuts with their distractors, reclaim, the tally.
fn round(l: &Loaded, dice: &mut Dice, a: &Args, name: &str) -> Tally {
    let (cuts_wanted, list, opts) = (a.cuts, a.list, &a.opts);
    let mut t = l.labelled.clone();
    let mut u = l.unlabelled.clone();
    let n = t.frames();
    let own = u.markers();
    let mut cuts: Vec<Cut> = Vec::new();
    for _ in 0..cuts_wanted * 20 {
        if cuts.len() == cuts_wanted || n < 40 {
            break;
        }
        let m = dice.int(0, t.markers() - 1);
        let len = dice.int(5, 200.min(n / 4));
        let first = dice.int(1, n - len - 1);
        let last = first + len - 1;
        // A whole recorded stretch, with the marker recorded on both sides, away from
        // another cut of it.
        if !(first - 1..=last + 1).all(|f| t.valid[m][f])
            || cuts
                .iter()
                .any(|c| c.marker == m && c.first <= last + 1 && first <= c.last + 1)
        {
            continue;
        }
        let row = u.markers();
        let src = t.xyz[m].clone();
        push(&mut u, n, first, last, |f| src[f]);
        for f in first..=last {
            t.valid[m][f] = false;
        }
        cuts.push(Cut {
            marker: m,
            row,
            first,
            last,
        });
    }
    // Distractors, each over the cut's frames and a little more.
    let mut distractors = Vec::new();
    for c in &cuts {
        let (a, b) = (c.first.saturating_sub(10), (c.last + 10).min(n - 1));
        let mid = (c.first + c.last) / 2;
        if let Some(o) = nearest(&t, c.marker, c.first.saturating_sub(1)) {
            let off = dice.direction().map(|v| v * dice.real(15.0, 60.0));
            let src = t.xyz[o].clone();
            let ok = t.valid[o].clone();
            let (a2, b2) = ((a..=b).find(|&f| ok[f]), (a..=b).rev().find(|&f| ok[f]));
            if let (Some(a2), Some(b2)) = (a2, b2) {
                distractors.push(u.markers());
                push(&mut u, n, a2, b2, |f| {
                    let p = if ok[f] { src[f] } else { src[a2] };
                    [p[0] + off[0], p[1] + off[1], p[2] + off[2]]
                });
                let shift = dice.direction().map(|v| v * dice.real(20.0, 80.0));
                distractors.push(u.markers());
                push(&mut u, n, a2, b2, |f| {
                    let p = if ok[f] { src[f] } else { src[a2] };
                    [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]
                });
            }
        }
        let p = l.labelled.xyz[c.marker][mid];
        let off = dice.direction().map(|v| v * dice.real(10.0, 40.0));
        distractors.push(u.markers());
        push(&mut u, n, a, b, |_| {
            [p[0] + off[0], p[1] + off[1], p[2] + off[2]]
        });
    }
    let r = find_reclaims(&t, &u, 1.0, opts);
    if list {
        for (p, f) in judge(&t, &u, 1.0, opts) {
            if cuts
                .iter()
                .any(|c| c.row == p.source && c.marker == p.marker)
                && !r.moves.iter().any(|m| m.piece == p)
            {
                println!("  piece {name}: {p:?} {f:?}");
            }
        }
    }
    tally(&cuts, &distractors, own, &r, l, &u, list, name)
}

#[allow(clippy::too_many_arguments)]
fn tally(
    cuts: &[Cut],
    distractors: &[usize],
    own: usize,
    r: &Reclaims,
    l: &Loaded,
    u: &Trial,
    list: bool,
    name: &str,
) -> Tally {
    let mut s = Tally::default();
    for c in cuts {
        s.fragments += 1;
        s.cut += c.last - c.first + 1;
        let mut right = 0;
        for mv in r.moves.iter().filter(|m| m.piece.source == c.row) {
            let p = mv.piece;
            for f in p.first.max(c.first)..=p.last.min(c.last) {
                let exact = u.xyz[c.row][f].map(f64::to_bits)
                    == l.labelled.xyz[c.marker][f].map(f64::to_bits);
                if p.marker == c.marker && exact {
                    right += 1;
                } else {
                    s.wrong += 1;
                    if list {
                        println!(
                            "  WRONG {name}: cut of marker {} frames {}–{} moved into {} at {f}",
                            c.marker, c.first, c.last, p.marker
                        );
                    }
                }
            }
        }
        s.right += right;
        if right == c.last - c.first + 1 {
            s.fragments_back += 1;
        } else if list {
            let why: Vec<String> = r
                .unsettled
                .iter()
                .filter(|x| x.piece.source == c.row)
                .map(|x| format!("{:?}", x.why))
                .collect();
            println!(
                "  missed {name}: marker {} frames {}–{} ({} of {} back) {}",
                c.marker,
                c.first,
                c.last,
                right,
                c.last - c.first + 1,
                why.join("; ")
            );
        }
    }
    for mv in r
        .moves
        .iter()
        .filter(|m| distractors.contains(&m.piece.source))
    {
        s.false_moves += mv.piece.len();
        if list {
            println!(
                "  FALSE {name}: distractor moved into marker {} frames {}–{}",
                mv.piece.marker, mv.piece.first, mv.piece.last
            );
        }
    }
    let _ = own;
    s
}

/// The trial's own unlabelled points: labelled gap samples, samples reclaimed, and the
/// moved samples' link residual (rms, mm) against the same links' over the marker's own
/// recorded frames.
fn real(l: &Loaded, opts: &ReclaimOptions) -> (usize, usize, usize, f64, f64) {
    let gaps: usize = l
        .labelled
        .valid
        .iter()
        .map(|v| v.iter().filter(|&&x| !x).count())
        .sum();
    let r = find_reclaims(&l.labelled, &l.unlabelled, 1.0, opts);
    let moved: usize = r.moves.iter().map(|m| m.piece.len()).sum();
    let links = segment_links(&l.labelled, opts);
    let (mut after, mut own, mut na, mut no) = (0.0, 0.0, 0usize, 0usize);
    let d = |a: &[f64; 3], b: &[f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    for mv in &r.moves {
        let p = mv.piece;
        after += mv.fit.rms_mm.powi(2) * mv.fit.checks as f64;
        na += mv.fit.checks;
        let t = &l.labelled;
        for lk in &links[p.marker] {
            for f in 0..t.frames() {
                if t.valid[p.marker][f] && t.valid[lk.other][f] {
                    own += (d(&t.xyz[p.marker][f], &t.xyz[lk.other][f]) - lk.d0_mm).powi(2);
                    no += 1;
                }
            }
        }
    }
    let rms = |s: f64, k: usize| {
        if k > 0 {
            (s / k as f64).sqrt()
        } else {
            f64::NAN
        }
    };
    (gaps, moved, r.unsettled.len(), rms(after, na), rms(own, no))
}

fn main() {
    let a = match args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("reclaim_eval: {e}");
            std::process::exit(2);
        }
    };
    let roots = corpus::roots();
    let mut files: Vec<(String, String, std::path::PathBuf)> = Vec::new();
    for &(_, lab, corp, rel) in FILES {
        if let Some(Some(root)) = roots.get(corp) {
            files.push((corp.to_string(), lab.to_string(), root.join(rel)));
        }
    }
    if let Some(labs) = testkit::c3d_labs() {
        let mut more: Vec<_> = std::fs::read_dir(&labs)
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        more.retain(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("c3d")));
        more.sort();
        for p in more {
            let stem = p
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            let lab = stem.split("__").next().unwrap_or("labs").to_string();
            files.push(("labs".into(), lab, p));
        }
    }
    if let Some(o) = &a.only {
        files.retain(|(_, _, p)| p.to_string_lossy().contains(o.as_str()));
    }
    let mut dice = Dice(a.seed.max(1));
    let mut per_set: BTreeMap<&str, Tally> = BTreeMap::new();
    let mut reals = Vec::new();
    for (corp, lab, path) in &files {
        let Ok(l) = load(path) else {
            continue;
        };
        if l.labelled.markers() < 3 || l.labelled.frames() < 40 {
            continue;
        }
        let name = format!(
            "{corp}/{}",
            path.file_name().unwrap_or_default().to_string_lossy()
        );
        let mut t = Tally::default();
        for _ in 0..a.rounds {
            t.add(&round(&l, &mut dice, &a, &name));
        }
        println!("{}", t.line(&format!("{corp}/{lab}")));
        let set = if TUNED.contains(&corp.as_str()) {
            "tuned (samples, extra, fullbody)"
        } else if corp == "more" {
            "held apart: more"
        } else {
            "held apart: labs"
        };
        per_set.entry(set).or_default().add(&t);
        if l.unlabelled.markers() > 0 {
            reals.push((name, real(&l, &a.opts), l.unlabelled.markers()));
        }
    }
    println!();
    for (set, t) in &per_set {
        println!("{}", t.line(set));
    }
    println!("\nthe corpora's own unlabelled points:");
    for (name, (gaps, moved, unsettled, after, own), n) in &reals {
        println!(
            "  {name}: {n} unlabelled, {gaps} labelled gap samples, {moved} reclaimed ({:.1} %), {unsettled} unsettled; link rms {after:.2} mm moved vs {own:.2} mm own",
            100.0 * *moved as f64 / (*gaps).max(1) as f64
        );
    }
}
