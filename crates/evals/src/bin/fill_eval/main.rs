//! Fill accuracy on every walking, running and full-body trial of the shared corpora
//! (issue 10): artificial gaps of 5–80 frames in one marker and in 2–3 neighbouring
//! markers, each single method against `auto`, per set and per rate, mean and max error in
//! mm; the calibration of `auto`'s expected errors; fills that step faster than the marker
//! ever moves. Coordinates are converted to mm before anything is pooled.
//!
//! ```sh
//! cargo run --release -p evals --bin fill_eval              # the full evaluation
//! cargo run --release -p evals --bin fill_eval -- --quick   # 10 gaps per cell, for iterating
//! ```
//! Options: `--gaps N` (per length, group and file; default 30), `--seed S`, `--only TEXT`
//! (files whose path contains TEXT), `--set walking|fullbody`, `--records FILE` (every
//! gap's errors as JSON lines, for further analysis; with `--replay`, the replayed records
//! with the expected errors the model now makes), `--replay FILE` (report again from
//! records), `--ablate` (with `--replay`: each expected-error feature left out in turn), `--nested
//! A,B,...` (records of full runs that differ in one choice of `auto`'s, the shipped one
//! first: the choice made leave-one-lab-out; a variant run with `--lengths` counts as the
//! shipped one at the lengths it did not run), `--lengths 40,80` (only these gap lengths: a
//! variant of a choice that acts on some lengths only costs that much), and the fill settings
//! a variant may change: `--auto-trials N`, `--rigid-donors N`, `--spline-context N`,
//! `--pca-neighbours N`, `--pca-variance F`, `--pca-window N`. `--trial-ends` knocks the gaps
//! out at a trial's start or end instead of inside it (the trial cut where the gap begins or
//! ends), and `--held-apart` runs the held-apart labs only; with either, the report closes
//! with the shipped expected-error model's figures on those gaps (within 2×, over twice,
//! what `--max-expected-error` leaves), for the CLI's help and docs/fill-evaluation.md.
//! `--skip-held-apart` runs every lab but those (their records can come from a
//! `--held-apart` run of the same build). With `--replay`: `--activities` (the expected
//! errors per activity, each trial's activity read from its corpus's README, labs and
//! activities held apart; `--activity-gaps FILE` writes each judged gap with its two
//! estimates as tab-separated lines), `--donors` (the gap's donors, chosen again from each
//! record's trial, measured and tried as expected-error features), `--motion` (the marker's
//! own motion around each gap, measured on its trial and tried likewise) and `--write-coefficients` (every lab's `auto` gaps written into
//! the committed gaps file, `crates/evals/data/expected_error_gaps.txt`, and the
//! model fitted on that file into the generated
//! `crates/repair/src/fill/auto/model/coefficients.rs`). `--refit` fits the committed gaps
//! file again into the generated file, without records (after a change to the fit).

mod activity;
mod donors;
mod fit;
mod motion;
mod records;
mod report;

use activity::per_activity;
use clap::Parser;
use evals::corpus::{self, load, load_recorded, FILES};
use fit::*;
use records::*;
use repair::{calibration, evaluate, EvalConfig, FillMethod, GapScore};
use report::*;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::io::Write;
use std::path::PathBuf;

/// The corpora every constant, candidate set and model weight of `auto` was chosen on.
const TUNED: [&str; 3] = ["samples", "extra", "fullbody"];

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
    /// Only the trials of this corpus (its short name in `corpus::roots`).
    corpus: Option<String>,
    records: Option<PathBuf>,
    replay: Option<PathBuf>,
    /// With `--replay`: the expected-error model with each feature left out in turn.
    ablate: bool,
    /// Records of `auto` under variants of one choice, the shipped variant first.
    nested: Vec<PathBuf>,
    methods: Option<Vec<FillMethod>>,
    /// Gap lengths to run (all of [`LENGTHS`] unless `--lengths`).
    lengths: Vec<usize>,
    fill: repair::FillOptions,
    /// Gaps at a trial's start or end (see `EvalConfig::at_trial_ends`).
    trial_ends: bool,
    /// Only the labs nothing was chosen on.
    held_apart: bool,
    /// Every lab but those nothing was chosen on (a run whose held-apart records come from
    /// another run of the same build).
    skip_held_apart: bool,
    /// With `--replay`: expected errors per activity, labs and activities held apart.
    activities: bool,
    /// With `--activities`: every judged gap with its two held-apart estimates, as
    /// tab-separated lines, for reading where an activity's estimates fail.
    activity_gaps: Option<PathBuf>,
    /// With `--replay`: the donors' evidence measured on each record's trial and tried as
    /// expected-error features (see `donors`).
    donors: bool,
    /// With `--replay`: the marker's own motion around each gap measured on its trial and
    /// tried as expected-error features (see `motion`).
    motion: bool,
    /// With `--replay`: the shipped model's gaps file and coefficients written anew.
    write_coefficients: bool,
    /// The coefficients fitted again on the committed gaps file.
    refit: bool,
}

