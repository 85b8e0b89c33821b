//! Labelling from a template on the labelled trials of the shared corpora (issue 47 item
//! 2): every label stripped, each trajectory split at its gaps and at random points into
//! fragments of 0.2–3 s, every fragment its own unlabelled trajectory (rows shuffled),
//! ghosts added (copies of a marker 15–60 mm off it, 0.2–1 s long), the trial's own
//! unlabelled points kept. The template is another c3d-labs trial of the same repository
//! with at least 80 % of the trial's markers (the La Trobe walk and drop jumps, the Padova
//! walks, the UWA walk, run and cut), else c3d-extra's Plug-in Gait
//! calibration when it names 80 % of them, else the trial's own first 2 s (not scored).
//! A labelled sample is *right* when its fragment gets its marker, *wrong* when another;
//! the rest is left unlabelled. Ghost samples given a label are *false*.
//!
//! Constants were chosen on `samples`, `extra` and `fullbody`; `more` and `labs` chose
//! nothing and are reported apart.
//!
//! ```sh
//! cargo run --release -p evals --bin label_eval
//! cargo run --release -p evals --bin label_eval -- --only MOtoNMS --list
//! cargo run --release -p evals --bin label_eval -- --other-subject --set fit_scale=1
//! ```
//!
//! `--other-subject` labels the CMU trials from a trial of another subject of the same
//! marker set instead (docs/label.md, "A template of another subject").

use clap::Parser;
use evals::corpus::{self, FILES};
use evals::dice::Dice;
use repair::label::{label, LabelOptions};
use repair::{Trial, Unlabelled};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The corpora every constant was chosen on.
const TUNED: [&str; 3] = ["samples", "extra", "fullbody"];

#[derive(Parser)]
#[command(about = "Labelling from a template on the corpora's stripped and fragmented trials")]
struct Cli {
    #[arg(long, default_value_t = 47)]
    seed: u64,
    /// Only the files whose path contains TEXT.
    #[arg(long, value_name = "TEXT")]
    only: Option<String>,
    /// Every wrong fragment.
    #[arg(long)]
    list: bool,
    /// A labelling constant for this run: floor_mm, floor_share, neighbours, cap, accept,
    /// absent, min_neighbours, beam, seed_frames, step, min_checked, min_share, margin,
    /// relabel_share, max_speed_mm_s, passes, relearn, fit_scale, scale_steps or scale_ratio.
    #[arg(long = "set", value_name = "FIELD=VALUE")]
    set: Vec<String>,
    /// Only the trials with a labelled trial of another subject of the same marker set in
    /// the corpora (the CMU trials: subjects 85, 135 and 02), each labelled from it.
    #[arg(long)]
    other_subject: bool,
}

/// A trial of the CMU marker set and the trial of another CMU subject it is labelled from
/// with `--other-subject` (file names; c3d-fullbody's 85 and 135 and c3d-more's subject 02
/// and basketball trial, whose subject its source does not name: 85's breakdance
/// is not it).
const OTHER_SUBJECT: [(&str, &str); 6] = [
    ("85_02.c3d", "135_02.c3d"),
    ("85_12.c3d", "135_02.c3d"),
    ("135_02.c3d", "85_02.c3d"),
    ("EmbodiedCognition__pagoda__cooper-motion.c3d", "85_02.c3d"),
    ("keenon__nimblephysics__cmu_02_05.c3d", "135_02.c3d"),
    (
        "keenon__nimblephysics__cmu_dribble_shoot_basketball.c3d",
        "135_02.c3d",
    ),
];

/// The trial of another subject `OTHER_SUBJECT` names for trial `i`, if loaded.
fn other_subject(
    i: usize,
    files: &[(String, String, PathBuf)],
    loaded: &[Option<Loaded>],
) -> Option<usize> {
    let file = |j: usize| {
        files[j]
            .2
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string()
    };
    let (_, t) = OTHER_SUBJECT.iter().find(|(a, _)| *a == file(i))?;
    (0..files.len()).find(|&j| j != i && file(j) == *t && loaded[j].is_some())
}

