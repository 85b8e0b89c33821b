//! Fill accuracy on every walking, running and full-body trial of the shared corpora
//! (issue 10): artificial gaps of 5–80 frames in one marker and in 2–3 neighbouring
//! markers, each single method against `auto`, per set and per rate, mean and max error in
//! mm; the calibration of `auto`'s expected errors; fills that step faster than the marker
//! ever moves. Coordinates are converted to mm before anything is pooled.
//!
//! ```sh
//! cargo run --release -p repair --example fill_eval              # the full evaluation
//! cargo run --release -p repair --example fill_eval -- --quick   # 10 gaps per cell, for iterating
//! ```
//! Options: `--gaps N` (per length, group and file; default 30), `--seed S`, `--only TEXT`
//! (files whose path contains TEXT), `--set walking|fullbody`, `--records FILE` (every
//! gap's errors as JSON lines, for further analysis).

mod corpus;

use corpus::load;
use repair::{calibration, evaluate, EvalConfig, FillMethod, GapScore};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;

/// (set, lab, corpus, path). Copies of one trial in other formats are listed once; files
/// too short for gaps, without markers, with every sample flagged invalid or static (NexGen
/// test1.c3d holds one pose) are left out.
const FILES: &[(&str, &str, &str, &str)] = &[
    (
        "walking",
        "mac",
        "samples",
        "sample_00/Motion Analysis Corporation/Walk1.c3d",
    ),
    (
        "walking",
        "ist",
        "samples",
        "sample_00/Innovative Sports Training/Gait with EMG.c3d",
    ),
    (
        "walking",
        "coda",
        "samples",
        "sample_00/Codamotion/codamotion_gaitwands_20150204.c3d",
    ),
    (
        "walking",
        "coda",
        "samples",
        "sample_00/Codamotion/codamotion_gaitwands_19970212.c3d",
    ),
    ("walking", "amass", "samples", "sample_01/Eb015pr.c3d"),
    ("walking", "vicon370", "samples", "sample_02/pc_real.c3d"),
    ("walking", "vicon370", "samples", "sample_03/gait-raw.c3d"),
    ("walking", "vicon370", "samples", "sample_04/sub_labels.c3d"),
    ("walking", "mac", "samples", "sample_06/newwalk.c3d"),
    ("walking", "mac", "samples", "sample_06/MACsample.c3d"),
    ("walking", "viconws", "samples", "sample_09/PlugInC3D.c3d"),
    ("walking", "amti", "samples", "sample_10/TYPE-3.c3d"),
    ("walking", "mac", "samples", "sample_11/evart.c3d"),
    ("walking", "viconws", "samples", "sample_11/2198928.c3d"),
    (
        "walking",
        "nexus",
        "samples",
        "sample_25/analogfpscale03.c3d",
    ),
    (
        "walking",
        "nexus",
        "samples",
        "sample_25/analogfpscale04.c3d",
    ),
    ("walking", "bts", "samples", "sample_28/dynamic.C3D"),
    ("walking", "marche", "samples", "sample_30/marche281.c3d"),
    ("walking", "marche", "samples", "sample_30/admarche2.c3d"),
    ("walking", "mac", "extra", "btkdata_Gait.c3d"),
    ("walking", "bts", "extra", "btkdata_561xxa01_anonym.C3D"),
    ("fullbody", "cmu", "fullbody", "85_02.c3d"),
    ("fullbody", "cmu", "fullbody", "85_12.c3d"),
    ("fullbody", "cmu", "fullbody", "135_02.c3d"),
    ("fullbody", "numediart", "fullbody", "03_rolling.c3d"),
    (
        "fullbody",
        "mac",
        "samples",
        "sample_00/Motion Analysis Corporation/Sample_Jump2.c3d",
    ),
    (
        "fullbody",
        "art",
        "samples",
        "sample_00/Advanced Realtime Tracking GmbH/arthuman-sample.c3d",
    ),
    ("fullbody", "art", "samples", "sample_37/ART-Human_real.c3d"),
    ("fullbody", "phoenix", "samples", "sample_13/Dance1.c3d"),
    ("fullbody", "mm", "samples", "sample_34/AlbertoREAL.c3d"),
    ("fullbody", "mm", "samples", "sample_34/Basketball.c3d"),
    (
        "fullbody",
        "phasespace",
        "samples",
        "sample_20/phasespace_sample.c3d",
    ),
    ("fullbody", "optitrack", "extra", "btkdata_mocap36.c3d"),
];

const LENGTHS: [usize; 5] = [5, 10, 20, 40, 80];
const SINGLES: [FillMethod; 8] = [
    FillMethod::Linear,
    FillMethod::Lagrange2,
    FillMethod::Lagrange5,
    FillMethod::Spline,
    FillMethod::Rigid,
    FillMethod::Pattern,
    FillMethod::Pca,
    FillMethod::Kalman,
];

