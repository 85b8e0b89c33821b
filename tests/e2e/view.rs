//! `c3dfix plot` and `c3dfix view`: the pictures and pages people judge a repair by.

use super::{c3dfix, s, sample, stderr};
use c3d::{Analog, C3d, Parameters, Points, Processor};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A stand-in for a repaired `walk_int.c3d`: gaps filled and spikes replaced from the truth,
/// marked as the repair pipeline marks them (residual 0, camera mask 0).
fn repaired(dir: &Path) -> PathBuf {
    let truth = c3d::read_file(sample("walk_truth.c3d")).unwrap();
    let mut c = c3d::read_file(sample("walk_int.c3d")).unwrap();
    let t = truth.points().clone();
    let p = c.points_mut();
    for k in 0..p.xyz.len() {
        let off = p.xyz[k]
            .iter()
            .zip(&t.xyz[k])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        if p.residual[k] < 0.0 || off > 20.0 {
            p.xyz[k] = t.xyz[k];
            p.residual[k] = 0.0;
            p.camera_mask[k] = 0;
        }
    }
    let out = dir.join("walk_repaired.c3d");
    std::fs::write(&out, c.to_bytes().unwrap()).unwrap();
    out
}

/// A synthetic trial of `markers` × `frames`, some samples invalid and some filled.
fn synthetic(path: &Path, markers: usize, frames: usize) {
    let mut pts = Points::new(frames, markers);
    for f in 0..frames {
        for i in 0..markers {
            let k = pts.index(f, i);
            let a = f as f32 * 0.01 + i as f32 * 0.3;
            pts.xyz[k] = [
                f as f32 * 0.5 + 100.0 * a.cos(),
                (i % 10) as f32 * 40.0 + 50.0 * a.sin(),
                (i / 10) as f32 * 160.0 + 100.0,
            ];
            pts.residual[k] = match (f + i * 7) % 97 {
                0..=2 => -1.0,
                3 => 0.0,
                _ => 0.5,
            };
        }
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 100.0).unwrap();
    let labels: Vec<String> = (0..markers).map(|i| format!("M{i:03}")).collect();
    ps.set_strings("POINT", "LABELS", &labels).unwrap();
    let c = C3d::new(pts, Analog::new(frames, 0, 1), ps, Processor::Intel, -1.0);
    std::fs::write(path, c.to_bytes().unwrap()).unwrap();
}

