//! The evaluation's tables: per set, length and method; the held-apart labs; every lab left
//! out; the worst cells; the nested leave-one-lab-out choice among variants.

use super::*;
use evals::stats::rank;

/// The shipped expected-error model (the one `repair` applies) on the held-apart labs'
/// `auto` gaps of this run, inside the trial or at its ends: how often the truth is within
/// 2× of the estimate or above twice it, and what `--max-expected-error` leaves. The model
/// was fitted on gaps inside trials only, so on gaps at a trial's end these figures are
/// what it gives a kind of gap it never saw; inside, the held-apart labs were among those
/// it was fitted on (the full run's leave-one-lab-out lines are the fair figure there).
pub(crate) fn shipped_on_held_apart(recs: &[Rec], ends: bool) {
    let place = if ends {
        "at a trial's start or end"
    } else {
        "inside the trial"
    };
    println!("\n### held apart, gaps {place}: the shipped expected-error model\n");
    for set in ["all", "walking", "fullbody"] {
        let v: Vec<GapScore> = recs
            .iter()
            .filter(|r| r.held && r.g.method == FillMethod::Auto)
            .filter(|r| set == "all" || r.set == set)
            .map(|r| r.g)
            .collect();
        println!("{}", calibration_line(&format!("{set}, {place}"), &v));
        println!("{}", catastrophic_line(&format!("{set}, {place}"), &v));
        if set == "all" {
            for limit in [15.0, 20.0, 30.0] {
                println!(
                    "{}",
                    limit_line(&format!("gaps {place}, the shipped model"), limit, &v)
                );
            }
        }
    }
}

/// A cell of the nested tables: set, markers (1; 2 for 2–3) and gap length.
type Cell = (&'static str, usize, usize);
/// Per lab and cell, the sum and count of `auto`'s mean errors.
type Sums<'a> = BTreeMap<(&'a str, Cell), (f64, usize)>;

/// Each variant's [`Sums`] over the gaps every variant ran. A variant run on some lengths
/// only (`--lengths`: a choice that cannot touch gaps of other lengths, such as the length a
/// candidate enters from) stands for the shipped variant at the lengths it did not run: the
/// gaps are the same, so are the fills.
fn variant_sums(variants: &[Vec<Rec>]) -> Vec<Sums<'_>> {
    let common = common_gaps(variants);
    let mut sums: Vec<Sums> = variants
        .iter()
        .zip(&common)
        .map(|(recs, keep)| {
            let mut m: BTreeMap<(&str, Cell), (f64, usize)> = BTreeMap::new();
            for (r, _) in recs
                .iter()
                .zip(keep)
                .filter(|(r, &k)| k && (r.held || r.tuned))
            {
                let e = m.entry((r.lab, (r.set, r.group, r.g.gap_len))).or_default();
                e.0 += r.g.mean;
                e.1 += 1;
            }
            m
        })
        .collect();
    let shipped = sums[0].clone();
    for s in sums.iter_mut().skip(1) {
        let ran: Vec<usize> = s.keys().map(|k| k.1 .2).collect();
        for (k, v) in &shipped {
            if !ran.contains(&k.1 .2) {
                s.insert(*k, *v);
            }
        }
    }
    sums
}

/// One row per set and markers: `ratio` of each cell, over the lengths.
fn cell_rows(labels: &str, ratio: &dyn Fn(Cell) -> Option<f64>) {
    for set in ["walking", "fullbody"] {
        for group in [1, 2] {
            let row: Vec<String> = LENGTHS
                .iter()
                .map(|&len| ratio((set, group, len)).map_or("–".into(), |r| format!("{r:.3}")))
                .collect();
            println!(
                "| {labels} | {set} | {} | {} |",
                if group == 1 { "one" } else { "2–3" },
                row.join(" / ")
            );
        }
    }
}