struct Args {
    gaps: usize,
    seed: u64,
    only: Option<String>,
    set: Option<String>,
    records: Option<PathBuf>,
    methods: Option<Vec<FillMethod>>,
    fill: repair::FillOptions,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        gaps: 30,
        seed: 1,
        only: None,
        set: None,
        records: None,
        methods: None,
        fill: repair::FillOptions::default(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(x) = it.next() {
        let mut val = || it.next().ok_or(format!("{x} needs a value"));
        match x.as_str() {
            "--quick" => a.gaps = 10,
            "--gaps" => a.gaps = val()?.parse().map_err(|_| "--gaps: a number")?,
            "--seed" => a.seed = val()?.parse().map_err(|_| "--seed: a number")?,
            "--only" => a.only = Some(val()?),
            "--set" => a.set = Some(val()?),
            "--records" => a.records = Some(PathBuf::from(val()?)),
            "--methods" => {
                a.methods = Some(
                    val()?
                        .split(',')
                        .map(|m| FillMethod::from_name(m).ok_or(format!("no method {m}")))
                        .collect::<Result<_, _>>()?,
                )
            }
            "--pca-neighbours" => {
                a.fill.pca_neighbours = val()?.parse().map_err(|_| "--pca-neighbours: a number")?
            }
            "--pca-window" => {
                a.fill.pca_window = val()?.parse().map_err(|_| "--pca-window: a number")?
            }
            "--pca-variance" => {
                a.fill.pca_variance = val()?.parse().map_err(|_| "--pca-variance: a number")?
            }
            _ => return Err(format!("unknown option {x}")),
        }
    }
    Ok(a)
}

/// One gap record with where it came from.
struct Rec {
    set: &'static str,
    lab: &'static str,
    rate: u32,
    group: usize,
    g: GapScore,
}

fn main() {
    let a = match args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("fill_eval: {e}");
            std::process::exit(2);
        }
    };
    let roots: BTreeMap<&str, Option<PathBuf>> = [
        ("samples", testkit::c3d_samples()),
        ("extra", testkit::c3d_extra()),
        ("fullbody", testkit::c3d_fullbody()),
    ]
    .into_iter()
    .collect();
    let methods = a.methods.clone().unwrap_or_else(|| {
        let mut m = SINGLES.to_vec();
        m.push(FillMethod::Auto);
        m
    });
    let mut recs: Vec<Rec> = Vec::new();
    let t0 = std::time::Instant::now();
    for &(set, lab, corpus, rel) in FILES {
        if a.set.as_deref().is_some_and(|s| s != set)
            || a.only.as_deref().is_some_and(|o| !rel.contains(o))
        {
            continue;
        }
        let Some(Some(root)) = roots.get(corpus) else {
            continue;
        };
        let path = root.join(rel);
        let trial = match load(&path) {
            Ok(t) if t.markers() >= 4 => t,
            Ok(_) => {
                eprintln!("{rel}: fewer than 4 markers, left out");
                continue;
            }
            Err(e) => {
                eprintln!("{rel}: {e}");
                continue;
            }
        };
        let rate = trial.rate_hz.round() as u32;
        // Groups of 2 and of 3 markers share the "2–3 markers" rows, half the gaps each.
        for (group, gaps) in [(1, a.gaps), (2, a.gaps.div_ceil(2)), (3, a.gaps / 2)] {
            let cfg = EvalConfig {
                gap_lengths: LENGTHS.to_vec(),
                gaps_per_length: gaps,
                methods: methods.clone(),
                group,
                seed: a.seed,
                fill: a.fill.clone(),
                markers: None,
            };
            match evaluate(&trial, &cfg) {
                Ok(ev) => recs.extend(ev.gaps.into_iter().map(|g| Rec {
                    set,
                    lab,
                    rate,
                    group: group.min(2),
                    g,
                })),
                Err(e) => eprintln!("{rel}: {e}"),
            }
        }
        eprintln!("{rel}: done at {:.0} s", t0.elapsed().as_secs_f64());
    }
    if let Some(p) = &a.records {
        let mut f = std::io::BufWriter::new(std::fs::File::create(p).expect("records file"));
        for r in &recs {
            let v = serde_json::json!({"set": r.set, "lab": r.lab, "rate": r.rate, "group": r.group, "gap": r.g});
            writeln!(f, "{v}").expect("write records");
        }
    }
    report(&recs);
}

fn mean(v: impl Iterator<Item = f64>) -> (f64, usize) {
    let (mut s, mut n) = (0.0, 0);
    for x in v {
        s += x;
        n += 1;
    }
    (if n > 0 { s / n as f64 } else { f64::NAN }, n)
}

