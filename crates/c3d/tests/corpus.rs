//! Every file of both real corpora: read succeeds (or the file is in the documented refused
//! list, with the expected error), and rewriting gives back the same bytes.

use std::path::Path;

/// Files that are refused, with a fragment of the expected error.
const REFUSED: &[(&str, &str)] = &[("btkdata_Empty.c3d", "file is 0 bytes")];

fn refused(p: &Path) -> Option<&'static str> {
    let name = p.file_name()?.to_string_lossy().to_string();
    REFUSED.iter().find(|(f, _)| *f == name).map(|(_, e)| *e)
}

#[test]
fn every_corpus_file_reads_and_rewrites_byte_identically() {
    let files = testkit::all_c3d_files();
    if files.is_empty() {
        return;
    }
    let mut failures = Vec::new();
    let mut read_ok = 0;
    for f in &files {
        let name = testkit::short(f);
        let bytes = std::fs::read(f).expect("read corpus file");
        match (c3d::read(bytes.clone()), refused(f)) {
            (Ok(c), None) => {
                read_ok += 1;
                match c.to_bytes() {
                    Ok(out) if out == bytes => {}
                    Ok(out) => {
                        let first = out.iter().zip(&bytes).position(|(a, b)| a != b);
                        failures.push(format!(
                            "{name}: rewrite differs (len {} vs {}, first difference at {first:?})",
                            out.len(),
                            bytes.len()
                        ))
                    }
                    Err(e) => failures.push(format!("{name}: rewrite failed: {e}")),
                }
            }
            (Ok(_), Some(_)) => failures.push(format!("{name}: expected to be refused but read")),
            (Err(e), Some(frag)) => {
                assert!(e.to_string().contains(frag), "{name}: {e}");
            }
            (Err(e), None) => failures.push(format!("{name}: read failed: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(read_ok >= 88, "only {read_ok} files read");
}