/// A choice of `auto`'s made leave-one-lab-out: `variants` are the records of full runs
/// that differ in that choice only (the shipped variant first). For each lab, the variant
/// is chosen on every other lab (the lowest mean over cells, set × markers × length, of
/// the log of its mean error over the shipped variant's) and that lab's gaps are reported
/// under it: the figures the choice earns on a lab it was not made on. Prints how many
/// labs' folds chose each variant, and the nested pooled errors of the held-apart and
/// the tuned labs against the shipped variant's.
pub(crate) fn nested(paths: &[PathBuf], variants: &[Vec<Rec>]) {
    let sums = variant_sums(variants);
    let held_lab: BTreeMap<&str, bool> = variants[0]
        .iter()
        .filter(|r| r.held || r.tuned)
        .map(|r| (r.lab, r.held))
        .collect();
    let cells: Vec<Cell> = {
        let mut c: Vec<Cell> = sums[0].keys().map(|k| k.1).collect();
        c.sort_unstable();
        c.dedup();
        c
    };
    let pooled = |v: usize, keep: &dyn Fn(&str) -> bool, cell: Cell| {
        let (s, n) = sums[v]
            .iter()
            .filter(|((lab, c), _)| *c == cell && keep(lab))
            .fold((0.0, 0), |a, (_, x)| (a.0 + x.0, a.1 + x.1));
        (n > 0).then(|| s / n as f64)
    };
    let mut chosen: BTreeMap<&str, usize> = BTreeMap::new();
    for &lab in held_lab.keys() {
        let others = |l: &str| l != lab;
        let score = |v: usize| {
            let r: Vec<f64> = cells
                .iter()
                .filter_map(|&c| Some((pooled(v, &others, c)? / pooled(0, &others, c)?).ln()))
                .collect();
            r.iter().sum::<f64>() / r.len().max(1) as f64
        };
        let best = (0..variants.len())
            .map(|v| (score(v), v))
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
        chosen.insert(lab, best.1);
    }
    println!(
        "
### nested leave-one-lab-out choice among {} variants

Compared on {} of the shipped run's {} gaps (those every variant ran).
",
        variants.len(),
        sums[0].values().map(|x| x.1).sum::<usize>(),
        variants[0]
            .iter()
            .filter(|r| (r.held || r.tuned) && r.g.method == FillMethod::Auto)
            .count()
    );
    for (v, p) in paths.iter().enumerate() {
        let labs: Vec<&str> = chosen.iter().filter(|x| *x.1 == v).map(|x| *x.0).collect();
        println!(
            "- {}{}: chosen in {} of {} folds ({})",
            p.display(),
            if v == 0 { " (shipped)" } else { "" },
            labs.len(),
            chosen.len(),
            labs.join(", ")
        );
    }
    println!(
        "
| labs | set | markers | nested ÷ shipped at 5 / 10 / 20 / 40 / 80 frames |"
    );
    println!("|---|---|---|---|");
    for (part, held) in [("held apart", true), ("tuned", false)] {
        cell_rows(part, &|cell| {
            let (mut nest, mut ship, mut n) = (0.0, 0.0, 0usize);
            for (&lab, &v) in &chosen {
                if held_lab[lab] != held {
                    continue;
                }
                if let (Some(a), Some(b)) = (sums[v].get(&(lab, cell)), sums[0].get(&(lab, cell))) {
                    nest += a.0;
                    ship += b.0;
                    n += 1;
                }
            }
            (n > 0).then(|| nest / ship)
        });
    }
    // What each variant does on its own, pooled like the table above: how much it would
    // have gained or lost had it shipped, on the labs of each part.
    println!(
        "
| variant | labs | set | markers | variant ÷ shipped at 5 / 10 / 20 / 40 / 80 frames |"
    );
    println!("|---|---|---|---|---|");
    for (v, p) in paths.iter().enumerate().skip(1) {
        let name = p
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into());
        for (part, held) in [("held apart", true), ("tuned", false)] {
            let keep = |l: &str| held_lab.get(l) == Some(&held);
            cell_rows(&format!("{name} | {part}"), &|cell| {
                Some(pooled(v, &keep, cell)? / pooled(0, &keep, cell)?)
            });
        }
    }
}

