//! Replays every input the fuzzer ever found a failure with (kept in `tests/fuzz-regressions/`),
//! plus the whole corpus, through the fuzz target's checks.

mod common {
    pub mod fuzz_check;
}

#[test]
fn fuzz_regressions_replay() {
    let dir = "crates/c3d/tests/fuzz-regressions";
    let n = testkit::replay_regressions(dir, common::fuzz_check::check);
    assert!(n >= 3, "only {n} regression inputs found in {dir}");
}

#[test]
fn corpus_passes_the_fuzz_checks() {
    for f in testkit::all_c3d_files() {
        let data = std::fs::read(&f).expect("read corpus file");
        common::fuzz_check::check(&data);
    }
}
