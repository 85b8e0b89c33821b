//! `c3dfix report` in a real browser: the page of a repaired corpus folder loads without a
//! console error, sorts, filters, draws its pictures, shows the numbers `batch --json`
//! printed, links to view pages that exist, and runs nothing a label or file name holds.

use super::view::{chromium, run_chromium_for};
use super::{c3dfix, s, stderr, stdout};
use std::collections::HashMap;
use std::path::Path;
use std::time::Duration;

const HOSTILE_LABEL: &str = "</script><svg onload=window.pwned=1>";
const HOSTILE_NAME: &str = "<svg onload=window.pwned=1>&'\"x.c3d";

/// A copy of `from` named [`HOSTILE_NAME`] in `dir`, its first label [`HOSTILE_LABEL`] with
/// a gap.
fn hostile_copy(from: &Path, dir: &Path) {
    let mut c = c3d::read_file(from).unwrap();
    let mut labels = c.point_labels();
    labels[0] = HOSTILE_LABEL.into();
    c.parameters
        .set_strings("POINT", "LABELS", &labels)
        .unwrap();
    // A gap, so that the label is drawn in the coverage picture.
    let p = c.points_mut();
    for f in 10..20 {
        let k = p.index(f, 0);
        p.residual[k] = -1.0;
    }
    std::fs::write(dir.join(HOSTILE_NAME), c.to_bytes().unwrap()).unwrap();
}

/// The page's self-test (`?selftest=1`) as JSON.
fn selftest(bin: &Path, page: &Path, profile: &Path) -> serde_json::Value {
    let url = format!("file://{}?selftest=1", page.display());
    let dom = run_chromium_for(
        bin,
        profile,
        &["--virtual-time-budget=5000", "--dump-dom"],
        &url,
        Duration::from_secs(180),
    );
    let start = dom.find("<pre id=\"selftest\">").expect("self-test ran") + 19;
    let end = start + dom[start..].find("</pre>").expect("self-test closed");
    let json = dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    serde_json::from_str(&json).expect("self-test JSON")
}