/// Which of `auto`'s records `--nested` compares: a gap is kept when every variant that ran
/// its length holds it. A variant run on fewer gaps (`--gaps N`: each length's first N, as
/// the gaps are drawn one after another from the length's own seed) is compared on those,
/// and the shipped run's other gaps are left out of every variant's cells rather than stand
/// in for it (which would pull its ratios towards 1). Lengths a variant did not run
/// (`--lengths`) are left to the shipped run as before.
///
/// A gap is known by its trial, run (1, 2 or 3 markers), length, marker, first frame and
/// how many gaps of its run and length had those before it (runs of 2 and 3 markers start
/// from the same draw, and a long run draws a place again now and then). Records written
/// before the run was kept are in the order the runs drew them, so the run is then
/// counted from the record order.
pub(crate) fn common_gaps(variants: &[Vec<Rec>]) -> Vec<Vec<bool>> {
    use std::collections::BTreeSet;
    type Key = (String, usize, usize, usize, usize, usize);
    // Each variant's lengths, and each of its records' key (`None`: not auto).
    let keyed: Vec<(BTreeSet<usize>, Vec<Option<Key>>)> = variants
        .iter()
        .map(|recs| {
            let mut lengths = BTreeSet::new();
            // Per (trial, group, length): the runs seen so far, for records without one.
            let mut runs: HashMap<(&str, usize, usize), usize> = HashMap::new();
            let mut seen: HashMap<Key, usize> = HashMap::new();
            let mut prev = None;
            let keys = recs
                .iter()
                .map(|r| {
                    if r.g.method != FillMethod::Auto {
                        return None;
                    }
                    let block = (r.file.as_str(), r.group, r.g.gap_len);
                    let run = if r.run > 0 {
                        r.run
                    } else {
                        let n = runs.entry(block).or_insert(0);
                        if prev != Some(block) {
                            *n += 1;
                        }
                        *n
                    };
                    prev = Some(block);
                    lengths.insert(r.g.gap_len);
                    let mut k = (r.file.clone(), run, r.g.gap_len, r.g.marker, r.g.first, 0);
                    let nth = seen.entry(k.clone()).or_insert(0);
                    k.5 = *nth;
                    *nth += 1;
                    Some(k)
                })
                .collect();
            (lengths, keys)
        })
        .collect();
    let sets: Vec<(&BTreeSet<usize>, HashSet<&Key>)> = keyed
        .iter()
        .map(|(l, k)| (l, k.iter().flatten().collect()))
        .collect();
    keyed
        .iter()
        .map(|(_, keys)| {
            keys.iter()
                .map(|k| {
                    k.as_ref().is_some_and(|k| {
                        sets.iter()
                            .all(|(lengths, set)| !lengths.contains(&k.2) || set.contains(k))
                    })
                })
                .collect()
        })
        .collect()
}

pub(crate) fn mean(v: impl Iterator<Item = f64>) -> (f64, usize) {
    let (mut s, mut n) = (0.0, 0);
    for x in v {
        s += x;
        n += 1;
    }
    (if n > 0 { s / n as f64 } else { f64::NAN }, n)
}

/// Pooled tables: rows (set or rate) × group, columns gap lengths; auto's mean (max) and
/// the best single method's mean on the same gaps.
pub(crate) fn table(title: &str, recs: &[&Rec]) {
    println!("\n### {title}\n");
    println!("| markers | | 5 | 10 | 20 | 40 | 80 |");
    println!("|---|---|---|---|---|---|---|");
    for group in [1, 2] {
        let name = if group == 1 { "one" } else { "2–3" };
        let cell = |m: FillMethod, len: usize, max: bool| {
            let v = recs
                .iter()
                .filter(|r| r.group == group && r.g.gap_len == len && r.g.method == m);
            if max {
                v.map(|r| r.g.max).fold(f64::NAN, f64::max)
            } else {
                mean(v.map(|r| r.g.mean)).0
            }
        };
        let mut auto = format!("| {name} | auto mean (max) |");
        let mut best = format!("| {name} | best single |");
        let mut ratio = format!("| {name} | auto / best |");
        let mut gf = format!("| {name} | published PCA (auto / it) |");
        for len in LENGTHS {
            let am = cell(FillMethod::Auto, len, false);
            let ax = cell(FillMethod::Auto, len, true);
            let (bm, bn) = SINGLES
                .iter()
                .map(|&m| (cell(m, len, false), m))
                .filter(|x| x.0.is_finite())
                .fold((f64::INFINITY, FillMethod::None), |a, b| {
                    if b.0 < a.0 {
                        b
                    } else {
                        a
                    }
                });
            auto += &format!(" {am:.2} ({ax:.0}) |");
            best += &format!(" {bm:.2} {} |", format!("{bn:?}").to_lowercase());
            ratio += &format!(" {:.2} |", am / bm);
            let g = cell(FillMethod::Gloersen, len, false);
            gf += &format!(" {g:.2} ({:.2}) |", am / g);
        }
        println!("{auto}\n{best}\n{ratio}\n{gf}");
    }
}

