//! Every corpus trial's `c3dfix view` page stands upright, checked in the page itself: its
//! self-test reads, through the page's own axis mapping, camera and projection, which lab
//! direction the home view shows as up on the screen and where the floor grid lies under
//! the markers. One headless Chromium loads every page, a few at a time in frames of one
//! harness page, so the whole corpus costs one browser start.

use super::view::{chromium, corpus_files, expected_up, run_chromium_for, unbase64};
use super::{c3dfix, s, stderr};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Most of a page's marker samples that may lie more than 5 % of the scene's size under
/// the floor grid. Plug-in Gait's segment axis points (LTIA, RTIA, …, stored as markers)
/// and stray unlabelled points hang below the feet in some trials: `sub_labels` has the most,
/// 0.84 % of its samples (LTIA and RTIA, 2 of 58 markers, up to 296 mm under the floor); a
/// scene on its side would have half its samples there.
const MAX_BELOW: f64 = 0.02;

/// Pages loaded at once: enough to keep both cores busy while one page parses its data.
const AT_ONCE: usize = 3;

/// The harness: loads `pages` (names in its folder) `AT_ONCE` at a time with `?selftest=1`,
/// collects each page's self-test as it posts it (60 s of virtual time at most per page),
/// and writes them all, by name, into `<pre id="results">` once every page has answered.
fn harness(pages: &[String]) -> String {
    let list = serde_json::to_string(pages).expect("page names as JSON");
    format!(
        r#"<!DOCTYPE html><html><head><meta charset="utf-8"></head><body><pre id="results"></pre><script>
const pages = {list};
const results = {{}}, live = [];
let next = 0;
function finish(entry, r) {{
  clearTimeout(entry.timer);
  results[entry.name] = r;
  entry.frame.remove();
  live.splice(live.indexOf(entry), 1);
  start();
}}
function start() {{
  while (live.length < {AT_ONCE} && next < pages.length) {{
    const entry = {{ name: pages[next++], frame: document.createElement('iframe') }};
    entry.frame.style.width = '900px';
    entry.frame.style.height = '600px';
    entry.frame.src = entry.name + '?selftest=1';
    entry.timer = setTimeout(() => finish(entry, {{ timeout: true }}), 60000);
    live.push(entry);
    document.body.appendChild(entry.frame);
  }}
  if (live.length === 0 && next >= pages.length) {{
    document.getElementById('results').textContent = JSON.stringify(results);
  }}
}}
window.addEventListener('message', (e) => {{
  const entry = live.find((x) => x.frame.contentWindow === e.source);
  if (entry && e.data && e.data.selftest) finish(entry, e.data.selftest);
}});
start();
</script></body></html>"#
    )
}

/// `c3dfix view` of each file into `dir` (two at a time), as `(file, page name)` for those
/// it makes a page of. A file it refuses must be refused cleanly (exit 2, no panic, no page).
fn make_pages(files: &[PathBuf], dir: &Path) -> Vec<(PathBuf, String)> {
    let work: Vec<(usize, &PathBuf)> = files.iter().enumerate().collect();
    let (a, b) = work.split_at(work.len() / 2);
    let run = |part: &[(usize, &PathBuf)]| -> Vec<(PathBuf, String)> {
        let mut made = Vec::new();
        for &(i, f) in part {
            let name = format!("p{i:03}.html");
            let page = dir.join(&name);
            let out = c3dfix(&["view", s(f), "-o", s(&page)]);
            if out.status.success() {
                made.push((f.clone(), name));
            } else {
                let e = stderr(&out);
                assert_eq!(out.status.code(), Some(2), "{}: {e}", f.display());
                assert!(
                    !e.contains("panicked") && !page.exists(),
                    "{}: {e}",
                    f.display()
                );
            }
        }
        made
    };
    std::thread::scope(|sc| {
        let h = sc.spawn(|| run(a));
        let mut made = run(b);
        made.extend(h.join().expect("view thread"));
        made.sort();
        made
    })
}