#[test]
fn the_report_page_of_a_repaired_folder_works_in_a_browser() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (out, extra) = (dir.path().join("repaired"), dir.path().join("extra"));
    std::fs::create_dir_all(&extra).unwrap();
    let o = c3dfix(&["batch", s(&more), "--out-dir", s(&out), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Each file's summary as `batch --json` printed it, by file name.
    let batch: HashMap<String, serde_json::Value> = stdout(&o)
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .filter(|v| v.get("file").is_some())
        .map(|v| {
            let name = Path::new(v["file"].as_str().unwrap())
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            (name, v["summary"].clone())
        })
        .collect();
    assert_eq!(batch.len(), 20);
    let small = more.join("tsalemink__C3D-parser__AUC_CB_Dynamic0003.c3d");
    let bytes = std::fs::read(&small).unwrap();
    std::fs::write(extra.join("truncated.c3d"), &bytes[..bytes.len() / 2]).unwrap();
    hostile_copy(&small, &extra);
    let page = dir.path().join("session.html");
    let o = c3dfix(&[
        "report",
        s(&more),
        s(&extra),
        "--repaired",
        s(&out),
        "--views",
        "-o",
        s(&page),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("22 trials:"), "{}", stdout(&o));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(!html.contains("<svg onload"), "raw markup from the data");
    assert!(html.contains("\\u003c/script\\u003e\\u003csvg onload=window.pwned=1\\u003e"));
    // Offline: nothing fetched (the SVG namespace is a name, not an address), and the page's
    // content security policy forbids any fetch.
    let text = html.replace("'http://www.w3.org/2000/svg'", "");
    for bad in ["http://", "https://", "src=", "@import", "url("] {
        assert!(!text.contains(bad), "page contains {bad:?}");
    }
    assert!(html.contains("content=\"default-src 'none'"));
    let Some(bin) = chromium() else { return };
    let r = selftest(&bin, &page, &dir.path().join("profile"));
    assert_eq!(r["errors"], serde_json::json!([]), "{r}");
    assert_eq!(r["ok"], true, "{r}");
    assert_eq!(r["injected"], 0, "{r}");
    assert_eq!(r["rows"], 22, "{r}");
    assert_eq!(r["shown_first_page"], 22, "{r}");
    assert_eq!(r["unreadable_rows"], 1, "{r}");
    assert_eq!(r["sorted_by_name"], true, "{r}");
    assert_eq!(r["sorted_desc_first"], 27567, "{r}");
    // Coverage, force and fill pictures of c3d-more's trials (pyCGM's and the puppeteer's
    // unlabelled points are no markers with gaps to draw, issue 47).
    assert!(r["pictures"].as_u64().unwrap() >= 30, "{r}");
    // Every row's numbers are batch's.
    let table = r["table"].as_array().unwrap();
    let mut compared = 0;
    for row in table {
        let Some(b) = batch.get(row["name"].as_str().unwrap()) else {
            continue;
        };
        assert_eq!(row["filled"], b["filled"], "{row}");
        assert_eq!(row["left"], b["left"], "{row}");
        assert_eq!(row["markers"], b["markers"], "{row}");
        for k in ["too_long", "uncertain", "no_donors"] {
            let want = b["left_because"]
                .get(k)
                .and_then(|v| v.as_u64())
                .unwrap_or(0);
            assert_eq!(row[k], want, "{k}: {row}");
        }
        compared += 1;
    }
    assert_eq!(compared, 20);
    // Every readable trial links to its view page, and every link resolves.
    let links = r["links"].as_array().unwrap();
    assert_eq!(links.len(), 21, "{r}");
    for l in links {
        let rel = l.as_str().unwrap();
        let decoded = rel.replace("%20", " ");
        assert!(
            dir.path().join(&decoded).is_file(),
            "{rel} does not resolve"
        );
    }
}

/// The report data a page holds (its JSON block, read back as the browser reads it).
fn page_data(html: &str) -> serde_json::Value {
    let open = "<script id=\"data\" type=\"application/json\">";
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").expect("data closed");
    serde_json::from_str(&html[start..end]).expect("data JSON")
}

#[test]
fn batch_report_html_shows_each_repairs_own_numbers() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (out, page) = (dir.path().join("out"), dir.path().join("batch.html"));
    let o = c3dfix(&[
        "batch",
        s(&more),
        "--out-dir",
        s(&out),
        "--json",
        "--report-html",
        s(&page),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let lines: Vec<serde_json::Value> = stdout(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .filter(|v: &serde_json::Value| v.get("file").is_some())
        .collect();
    let data = page_data(&std::fs::read_to_string(&page).unwrap());
    let rows = data["report"]["trials"].as_array().unwrap();
    assert_eq!(rows.len(), 20);
    assert_eq!(lines.len(), 20);
    for row in rows {
        // Lines come as the files finish; rows in the plan's order.
        let line = lines.iter().find(|l| l["file"] == row["file"]).unwrap();
        let sum = &line["summary"];
        assert_eq!(row["repair_source"], "summary");
        assert_eq!(row["repaired"], sum["output"]);
        for k in ["filled", "left", "left_because", "spikes", "markers"] {
            assert_eq!(row[k], sum[k], "{k}: {}", row["name"]);
        }
        assert_eq!(
            row["expected_error_mm_max"].as_f64(),
            sum["expected_error_mm_max"].as_f64(),
            "{}",
            row["name"]
        );
        assert_eq!(
            row["swaps_found"],
            sum["swap_list"].as_array().map_or(0, Vec::len)
        );
    }
    // Labelled markers only (issue 47): pyCGM's and the puppeteer's unlabelled points are
    // no longer filled.
    assert_eq!(data["report"]["summary"]["filled"], 655);
    assert_eq!(data["report"]["summary"]["swaps_found"], 3);
    // A page is never written over an input, and an existing one only with --force.
    let o = c3dfix(&[
        "batch",
        s(&more),
        "--out-dir",
        s(&out),
        "--report-html",
        s(&page),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("exists"), "{}", stderr(&o));
}

#[test]
fn report_asks_for_an_output_and_draws_no_bar_when_piped() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let o = c3dfix(&["report", s(&more)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("-o REPORT.html, --json"),
        "{}",
        stderr(&o)
    );
    let o = c3dfix(&["report", s(&more), "--json", "--views"]);
    assert_eq!(o.status.code(), Some(2), "views need a page beside them");
    let page = dir.path().join("p.html");
    let o = c3dfix(&["report", s(&more), "-o", s(&page)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Standard error is a pipe here: no progress bar, nothing at all.
    assert_eq!(stderr(&o), "");
    assert!(stdout(&o).starts_with("20 trials: "), "{}", stdout(&o));
    // The page is never written over a trial it reads, force or not.
    let trial = more.join("tsalemink__C3D-parser__AUC_CB_Dynamic0003.c3d");
    let o = c3dfix(&["report", s(&more), "-o", s(&trial), "--force"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("is the input file"), "{}", stderr(&o));
}
