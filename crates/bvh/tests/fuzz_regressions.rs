//! Replays every input the BVH fuzz target ever failed on (kept in `tests/fuzz-regressions/`),
//! and the real corpus, through the fuzz target's checks.

mod common {
    pub mod fuzz_check;
}

#[test]
fn fuzz_regressions_replay() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions");
    let (mut parsed, mut refused) = (0, 0);
    for e in std::fs::read_dir(&dir)
        .expect("regression folder")
        .flatten()
    {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.ends_with(".md") {
            continue;
        }
        let data = std::fs::read(e.path()).expect("read regression input");
        common::fuzz_check::check(&data);
        // The name says what the input must do (see the folder's README).
        let result = bvh::parse(&String::from_utf8_lossy(&data));
        if name.starts_with("parses_") {
            assert!(result.is_ok(), "{name}: {:?}", result.err());
            parsed += 1;
        } else if name.starts_with("refused_") {
            assert!(result.is_err(), "{name} parsed");
            refused += 1;
        } else {
            panic!("{name}: regression inputs are named parses_* or refused_*");
        }
    }
    eprintln!("{parsed} inputs parsed, {refused} refused");
    // An empty folder would make this test pass while replaying nothing.
    assert_eq!(
        (parsed, refused),
        (2, 7),
        "inputs added or lost: update the counts"
    );
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