pub(crate) fn report(recs: &[Rec]) {
    let all: Vec<&Rec> = recs.iter().collect();
    let files_note = "Mean 3D error in mm over the artificial gaps (max in brackets)";
    println!(
        "{files_note}; best single: the single method with the lowest pooled mean in that cell."
    );
    for set in ["walking", "fullbody"] {
        let v: Vec<&Rec> = all.iter().copied().filter(|r| r.set == set).collect();
        if !v.is_empty() {
            table(set, &v);
        }
    }
    // The walking trials at the rates of the issue's own (100, 120 and 240 Hz), whose
    // thresholds are per frame: a gap of as many frames at 30–65 Hz spans 2–8× the time.
    let v: Vec<&Rec> = all
        .iter()
        .copied()
        .filter(|r| r.set == "walking" && [100, 120, 240].contains(&r.rate))
        .collect();
    if !v.is_empty() {
        table("walking at 100, 120 and 240 Hz", &v);
    }
    let mut rates: Vec<u32> = recs.iter().map(|r| r.rate).collect();
    rates.sort_unstable();
    rates.dedup();
    for rate in rates {
        let v: Vec<&Rec> = all.iter().copied().filter(|r| r.rate == rate).collect();
        table(&format!("{rate} Hz"), &v);
    }
    // Auto's own numbers: calibration and plausibility.
    let auto: Vec<GapScore> = recs
        .iter()
        .filter(|r| r.g.method == FillMethod::Auto)
        .map(|r| r.g)
        .collect();
    let c = calibration(&auto, 0.0);
    let missing = auto.iter().filter(|g| g.expected.is_none()).count();
    println!("\n### auto's expected error\n");
    println!(
        "{} gaps ({} without an estimate): Spearman {:.3}, within 2x {:.1} %, over-confident {:.1} %, under-confident {:.1} %, median real/expected {:.2}",
        c.gaps,
        missing,
        c.spearman,
        100.0 * c.within_2x,
        100.0 * c.over_confident,
        100.0 * c.under_confident,
        c.median_ratio
    );
    for set in ["walking", "fullbody"] {
        let v: Vec<GapScore> = recs
            .iter()
            .filter(|r| r.g.method == FillMethod::Auto && r.set == set)
            .map(|r| r.g)
            .collect();
        let c = calibration(&v, 0.0);
        println!(
            "- {set}: {} gaps, Spearman {:.3}, within 2x {:.1} %, over-confident {:.1} %",
            c.gaps,
            c.spearman,
            100.0 * c.within_2x,
            100.0 * c.over_confident
        );
    }
    calibrate(recs);
    let wild = auto.iter().filter(|g| g.step_ratio > 1.5).count();
    let worst = auto.iter().map(|g| g.step_ratio).fold(0.0, f64::max);
    println!("\n### plausibility\n\nauto fills with a step above 1.5x the marker's largest recorded step: {wild} of {} (largest ratio {worst:.2})", auto.len());
    let mut labs: Vec<&str> = recs.iter().map(|r| r.lab).collect();
    labs.sort_unstable();
    labs.dedup();
    println!("\nlabs: {}", labs.join(", "));
}

/// One line of an expected-error calibration: `label`, then how the gaps' expected errors
/// match their real ones.
pub(crate) fn calibration_line(label: &str, v: &[GapScore]) -> String {
    let c = calibration(v, 0.0);
    format!(
        "- {label}: {} gaps, Spearman {:.3}, within 2x {:.1} %, over-confident {:.1} %, under-confident {:.1} %",
        c.gaps,
        c.spearman,
        100.0 * c.within_2x,
        100.0 * c.over_confident,
        100.0 * c.under_confident
    )
}