/// Fill accuracy on the corpora's trials, and the fit of `auto`'s expected errors (see the
/// module's documentation for what each option runs).
#[derive(Parser)]
#[command(name = "fill_eval")]
struct Cli {
    /// 10 gaps per length, group and file, for iterating.
    #[arg(long, conflicts_with = "gaps")]
    quick: bool,
    /// Gaps per length, group and file [default: 30].
    #[arg(long)]
    gaps: Option<usize>,
    /// The gaps' random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Only files whose path contains TEXT.
    #[arg(long, value_name = "TEXT")]
    only: Option<String>,
    /// Only the trials of this set (walking, fullbody).
    #[arg(long)]
    set: Option<String>,
    /// Only the trials of this corpus (samples, extra, fullbody, more, labs).
    #[arg(long)]
    corpus: Option<String>,
    /// Every gap's errors as JSON lines (with --replay: the replayed records with the
    /// expected errors the model now makes).
    #[arg(long, value_name = "FILE")]
    records: Option<PathBuf>,
    /// Report again from records.
    #[arg(long, value_name = "FILE")]
    replay: Option<PathBuf>,
    /// With --replay: each expected-error feature left out in turn.
    #[arg(long)]
    ablate: bool,
    /// Records of full runs that differ in one choice of `auto`'s, the shipped one first.
    #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
    nested: Vec<PathBuf>,
    /// Only these fill methods (comma-separated names).
    #[arg(long, value_delimiter = ',', value_parser = method)]
    methods: Option<Vec<FillMethod>>,
    /// Only these gap lengths (of 5, 10, 20, 40, 80).
    #[arg(long, value_delimiter = ',', value_parser = length)]
    lengths: Option<Vec<usize>>,
    /// `auto`'s trial candidates.
    #[arg(long, value_name = "N")]
    auto_trials: Option<usize>,
    /// The rigid fill's donors.
    #[arg(long, value_name = "N")]
    rigid_donors: Option<usize>,
    /// The spline's context frames.
    #[arg(long, value_name = "N")]
    spline_context: Option<usize>,
    /// The PCA fill's neighbours.
    #[arg(long, value_name = "N")]
    pca_neighbours: Option<usize>,
    /// The PCA fill's kept variance.
    #[arg(long, value_name = "F")]
    pca_variance: Option<f64>,
    /// The PCA fill's window.
    #[arg(long, value_name = "N")]
    pca_window: Option<usize>,
    /// Gaps at a trial's start or end instead of inside it.
    #[arg(long)]
    trial_ends: bool,
    /// The held-apart labs only.
    #[arg(long)]
    held_apart: bool,
    /// Every lab but the held-apart ones.
    #[arg(long)]
    skip_held_apart: bool,
    /// With --replay: the expected errors per activity.
    #[arg(long)]
    activities: bool,
    /// With --activities: every judged gap with its two estimates, tab-separated.
    #[arg(long, value_name = "FILE")]
    activity_gaps: Option<PathBuf>,
    /// With --replay: the gaps' donors measured and tried as expected-error features.
    #[arg(long)]
    donors: bool,
    /// With --replay: the marker's motion around each gap tried as expected-error features.
    #[arg(long)]
    motion: bool,
    /// With --replay: the committed gaps file and the generated coefficients written anew.
    #[arg(long, requires = "replay")]
    write_coefficients: bool,
    /// The committed gaps file fitted again into the generated coefficients.
    #[arg(long)]
    refit: bool,
}

/// A fill method by its name, as `c3dfix repair --method` takes it.
fn method(name: &str) -> Result<FillMethod, String> {
    FillMethod::from_name(name).ok_or(format!("no method {name}"))
}

/// A gap length the evaluation runs (one of [`LENGTHS`]).
fn length(l: &str) -> Result<usize, String> {
    l.parse()
        .ok()
        .filter(|l| LENGTHS.contains(l))
        .ok_or(format!("{l} is not one of {LENGTHS:?}"))
}

fn args() -> Args {
    let c = Cli::parse();
    let d = repair::FillOptions::default();
    Args {
        gaps: c.gaps.unwrap_or(if c.quick { 10 } else { 30 }),
        seed: c.seed,
        only: c.only,
        set: c.set,
        corpus: c.corpus,
        records: c.records,
        replay: c.replay,
        ablate: c.ablate,
        nested: c.nested,
        methods: c.methods,
        lengths: c.lengths.unwrap_or_else(|| LENGTHS.to_vec()),
        fill: repair::FillOptions {
            pca_neighbours: c.pca_neighbours.unwrap_or(d.pca_neighbours),
            pca_window: c.pca_window.unwrap_or(d.pca_window),
            pca_variance: c.pca_variance.unwrap_or(d.pca_variance),
            auto_trials: c.auto_trials.unwrap_or(d.auto_trials),
            rigid_donors: c.rigid_donors.unwrap_or(d.rigid_donors),
            spline_context: c.spline_context.unwrap_or(d.spline_context),
            ..d
        },
        trial_ends: c.trial_ends,
        held_apart: c.held_apart,
        skip_held_apart: c.skip_held_apart,
        activities: c.activities,
        activity_gaps: c.activity_gaps,
        donors: c.donors,
        motion: c.motion,
        write_coefficients: c.write_coefficients,
        refit: c.refit,
    }
}

