//! Whole commands as a user runs them, each a fresh process: `c3dfix info --json` against a
//! process that only loads the file with c3dio (this bench binary itself, started with
//! `C3DFIX_BENCH_C3DIO_LOAD=FILE`), in the same run, on the generated long trial (100 000
//! frames × 100 markers, about 162 MB) and on the real trials of 1.5–2.6 MB in the corpora.
//! After the timings, the peak memory and time of `info`, `gaps`, a byte-identical `convert`
//! and `repair --fill auto` on the long trial (memory as a multiple of the file's size),
//! beside an earlier build's when `C3DFIX_BENCH_BEFORE=PATH/TO/c3dfix` is set.
//!
//! `cargo bench -p c3dfix-cli --bench commands` (C3D_SAMPLES etc. as for the tests).

use criterion::{criterion_group, BenchmarkId, Criterion};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

#[path = "../../c3d/examples/common/big_trial.rs"]
mod big_trial;
#[path = "../tests/common/peak.rs"]
mod peak;
use peak::peak_memory;

const PEER: &str = "C3DFIX_BENCH_C3DIO_LOAD";
const BIN: &str = env!("CARGO_BIN_EXE_c3dfix");
/// An earlier build of the binary to compare with, in the memory table.
const BEFORE: &str = "C3DFIX_BENCH_BEFORE";

/// The peer: load `path` with c3dio as a program that only reads a file would.
fn c3dio_load(path: &str) -> i32 {
    match c3dio::C3d::load(path) {
        Ok(c) => {
            println!("{} frames", c.points.points.rows());
            0
        }
        Err(e) => {
            eprintln!("{path}: {e:?}");
            1
        }
    }
}

/// Run a command to its end; its output is discarded.
fn run(cmd: &mut Command) {
    let ok = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    assert!(ok, "{cmd:?} failed");
}

fn c3dfix(args: &[&str], file: &Path) -> Command {
    let mut c = Command::new(BIN);
    c.args(args).arg(file);
    c
}

fn peer(file: &Path) -> Command {
    let mut c = Command::new(std::env::current_exe().expect("the bench binary"));
    c.env(PEER, file);
    c
}

/// The generated long trial, written once into the temporary folder (and dropped from
/// memory before anything is measured).
fn long_trial() -> PathBuf {
    let p = std::env::temp_dir().join("c3dfix_bench_big_100k_x_100.c3d");
    let bytes = big_trial::big_trial().expect("generate the long trial");
    std::fs::write(&p, bytes).expect("write the long trial");
    p
}

/// Real trials of 1.5–2.6 MB that c3dio reads too.
fn real_trials() -> Vec<PathBuf> {
    let mut v = Vec::new();
    for d in [
        testkit::c3d_samples(),
        testkit::c3d_extra(),
        testkit::c3d_fullbody(),
    ]
    .into_iter()
    .flatten()
    {
        for f in testkit::files_with_ext(&d, "c3d") {
            let size = std::fs::metadata(&f).map_or(0, |m| m.len());
            if (1_500_000..2_600_000).contains(&size) && c3dio::C3d::load_path(f.clone()).is_ok() {
                v.push(f);
            }
        }
    }
    v.sort();
    v
}

fn bench(c: &mut Criterion) {
    let long = long_trial();
    let mut files = vec![long.clone()];
    files.extend(real_trials());
    let mut g = c.benchmark_group("info_process");
    g.measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_millis(500))
        .sample_size(10);
    for f in &files {
        let name = f
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        g.bench_with_input(BenchmarkId::new("c3dfix_info_json", &name), f, |b, f| {
            b.iter(|| run(&mut c3dfix(&["info", "--json"], f)))
        });
        g.bench_with_input(BenchmarkId::new("c3dio_load", &name), f, |b, f| {
            b.iter(|| run(&mut peer(f)))
        });
    }
    g.finish();
    memory_table(&long);
}

/// Peak resident memory (bytes) of a command run to its end.
/// Peak memory and wall time of each command on the long trial, once each, for this build
/// and (when `C3DFIX_BENCH_BEFORE` names one) an earlier build of the binary.
fn memory_table(long: &Path) {
    let size = std::fs::metadata(long).map_or(1, |m| m.len()) as f64;
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out.c3d");
    let o = out.to_string_lossy().into_owned();
    let mut bins = vec![("this build", PathBuf::from(BIN))];
    if let Some(b) = std::env::var_os(BEFORE) {
        bins.push(("before", PathBuf::from(b)));
    }
    let commands: [(&str, Vec<&str>); 5] = [
        ("info --json", vec!["info", "--json"]),
        ("gaps", vec!["gaps"]),
        (
            "convert (byte-identical)",
            vec!["convert", "--force", "-o", &o],
        ),
        (
            "convert --processor dec",
            vec!["convert", "--processor", "dec", "--force", "-o", &o],
        ),
        (
            "repair --fill auto",
            vec!["repair", "--fill", "auto", "--force", "-o", &o],
        ),
    ];
    println!(
        "\npeak memory and time on {} ({:.0} MB)",
        long.display(),
        size / 1e6
    );
    let show = |who: &str, name: &str, cmd: &mut Command| {
        let t = std::time::Instant::now();
        match peak_memory(cmd) {
            Some(b) => println!(
                "  {who:<10} {name:<26} {:>7.0} MB  {:.2}× the file  {:>6.2} s",
                b as f64 / 1e6,
                b as f64 / size,
                t.elapsed().as_secs_f64()
            ),
            None => println!("  {who:<10} {name:<26} (not measured here)"),
        }
    };
    for (name, args) in &commands {
        for (who, bin) in &bins {
            let mut c = Command::new(bin);
            c.args(args).arg(long);
            show(who, name, &mut c);
        }
    }
    show("c3dio", "load", &mut peer(long));
}

criterion_group!(benches, bench);

fn main() {
    if let Ok(path) = std::env::var(PEER) {
        std::process::exit(c3dio_load(&path));
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