fn no_leftovers(dir: &Path) {
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains("c3dfix-tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn plot_writes_svg_and_png_with_labels() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("rkne.svg");
    let out = c3dfix(&[
        "plot",
        s(&sample("walk_int.c3d")),
        "--marker",
        "RKNE,lank",
        "--analog",
        "1",
        "-o",
        s(&svg),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"), "{}", &text[..100]);
    assert!(text.trim_end().ends_with("</svg>"));
    for want in [
        "walk_int.c3d",
        "RKNE",
        "LANK",
        "Time (s)",
        "X (mm)",
        "Z (mm)",
        "analog",
    ] {
        assert!(text.contains(want), "{want} missing");
    }
    let png = dir.path().join("rkne.png");
    let out = c3dfix(&[
        "plot",
        s(&sample("walk_float.c3d")),
        "--marker",
        "RKNE",
        "-o",
        s(&png),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let bytes = std::fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"));
    // No overwrite without --force.
    let out = c3dfix(&[
        "plot",
        s(&sample("walk_int.c3d")),
        "--marker",
        "RKNE",
        "-o",
        s(&svg),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--force"));
}

/// A trial repaired with a low-pass filter only: `plot --against` shows its moved samples
/// as filtered, never as spikes (the file's C3DFIX record says no spike stage ran).
#[test]
fn plot_against_shows_filtered_samples_as_filtered() {
    let dir = tempfile::tempdir().unwrap();
    let rep = dir.path().join("lp.c3d");
    let out = c3dfix(&[
        "repair",
        s(&sample("walk_int.c3d")),
        "-o",
        s(&rep),
        "--lowpass",
        "butterworth:4:6",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = dir.path().join("lp.svg");
    let out = c3dfix(&[
        "plot",
        s(&rep),
        "--against",
        s(&sample("walk_int.c3d")),
        "--marker",
        "LKNE",
        "-o",
        s(&svg),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("filtered"), "no filtered samples drawn");
    assert!(
        !text.contains("removed as spike"),
        "filtered samples drawn as spikes"
    );
    // With spikes removed too, LKNE's spike at frame 75 is a spike again.
    let both = dir.path().join("both.c3d");
    let out = c3dfix(&[
        "repair",
        s(&sample("walk_int.c3d")),
        "-o",
        s(&both),
        "--spikes",
        "hampel",
        "--lowpass",
        "butterworth:4:6",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = c3dfix(&[
        "plot",
        s(&both),
        "--against",
        s(&sample("walk_int.c3d")),
        "--marker",
        "LKNE",
        "-o",
        s(&svg),
        "--force",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("removed as spike"), "the spike is not marked");
    assert!(text.contains("filtered"), "no filtered samples drawn");
}

#[test]
fn plot_against_the_original_marks_the_repairs() {
    let dir = tempfile::tempdir().unwrap();
    let rep = repaired(dir.path());
    let svg = dir.path().join("cmp.svg");
    let out = c3dfix(&[
        "plot",
        s(&rep),
        "--against",
        s(&sample("walk_int.c3d")),
        "--marker",
        "RKNE,LKNE",
        "-o",
        s(&svg),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    for want in [
        "original",
        "repaired",
        "gap in original",
        "filled (residual 0)",
        "removed as spike",
    ] {
        assert!(text.contains(want), "{want} missing");
    }
    // The same as PNG, kept beside the build to look at.
    let art = testkit::workspace_root()
        .join("target")
        .join("e2e-artifacts");
    std::fs::create_dir_all(&art).unwrap();
    let png = art.join("plot_against.png");
    let out = c3dfix(&[
        "plot",
        s(&rep),
        "--against",
        s(&sample("walk_int.c3d")),
        "--marker",
        "RKNE,LKNE",
        "--analog",
        "1",
        "-o",
        s(&png),
        "--force",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn bad_plot_and_view_requests_say_why_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let walk = sample("walk_int.c3d");
    let svg = dir.path().join("x.svg");
    let html = dir.path().join("x.html");
    let sticks = dir.path().join("sticks.json");
    std::fs::write(&sticks, r#"[["LKNE", "NOSE"]]"#).unwrap();
    let empty = dir.path().join("empty.c3d");
    let c = C3d::new(
        Points::new(10, 0),
        Analog::new(10, 1, 1),
        Parameters::new(),
        Processor::Intel,
        -1.0,
    );
    std::fs::write(&empty, c.to_bytes().unwrap()).unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["plot", s(&walk), "--marker", "NOSE", "-o", s(&svg)],
            "NOSE",
        ),
        (
            vec![
                "plot",
                s(&walk),
                "--marker",
                "RKNE",
                "--analog",
                "EMG9",
                "-o",
                s(&svg),
            ],
            "EMG9",
        ),
        (
            vec!["plot", s(&walk), "--marker", "RKNE", "-o", s(&html)],
            ".svg or .png",
        ),
        (
            vec!["plot", s(&empty), "--marker", "RKNE", "-o", s(&svg)],
            "no 3D points",
        ),
        (
            vec!["view", s(&walk), "--sticks", s(&sticks), "-o", s(&html)],
            "NOSE",
        ),
        (vec!["view", s(&empty), "-o", s(&html)], "no 3D points"),
    ];
    for (args, want) in cases {
        let out = c3dfix(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let e = stderr(&out);
        assert!(e.contains(want), "{args:?}: {e}");
        assert!(!e.contains("panicked"), "{e}");
        if want == "NOSE" {
            assert!(
                e.contains("available") && e.contains("LASI") && e.contains("RKNE"),
                "{e}"
            );
        }
        assert!(!svg.exists() && !html.exists(), "{args:?} wrote output");
    }
    no_leftovers(dir.path());
}

/// The page must work offline: nothing in it may point at the network.
fn assert_offline(html: &str) {
    for bad in ["http://", "https://", "src=", "href=", "@import", "url("] {
        assert!(!html.contains(bad), "page contains {bad:?}");
    }
}

#[test]
fn view_writes_a_self_contained_page() {
    let dir = tempfile::tempdir().unwrap();
    let rep = repaired(dir.path());
    let html = dir.path().join("walk.html");
    let out = c3dfix(&[
        "view",
        s(&rep),
        "--against",
        s(&sample("walk_int.c3d")),
        "-o",
        s(&html),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&html).unwrap();
    assert_offline(&text);
    for want in [
        "window.c3dfixViewer",
        "id=\"frame\"",
        "\"RKNE\"",
        "walk_repaired.c3d",
    ] {
        assert!(text.contains(want), "{want} missing");
    }
}

/// A headless Chromium, or `None` (after saying so) when there is none outside CI.
pub(crate) fn chromium() -> Option<PathBuf> {
    let names = ["chromium", "chromium-browser", "google-chrome"];
    let path = std::env::var_os("PATH").unwrap_or_default();
    let found = std::env::split_paths(&path)
        .flat_map(|d| names.iter().map(move |n| d.join(n)))
        .find(|p| p.is_file());
    if found.is_none() {
        let ci = std::env::var_os("CI").is_some_and(|v| !v.is_empty() && v != "false" && v != "0");
        assert!(!ci, "CI needs chromium for the viewer's browser test");
        eprintln!("skipping: chromium not found (install chromium to run the browser test)");
        testkit::skipped("chromium not found");
    }
    found
}

/// Run headless Chromium with `args` then `url`, and give back its standard output.
fn run_chromium(bin: &Path, profile: &Path, args: &[&str], url: &str) -> String {
    run_chromium_for(bin, profile, args, url, Duration::from_secs(180))
}

/// [`run_chromium`], killed and failed after `limit`.
pub(crate) fn run_chromium_for(
    bin: &Path,
    profile: &Path,
    args: &[&str],
    url: &str,
    limit: Duration,
) -> String {
    let mut child = Command::new(bin)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--window-size=1200,800",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start chromium");
    let mut out = child.stdout.take().expect("chromium stdout");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut out, &mut s);
        s
    });
    let start = Instant::now();
    loop {
        if child.try_wait().expect("wait for chromium").is_some() {
            break;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish in {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    reader.join().expect("chromium output")
}

/// The page's own self-test (`?selftest=1`) under virtual time: no console errors, a painted
/// canvas, play advancing the frame counter, the slider moving the frame.
pub(super) fn selftest(bin: &Path, page: &Path, profile: &Path) -> serde_json::Value {
    let url = format!("file://{}?selftest=1", page.display());
    let dom = run_chromium(
        bin,
        profile,
        &["--virtual-time-budget=5000", "--dump-dom"],
        &url,
    );
    let start = dom.find("<pre id=\"selftest\">").expect("self-test ran") + 19;
    let end = start + dom[start..].find("</pre>").expect("self-test closed");
    let json = dom[start..end]
        .replace("&amp;", "&")
        .replace("&lt;", "<")
        .replace("&gt;", ">");
    serde_json::from_str(&json).expect("self-test JSON")
}

/// A trial recorded before the subject walks into view (BMC's gait trial: no marker until
/// frame 134 of 487) opens where the markers are, not on an empty floor; a trial seen from
/// its first frame opens there.
#[test]
fn the_viewer_opens_where_the_markers_are() {
    let Some(bin) = chromium() else { return };
    let Some(late) = testkit::c3d_labs_trial("BMClab__BMC__Gait") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    for (trial, first_seen) in [(late, 134), (sample("walk_int.c3d"), 1)] {
        let page = dir.path().join("page.html");
        let out = c3dfix(&["view", s(&trial), "-o", s(&page), "--force"]);
        assert!(out.status.success(), "{}", stderr(&out));
        let r = selftest(&bin, &page, &dir.path().join("profile"));
        assert_eq!(r["errors"], serde_json::json!([]), "{r}");
        assert_eq!(r["opened_at"], first_seen, "{}: {r}", trial.display());
        assert!(r["markers_drawn"].as_u64().unwrap() > 20, "{r}");
    }
}

#[test]
fn the_viewer_plays_in_a_browser() {
    let Some(bin) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let rep = repaired(dir.path());
    let page = dir.path().join("walk.html");
    let out = c3dfix(&[
        "view",
        s(&rep),
        "--against",
        s(&sample("walk_int.c3d")),
        "-o",
        s(&page),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let r = selftest(&bin, &page, &dir.path().join("profile"));
    assert_eq!(r["errors"], serde_json::json!([]), "{r}");
    assert!(r["painted_pixels"].as_u64().unwrap() > 500, "{r}");
    assert!(r["markers_drawn"].as_u64().unwrap() > 20, "{r}");
    assert!(
        r["played_to"].as_u64().unwrap() > 0,
        "play did not advance: {r}"
    );
    assert!(r["counter_after_play"] != "Frame 1 (1/400) 0.000 s", "{r}");
    assert_eq!(r["slider_frame"], 7, "{r}");
    assert!(
        r["counter_after_slider"]
            .as_str()
            .unwrap()
            .contains("(8/400)"),
        "{r}"
    );
    assert_eq!(r["ok"], true, "{r}");

    screenshot(&bin, &page, &dir.path().join("profile"), "viewer.png");
}

/// A screenshot of `page` to look at, kept beside the build in `target/e2e-artifacts/`.
fn screenshot(bin: &Path, page: &Path, profile: &Path, name: &str) {
    let art = testkit::workspace_root()
        .join("target")
        .join("e2e-artifacts");
    std::fs::create_dir_all(&art).unwrap();
    let shot = art.join(name);
    let _ = std::fs::remove_file(&shot);
    let url = format!("file://{}", page.display());
    let arg = format!("--screenshot={}", shot.display());
    run_chromium(bin, profile, &["--virtual-time-budget=2000", &arg], &url);
    let png = std::fs::read(&shot).expect("screenshot written");
    assert!(png.starts_with(b"\x89PNG"));
}

#[test]
fn a_long_trial_plots_small() {
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join("long.c3d");
    synthetic(&long, 2, 100_000);
    let svg = dir.path().join("long.svg");
    let out = c3dfix(&["plot", s(&long), "--marker", "M001", "-o", s(&svg)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let size = std::fs::metadata(&svg).unwrap().len();
    // Min/max per pixel column: the drawing does not grow with the trial.
    assert!(size < 1_500_000, "{size}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("M001") && text.contains("Time (s)"));
}

#[test]
fn a_large_trial_makes_a_compact_page_that_plays() {
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.c3d");
    synthetic(&big, 100, 10_000);
    let page = dir.path().join("big.html");
    let t = Instant::now();
    let out = c3dfix(&["view", s(&big), "-o", s(&page)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let size = std::fs::metadata(&page).unwrap().len();
    eprintln!(
        "100 markers x 10 000 frames: {size} bytes in {:?}",
        t.elapsed()
    );
    // 12 MB of floats in base64 plus a byte of flags per sample, and little else.
    assert!(size < 18_000_000, "{size}");
    assert_offline(&std::fs::read_to_string(&page).unwrap());
    let Some(bin) = chromium() else { return };
    let r = selftest(&bin, &page, &dir.path().join("profile"));
    assert_eq!(r["ok"], true, "{r}");
}

/// The shared BVH sample of a walk, or `None` (after saying so) without the corpus.
fn bvh_walk() -> Option<PathBuf> {
    let dir = testkit::bvh_samples()?;
    Some(dir.join("bvhtoolbox_walk01.bvh"))
}

#[test]
fn view_draws_a_bvh_skeleton_against_its_keyframed_rebuild() {
    let Some(walk) = bvh_walk() else { return };
    let dir = tempfile::tempdir().unwrap();
    let rebuilt = dir.path().join("rebuilt.bvh");
    let out = c3dfix(&["keyframes", s(&walk), "--keys", "8", "-o", s(&rebuilt)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let html = dir.path().join("walk.html");
    let out = c3dfix(&["view", s(&rebuilt), "--against", s(&walk), "-o", s(&html)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&html).unwrap();
    assert_offline(&text);
    for want in [
        "\"kind\":\"bvh\"",
        "units of the file",
        "\"Hips\"",
        "_End\"",
        "rebuilt.bvh vs bvhtoolbox_walk01.bvh",
    ] {
        assert!(text.contains(want), "{want} missing");
    }

    // A different skeleton is refused, naming what differs; nothing is written.
    let other = dir.path().join("other.bvh");
    let renamed = std::fs::read_to_string(&walk)
        .unwrap()
        .replacen("Hips", "Pelvis", 1);
    std::fs::write(&other, renamed).unwrap();
    let bad = dir.path().join("bad.html");
    let out = c3dfix(&["view", s(&walk), "--against", s(&other), "-o", s(&bad)]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("only in bvhtoolbox_walk01.bvh: [Hips]"),
        "{err}"
    );
    assert!(err.contains("only in other.bvh: [Pelvis]"), "{err}");
    assert!(!bad.exists());

    let Some(bin) = chromium() else { return };
    let r = selftest(&bin, &html, &dir.path().join("profile"));
    assert_eq!(r["errors"], serde_json::json!([]), "{r}");
    assert!(r["painted_pixels"].as_u64().unwrap() > 500, "{r}");
    assert!(r["markers_drawn"].as_u64().unwrap() > 15, "{r}");
    assert_eq!(r["ok"], true, "{r}");
    screenshot(&bin, &html, &dir.path().join("profile"), "viewer_bvh.png");
}

#[test]
fn the_viewer_draws_the_plates_and_the_ground_reaction() {
    let Some(corpus) = testkit::c3d_samples() else {
        return;
    };
    let file = corpus.join("sample_10").join("TYPE-2a.c3d");
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("grf.html");
    let out = c3dfix(&["view", s(&file), "-o", s(&page)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&page).unwrap();
    assert_offline(&text);
    // Both plates' outlines, as FORCE_PLATFORM:CORNERS gives them (mm).
    assert!(
        text.contains("\"plates\":[{\"index\":1,\"corners\":[[482.6,486.0,0.0],"),
        "plate 1 missing"
    );
    assert!(text.contains("{\"index\":2,\"corners\":[[533.4,71.0,0.0],"));
    assert!(text.contains("<script id=\"forces\" type=\"text/plain\">"));
    // A file without plates carries none.
    let walk = dir.path().join("walk.html");
    let out = c3dfix(&["view", s(&sample("walk_int.c3d")), "-o", s(&walk)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let walk_text = std::fs::read_to_string(&walk).unwrap();
    assert!(walk_text.contains("\"plates\":[]"));

    let Some(bin) = chromium() else { return };
    let r = selftest(&bin, &page, &dir.path().join("profile"));
    assert_eq!(r["errors"], serde_json::json!([]), "{r}");
    assert_eq!(r["plates"], 2, "{r}");
    assert_eq!(r["plates_drawn"], 2, "{r}");
    // The first frame whose first analog sample has a COP on some plate (as `forces` says)
    // shows an arrow; frame 0, where neither plate is loaded, shows none.
    let out = c3dfix(&["forces", "--json", s(&file)]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let loaded = (0..360)
        .find(|f| {
            v["platforms"]
                .as_array()
                .unwrap()
                .iter()
                .any(|p| p["cop"][f * 16][0].is_number())
        })
        .unwrap();
    assert_eq!(r["loaded_frame"], loaded, "{r}");
    assert!(r["arrows_drawn"].as_u64().unwrap() >= 1, "{r}");
    assert_eq!(r["unloaded_frame"], 0, "{r}");
    assert_eq!(r["arrows_unloaded"], 0, "{r}");
    assert_eq!(r["ok"], true, "{r}");
    screenshot(
        &bin,
        &page,
        &dir.path().join("profile"),
        "viewer_plates.png",
    );
}

/// Every C3D file of the corpora that are present, sorted (empty without any).
pub(crate) fn corpus_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for d in [
        testkit::c3d_samples(),
        testkit::c3d_extra(),
        testkit::c3d_fullbody(),
        testkit::c3d_more(),
    ]
    .into_iter()
    .flatten()
    {
        collect_c3d(&d, &mut files);
    }
    files.sort();
    files
}

/// The lab's up of the corpus file `name`, as its source knows it.
pub(crate) fn expected_up(name: &str) -> &'static str {
    // Labs whose data is not Z-up, each known from its source: OpenSim-style Y-up trials
    // (nimblephysics' own captures), MotionMonitor and ezc3d's metre trial whose plates face
    // +y, NexGen's Y-up markers, BTS systems (sample_28, BTK's 561xxa01) whose plates face +y
    // and whose lowest markers stay at one y.
    const Y_UP: [&str; 9] = [
        "btkdata_561xxa01_anonym.C3D",
        "dynamic.C3D",
        "standing.C3D",
        "type1.C3D",
        "keenon__nimblephysics__nick_freeform_001.c3d",
        "keenon__nimblephysics__squat.c3d",
        "pyomeca__ezc3d-testFiles__FP_Type1.c3d",
        "MotionMonitorC3D.c3d",
        "test1.c3d",
    ];
    // Phoenix's dance and golf trials stand on X: their lowest marker stays 0–70 mm above
    // x = 0 all through, as a floor at the origin holds it.
    const X_UP: [&str; 4] = ["Dance.c3d", "Dance1.c3d", "golfswing.c3d", "golfswing1.c3d"];
    // Files where no floor tells the markers' up (a cube, a robot arm's plane): what is
    // reported is pinned so that a change is seen, not claimed to be the truth.
    const NO_FLOOR: [(&str, &str); 2] =
        [("btkdata_MyCube.c3d", "-x"), ("BKINtechnologies.c3d", "-x")];
    // Stood up by the floor, where the markers' spread alone said otherwise: CMU's subject
    // rolling on the floor (wider than tall; its lowest marker 5–31 mm above z = 0 in 90 %
    // of frames) and ART's two people side by side and body with hands (wider than tall
    // along x; lowest marker 64–82 mm above z = 0, highest 1.50–1.58 m: a standing
    // person's feet and head) are +z, as the rest of their labs.
    if let Some((_, u)) = NO_FLOOR.iter().find(|(n, _)| *n == name) {
        u
    } else if X_UP.contains(&name) {
        "+x"
    } else if Y_UP.contains(&name) {
        "+y"
    } else {
        "+z"
    }
}

/// The lab's up as `info --json` reports it, for every file of every corpus: from the plates
/// wherever a file has plates with sound CORNERS, else from the markers. The viewer, the
/// OpenSim export and `plot --forces` all stand on this one answer.
#[test]
fn every_corpus_trial_has_the_expected_up() {
    let files = corpus_files();
    if files.is_empty() {
        return;
    }
    let (mut from_plates, mut checked) = (0, 0);
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let out = c3dfix(&["info", "--json", s(f)]);
        if !out.status.success() {
            continue; // the corpora's unreadable files, refused elsewhere
        }
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let up = v["up"].as_str();
        let plates = v["force_platforms"].as_array().unwrap().len();
        if v["points"] == 0 || up.is_none() {
            // No markers with a valid sample and no plates: nothing to stand on.
            assert!(up.is_none() && plates == 0, "{name}: {v}");
            continue;
        }
        assert_eq!(
            up.unwrap(),
            expected_up(&name),
            "{name}: {}",
            v["up_source"]
        );
        if plates > 0 {
            assert_eq!(v["up_source"], "plates", "{name}");
            from_plates += 1;
        }
        checked += 1;
    }
    assert!(
        checked >= 90 && from_plates >= 60,
        "{checked} {from_plates}"
    );
}

fn collect_c3d(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            collect_c3d(&p, out);
        } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("c3d")) {
            out.push(p);
        }
    }
}

/// A Plug-in Gait trial stands on +z in the viewer, without its model outputs (angles,
/// moments, powers stored as points) among the drawn markers; and its writer, which stores
/// residual 0 for every sample, marks nothing as filled.
#[test]
fn the_viewer_stands_plug_in_gait_upright_without_model_outputs() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let file = more.join("martinfelis__puppeteer__testdata.c3d");
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("pig.html");
    let out = c3dfix(&["view", s(&file), "-o", s(&page)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&page).unwrap();
    assert!(text.contains("\"up\":2,\"up_positive\":true"));
    let start = text.find("\"labels\":[").unwrap();
    let drawn = &text[start..start + text[start..].find(']').unwrap()];
    assert!(drawn.contains("\"LKNE\""), "{drawn}");
    for output in ["LHipAngles", "LKneeAngles", "LHipMoment", "LHipPower"] {
        assert!(!drawn.contains(&format!("\"{output}\"")), "{output} drawn");
    }
    let c = c3d::read(std::fs::read(&file).unwrap()).unwrap();
    let outputs = c.model_output_labels().len();
    assert!(outputs >= 26, "{outputs}");
    let count = drawn.matches("\",\"").count() + 1;
    assert_eq!(count, c.point_count() - outputs);
    // Every valid sample has residual 0 in this file: none is flagged filled (bit 2).
    let fstart = text
        .find("<script id=\"flags\" type=\"text/plain\">")
        .unwrap()
        + 37;
    let flags = unbase64(&text[fstart..fstart + text[fstart..].find('<').unwrap()]);
    assert_eq!(flags.len(), count * c.frames());
    assert!(flags.iter().any(|f| f & 1 == 1));
    assert!(flags.iter().all(|f| f & 2 == 0));
}

pub(crate) fn unbase64(text: &str) -> Vec<u8> {
    const B64: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = Vec::new();
    let (mut acc, mut bits) = (0u32, 0);
    for ch in text.trim().bytes().filter(|&c| c != b'=') {
        acc = (acc << 6) | B64.iter().position(|&b| b == ch).unwrap() as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    out
}

/// Plots speak the file's time base: `FMC_MH0222_BP15` holds frames 260–550 at 100 Hz, so
/// its time axis runs from 2.59 s to 5.49 s (ticks up to 5.0), as its events and the
/// other outputs do, not from 0 to 2.9 s.
#[test]
fn plots_are_on_the_files_time_base() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let f = more.join("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d");
    let dir = tempfile::tempdir().unwrap();
    for (name, extra) in [
        ("m.svg", ["--marker", "LASI"]),
        ("f.svg", ["--forces", "--force"]),
    ] {
        let svg = dir.path().join(name);
        let mut args = vec!["plot", s(&f), "-o", s(&svg)];
        args.extend(extra);
        let out = c3dfix(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        let text = std::fs::read_to_string(&svg).unwrap();
        let ticks: Vec<&str> = text
            .split("</text>")
            .filter_map(|t| t.rsplit('>').next())
            .map(str::trim)
            .collect();
        assert!(ticks.contains(&"5.0"), "{name}: {ticks:?}");
        assert!(ticks.contains(&"3.0"), "{name}: {ticks:?}");
    }
}