fn main() {
    let a = args();
    if a.refit {
        if let Err(e) = refit() {
            eprintln!("fill_eval: --refit: {e}");
            std::process::exit(2);
        }
        return;
    }
    if !a.nested.is_empty() {
        match a
            .nested
            .iter()
            .map(|p| replay(p))
            .collect::<Result<Vec<_>, _>>()
        {
            Ok(variants) => nested(&a.nested, &variants),
            Err(e) => {
                eprintln!("fill_eval: --nested: {e}");
                std::process::exit(2);
            }
        }
        return;
    }
    if let Some(path) = &a.replay {
        replayed(&a, path);
        return;
    }
    let recs = run(&a);
    if let Some(p) = &a.records {
        write_records(p, &recs);
    }
    // The corpora everything was chosen on, as before; then the labs nothing was chosen on
    // (the CMU trials of `c3d-more` are in neither: their lab was tuned on).
    let tuned: Vec<Rec> = recs.iter().filter(|r| r.tuned).map(Rec::clone).collect();
    report(&tuned);
    held_apart(&recs);
    if a.trial_ends || a.held_apart {
        shipped_on_held_apart(&recs, a.trial_ends);
    }
}

/// `--replay`: the tables again from records, with what `--ablate`, `--activities`,
/// `--donors` and `--write-coefficients` add.
fn replayed(a: &Args, path: &std::path::Path) {
    match replay(path) {
        Ok(recs) => {
            // Replayed records written again carry the expected errors the model now
            // in the code makes.
            if let Some(p) = &a.records {
                write_records(p, &recs);
            }
            let tuned: Vec<Rec> = recs.iter().filter(|r| r.tuned).map(Rec::clone).collect();
            report(&tuned);
            held_apart(&recs);
            if a.ablate {
                ablation(&recs);
            }
            if a.activities {
                per_activity(&recs, a.activity_gaps.as_deref());
            }
            if a.donors {
                donors::donor_study(&recs);
            }
            if a.motion {
                motion::motion_study(&recs);
            }
            if a.write_coefficients {
                let name = path.file_name().unwrap_or_default().to_string_lossy();
                if let Err(e) = write_coefficients(&recs, &format!("`{name}`")) {
                    eprintln!("fill_eval: --write-coefficients: {e}");
                    std::process::exit(2);
                }
            }
        }
        Err(e) => {
            eprintln!("fill_eval: {}: {e}", path.display());
            std::process::exit(2);
        }
    }
}

/// The evaluation over the corpora's trials (as `a` selects them): every gap's record, each
/// trial's progress on stderr.
fn run(a: &Args) -> Vec<Rec> {
    let roots = corpus::roots();
    let methods = a.methods.clone().unwrap_or_else(|| {
        let mut m = SINGLES.to_vec();
        m.push(FillMethod::Gloersen);
        m.push(FillMethod::Auto);
        m
    });
    let mut recs: Vec<Rec> = Vec::new();
    let t0 = std::time::Instant::now();
    let tuned_labs: Vec<&str> = FILES
        .iter()
        .filter(|f| TUNED.contains(&f.2))
        .map(|f| f.1)
        .collect();
    for &(set, lab, corpus, rel) in FILES {
        let held = !TUNED.contains(&corpus) && !tuned_labs.contains(&lab);
        if a.set.as_deref().is_some_and(|s| s != set)
            || a.corpus.as_deref().is_some_and(|c| c != corpus)
            || a.only.as_deref().is_some_and(|o| !rel.contains(o))
            || (a.held_apart && !held)
            || (a.skip_held_apart && held)
        {
            continue;
        }
        let Some(Some(root)) = roots.get(corpus) else {
            continue;
        };
        let path = root.join(rel);
        // Trials of `c3d-more` and `c3d-labs` may hold the capture software's fills
        // (residual 0), which are no truth: where a trial has recorded residuals, they
        // count as missing.
        let loaded = if corpus::holds_fills(corpus) {
            load_recorded(&path)
        } else {
            load(&path)
        };
        let trial = match loaded {
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
                gap_lengths: a.lengths.clone(),
                gaps_per_length: gaps,
                methods: methods.clone(),
                group,
                seed: a.seed,
                fill: a.fill.clone(),
                markers: None,
                at_trial_ends: a.trial_ends,
            };
            match evaluate(&trial, &cfg) {
                Ok(ev) => recs.extend(ev.gaps.into_iter().map(|g| Rec {
                    file: rel.to_string(),
                    held,
                    tuned: TUNED.contains(&corpus),
                    set,
                    lab,
                    rate,
                    group: group.min(2),
                    run: group,
                    g,
                })),
                Err(e) => eprintln!("{rel}: {e}"),
            }
        }
        eprintln!("{rel}: done at {:.0} s", t0.elapsed().as_secs_f64());
    }
    recs
}