/// How the fills off by more than 20 mm fare under their expected errors: how many get
/// one above 10 mm (within 2× or cautious) and above `repair`'s default limit of 20 mm
/// (left `uncertain`), and how many fills within 10 mm that limit would leave.
pub(crate) fn catastrophic_line(label: &str, v: &[GapScore]) -> String {
    let above = |g: &GapScore, e: f64| g.expected.is_some_and(|x| x > e);
    let bad: Vec<&GapScore> = v.iter().filter(|g| g.mean > 20.0).collect();
    let flagged = bad.iter().filter(|g| above(g, 10.0)).count();
    let unc = bad.iter().filter(|g| above(g, 20.0)).count();
    let false_unc = v
        .iter()
        .filter(|g| g.mean <= 10.0 && above(g, 20.0))
        .count();
    format!(
        "- {label}: fills off by more than 20 mm: {}, of them expected above 10 mm {flagged}, above the default limit of 20 mm {unc}; fills within 10 mm expected above 20 mm: {false_unc}",
        bad.len()
    )
}

/// What `repair --max-expected-error LIMIT` (mm) leaves `uncertain` of the gaps `v`: the
/// share of all gaps, and of the fills off by more than 50 mm, by more than 20 mm and
/// within 5 mm (the CLI's help quotes this line for the held-apart labs).
pub(crate) fn limit_line(label: &str, limit: f64, v: &[GapScore]) -> String {
    let left = |keep: &dyn Fn(&GapScore) -> bool| {
        let of: Vec<&GapScore> = v.iter().filter(|g| keep(g)).collect();
        let n = of
            .iter()
            .filter(|g| g.expected.is_some_and(|e| e > limit))
            .count();
        (100.0 * n as f64 / of.len().max(1) as f64, of.len())
    };
    let (all, gaps) = left(&|_| true);
    let (b50, n50) = left(&|g| g.mean > 50.0);
    let (b20, n20) = left(&|g| g.mean > 20.0);
    let (g5, n5) = left(&|g| g.mean <= 5.0);
    format!(
        "- held-apart labs, {label}, a limit of {limit} mm leaves {all:.1} % of {gaps} gaps: {b50:.0} % of the {n50} fills off by more than 50 mm, {b20:.0} % of the {n20} off by more than 20 mm, {g5:.2} % of the {n5} within 5 mm"
    )
}

/// Mean error of `m` over the gaps of `recs` of `group` and `len` (NaN without any).
pub(crate) fn cell_mean(recs: &[&Rec], group: usize, len: usize, m: FillMethod) -> f64 {
    mean(
        recs.iter()
            .filter(|r| r.group == group && r.g.gap_len == len && r.g.method == m)
            .map(|r| r.g.mean),
    )
    .0
}

/// The lowest mean of a single method in a cell, and the method.
pub(crate) fn best_single(recs: &[&Rec], group: usize, len: usize) -> (f64, FillMethod) {
    SINGLES
        .iter()
        .map(|&m| (cell_mean(recs, group, len, m), m))
        .filter(|x| x.0.is_finite())
        .fold((f64::INFINITY, FillMethod::None), |a, b| {
            if b.0 < a.0 {
                b
            } else {
                a
            }
        })
}