fn options(sets: &[String]) -> Result<LabelOptions, String> {
    let mut o = LabelOptions::default();
    for kv in sets {
        let (k, v) = kv.split_once('=').ok_or("--set FIELD=VALUE")?;
        let x: f64 = v.parse().map_err(|e| format!("--set {k}: {e}"))?;
        match k {
            "floor_mm" => o.floor_mm = x,
            "floor_share" => o.floor_share = x,
            "neighbours" => o.neighbours = x as usize,
            "cap" => o.cap = x,
            "accept" => o.accept = x,
            "absent" => o.absent = x,
            "min_neighbours" => o.min_neighbours = x as usize,
            "beam" => o.beam = x as usize,
            "seed_frames" => o.seed_frames = x as usize,
            "seed_every_s" => o.seed_every_s = x,
            "seed_all" => o.seed_all = x != 0.0,
            "seed_chain" => o.seed_chain = x as usize,
            "step" => o.step = x as usize,
            "min_checked" => o.min_checked = x as usize,
            "min_share" => o.min_share = x,
            "margin" => o.margin = x,
            "relabel_share" => o.relabel_share = x,
            "max_speed_mm_s" => o.max_speed_mm_s = x,
            "passes" => o.passes = x as usize,
            "relearn" => o.relearn = x as usize,
            "fit_scale" => o.fit_scale = x != 0.0,
            "scale_steps" => o.scale_steps = x as usize,
            "scale_ratio" => o.scale_ratio = x,
            "first_floor_share" => o.first_floor_share = x,
            "relearn_template" => o.relearn_template = x != 0.0,
            "vote_margin" => o.vote_margin = x,
            "exchange_margin" => o.exchange_margin = x,
            _ => return Err(format!("no option {k}")),
        }
    }
    Ok(o)
}

/// A trial's labelled markers (with names) and its own unlabelled points, in mm.
struct Loaded {
    names: Vec<String>,
    labelled: Trial,
    unlabelled: Trial,
}

fn bare(l: &str) -> String {
    l.rsplit(':')
        .next()
        .unwrap_or(l)
        .trim()
        .to_ascii_uppercase()
}

fn load(path: &Path) -> Result<Loaded, String> {
    let c = c3d::read_file(path).map_err(|e| e.to_string())?;
    let outputs = c.model_output_labels();
    let labels = c.point_labels();
    let rule = Unlabelled::common();
    let p = c.points();
    let mut seen = std::collections::BTreeSet::new();
    let markers: Vec<usize> = (0..labels.len())
        .filter(|&i| !outputs.contains(&labels[i]))
        .filter(|&i| (0..p.frames()).any(|f| p.is_valid(f, i) && p.trajectory(i)[f] != [0.0; 3]))
        .collect();
    let (u, l): (Vec<usize>, Vec<usize>) = markers
        .into_iter()
        .partition(|&i| rule.is_unlabelled(&labels[i]));
    let l: Vec<usize> = l
        .into_iter()
        .filter(|&i| seen.insert(bare(&labels[i])))
        .collect();
    Ok(Loaded {
        names: l.iter().map(|&i| bare(&labels[i])).collect(),
        labelled: corpus::trial_of(&c, &l, false)?,
        unlabelled: corpus::trial_of(&c, &u, false)?,
    })
}

fn window(t: &Trial, a: usize, b: usize) -> Trial {
    Trial {
        rate_hz: t.rate_hz,
        xyz: t.xyz.iter().map(|r| r[a..b].to_vec()).collect(),
        valid: t.valid.iter().map(|r| r[a..b].to_vec()).collect(),
    }
}

#[derive(Default, Clone, Copy)]
struct Tally {
    trials: usize,
    samples: usize,
    right: usize,
    wrong: usize,
    ghost: usize,
    ghost_labelled: usize,
    not_in_template: usize,
    seconds: f64,
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.trials += o.trials;
        self.samples += o.samples;
        self.right += o.right;
        self.wrong += o.wrong;
        self.ghost += o.ghost;
        self.ghost_labelled += o.ghost_labelled;
        self.not_in_template += o.not_in_template;
        self.seconds += o.seconds;
    }
    fn line(&self, name: &str) -> String {
        let pct = |a: usize, n: usize| 100.0 * a as f64 / n.max(1) as f64;
        format!(
            "{name:<44} {:>3} trials {:>8} samples: right {:>6.2} %  wrong {:>5.2} %  left {:>5.2} %  ghosts labelled {:>5.2} %  ({:.1} s)",
            self.trials,
            self.samples,
            pct(self.right, self.samples),
            pct(self.wrong, self.samples),
            pct(self.samples - self.right - self.wrong, self.samples),
            pct(self.ghost_labelled, self.ghost),
            self.seconds
        )
    }
}

/// A row of the stripped trial: coordinates, validity, its truth, whether a ghost.
type Row = (Vec<[f64; 3]>, Vec<bool>, Option<usize>, bool);

