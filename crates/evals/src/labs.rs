//! The lab a corpus trial comes from, as the evaluations report by lab: constants are
//! chosen on some labs and reported on the others, so a trial's lab is read from where it
//! sits in the corpus, by rule.

use std::path::Path;

/// The lab of an event evaluation's trial `path` of corpus `corpus` (the corpus's folder
/// name) under `root`: each `sample_NN` folder of `c3d-samples`; each `owner` of
/// `c3d-more`'s `owner__repository__trial` names (and the trial's first word for
/// `tsalemink`'s three labs); each owner of `c3d-labs`' names likewise; CMU or numediart in `c3d-fullbody`; BTK for `c3d-extra`.
/// Prefixed by the corpus, as `c3d-samples/sample_00`.
pub fn of_trial(corpus: &str, path: &Path, root: &Path) -> String {
    let rel = path.strip_prefix(root).unwrap_or(path);
    let first = rel
        .components()
        .next()
        .map(|c| c.as_os_str().to_string_lossy().to_string())
        .unwrap_or_default();
    match corpus {
        "c3d-samples" => format!("c3d-samples/{first}"),
        "c3d-more" => {
            let parts: Vec<&str> = first.split("__").collect();
            if parts.first() == Some(&"tsalemink") {
                let trial = parts.get(2).and_then(|t| t.split('_').next()).unwrap_or("");
                format!("c3d-more/tsalemink/{trial}")
            } else {
                format!("c3d-more/{}", parts.first().copied().unwrap_or(""))
            }
        }
        "c3d-labs" => {
            let owner = first.split("__").next().unwrap_or("");
            format!("c3d-labs/{owner}")
        }
        "c3d-fullbody" => {
            if first.starts_with("03_") {
                "c3d-fullbody/numediart".into()
            } else {
                "c3d-fullbody/cmu".into()
            }
        }
        _ => format!("{corpus}/btk"),
    }
}

/// The lab of a trial by its short name (`testkit::short`, as `c3d-samples/sample_00/…`):
/// its folder in `c3d-samples`, its source in `c3d-more` (the part before `__`), else the
/// corpus (`c3d-extra` is BTK's). Unprefixed, as the plate evaluation's table prints it.
pub fn of_short(short: &str) -> String {
    let mut parts = short.split('/');
    match (parts.next(), parts.next()) {
        (Some("c3d-samples"), Some(dir)) => dir.to_string(),
        (Some(_), Some(file)) if file.contains("__") => {
            file.split("__").next().unwrap_or(file).to_string()
        }
        (Some(corpus), _) => corpus.to_string(),
        _ => short.to_string(),
    }
}
