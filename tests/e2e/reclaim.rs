//! Issue 47 through the command: `c3dfix reclaim` lists what `repair --reclaim on` moves, the
//! summary says it, a second repair changes nothing, and a misspelt mode is a usage error
//! naming the flag.

use super::{c3dfix, s, stderr, stdout};

#[test]
fn reclaim_lists_what_repair_moves_and_a_rerun_changes_nothing() {
    let Some(labs) = testkit::c3d_labs() else {
        eprintln!("C3D_LABS absent: skipped");
        return;
    };
    let src = labs.join("RehabEngGroup__MOtoNMS__Fast_Walking.c3d");
    let o = c3dfix(&["reclaim", s(&src), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let listed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let settled = listed["settled"].as_array().unwrap();
    assert!(!settled.is_empty());
    assert_eq!(
        (listed["markers"].as_u64(), listed["unlabelled"].as_u64()),
        (Some(51), Some(29))
    );
    let samples: u64 = settled.iter().map(|b| b["samples"].as_u64().unwrap()).sum();
    assert!(settled.iter().all(|b| b["action"] == "reported"));
    assert!(settled[0]["fit"]["verdict"] == "fits", "{}", settled[0]);
    let dir = tempfile::tempdir().unwrap();
    let (r1, r2) = (dir.path().join("r1.c3d"), dir.path().join("r2.c3d"));
    let o = c3dfix(&["repair", s(&src), "-o", s(&r1), "--reclaim", "on", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["reclaimed"].as_u64(), Some(samples));
    assert!(v["reclaim_list"]
        .as_array()
        .unwrap()
        .iter()
        .all(|b| b["action"] == "moved"));
    let o = c3dfix(&["repair", s(&r1), "-o", s(&r2), "--reclaim", "on"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("skipped  reclaim (--reclaim on): the file records it as done"),
        "{text}"
    );
    assert_eq!(std::fs::read(&r1).unwrap(), std::fs::read(&r2).unwrap());
    // The default reports and moves nothing.
    let o = c3dfix(&["repair", s(&src), "-o", s(&r2), "--force"]);
    let text = stdout(&o);
    assert!(text.contains("reported (--reclaim on moves it)"), "{text}");
    assert!(
        text.contains("unlabelled 29 points (12590 samples)"),
        "{text}"
    );
    let o = c3dfix(&[
        "repair",
        s(&src),
        "-o",
        s(&r2),
        "--force",
        "--reclaim",
        "maybe",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--reclaim"), "{}", stderr(&o));
}
