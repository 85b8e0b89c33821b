//! Running one job per file on a pool of threads, for `batch` and `convert`: a failure is
//! kept with its file and the others go on; progress shows on a terminal; with `--json` each
//! file's line is printed as soon as it is done, so a killed run still leaves a record of
//! what it finished.

use anyhow::Result;
use c3dfix::targets::Target;
use std::io::{IsTerminal, Write};
use std::sync::Mutex;

/// Run `work` on every target with `jobs` threads (None: one per core). With `json`, each
/// file's line is `{"file", "ok": true, key: result}` or `{"file", "ok": false, "error"}`;
/// otherwise failures are printed as they come. Results come back in the targets' order,
/// errors as their full message.
pub fn run_each<T, W>(
    targets: &[Target],
    jobs: Option<c3dfix::Jobs>,
    json: bool,
    work: W,
    key: &str,
) -> Result<Vec<Result<T, String>>>
where
    T: Send + serde::Serialize,
    W: Fn(&Target) -> Result<T> + Sync,
{
    let line = |t: &Target, r: &Result<T, String>| {
        let file = t.input.display().to_string();
        match r {
            Ok(v) => serde_json::json!({"file": file, "ok": true, key: v}),
            Err(e) => serde_json::json!({"file": file, "ok": false, "error": e}),
        }
    };
    let bar = (!json && std::io::stderr().is_terminal()).then(|| {
        let b = indicatif::ProgressBar::new(targets.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    // One writer at a time, so lines from parallel jobs never interleave.
    let out_lock = Mutex::new(());
    let results = jobs.unwrap_or_default().each(targets, |t| {
        let r = work(t).map_err(|e| crate::console::describe(&e));
        let _guard = out_lock.lock();
        if json {
            let mut so = std::io::stdout().lock();
            let _ = writeln!(so, "{}", line(t, &r));
        } else if let Err(e) = &r {
            match &bar {
                Some(b) => b.println(format!("failed: {e}")),
                None => crate::console::errln!("failed: {e}"),
            }
        }
        if let Some(b) = &bar {
            b.set_message(crate::output::file_name(&t.input));
            b.inc(1);
        }
        r
    })?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    Ok(results)
}
