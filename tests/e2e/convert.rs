//! `convert` and `batch` over many files: in place on real trials, each file once however it
//! was named, lists and shards, and an in-place run killed at random moments.

use super::{c3dfix, killed_after, s, sample, stderr, stdout};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Copy every C3D file of the real corpora into `dir`, keeping their folders; returns
/// (copy, original) pairs.
fn copy_corpora(dir: &Path) -> Vec<(PathBuf, PathBuf)> {
    let mut out = Vec::new();
    for (name, root) in [
        ("samples", testkit::c3d_samples()),
        ("extra", testkit::c3d_extra()),
    ] {
        let Some(root) = root else { continue };
        for f in testkit::files_with_ext(&root, "c3d") {
            let copy = dir.join(name).join(f.strip_prefix(&root).unwrap());
            std::fs::create_dir_all(copy.parent().unwrap()).unwrap();
            std::fs::copy(&f, &copy).unwrap();
            out.push((copy, f));
        }
    }
    out
}

/// The JSON lines of a run: (per-file lines, summary).
fn json_lines(out: &std::process::Output) -> (Vec<serde_json::Value>, serde_json::Value) {
    let mut lines: Vec<serde_json::Value> = stdout(out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    let summary = lines.pop().expect("a summary line");
    (lines, summary["summary"].clone())
}

/// Point coordinates (where valid), validity, and analog values in physical units, compared
/// as numbers: the same trial in any processor or number format gives the same values.
fn same_values(a: &c3d::C3d, b: &c3d::C3d, what: &str) {
    let (pa, pb) = (a.points(), b.points());
    assert_eq!(
        (pa.frames(), pa.count()),
        (pb.frames(), pb.count()),
        "{what}"
    );
    for k in 0..pa.xyz.len() {
        let (va, vb) = (pa.residual[k] >= 0.0, pb.residual[k] >= 0.0);
        assert_eq!(va, vb, "{what}: validity of sample {k}");
        if va {
            assert_eq!(pa.xyz[k], pb.xyz[k], "{what}: sample {k}");
        }
    }
    assert_eq!(a.analog_labels(), b.analog_labels(), "{what}");
    let (xa, xb) = (a.analog_physical(), b.analog_physical());
    assert_eq!(xa.len(), xb.len(), "{what}");
    if let Some(k) = (0..xa.len()).find(|&k| xa[k] != xb[k]) {
        panic!("{what}: analog value {k}: {} vs {}", xa[k], xb[k]);
    }
}

#[test]
fn convert_a_folder_in_place_to_dec_and_back_keeps_every_value() {
    let dir = tempfile::tempdir().unwrap();
    let files = copy_corpora(dir.path());
    if files.is_empty() {
        return;
    }
    let root = s(dir.path());
    let o = c3dfix(&[
        "convert",
        root,
        "--in-place",
        "--processor",
        "dec",
        "--jobs",
        "2",
        "--json",
    ]);
    let (lines, summary) = json_lines(&o);
    // The corpora's one unreadable file (empty) fails and is left as it was; exit code 1.
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(summary["failed"], 1, "{summary}");
    assert_eq!(summary["files"].as_u64(), Some(files.len() as u64));
    assert_eq!(lines.len(), files.len());
    let failed: Vec<_> = lines.iter().filter(|l| l["ok"] != true).collect();
    assert!(
        failed[0]["file"]
            .as_str()
            .unwrap()
            .ends_with("btkdata_Empty.c3d"),
        "{failed:?}"
    );
    let mut checked = 0;
    for (copy, original) in &files {
        let bytes = std::fs::read(copy).unwrap();
        let Ok(before) = c3d::read_file(original) else {
            assert_eq!(bytes, std::fs::read(original).unwrap());
            continue;
        };
        let after = c3d::read(bytes).unwrap();
        assert_eq!(after.processor(), c3d::Processor::Dec, "{}", copy.display());
        assert_eq!(after.format(), before.format());
        same_values(&before, &after, &copy.display().to_string());
        checked += 1;
    }
    assert!(checked >= 89, "{checked}");

    let o = c3dfix(&[
        "convert",
        root,
        "--in-place",
        "--processor",
        "intel",
        "--format",
        "float",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    for (copy, original) in &files {
        let Ok(before) = c3d::read_file(original) else {
            continue;
        };
        let after = c3d::read_file(copy).unwrap();
        assert_eq!(
            (after.processor(), after.format()),
            (c3d::Processor::Intel, c3d::NumberFormat::Float)
        );
        same_values(&before, &after, &copy.display().to_string());
    }
}

#[test]
fn convert_many_refuses_bad_combinations_and_keeps_backups() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = std::fs::read(sample("walk_int.c3d")).unwrap();
    std::fs::write(d.join("a.c3d"), &good).unwrap();
    std::fs::write(d.join("b.c3d"), &good).unwrap();
    let a = s(&d.join("a.c3d")).to_string();
    let b = s(&d.join("b.c3d")).to_string();
    for (args, expect) in [
        (vec!["convert", &a, &b, "-o", "x.c3d"], "one input file"),
        (vec!["convert", &a], "--out-dir DIR or --in-place"),
        (
            vec!["convert", &a, "--in-place", "--out-dir", "o"],
            "not both",
        ),
        (
            vec!["convert", &a, "--out-dir", "o", "--backup"],
            "--backup",
        ),
        (vec!["convert", &a, "--in-place", "--shard", "4/3"], "K/N"),
    ] {
        let o = c3dfix(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(expect), "{args:?}: {}", stderr(&o));
    }
    assert_eq!(std::fs::read(d.join("a.c3d")).unwrap(), good);
    let o = c3dfix(&[
        "convert",
        &a,
        &b,
        "--in-place",
        "--backup",
        "--processor",
        "sgi",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("2 files: 2 converted, 0 already so, 0 failed"),
        "{}",
        stdout(&o)
    );
    assert_eq!(std::fs::read(d.join("a.c3d.bak")).unwrap(), good);
    // Already SGI: nothing is rewritten, the backup stays the true original.
    let o = c3dfix(&[
        "convert",
        &a,
        "--in-place",
        "--backup",
        "--processor",
        "sgi",
        "--json",
    ]);
    let (lines, summary) = json_lines(&o);
    assert_eq!(summary["unchanged"], 1);
    assert_eq!(lines[0]["result"]["unchanged"], true);
    assert_eq!(std::fs::read(d.join("a.c3d.bak")).unwrap(), good);
    // --jobs has a range (issue 14), and within it no more threads start than there are
    // files.
    let out = d.join("out");
    let o = c3dfix(&[
        "convert",
        &a,
        &b,
        "--out-dir",
        s(&out),
        "--jobs",
        "18446744073709551615",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("1 to 256"), "{}", stderr(&o));
    let o = c3dfix(&["convert", &a, &b, "--out-dir", s(&out), "--jobs", "256"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("a.c3d").is_file() && out.join("b.c3d").is_file());
}

#[test]
fn a_batch_naming_a_file_twice_processes_it_once() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir_all(input.join("sub")).unwrap();
    let good = std::fs::read(sample("walk_int.c3d")).unwrap();
    for p in ["a.c3d", "sub/b.c3d"] {
        std::fs::write(input.join(p), &good).unwrap();
    }
    let out = dir.path().join("out");
    let twice = input.join("sub/../a.c3d");
    let o = c3dfix(&[
        "batch",
        s(&input),
        s(&input.join("a.c3d")),
        s(&twice),
        "--out-dir",
        s(&out),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (lines, summary) = json_lines(&o);
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert_eq!(
        (summary["repaired"].as_u64(), summary["duplicates"].as_u64()),
        (Some(2), Some(2))
    );
    assert!(out.join("a.c3d").is_file() && out.join("sub/b.c3d").is_file());

    // In place, through a symbolic link too: the file is repaired once, the link stays a link.
    #[cfg(unix)]
    {
        let link = dir.path().join("link.c3d");
        std::os::unix::fs::symlink(input.join("a.c3d"), &link).unwrap();
        let o = c3dfix(&["batch", s(&input), s(&link), "--in-place", "--json"]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let (lines, summary) = json_lines(&o);
        assert_eq!((lines.len(), summary["duplicates"].as_u64()), (2, Some(1)));
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_ne!(std::fs::read(input.join("a.c3d")).unwrap(), good);
    }
}

#[test]
fn sharded_batches_from_a_list_write_every_file_exactly_once() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("archive");
    let good = std::fs::read(sample("walk_int.c3d")).unwrap();
    let mut listed = Vec::new();
    for i in 0..11 {
        let f = input.join(format!("s{}/t{i:02}.c3d", i % 3));
        std::fs::create_dir_all(f.parent().unwrap()).unwrap();
        std::fs::write(&f, &good).unwrap();
        listed.push(f);
    }
    let list = dir.path().join("list.txt");
    let text: String = listed.iter().map(|f| format!("{}\n", s(f))).collect();
    std::fs::write(&list, text).unwrap();
    let out = dir.path().join("out");
    let mut seen = Vec::new();
    for k in 1..=3 {
        // Without --force, a file written by two shards would fail the second one.
        let o = c3dfix(&[
            "batch",
            "--files-from",
            s(&list),
            "--shard",
            &format!("{k}/3"),
            "--out-dir",
            s(&out),
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(0), "shard {k}: {}", stderr(&o));
        let (lines, summary) = json_lines(&o);
        assert_eq!(summary["listed"], 11);
        assert_eq!(summary["shard"], format!("{k}/3"));
        assert!((3..=4).contains(&lines.len()), "shard {k}: {}", lines.len());
        seen.extend(
            lines
                .iter()
                .map(|l| l["file"].as_str().unwrap().to_string()),
        );
    }
    let distinct: BTreeSet<_> = seen.iter().cloned().collect();
    assert_eq!(seen.len(), 11);
    let expected: BTreeSet<_> = listed.iter().map(|f| s(f).to_string()).collect();
    assert_eq!(distinct, expected);
    for f in &listed {
        let name = f.file_name().unwrap();
        assert!(out.join(name).is_file(), "{}", f.display());
    }

    // The same list from standard input.
    let mut child = Command::new(env!("CARGO_BIN_EXE_c3dfix"))
        .args(["convert", "--files-from", "-", "--in-place", "--json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    {
        use std::io::Write;
        let mut stdin = child.stdin.take().unwrap();
        stdin.write_all(&std::fs::read(&list).unwrap()).unwrap();
    }
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let (lines, summary) = json_lines(&o);
    assert_eq!((lines.len(), summary["unchanged"].as_u64()), (11, Some(11)));
}

/// A number from the operating system's randomness (std seeds hash maps with it), so each run
/// kills at other moments.
fn random_u64() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    std::collections::hash_map::RandomState::new()
        .build_hasher()
        .finish()
}

#[test]
fn killing_an_in_place_convert_leaves_each_file_original_or_fully_converted() {
    // Real trials of several sizes, several copies each; the generated walk when the corpus
    // is absent.
    let mut trials: Vec<PathBuf> = testkit::c3d_samples()
        .map(|d| {
            [
                "sample_01/Eb015pi.c3d",
                "sample_01/Eb015pr.c3d",
                "sample_16/basketball.c3d",
                "sample_17/128analogchannels.c3d",
                "sample_36/18124framesi.c3d",
            ]
            .iter()
            .map(|f| d.join(f))
            .filter(|f| f.is_file())
            .collect()
        })
        .unwrap_or_default();
    if trials.is_empty() {
        trials.push(sample("walk_int.c3d"));
    }
    let dir = tempfile::tempdir().unwrap();
    let fill = |folder: &Path| {
        std::fs::create_dir_all(folder).unwrap();
        for i in 0..120 {
            let t = &trials[i % trials.len()];
            std::fs::copy(t, folder.join(format!("t{i:03}.c3d"))).unwrap();
        }
    };
    let args = |folder: &Path| {
        vec![
            "convert".to_string(),
            s(folder).to_string(),
            "--in-place".into(),
            "--processor".into(),
            "dec".into(),
            "--format".into(),
            "float".into(),
            "--jobs".into(),
            "2".into(),
        ]
    };
    // A whole run gives each file's converted bytes, and how long a run takes.
    let whole = dir.path().join("whole");
    fill(&whole);
    let started = std::time::Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_c3dfix"))
        .args(args(&whole))
        .output()
        .unwrap();
    let run_ms = started.elapsed().as_millis() as u64;
    assert!(o.status.success(), "{}", stderr(&o));
    let original = |i: usize| std::fs::read(&trials[i % trials.len()]).unwrap();
    let converted: Vec<Vec<u8>> = (0..120)
        .map(|i| std::fs::read(whole.join(format!("t{i:03}.c3d"))).unwrap())
        .collect();
    for round in 0..6 {
        let folder = dir.path().join(format!("round{round}"));
        fill(&folder);
        let delay_ms = random_u64() % (run_ms + 1);
        killed_after(args(&folder), delay_ms);
        let mut done = 0;
        for e in std::fs::read_dir(&folder).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.contains("c3dfix-tmp") {
                // An interrupted write leaves only its temporary file, never a partial trial.
                continue;
            }
            let i: usize = name[1..4].parse().unwrap();
            let bytes = std::fs::read(e.path()).unwrap();
            assert!(
                bytes == original(i) || bytes == converted[i],
                "round {round} (killed after {delay_ms} ms): {name} is neither the original nor the converted file"
            );
            done += usize::from(bytes == converted[i]);
        }
        eprintln!("killed after {delay_ms} of {run_ms} ms: {done} of 120 files converted");
    }
}
