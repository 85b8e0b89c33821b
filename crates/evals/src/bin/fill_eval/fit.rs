//! The expected-error model's fit: its features, the weighted regression, the calibration
//! of the estimates, and the ablation of each feature.

use super::*;

use evals::fit::{Model, Sample, FEATURE_NAMES};

/// Number of features.
pub(crate) const K: usize = repair::fill::FEATURES;

/// `auto`'s gaps with evidence as the fit takes them (see [`evals::fit::fit`]).
pub(crate) fn samples<'a>(gs: &[(&'a str, &GapScore)]) -> Vec<Sample<'a>> {
    gs.iter()
        .filter_map(|(lab, g)| {
            Some(Sample {
                lab,
                evidence: g.evidence?,
                error: g.mean,
            })
        })
        .collect()
}

/// The expected-error model fitted on `gs` (see [`evals::fit::fit`]).
pub(crate) fn fit(gs: &[(&str, &GapScore)]) -> Option<Model> {
    evals::fit::fit(&samples(gs))
}

/// [`fit()`] with only the features of `mask` (the others' weights stay 0).
pub(crate) fn fit_masked(gs: &[(&str, &GapScore)], mask: &[bool; K]) -> Option<Model> {
    evals::fit::fit_masked(&samples(gs), mask)
}

/// The shipped model's fit written where `repair` reads it (`--write-coefficients`): every
/// lab's `auto` gaps, tuned and held apart, into the compact gaps file, then the model
/// fitted on that file as read back into the generated source, so that the
/// `coefficients` test, which fits the same file, gets the same numbers.
pub(crate) fn write_coefficients(recs: &[Rec], source: &str) -> Result<(), String> {
    let all: Vec<(&str, &GapScore)> = recs
        .iter()
        .filter(|r| (r.held || r.tuned) && r.g.method == FillMethod::Auto)
        .map(|r| (r.lab, &r.g))
        .collect();
    let header = format!(
        "The artificial gaps `auto` filled in `fill_eval`'s run over every lab (tuned and held\n\
         apart), which `repair`'s expected-error model is fitted on: one line per gap, grouped\n\
         by lab (see `evals::fit::read`). Written by `fill_eval -- --replay RECORDS\n\
         --write-coefficients` from {source}."
    );
    let text = evals::fit::write(&samples(&all), &header);
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = crate_dir.join(evals::fit::GAPS_FILE);
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {}", path.display());
    refit()
}

/// The model fitted on the committed gaps file, written into the generated source
/// (`--refit`, and the last step of `--write-coefficients`).
pub(crate) fn refit() -> Result<(), String> {
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = crate_dir.join(evals::fit::GAPS_FILE);
    let text = std::fs::read_to_string(&input).map_err(|e| format!("{}: {e}", input.display()))?;
    let gaps = evals::fit::read(&text).map_err(|e| format!("{}: {e}", input.display()))?;
    let m = evals::fit::fit(&gaps.samples())
        .ok_or(format!("{}: too few gaps to fit", input.display()))?;
    let out = crate_dir.join(evals::fit::SOURCE_FILE);
    std::fs::write(
        &out,
        evals::fit::render(&m, gaps.gaps.len(), gaps.labs.len()),
    )
    .map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!(
        "wrote {} ({} gaps of {} labs): c1 {:.6}, c0 {:.6}",
        out.display(),
        gaps.gaps.len(),
        gaps.labs.len(),
        m.c1,
        m.c0
    );
    Ok(())
}

