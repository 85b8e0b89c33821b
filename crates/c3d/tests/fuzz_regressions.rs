//! Replays every input the fuzzer ever found a failure with (kept in `tests/fuzz-regressions/`),
//! plus the whole corpus, through the fuzz target's checks.

mod common {
    pub mod fuzz_check;
}

#[test]
fn fuzz_regressions_replay() {
    let dir = testkit::workspace_root().join("crates/c3d/tests/fuzz-regressions");
    let mut n = 0;
    for e in std::fs::read_dir(&dir)
        .expect("regression folder")
        .flatten()
    {
        if e.path().extension().is_some_and(|x| x == "md") {
            continue;
        }
        let data = std::fs::read(e.path()).expect("read regression file");
        common::fuzz_check::check(&data);
        n += 1;
    }
    eprintln!("{n} regression inputs replayed");
    assert!(
        n >= 3,
        "only {n} regression inputs found in {}",
        dir.display()
    );
}

#[test]
fn corpus_passes_the_fuzz_checks() {
    for f in testkit::all_c3d_files() {
        let data = std::fs::read(&f).expect("read corpus file");
        common::fuzz_check::check(&data);
    }
}
