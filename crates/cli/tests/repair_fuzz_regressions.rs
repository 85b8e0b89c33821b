//! Replays every input on which the `repair` fuzz target once failed (kept in
//! `tests/fuzz-regressions/`), and the shared corpora, through the target's checks.

mod common {
    pub mod repair_check;
}

#[test]
fn repair_fuzz_regressions_replay() {
    testkit::replay_regressions(
        "crates/cli/tests/fuzz-regressions",
        common::repair_check::check,
    );
}

#[test]
fn small_corpus_files_pass_the_repair_checks() {
    // The repair is the slow part: files up to 300 kB, as the fuzz corpus takes them.
    for f in testkit::all_c3d_files() {
        let data = std::fs::read(&f).expect("read corpus file");
        if data.len() <= 300_000 {
            common::repair_check::check(&data);
        }
    }
}
