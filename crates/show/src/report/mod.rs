//! The session report page (`c3dfix report`, `batch --report-html`, Python's
//! `c3dfix.report`): one self-contained HTML file — data, code and styles inlined, nothing
//! fetched — that shows [`c3dfix::report::SessionReport`] as a summary and a sortable,
//! filterable table, one row per trial, with its pictures drawn small on demand; and, with
//! views, each trial's viewer page in a folder beside it.
//!
//! The data go into a JSON script block with `<`, `>` and `&` escaped, and the page's code
//! puts every value into the page as text, never as markup: a marker label or a file name
//! cannot end the script block nor run anything. The table shows 50 rows a page, so a
//! thousand trials open as fast as fifty.

use crate::view::{escape_html, file_page, fill, script_json};
use crate::Result;
use c3dfix::report::SessionReport;
use serde::Serialize;
use std::path::{Path, PathBuf};

const TEMPLATE: &str = include_str!("report.html");
const SCRIPT: &str = include_str!("report.js");

/// What the page says besides the report.
#[derive(Serialize)]
struct Meta<'a> {
    title: &'a str,
    /// The folder of the view pages, relative to the report.
    views_dir: &'a str,
}

#[derive(Serialize)]
struct Data<'a> {
    meta: Meta<'a>,
    report: &'a SessionReport,
}

/// The folder the view pages of the report at `out` go in: `NAME_views` beside it.
pub fn views_dir(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "report".into());
    out.with_file_name(format!("{stem}_views"))
}

/// The report page of `report`, titled `title`; view links point into `views_dir` (a
/// folder name relative to the page).
pub fn page(report: &SessionReport, title: &str, views_dir: &str) -> Result<String> {
    let data = Data {
        meta: Meta { title, views_dir },
        report,
    };
    let fields = [
        ("TITLE", escape_html(title)),
        ("DATA", script_json(&data)?),
        ("SCRIPT", SCRIPT.to_string()),
    ];
    Ok(fill(TEMPLATE, &fields))
}

/// Write the view page of every row that names one (see [`c3dfix::report::ReportOptions`])
/// into [`views_dir`]`(out)`, in parallel, each atomically: the repaired copy drawn over the
/// trial as recorded when there is one, else the trial. A page that cannot be made leaves
/// its row without a link and says why among the row's warnings. `force` replaces existing
/// pages. Returns how many pages were written.
pub fn write_views(report: &mut SessionReport, out: &Path, force: bool) -> Result<usize> {
    use rayon::prelude::*;
    let dir = views_dir(out);
    if report.trials.iter().any(|r| r.view.is_some()) {
        std::fs::create_dir_all(&dir).map_err(|e| {
            c3dfix::Error::Output(format!("cannot create the folder {}: {e}", dir.display()))
        })?;
    }
    let written = forkpool::install(|| {
        report
            .trials
            .par_iter_mut()
            .filter(|r| r.view.is_some())
            .map(|r| {
                let name = r.view.clone().unwrap_or_default();
                match view_of(r, &dir.join(&name), force) {
                    Ok(()) => 1,
                    Err(e) => {
                        r.view = None;
                        r.warnings.push(format!("no view page: {e}"));
                        0
                    }
                }
            })
            .sum()
    });
    Ok(written)
}

/// The view page of one row, written to `to`.
fn view_of(r: &c3dfix::report::TrialRow, to: &Path, force: bool) -> Result<()> {
    let input = Path::new(&r.file);
    let c = c3dfix::open_mapped(input)?;
    let copy = match &r.repaired {
        Some(p) if r.repaired_error.is_none() => Some((c3dfix::open_mapped(p)?, PathBuf::from(p))),
        _ => None,
    };
    let html = match &copy {
        Some((rc, path)) => {
            let name = file_name(path);
            file_page(
                rc,
                path,
                &name,
                Some((&c, &r.name)),
                None,
                false,
                &mut |_| {},
            )?
        }
        None => file_page(&c, input, &r.name, None, None, false, &mut |_| {})?,
    };
    c3dfix::save::write_atomic(to, html.as_bytes(), force)?;
    Ok(())
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}

/// Write `report` as a page to `out` (atomically; an existing file only with `force`), after
/// its view pages when its rows name them. Every file the report reads is refused as `out`.
pub fn write(report: &mut SessionReport, out: &Path, force: bool) -> Result<()> {
    let inputs: Vec<&Path> = report
        .trials
        .iter()
        .flat_map(|r| std::iter::once(r.file.as_str()).chain(r.repaired.as_deref()))
        .map(Path::new)
        .collect();
    c3dfix::save::refuse_input(out, &inputs, "the report")?;
    c3dfix::save::check_destination(out, force)?;
    write_views(report, out, force)?;
    let dir = views_dir(out);
    let dir_name = file_name(&dir);
    let title = file_name(out);
    let html = page(report, &title, &dir_name)?;
    c3dfix::save::write_atomic(out, html.as_bytes(), force)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use c3dfix::report::TrialRow;

    #[test]
    fn hostile_text_stays_inside_the_data_block() {
        let rep = SessionReport {
            summary: Default::default(),
            trials: vec![TrialRow {
                file: "a/</script><svg onload=alert(1)>&\"'.c3d".into(),
                name: "</script><svg onload=alert(1)>&\"'.c3d".into(),
                problem: Some("<!-- <script>".into()),
                ..TrialRow::default()
            }],
        };
        let html = page(&rep, "<b>t</b>", "x_views").unwrap();
        assert!(!html.contains("<svg onload"), "raw markup leaked");
        assert!(!html.contains("<!-- <script>"));
        assert!(html.contains("\\u003c/script\\u003e\\u003csvg onload=alert(1)\\u003e"));
        assert!(html.contains("<title>&lt;b&gt;t&lt;/b&gt; — c3dfix report</title>"));
        // One data block, closed once.
        assert_eq!(html.matches("</script>").count(), 2);
    }
}
