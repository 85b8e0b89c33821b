//! Replays every input the BVH fuzz target ever failed on (kept in `tests/fuzz-regressions/`),
//! and the real corpus, through the fuzz target's checks.

mod common {
    pub mod fuzz_check;
}

#[test]
fn fuzz_regressions_replay() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions");
    for e in std::fs::read_dir(&dir)
        .expect("regression folder")
        .flatten()
    {
        if e.path().extension().is_some_and(|x| x == "md") {
            continue;
        }
        common::fuzz_check::check(&std::fs::read(e.path()).expect("read regression input"));
    }
}

#[test]
fn corpus_passes_the_fuzz_checks() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    for f in testkit::files_with_ext(&dir, "bvh") {
        common::fuzz_check::check(&std::fs::read(&f).expect("read corpus file"));
    }
}
