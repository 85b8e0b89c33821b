//! The expected-error model `auto` ships is the fit of the committed gaps file: the fit is
//! run again on that file and its coefficients must be the generated source's, so no
//! coefficient is pasted by hand or left behind by a change to the fit or the features.

use std::path::Path;
use std::sync::OnceLock;

use evals::fit::{self, Gaps, Model, GAPS_FILE, REFIT, SOURCE_FILE};

/// The committed gaps and the model fitted on them, once for every test (the fit takes a
/// second or two).
fn committed() -> &'static (Gaps, Model) {
    static FITTED: OnceLock<(Gaps, Model)> = OnceLock::new();
    FITTED.get_or_init(fit_committed)
}

fn fit_committed() -> (Gaps, Model) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = dir.join(GAPS_FILE);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let gaps = fit::read(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let model = fit::fit(&gaps.samples()).expect("the committed gaps are enough to fit");
    (gaps, model)
}

/// Numbers in a line of source, and the line with each replaced by `#`.
fn split_numbers(line: &str) -> (String, Vec<f64>) {
    let mut text = String::new();
    let mut nums = Vec::new();
    for tok in line.split_inclusive([' ', ',', ';', '[', ']']) {
        let core = tok.trim_end_matches([' ', ',', ';', '[', ']']);
        match core.parse::<f64>() {
            Ok(v) if core.contains('.') => {
                nums.push(v);
                text.push('#');
                text.push_str(&tok[core.len()..]);
            }
            _ => text.push_str(tok),
        }
    }
    (text, nums)
}

#[test]
fn generated_coefficients_are_the_fit_of_the_committed_gaps() {
    let (gaps, model) = committed();
    let want = fit::render(model, gaps.gaps.len(), gaps.labs.len());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SOURCE_FILE);
    let have = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let stale = format!(
        "{} is not what the fit makes of {GAPS_FILE}: run `{REFIT}`",
        path.display()
    );
    let (want, have): (Vec<&str>, Vec<&str>) = (want.lines().collect(), have.lines().collect());
    assert_eq!(want.len(), have.len(), "{stale}");
    // The text exactly; the numbers to 1e-6 beyond their six printed decimals, so that a
    // last digit rounded the other way by another platform's `exp` or `ln` is no failure.
    for (w, h) in want.iter().zip(&have) {
        let (wt, wn) = split_numbers(w);
        let (ht, hn) = split_numbers(h);
        assert_eq!(wt, ht, "{stale}");
        assert_eq!(wn.len(), hn.len(), "{stale}");
        for (a, b) in wn.iter().zip(&hn) {
            assert!((a - b).abs() <= 2e-6, "{stale}: {w} against {h}");
        }
    }
}

#[test]
fn the_fit_holds_its_gaps_within_twice_their_estimate() {
    let (gaps, model) = committed();
    assert!(gaps.labs.len() >= 20, "{} labs", gaps.labs.len());
    assert!(gaps.gaps.len() >= 20_000, "{} gaps", gaps.gaps.len());
    let ratios: Vec<f64> = gaps
        .samples()
        .iter()
        .map(|g| g.error / model.expected(&g.evidence))
        .collect();
    let n = ratios.len() as f64;
    let within = ratios.iter().filter(|r| (0.5..=2.0).contains(*r)).count() as f64 / n;
    let over = ratios.iter().filter(|&&r| r > 2.0).count() as f64 / n;
    println!("within 2x {within:.4}, above twice {over:.4}");
    // The margin is set on labs the regression never saw, so the gaps it was fitted on sit
    // inside the limit on gaps above twice their estimate. Within 2x: the older corpora's
    // labs hold 81 %; `c3d-labs`' trials (drop jumps, lifts, sprints, a sit-to-stand, 11
    // labs) spread wider, 74 % within 2x judged each lab apart, and bring all 36 labs to
    // 78.9 % on the fit's own gaps (docs/fill-evaluation.md, "With c3d-labs"); with the
    // method leading the fill and the speed beside the gap, 79.4 % and 3.9 % ("Issue 45
    // item 7, third round").
    assert!(within >= 0.78, "within 2x: {within:.3}");
    assert!(over <= 0.05, "above twice: {over:.3}");
}

#[test]
fn auto_uses_the_generated_coefficients() {
    let (gaps, model) = committed();
    // `calibrated` reads the generated file, whose numbers are the fit's to six decimals.
    for g in gaps.samples().iter().step_by(97) {
        let shipped = repair::fill::calibrated(&g.evidence);
        let fitted = model.expected(&g.evidence);
        assert!(
            (shipped / fitted - 1.0).abs() < 1e-3,
            "{}: calibrated {shipped} against the fit's {fitted}",
            g.lab
        );
    }
}