/// Pooled tables: rows (set or rate) × group, columns gap lengths; auto's mean (max) and
/// the best single method's mean on the same gaps.
fn table(title: &str, recs: &[&Rec]) {
    println!("\n### {title}\n");
    println!("| markers | | 5 | 10 | 20 | 40 | 80 |");
    println!("|---|---|---|---|---|---|---|");
    for group in [1, 2] {
        let name = if group == 1 { "one" } else { "2–3" };
        let cell = |m: FillMethod, len: usize, max: bool| {
            let v = recs
                .iter()
                .filter(|r| r.group == group && r.g.gap_len == len && r.g.method == m);
            if max {
                v.map(|r| r.g.max).fold(f64::NAN, f64::max)
            } else {
                mean(v.map(|r| r.g.mean)).0
            }
        };
        let mut auto = format!("| {name} | auto mean (max) |");
        let mut best = format!("| {name} | best single |");
        let mut ratio = format!("| {name} | auto / best |");
        for len in LENGTHS {
            let am = cell(FillMethod::Auto, len, false);
            let ax = cell(FillMethod::Auto, len, true);
            let (bm, bn) = SINGLES
                .iter()
                .map(|&m| (cell(m, len, false), m))
                .filter(|x| x.0.is_finite())
                .fold((f64::INFINITY, FillMethod::None), |a, b| {
                    if b.0 < a.0 {
                        b
                    } else {
                        a
                    }
                });
            auto += &format!(" {am:.2} ({ax:.0}) |");
            best += &format!(" {bm:.2} {} |", format!("{bn:?}").to_lowercase());
            ratio += &format!(" {:.2} |", am / bm);
        }
        println!("{auto}\n{best}\n{ratio}");
    }
}

fn report(recs: &[Rec]) {
    let all: Vec<&Rec> = recs.iter().collect();
    let files_note = "Mean 3D error in mm over the artificial gaps (max in brackets)";
    println!(
        "{files_note}; best single: the single method with the lowest pooled mean in that cell."
    );
    for set in ["walking", "fullbody"] {
        let v: Vec<&Rec> = all.iter().copied().filter(|r| r.set == set).collect();
        if !v.is_empty() {
            table(set, &v);
        }
    }
    let mut rates: Vec<u32> = recs.iter().map(|r| r.rate).collect();
    rates.sort_unstable();
    rates.dedup();
    for rate in rates {
        let v: Vec<&Rec> = all.iter().copied().filter(|r| r.rate == rate).collect();
        table(&format!("{rate} Hz"), &v);
    }
    // Auto's own numbers: calibration and plausibility.
    let auto: Vec<GapScore> = recs
        .iter()
        .filter(|r| r.g.method == FillMethod::Auto)
        .map(|r| r.g)
        .collect();
    let c = calibration(&auto, 0.0);
    let missing = auto.iter().filter(|g| g.expected.is_none()).count();
    println!("\n### auto's expected error\n");
    println!(
        "{} gaps ({} without an estimate): Spearman {:.3}, within 2x {:.1} %, over-confident {:.1} %, under-confident {:.1} %, median real/expected {:.2}",
        c.gaps,
        missing,
        c.spearman,
        100.0 * c.within_2x,
        100.0 * c.over_confident,
        100.0 * c.under_confident,
        c.median_ratio
    );
    for set in ["walking", "fullbody"] {
        let v: Vec<GapScore> = recs
            .iter()
            .filter(|r| r.g.method == FillMethod::Auto && r.set == set)
            .map(|r| r.g)
            .collect();
        let c = calibration(&v, 0.0);
        println!(
            "- {set}: {} gaps, Spearman {:.3}, within 2x {:.1} %, over-confident {:.1} %",
            c.gaps,
            c.spearman,
            100.0 * c.within_2x,
            100.0 * c.over_confident
        );
    }
    calibrate(recs);
    let wild = auto.iter().filter(|g| g.step_ratio > 1.5).count();
    let worst = auto.iter().map(|g| g.step_ratio).fold(0.0, f64::max);
    println!("\n### plausibility\n\nauto fills with a step above 1.5x the marker's largest recorded step: {wild} of {} (largest ratio {worst:.2})", auto.len());
    let mut labs: Vec<&str> = recs.iter().map(|r| r.lab).collect();
    labs.sort_unstable();
    labs.dedup();
    println!("\nlabs: {}", labs.join(", "));
}

/// Features of the expected-error model: ln(expected / scored) = β · [1, ln q, ln(gap
/// length), (ln q)², ln q₃, ln h, ln bend, ln drift, refilled, ln rescored] + offset, with
/// q = spread / scored,
/// q₃ = spread3 / scored and h = spread_holes / scored, every ratio clamped to [0.05, 20]
/// and taken as 1 where it is unknown (fewer than three or two candidates, holes without
/// bend, no donor method). The square lets the estimate grow faster when the candidates
/// disagree far beyond their scores. `repair` makes them, for `calibrated` and for this fit.
fn features(g: &GapScore) -> Option<[f64; K]> {
    g.calibration_features()
}