/// The stripped, fragmented trial with ghosts: rows and each row's truth (a template
/// marker, or `None` for the trial's own unlabelled points and the ghosts, with whether it
/// is a ghost).
fn fragmented(
    t: &Trial,
    truth_of: &[Option<usize>],
    own: &Trial,
    dice: &mut Dice,
) -> (Trial, Vec<(Option<usize>, bool)>) {
    let n = t.frames();
    let rate = t.rate_hz;
    let mut rows: Vec<Row> = Vec::new();
    for (m, &truth) in truth_of.iter().enumerate().take(t.markers()) {
        let mut f = 0;
        while f < n {
            if !t.valid[m][f] {
                f += 1;
                continue;
            }
            let len = ((dice.real(0.2, 3.0) * rate) as usize).max(1);
            let mut e = f;
            while e < n && e < f + len && t.valid[m][e] {
                e += 1;
            }
            let mut x = vec![[0.0; 3]; n];
            let mut v = vec![false; n];
            x[f..e].copy_from_slice(&t.xyz[m][f..e]);
            v[f..e].fill(true);
            rows.push((x, v, truth, false));
            f = e;
        }
    }
    for r in 0..own.markers() {
        rows.push((own.xyz[r].clone(), own.valid[r].clone(), None, false));
    }
    // Ghosts: a tenth of the markers, each a copy of a marker 15–60 mm off it.
    for _ in 0..(t.markers() / 10).max(1) {
        let m = dice.int(0, t.markers() - 1);
        let len = ((dice.real(0.2, 1.0) * rate) as usize).clamp(1, n);
        let a = dice.int(0, n - len);
        let off = dice.real(15.0, 60.0);
        let d = [
            dice.real(-1.0, 1.0),
            dice.real(-1.0, 1.0),
            dice.real(-1.0, 1.0),
        ];
        let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-9);
        let d = d.map(|c| c * off / norm);
        let mut x = vec![[0.0; 3]; n];
        let mut v = vec![false; n];
        for f in a..a + len {
            if t.valid[m][f] {
                let p = t.xyz[m][f];
                x[f] = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
                v[f] = true;
            }
        }
        rows.push((x, v, None, true));
    }
    for i in (1..rows.len()).rev() {
        rows.swap(i, dice.int(0, i));
    }
    let truth = rows.iter().map(|r| (r.2, r.3)).collect();
    let (xyz, valid) = rows.into_iter().map(|r| (r.0, r.1)).unzip();
    (
        Trial {
            rate_hz: rate,
            xyz,
            valid,
        },
        truth,
    )
}

/// One trial labelled from `template` (`own_start`: the template is the trial's own first
/// frames, which are not scored).
fn run(
    l: &Loaded,
    template: &Loaded,
    own_start: usize,
    dice: &mut Dice,
    opts: &LabelOptions,
    list: bool,
    name: &str,
) -> Tally {
    let tindex: BTreeMap<&str, usize> = template
        .names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    let truth_of: Vec<Option<usize>> = l
        .names
        .iter()
        .map(|n| tindex.get(n.as_str()).copied())
        .collect();
    let n = l.labelled.frames();
    let (t, own) = (
        window(&l.labelled, own_start, n),
        window(&l.unlabelled, own_start, n),
    );
    let tt = if own_start > 0 {
        window(&template.labelled, 0, own_start)
    } else {
        template.labelled.clone()
    };
    let (trial, truth) = fragmented(&t, &truth_of, &own, dice);
    let given = vec![None; trial.markers()];
    let start = Instant::now();
    let out = match label(&tt, 1.0, &trial, 1.0, &given, opts) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{name}: {e}");
            return Tally::default();
        }
    };
    let mut tally = Tally {
        trials: 1,
        seconds: start.elapsed().as_secs_f64(),
        ..Tally::default()
    };
    for (m, &tm) in truth_of.iter().enumerate() {
        if tm.is_none() {
            tally.not_in_template += t.valid[m].iter().filter(|&&v| v).count();
        }
    }
    for a in &out.fragments {
        let g = a.fragment;
        let samples = trial.valid[g.row][g.first..=g.last]
            .iter()
            .filter(|&&v| v)
            .count();
        match truth[g.row] {
            (Some(m), _) => {
                tally.samples += samples;
                match a.label {
                    Some(x) if x == m => tally.right += samples,
                    Some(x) => {
                        tally.wrong += samples;
                        if list {
                            println!(
                                "  wrong {name}: {} frames {}–{} as {} ({:?}, {} of {} votes)",
                                template.names[m],
                                g.first + own_start,
                                g.last + own_start,
                                template.names[x],
                                a.outcome,
                                a.votes,
                                a.checked
                            );
                        }
                    }
                    None => {}
                }
            }
            (None, true) => {
                tally.ghost += samples;
                if a.label.is_some() {
                    tally.ghost_labelled += samples;
                }
            }
            (None, false) => {}
        }
    }
    tally
}