/// Each feature of the expected-error model left out in turn: the model judged
/// leave-one-lab-out on the tuned labs (each lab by a fit to the others, the margin chosen
/// inside that fit as always), which decides whether a feature pays, and the model fitted
/// on all tuned labs judged on the held-apart labs, which reports it.
pub(crate) fn ablation(recs: &[Rec]) {
    use rayon::prelude::*;
    let tuned: Vec<(&str, &GapScore)> = recs
        .iter()
        .filter(|r| r.tuned && r.g.method == FillMethod::Auto)
        .map(|r| (r.lab, &r.g))
        .collect();
    let held: Vec<&GapScore> = recs
        .iter()
        .filter(|r| r.held && r.g.method == FillMethod::Auto)
        .map(|r| &r.g)
        .collect();
    let mut labs: Vec<&str> = tuned.iter().map(|r| r.0).collect();
    labs.sort_unstable();
    labs.dedup();
    let start = [true; K];
    let variants: Vec<Option<usize>> = std::iter::once(None)
        .chain((1..K).filter(|&k| start[k]).map(Some))
        .collect();
    let rows: Vec<String> = variants
        .par_iter()
        .map(|&out| {
            let mut mask = start;
            if let Some(k) = out {
                mask[k] = false;
            }
            let mut lolo = Vec::new();
            for lab in &labs {
                let train: Vec<(&str, &GapScore)> =
                    tuned.iter().filter(|r| r.0 != *lab).copied().collect();
                if let Some(m) = fit_masked(&train, &mask) {
                    lolo.extend(tuned.iter().filter(|r| r.0 == *lab).map(|r| GapScore {
                        expected: predict(r.1, &m).or(r.1.expected),
                        ..*r.1
                    }));
                }
            }
            let a = calibration(&lolo, 0.0);
            let h = fit_masked(&tuned, &mask).map(|m| {
                let v: Vec<GapScore> = held
                    .iter()
                    .map(|g| GapScore {
                        expected: predict(g, &m).or(g.expected),
                        ..**g
                    })
                    .collect();
                calibration(&v, 0.0)
            });
            let name = out.map_or("(none)", |k| FEATURE_NAMES[k]);
            format!(
                "| {name} | {:.3} | {:.1} | {:.1} | {} |",
                a.spearman,
                100.0 * a.within_2x,
                100.0 * a.over_confident,
                h.map_or("–".into(), |h| format!(
                    "{:.3} | {:.1} | {:.1}",
                    h.spearman,
                    100.0 * h.within_2x,
                    100.0 * h.over_confident
                ))
            )
        })
        .collect();
    println!("\n### expected-error model: each feature left out\n");
    println!("| left out | tuned LOLO Spearman | within 2x % | over % | held apart Spearman | within 2x % | over % |");
    println!("|---|---|---|---|---|---|---|");
    rows.iter().for_each(|r| println!("{r}"));
}

/// `g`'s expected error under `m` (`None` without evidence).
pub(crate) fn predict(g: &GapScore, m: &Model) -> Option<f64> {
    Some(m.expected(&g.evidence?))
}

/// The expected-error model fitted leave-one-lab-out: each lab's gaps are estimated by a
/// model fitted on the other labs only.
pub(crate) fn calibrate(recs: &[Rec]) {
    let auto: Vec<&Rec> = recs
        .iter()
        .filter(|r| r.g.method == FillMethod::Auto)
        .collect();
    let out = left_out(&auto);
    let show = |name: &str, v: Vec<GapScore>| {
        println!(
            "{}",
            calibration_line(&format!("{name}, model fitted leave-one-lab-out"), &v)
        );
    };
    show("all", out.iter().map(|x| x.1).collect());
    for set in ["walking", "fullbody"] {
        show(
            set,
            out.iter().filter(|x| x.0.set == set).map(|x| x.1).collect(),
        );
    }
}

/// `auto`'s gaps of every lab in `auto`, each with the expected error of the model fitted to
/// the other labs' gaps (a lab whose fit fails is left out; a gap without evidence keeps
/// its prior).
pub(crate) fn left_out<'a>(auto: &[&'a Rec]) -> Vec<(&'a Rec, GapScore)> {
    use rayon::prelude::*;
    let mut labs: Vec<&str> = auto.iter().map(|r| r.lab).collect();
    labs.sort_unstable();
    labs.dedup();
    labs.par_iter()
        .flat_map_iter(|lab| {
            let train: Vec<(&str, &GapScore)> = auto
                .iter()
                .filter(|r| r.lab != *lab)
                .map(|r| (r.lab, &r.g))
                .collect();
            let model = fit(&train);
            auto.iter()
                .filter(|r| r.lab == *lab)
                .filter_map(|r| {
                    // A gap without evidence keeps its prior (see `repair`'s `prior`).
                    let expected = predict(&r.g, &model?).or(r.g.expected);
                    Some((*r, GapScore { expected, ..r.g }))
                })
                .collect::<Vec<_>>()
        })
        .collect()
}