/// Number of features.
const K: usize = repair::fill::FEATURES;

/// Median regression of ln(real / scored) on the features (iteratively reweighted least
/// squares, residuals floored at 0.05), and the offset that leaves 5 % of the fitted gaps
/// above twice their estimate. The median, not the mean: a fit that keeps most gaps close
/// to their estimate puts more of them within 2× once the offset caps over-confidence, and
/// the real errors' heavy tails pull a least-squares fit about.
fn fit(gs: &[&GapScore]) -> Option<([f64; K], f64)> {
    let rows: Vec<([f64; K], f64)> = gs
        .iter()
        .filter_map(|g| {
            Some((
                features(g)?,
                (g.mean.max(1e-9) / g.evidence?.scored.max(1e-9)).ln(),
            ))
        })
        .collect();
    if rows.len() < 2 * K {
        return None;
    }
    let mut w = vec![1.0; rows.len()];
    let mut beta = [0.0; K];
    for _ in 0..15 {
        let mut m = [[0.0; K + 1]; K];
        for ((x, y), wi) in rows.iter().zip(&w) {
            for i in 0..K {
                m[i][K] += wi * x[i] * y;
                for j in 0..K {
                    m[i][j] += wi * x[i] * x[j];
                }
            }
        }
        beta = solve(m)?;
        for ((x, y), wi) in rows.iter().zip(w.iter_mut()) {
            *wi = 1.0 / (y - dot(&beta, x)).abs().max(0.05);
        }
    }
    let mut res: Vec<f64> = rows.iter().map(|(x, y)| y - dot(&beta, x)).collect();
    res.sort_by(f64::total_cmp);
    let q95 = res.get(res.len() * 95 / 100).copied()?;
    Some((beta, q95 - std::f64::consts::LN_2))
}

fn dot(a: &[f64; K], b: &[f64; K]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Gauss–Jordan elimination with partial pivoting on the K × (K + 1) augmented system.
fn solve(mut m: [[f64; K + 1]; K]) -> Option<[f64; K]> {
    for c in 0..K {
        let p = (c..K).max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))?;
        m.swap(c, p);
        if m[c][c].abs() < 1e-12 {
            return None;
        }
        let pivot = m[c];
        for (r, row) in m.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (x, p) in row.iter_mut().zip(pivot).skip(c) {
                    *x -= f * p;
                }
            }
        }
    }
    Some(std::array::from_fn(|i| m[i][K] / m[i][i]))
}

fn predict(g: &GapScore, beta: [f64; K], off: f64) -> Option<f64> {
    let x = features(g)?;
    Some(g.evidence?.scored * (dot(&beta, &x) + off).exp())
}

/// The expected-error model fitted leave-one-lab-out: each lab's gaps are estimated by a
/// model fitted on the other labs only.
fn calibrate(recs: &[Rec]) {
    let auto: Vec<&Rec> = recs
        .iter()
        .filter(|r| r.g.method == FillMethod::Auto)
        .collect();
    let mut labs: Vec<&str> = auto.iter().map(|r| r.lab).collect();
    labs.sort_unstable();
    labs.dedup();
    let mut out: Vec<(&str, GapScore)> = Vec::new();
    for lab in &labs {
        let train: Vec<&GapScore> = auto
            .iter()
            .filter(|r| r.lab != *lab)
            .map(|r| &r.g)
            .collect();
        let Some((beta, off)) = fit(&train) else {
            continue;
        };
        for r in auto.iter().filter(|r| r.lab == *lab) {
            let mut g = r.g;
            g.expected = predict(&g, beta, off);
            out.push((r.set, g));
        }
    }
    let show = |name: &str, v: Vec<GapScore>| {
        let c = calibration(&v, 0.0);
        println!(
            "- {name}, model fitted leave-one-lab-out: {} gaps, Spearman {:.3}, within 2x {:.1} %, over-confident {:.1} %, under-confident {:.1} %",
            c.gaps,
            c.spearman,
            100.0 * c.within_2x,
            100.0 * c.over_confident,
            100.0 * c.under_confident
        );
    };
    show("all", out.iter().map(|x| x.1).collect());
    for set in ["walking", "fullbody"] {
        show(
            set,
            out.iter().filter(|x| x.0 == set).map(|x| x.1).collect(),
        );
    }
    let all: Vec<&GapScore> = auto.iter().map(|r| &r.g).collect();
    if let Some((beta, off)) = fit(&all) {
        let b: Vec<String> = beta.iter().map(|b| format!("{b:.4}")).collect();
        println!(
            "- model fitted on every lab (the constants shipped): beta {}, offset {off:.4}",
            b.join(" ")
        );
    }
}