/// The template for trial `i`: another c3d-labs trial of the same repository (the same
/// subject's session) with at least 80 % of its markers (the most in common), else the
/// Plug-in Gait calibration if it names 80 %, else none (the trial's own first seconds).
/// The other corpora's labs group unrelated subjects and marker sets, so they are not
/// paired.
fn template_for(
    i: usize,
    files: &[(String, String, PathBuf)],
    loaded: &[Option<Loaded>],
    pig: Option<&Loaded>,
) -> Option<usize> {
    let l = loaded[i].as_ref()?;
    let share = |t: &Loaded| {
        l.names.iter().filter(|n| t.names.contains(n)).count() as f64 / l.names.len().max(1) as f64
    };
    let best = (0..files.len())
        .filter(|&j| {
            j != i && files[i].0 == "labs" && files[j].0 == "labs" && files[j].1 == files[i].1
        })
        .filter_map(|j| loaded[j].as_ref().map(|t| (j, share(t))))
        .filter(|&(_, s)| s >= 0.8)
        .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)));
    if let Some((j, _)) = best {
        return Some(j);
    }
    pig.filter(|p| share(p) >= 0.8).map(|_| usize::MAX)
}

fn main() {
    let cli = Cli::parse();
    let opts = match options(&cli.set) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("label_eval: {e}");
            std::process::exit(2);
        }
    };
    let roots = corpus::roots();
    let mut files: Vec<(String, String, PathBuf)> = Vec::new();
    let mut activity: Vec<&'static str> = Vec::new();
    for &(set, lab, corp, rel) in FILES {
        if let Some(Some(root)) = roots.get(corp) {
            files.push((corp.to_string(), lab.to_string(), root.join(rel)));
            let readme = std::fs::read_to_string(root.join("README.md")).ok();
            activity.push(corpus::activity(readme.as_deref(), rel, set));
        }
    }
    if let Some(labs) = testkit::c3d_labs() {
        let readme = std::fs::read_to_string(labs.join("README.md")).ok();
        let mut more: Vec<_> = std::fs::read_dir(&labs)
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        more.retain(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("c3d")));
        more.sort();
        // Trials the shared list already names are not read twice.
        more.retain(|p| !files.iter().any(|(_, _, q)| q == p));
        for p in more {
            let stem = p
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            let mut parts = stem.split("__");
            let lab = format!(
                "{}__{}",
                parts.next().unwrap_or(""),
                parts.next().unwrap_or("")
            );
            activity.push(corpus::activity(readme.as_deref(), &stem, "other"));
            files.push(("labs".into(), lab, p));
        }
    }
    let pig = testkit::c3d_extra()
        .map(|r| r.join("btkdata_PiG_Calibration-FlatFoot-One.c3d"))
        .and_then(|p| load(&p).ok());
    let keep: Vec<bool> = files
        .iter()
        .map(|(_, _, p)| {
            cli.only
                .as_ref()
                .is_none_or(|o| p.to_string_lossy().contains(o.as_str()))
        })
        .collect();
    let loaded: Vec<Option<Loaded>> = files
        .iter()
        .map(|(_, _, p)| {
            load(p)
                .ok()
                .filter(|l| l.labelled.markers() >= 4 && l.labelled.frames() >= 40)
        })
        .collect();
    let mut dice = Dice(cli.seed.max(1));
    let mut per: BTreeMap<String, Tally> = BTreeMap::new();
    for i in 0..files.len() {
        let Some(l) = loaded[i].as_ref().filter(|_| keep[i]) else {
            continue;
        };
        let (corp, lab, path) = &files[i];
        let name = format!(
            "{corp}/{}",
            path.file_name().unwrap_or_default().to_string_lossy()
        );
        let chosen = if cli.other_subject {
            match other_subject(i, &files, &loaded) {
                Some(j) => Some(j),
                None => continue,
            }
        } else {
            template_for(i, &files, &loaded, pig.as_ref())
        };
        let kind_of_lab = if cli.other_subject {
            "another subject"
        } else {
            "same lab"
        };
        let (t, kind, own_start) = match chosen {
            Some(usize::MAX) => (pig.as_ref().expect("found above"), "static PiG", 0),
            Some(j) => (loaded[j].as_ref().expect("loaded"), kind_of_lab, 0),
            None => {
                let s = ((2.0 * l.labelled.rate_hz) as usize).min(l.labelled.frames() / 3);
                (l, "own first 2 s", s)
            }
        };
        let tally = run(l, t, own_start, &mut dice, &opts, cli.list, &name);
        println!("{}", tally.line(&format!("{name} [{kind}]")));
        let set = if TUNED.contains(&corp.as_str()) {
            "tuned"
        } else {
            "held apart"
        };
        for key in [
            format!("{set}: all"),
            format!("{set}: lab {corp}/{lab}"),
            format!("{set}: activity {}", activity[i]),
            format!("{set}: template {kind}"),
        ] {
            per.entry(key).or_default().add(&tally);
        }
    }
    println!();
    for (k, t) in &per {
        println!("{}", t.line(k));
    }
}