/// What a page draws of its file: no model output among its markers (angles, moments and
/// powers stored as points are no positions), and "filled" exactly on the valid samples the
/// file marks as computed (residual 0), none where the writer stores residual 0 for every
/// sample (it marks nothing then). Gives back the samples drawn filled and whether the
/// library knows the lab's up (`None`: no plates and no marker sample, nothing to stand on).
fn draws_markers_and_marked_fills(file: &Path, page: &Path) -> (usize, bool) {
    let c = c3d::read_file(file).unwrap();
    let html = std::fs::read_to_string(page).unwrap();
    let text = |id: &str| {
        let open = format!("<script id=\"{id}\" type=\"");
        let start = html.find(&open).expect("a data block") + open.len();
        let start = start + html[start..].find('>').unwrap() + 1;
        &html[start..start + html[start..].find("</script>").unwrap()]
    };
    let meta: serde_json::Value = serde_json::from_str(text("meta")).expect("meta JSON");
    let labels: Vec<&str> = meta["labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    let outputs = c.model_output_labels();
    let name = file.display();
    for o in &outputs {
        assert!(
            !labels.contains(&o.trim()),
            "{name}: model output {o} drawn"
        );
    }
    // The drawn markers are the file's markers in its order (labels may repeat: by place).
    let all = c.point_labels();
    let drawn = c3dfix::markers::marker_indices(&c);
    let want: Vec<&str> = drawn.iter().map(|&i| all[i].trim()).collect();
    assert_eq!(labels, want, "{name}");
    let flags = unbase64(text("flags"));
    let p = c.points();
    assert_eq!(flags.len(), drawn.len() * p.frames(), "{name}");
    let recorded = (0..p.xyz.len()).any(|k| p.is_valid_at(k) && p.residual[k] > 0.0);
    let mut filled = 0;
    for f in 0..p.frames() {
        for (j, &i) in drawn.iter().enumerate() {
            let k = p.index(f, i);
            let marked = recorded && p.is_valid_at(k) && p.residual[k] == 0.0;
            let shown = flags[f * drawn.len() + j] & 2 != 0;
            assert_eq!(shown, marked, "{name}: {} at frame index {f}", all[i]);
            filled += usize::from(shown);
        }
    }
    (filled, c3dfix::axes::up(&c).is_some())
}

#[test]
fn every_corpus_trials_page_stands_upright() {
    let files = corpus_files();
    if files.is_empty() {
        eprintln!("skipping: no corpus found (set C3D_SAMPLES, C3D_EXTRA, C3D_FULLBODY, C3D_MORE)");
        testkit::skipped("no corpus");
        return;
    }
    let Some(bin) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let t = Instant::now();
    let pages = make_pages(&files, dir.path());
    let made = t.elapsed();
    let mut filled = 0;
    let mut standing = Vec::new();
    for (file, page) in &pages {
        let (n, up) = draws_markers_and_marked_fills(file, &dir.path().join(page));
        filled += n;
        standing.push(up);
    }
    eprintln!("{filled} samples drawn as filled over the corpus, each marked in its file");
    let names: Vec<String> = pages.iter().map(|p| p.1.clone()).collect();
    let index = dir.path().join("index.html");
    std::fs::write(&index, harness(&names)).unwrap();
    let t = Instant::now();
    let dom = run_chromium_for(
        &bin,
        &dir.path().join("profile"),
        &["--virtual-time-budget=100000000", "--dump-dom"],
        &format!("file://{}", index.display()),
        Duration::from_secs(900),
    );
    eprintln!(
        "{} of {} corpus files viewed in {made:?}, their pages' self-tests in {:?}",
        pages.len(),
        files.len(),
        t.elapsed()
    );
    let start = dom.find("<pre id=\"results\">").expect("harness ran") + 18;
    let end = start + dom[start..].find("</pre>").expect("results closed");
    let json = dom[start..end]
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    let results: serde_json::Value = serde_json::from_str(&json).unwrap_or_else(|e| {
        panic!(
            "every page answered ({e}): {}",
            &dom[start..end.min(start + 500)]
        )
    });
    let mut failures = Vec::new();
    let mut worst_below = (0.0, String::new());
    for ((file, page), &up_known) in pages.iter().zip(&standing) {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let r = &results[page.as_str()];
        if r["timeout"] == true || r["errors"] != serde_json::json!([]) {
            failures.push(format!("{name}: {r}"));
            continue;
        }
        if !up_known {
            continue; // no plates and no marker sample: no up to stand on
        }
        let want = expected_up(&name);
        let share = r["screen_up_share"].as_f64().unwrap_or(0.0);
        // Without a marker sample (plates only) there is nothing to put on the floor.
        let below = r["below_floor"].as_f64().unwrap_or(0.0);
        if below > worst_below.0 {
            worst_below = (below, name.clone());
        }
        if r["screen_up"] != want || share < 0.99 || below > MAX_BELOW {
            failures.push(format!("{name} (expected up {want}): {r}"));
        }
    }
    eprintln!(
        "most samples under the floor grid: {:.2} % ({})",
        100.0 * worst_below.0,
        worst_below.1
    );
    assert!(pages.len() >= 100, "{} pages", pages.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