/// The held-apart evaluation: the labs of `../c3d-more` other than CMU's, on which no
/// constant or candidate set of `auto` was chosen (they were chosen on the corpora in
/// [`TUNED`]), as a new lab meets `auto`: its pooled tables, the spread over labs, and the
/// expected-error model's calibration there, fitted on the tuned labs and fitted
/// leave-one-lab-out on every lab (the shipped model is fitted on every lab).
pub(crate) fn held_apart(recs: &[Rec]) {
    let held: Vec<&Rec> = recs.iter().filter(|r| r.held).collect();
    if held.is_empty() {
        return;
    }
    let mut labs: Vec<&str> = held.iter().map(|r| r.lab).collect();
    labs.sort_unstable();
    labs.dedup();
    println!(
        "\n## Held apart: {} labs on which nothing was chosen ({})",
        labs.len(),
        labs.join(", ")
    );
    for set in ["walking", "fullbody"] {
        let v: Vec<&Rec> = held.iter().copied().filter(|r| r.set == set).collect();
        if !v.is_empty() {
            let mut n: Vec<&str> = v.iter().map(|r| r.lab).collect();
            n.sort_unstable();
            n.dedup();
            table(&format!("held apart: {set} ({} labs)", n.len()), &v);
        }
    }
    println!("\nThresholds: walking one marker 0.7 / 1.4 / 2.8 / 4.2 / 6.5 mm, 2–3 markers 0.9 / 1.3 / 2.5 / 5.8 / 15 mm; full body auto / best ≤ 1 at 5 and 10 frames, ≤ 0.85 from 20.");
    // Per lab: auto's mean and its ratio to the lab's own best single method per cell.
    println!("\n### held apart, per lab: auto mean (auto / the lab's best single method)\n");
    println!("| lab | set | markers | 5 | 10 | 20 | 40 | 80 |");
    println!("|---|---|---|---|---|---|---|---|");
    // Each lab's held-apart records per set, grouped once for the per-lab tables.
    let per_lab: Vec<(&str, &str, Vec<&Rec>)> = labs
        .iter()
        .flat_map(|lab| ["walking", "fullbody"].map(|set| (*lab, set)))
        .map(|(lab, set)| {
            let v: Vec<&Rec> = held
                .iter()
                .copied()
                .filter(|r| r.lab == lab && r.set == set)
                .collect();
            (lab, set, v)
        })
        .filter(|x| !x.2.is_empty())
        .collect();
    // (set, group, len) -> ratios over labs.
    let mut spread: BTreeMap<(&str, usize, usize), Vec<f64>> = BTreeMap::new();
    lab_rows(&per_lab, |_, set, _, v, group, len| {
        let a = cell_mean(v, group, len, FillMethod::Auto);
        let (b, _) = best_single(v, group, len);
        if (a / b).is_finite() {
            spread.entry((set, group, len)).or_default().push(a / b);
        }
        format!(" {a:.2} ({:.2}) |", a / b)
    });
    // Per lab: auto against Gløersen & Federolf's published PCA.
    println!("\n### held apart, per lab: auto / the published PCA (Gløersen & Federolf 2016)\n");
    println!("| lab | set | markers | 5 | 10 | 20 | 40 | 80 |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut losses = Vec::new();
    lab_rows(&per_lab, |lab, set, name, v, group, len| {
        let a = cell_mean(v, group, len, FillMethod::Auto);
        let g = cell_mean(v, group, len, FillMethod::Gloersen);
        if len >= 40 && a > g {
            losses.push(format!(
                "{lab} {set} {name} {len}: {a:.2} against {g:.2} mm"
            ));
        }
        format!(" {:.2} |", a / g)
    });
    println!(
        "\nCells of 40 and 80 frames where auto loses to the published PCA: {}{}",
        losses.len(),
        if losses.is_empty() {
            String::new()
        } else {
            format!(" ({})", losses.join("; "))
        }
    );
    spread_table(&spread);
    worst_per_cell(&held);
    held_apart_estimates(recs, &held);
    every_lab_left_out(recs);
    let auto: Vec<&GapScore> = held
        .iter()
        .filter(|r| r.g.method == FillMethod::Auto)
        .map(|r| &r.g)
        .collect();
    let wild = auto.iter().filter(|g| g.step_ratio > 1.5).count();
    let worst = auto.iter().map(|g| g.step_ratio).fold(0.0, f64::max);
    println!("\n### held apart: plausibility\n\nauto fills with a step above 1.5x the marker's largest recorded step: {wild} of {} (largest ratio {worst:.2})", auto.len());
}

/// The spread over the held-apart labs of `auto` / the lab's best single method, per set,
/// markers and length (`spread`: the ratios of each cell over labs): min / median / max and
/// how many labs lie above 1.
fn spread_table(spread: &BTreeMap<(&str, usize, usize), Vec<f64>>) {
    println!("\n### held apart, spread over labs of auto / the lab's best single method: min / median / max (labs above 1)\n");
    println!("| set | markers | 5 | 10 | 20 | 40 | 80 |");
    println!("|---|---|---|---|---|---|---|");
    for set in ["walking", "fullbody"] {
        for group in [1, 2] {
            let name = if group == 1 { "one" } else { "2–3" };
            let mut row = format!("| {set} | {name} |");
            for len in LENGTHS {
                let r = evals::stats::sorted(
                    spread
                        .get(&(set, group, len))
                        .into_iter()
                        .flatten()
                        .copied(),
                );
                let (Some(lo), Some(mid), Some(hi)) = (r.first(), rank(&r, 1, 2), r.last()) else {
                    row += " – |";
                    continue;
                };
                let above = r.iter().filter(|&&x| x > 1.0).count();
                row += &format!(" {lo:.2} / {mid:.2} / {hi:.2} ({above}) |");
            }
            println!("{row}");
        }
    }
}

/// `auto`'s expected errors on the held-apart labs' gaps: the shipped model's (fitted on
/// every lab, these included) and the model this run fits on the tuned labs alone.
fn held_apart_estimates(recs: &[Rec], held: &[&Rec]) {
    // The shipped expected-error model was fitted on every lab, these included: its figures
    // here are not held apart (the leave-one-lab-out lines below are), but its lines on
    // the fills off by more than 20 mm are what `repair` now does with them.
    println!(
        "\n### held apart: auto's expected error (the shipped model, fitted on these labs too)\n"
    );
    for set in ["all", "walking", "fullbody"] {
        let v: Vec<GapScore> = held
            .iter()
            .filter(|r| r.g.method == FillMethod::Auto && (set == "all" || r.set == set))
            .map(|r| r.g)
            .collect();
        println!("{}", calibration_line(set, &v));
        println!("{}", catastrophic_line(set, &v));
    }
    // The model fitted by this run on the tuned labs' gaps only: the single split.
    let tuned: Vec<(&str, &GapScore)> = recs
        .iter()
        .filter(|r| r.tuned && r.g.method == FillMethod::Auto)
        .map(|r| (r.lab, &r.g))
        .collect();
    if let Some(m) = fit(&tuned) {
        for set in ["all", "walking", "fullbody"] {
            let v: Vec<GapScore> = held
                .iter()
                .filter(|r| r.g.method == FillMethod::Auto && (set == "all" || r.set == set))
                .map(|r| GapScore {
                    expected: predict(&r.g, &m).or(r.g.expected),
                    ..r.g
                })
                .collect();
            println!(
                "{}",
                calibration_line(
                    &format!("{set}, model fitted by this run on the tuned labs"),
                    &v
                )
            );
        }
    }
}

/// The expected-error model fitted leave-one-lab-out over every lab, tuned and held apart
/// alike: each lab's gaps estimated by the model (margin included) fitted to all the other
/// labs, as the shipped model, fitted to every lab, meets a new one. Reported for the
/// held-apart labs, the tuned labs and all of them; then the constants fitted to every
/// lab, which `repair` ships.
pub(crate) fn every_lab_left_out(recs: &[Rec]) {
    let auto: Vec<&Rec> = recs
        .iter()
        .filter(|r| (r.held || r.tuned) && r.g.method == FillMethod::Auto)
        .collect();
    let out = left_out(&auto);
    for (part, keep) in [
        ("held-apart labs", Some(true)),
        ("tuned labs", Some(false)),
        ("every lab", None),
    ] {
        for set in ["all", "walking", "fullbody"] {
            let v: Vec<GapScore> = out
                .iter()
                .filter(|(r, _)| keep.is_none_or(|h| r.held == h) && (set == "all" || r.set == set))
                .map(|x| x.1)
                .collect();
            println!(
                "{}",
                calibration_line(
                    &format!("{part}, {set}, each lab by a model fitted to every other lab"),
                    &v
                )
            );
        }
    }
    // What `--max-expected-error` does for a new lab: the held-apart labs' gaps, each
    // estimated by the model fitted to the other labs.
    let held: Vec<GapScore> = out.iter().filter(|(r, _)| r.held).map(|x| x.1).collect();
    for limit in [15.0, 20.0, 30.0] {
        println!(
            "{}",
            limit_line(
                "each lab by a model fitted to every other lab",
                limit,
                &held
            )
        );
    }
    // Lab by lab: a new lab is one more draw from these, so their spread says how far a
    // user's lab may stray from the pooled figures.
    let mut labs: Vec<(&str, bool)> = out.iter().map(|(r, _)| (r.lab, r.held)).collect();
    labs.sort_unstable();
    labs.dedup();
    let mut row = String::from("- per lab, each by a model fitted to every other lab (within 2x / over-confident %, * held apart):");
    for (lab, held) in labs {
        let v: Vec<GapScore> = out
            .iter()
            .filter(|(r, _)| r.lab == lab)
            .map(|x| x.1)
            .collect();
        let c = calibration(&v, 0.0);
        let mark = if held { "*" } else { "" };
        row += &format!(
            " {lab}{mark} {:.0}/{:.1} ({}),",
            100.0 * c.within_2x,
            100.0 * c.over_confident,
            c.gaps
        );
    }
    println!("{}", row.trim_end_matches(','));
    let all: Vec<(&str, &GapScore)> = auto.iter().map(|r| (r.lab, &r.g)).collect();
    if let Some(m) = fit(&all) {
        let f = |v: &[f64; K]| v.map(|b| format!("{b:.6}")).join(", ");
        println!(
            "- model fitted on every lab, tuned and held apart (the constants shipped): beta [{}], gamma [{}], c1 {:.6}, c0 {:.6}",
            f(&m.beta),
            f(&m.gamma),
            m.c1,
            m.c0
        );
    }
}

/// Prints a row per lab, set and markers (one, 2–3) of `per_lab`, with `cell`'s text for
/// each gap length (it gets the lab, set, markers' name, records, group and length).
pub(crate) fn lab_rows<'a>(
    per_lab: &[(&'a str, &'a str, Vec<&'a Rec>)],
    mut cell: impl FnMut(&'a str, &'a str, &str, &[&Rec], usize, usize) -> String,
) {
    for (lab, set, v) in per_lab {
        for group in [1, 2] {
            let name = if group == 1 { "one" } else { "2–3" };
            let mut row = format!("| {lab} | {set} | {name} |");
            for len in LENGTHS {
                row += &cell(lab, set, name, v, group, len);
            }
            println!("{row}");
        }
    }
}

/// The largest error of `auto` in each cell (set, markers, length): the lab, the method
/// its fill came from, its expected error and what that was made from (score on the
/// artificial gaps, the two best candidates' spread on the real gap): the fills a user
/// is most misled by when the estimate is small.
pub(crate) fn worst_per_cell(recs: &[&Rec]) {
    println!("\n### held apart: auto's largest error per cell\n");
    println!("| set | markers | frames | lab | mean (max) mm | method | expected | scored | spread | refilled |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for set in ["walking", "fullbody"] {
        for group in [1, 2] {
            for len in LENGTHS {
                let worst = recs
                    .iter()
                    .filter(|r| {
                        r.set == set
                            && r.group == group
                            && r.g.gap_len == len
                            && r.g.method == FillMethod::Auto
                    })
                    .max_by(|a, b| a.g.mean.total_cmp(&b.g.mean));
                let Some(r) = worst else {
                    continue;
                };
                let name = if group == 1 { "one" } else { "2–3" };
                let m =
                    r.g.chosen
                        .map_or("–".to_string(), |m| format!("{m:?}").to_lowercase());
                let e = r.g.evidence;
                println!(
                    "| {set} | {name} | {len} | {} | {:.1} ({:.0}) | {m} | {:.1} | {:.2} | {:.1} | {} |",
                    r.lab,
                    r.g.mean,
                    r.g.max,
                    r.g.expected.unwrap_or(f64::NAN),
                    e.map_or(f64::NAN, |d| d.scored),
                    e.map_or(f64::NAN, |d| d.spread),
                    e.is_some_and(|d| d.refilled)
                );
            }
        }
    }
}
