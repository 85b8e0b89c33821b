//! The marker's own motion around a gap as expected-error features (issue 45 item 7),
//! measured after the fact on replayed records (`--replay FILE --motion`): each record's
//! trial is read again as the records' run read it, the gap knocked out of its marker, and
//! what the marker does beside the gap and over the whole trial measured. Each measure is
//! then added to the shipped features in turn and judged per activity, each lab's gaps by
//! the β and γ fitted without that lab (see [`evals::fit::fit_rows_apart`]), on the older
//! corpora's labs (where a feature is chosen) and on `c3d-labs`' (where it is reported).
//!
//! Why these: a drop jump's landing or a lift's swing and a walk's stretch of the same
//! speed get the same evidence from the shipped features, and the activities beyond
//! walking miss the goal both ways. What differs is how hard the marker accelerates next to
//! the gap, against its pace and against the score its artificial gaps gave.
//!
//! The third round (issue 45 item 7) added the marker's bursts, its acceleration beside
//! the gap over its median, the gap's place in the marker's range, its room, and "M", the
//! method leading the fill as six indicators (the records' `chosen`), alone and with
//! measures beside it. The base of every row is the shipped features less the two this
//! study chose (`speed`, measure 3, and the lead's indicators), so the choice is made again
//! from the same records; "M + 3" is what ships.

use super::activity::activities_of;
use super::*;
use evals::fit::{fit_rows_apart, ln_real_over_scored};
use rayon::prelude::*;
use repair::fill::{accel_ratio, features, speed_ratio, FEATURES, LEADS};
use repair::Trial;

/// The measures tried, each one feature (ln of the measure less its median).
const MEASURES: [&str; 12] = [
    "acceleration beside the gap x len^2 / scored",
    "acceleration beside the gap / the marker's mean acceleration",
    "speed beside the gap / the marker's mean speed",
    "scored / step beside the gap",
    "acceleration beside the gap x len / step beside it",
    "largest acceleration beside the gap / the marker's mean acceleration",
    "the marker's mean acceleration x len^2 / scored",
    "the marker's mean acceleration / its mean step",
    "the marker's mean acceleration / its median acceleration (bursts)",
    "acceleration beside the gap / the marker's median acceleration",
    "the gap's distance from the marker's middle / its usual distance (extremes)",
    "the marker's recorded frames / the gap's length (room)",
];
const NM: usize = MEASURES.len();

/// Most extra columns a variant adds to the shipped features.
const EXTRA: usize = 8;

/// The variants tried: each a name and the extra columns it adds (indices into the
/// measures' columns, then the indicators of `repair::fill::LEADS` after them).
fn variants() -> Vec<(String, Vec<usize>)> {
    let leads: Vec<usize> = (NM..NM + LEADS.len()).collect();
    let mut v: Vec<(String, Vec<usize>)> = vec![("none (the shipped features)".into(), vec![])];
    v.extend(
        MEASURES
            .iter()
            .enumerate()
            .map(|(k, m)| (format!("{}. {m}", k + 1), vec![k])),
    );
    v.push((
        "M. the method leading the fill (6 indicators)".into(),
        leads.clone(),
    ));
    for k in [&[2][..], &[5], &[11], &[2, 11], &[2, 10]] {
        let mut c = leads.clone();
        c.extend(k);
        let names: Vec<String> = k.iter().map(|k| (k + 1).to_string()).collect();
        v.push((format!("M + {}", names.join(" + ")), c));
    }
    v
}

/// One record with its measures (`None` where a measure has nothing to read).
type Measured<'a> = (&'a Rec, [Option<f64>; NM]);

/// Every record's extra columns, column by column.
type Columns = Vec<Vec<f64>>;

/// The study: the measures for every record whose trial can be read, then per measure
/// the per-activity figures with it added to the model.
pub(crate) fn motion_study(recs: &[Rec]) {
    let (measured, selected, _): (Vec<Measured>, _, _) = measure_by_trial(
        recs,
        |r| r.g.method == FillMethod::Auto && r.g.evidence.is_some() && (r.held || r.tuned),
        measure_trial,
        "the motion study",
    );
    let act = activities_of(recs);
    println!(
        "\n### the marker's motion as expected-error features\n\n{} records matched (of {}).\n",
        measured.len(),
        selected
    );
    for (k, name) in MEASURES.iter().enumerate() {
        let known: Vec<f64> = measured.iter().filter_map(|m| m.1[k]).collect();
        println!(
            "- {}. {name}: known on {} records, median {:.4}",
            k + 1,
            known.len(),
            evals::stats::median(known).unwrap_or(f64::NAN)
        );
    }
    let labs_corpus = |r: &Rec| FILES.iter().any(|f| f.3 == r.file && f.2 == "labs");
    let mut names: Vec<&str> = measured.iter().map(|m| act[&m.0.file]).collect();
    names.sort_unstable();
    names.dedup();
    // Activities with gaps from two labs or more.
    let names: Vec<&str> = names
        .into_iter()
        .filter(|n| {
            let mut l: Vec<&str> = measured
                .iter()
                .filter(|m| act[&m.0.file] == *n)
                .map(|m| m.0.lab)
                .collect();
            l.sort_unstable();
            l.dedup();
            l.len() >= 2
        })
        .collect();
    println!(
        "\nEach cell: within 2x / over twice % / median estimate over median error, each lab by the β and γ fitted without it; older corpora's labs | c3d-labs' labs | every lab.\n"
    );
    println!("| feature added | all | {} |", names.join(" | "));
    println!("|---|---|{}", "---|".repeat(names.len()));
    let mut cols: Columns = (0..NM).map(|k| column(&measured, k)).collect();
    for m in LEADS {
        cols.push(
            measured
                .iter()
                .map(|(r, _)| f64::from(u8::from(r.g.chosen == Some(m))))
                .collect(),
        );
    }
    let only = std::env::var("MOTION_ONLY").ok();
    let variants: Vec<(String, Vec<usize>)> = variants()
        .into_iter()
        .filter(|v| {
            only.as_deref()
                .is_none_or(|o| o.split(',').any(|o| v.0.starts_with(o)))
        })
        .collect();
    let rows: Vec<String> = variants
        .iter()
        .map(|(name, extra)| {
            let est = judge(&measured, &cols, extra);
            let cell = |keep: &dyn Fn(&Rec) -> bool| {
                let part = |f: &dyn Fn(&Rec) -> bool| {
                    let v: Vec<(GapScore, f64)> = est
                        .iter()
                        .zip(&measured)
                        .filter(|(_, m)| keep(m.0) && f(m.0))
                        .filter_map(|(e, m)| e.map(|e| (e, m.0.g.mean)))
                        .collect();
                    if v.is_empty() {
                        return "–".to_string();
                    }
                    let g: Vec<GapScore> = v.iter().map(|x| x.0).collect();
                    let c = calibration(&g, 0.0);
                    let sharp = evals::stats::median(g.iter().filter_map(|x| x.expected))
                        .unwrap_or(f64::NAN)
                        / evals::stats::median(v.iter().map(|x| x.1)).unwrap_or(f64::NAN);
                    format!(
                        "{:.1}/{:.1}/{sharp:.2}",
                        100.0 * c.within_2x,
                        100.0 * c.over_confident
                    )
                };
                format!(
                    "{} \\| {} \\| {}",
                    part(&|r| !labs_corpus(r)),
                    part(&|r| labs_corpus(r)),
                    part(&|_| true)
                )
            };
            let mut cells = vec![cell(&|_| true)];
            cells.extend(names.iter().map(|n| cell(&|r: &Rec| act[&r.file] == *n)));
            let line = format!("| {name} | {} |", cells.join(" | "));
            eprintln!("{line}");
            line
        })
        .collect();
    rows.iter().for_each(|r| println!("{r}"));
}

/// Each `auto` record without the marker's acceleration or speed beside its gap (see
/// [`repair::fill::Diag::accel`] and [`repair::fill::Diag::speed`]; records made before
/// they were evidence) gets them from its trial, read as the records' run read it, with
/// `auto`'s own functions. A trial that cannot be read or matched leaves its records
/// without them (the features then read as typical), said on stderr.
pub(crate) fn fill_in_accel(recs: &mut [Rec]) {
    let mut by_file: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, r) in recs.iter().enumerate() {
        if r.g.method == FillMethod::Auto
            && r.g
                .evidence
                .is_some_and(|d| d.accel.is_none() || d.speed.is_none())
        {
            by_file.entry(r.file.clone()).or_default().push(i);
        }
    }
    if by_file.is_empty() {
        return;
    }
    type Found = (usize, Option<f64>, Option<f64>);
    let found: Vec<Found> = by_file
        .par_iter()
        .flat_map_iter(|(file, idx)| {
            let rs: Vec<(usize, &Rec)> = idx.iter().map(|&i| (i, &recs[i])).collect();
            match read_trial(file, &rs) {
                Ok(t) => rs
                    .iter()
                    .map(|&(i, r)| {
                        let (m, a, len) = (r.g.marker, r.g.first, r.g.gap_len);
                        let ok = |f: usize| t.valid[m][f] && !(a..a + len).contains(&f);
                        (
                            i,
                            accel_ratio(&t.xyz[m], ok, a, len),
                            speed_ratio(&t.xyz[m], ok, a, len),
                        )
                    })
                    .collect::<Vec<_>>(),
                Err(e) => {
                    eprintln!("{file}: {e}: its records keep no motion beside the gap");
                    Vec::new()
                }
            }
        })
        .collect();
    eprintln!(
        "the marker's acceleration and speed beside the gap read from the trials for {} records",
        found.len()
    );
    for (i, acc, speed) in found {
        if let Some(d) = recs[i].g.evidence.as_mut() {
            d.accel = d.accel.or(acc);
            d.speed = d.speed.or(speed);
        }
    }
}

/// Measure `k` of every record as a feature: ln of the measure, less its median over the
/// records that have it (so a record without it reads as a typical one).
fn column(measured: &[Measured], k: usize) -> Vec<f64> {
    let med = evals::stats::median(
        measured
            .iter()
            .filter_map(|m| m.1[k])
            .map(|v| v.clamp(1e-4, 1e4).ln()),
    )
    .unwrap_or(0.0);
    measured
        .iter()
        .map(|m| m.1[k].map_or(0.0, |v| v.clamp(1e-4, 1e4).ln() - med))
        .collect()
}

/// Every record's estimate as a new lab meets it, with the shipped features and the
/// columns `extra` of `cols` (at most [`EXTRA`]; the rest 0, which the fit weighs 0).
fn judge(measured: &[Measured], cols: &Columns, extra: &[usize]) -> Vec<Option<GapScore>> {
    // The study's base is the model before this study's choice: the shipped features but
    // `speed` and the lead's indicators (the last 1 + LEADS of them), which the variants
    // add as measure 3 and "M", so the choice can be made again from the same records.
    let shipped = |i: usize| {
        let mut x = measured[i]
            .0
            .g
            .evidence
            .as_ref()
            .map_or([0.0; FEATURES], features);
        x[FEATURES - 1 - LEADS.len()..].fill(0.0);
        x
    };
    judge_n(measured, &|i| -> [f64; FEATURES + EXTRA] {
        let mut x = [0.0; FEATURES + EXTRA];
        x[..FEATURES].copy_from_slice(&shipped(i));
        for (j, &c) in extra.iter().take(EXTRA).enumerate() {
            x[FEATURES + j] = cols[c][i];
        }
        x
    })
}

fn judge_n<const N: usize>(
    measured: &[Measured],
    x: &(dyn Fn(usize) -> [f64; N] + Sync),
) -> Vec<Option<GapScore>> {
    let rows: Vec<(&str, [f64; N], f64)> = measured
        .iter()
        .enumerate()
        .map(|(i, (r, _))| {
            let scored = r.g.evidence.map_or(0.0, |d| d.scored);
            (r.lab, x(i), ln_real_over_scored(r.g.mean, scored))
        })
        .collect();
    let Some((_, apart)) = fit_rows_apart(&rows) else {
        return vec![None; rows.len()];
    };
    apart
        .iter()
        .zip(measured)
        .map(|(l, (r, _))| {
            let scored = r.g.evidence?.scored.max(1e-12);
            Some(GapScore {
                expected: Some(scored * l.as_ref()?.exp()),
                ..r.g
            })
        })
        .collect()
}

/// One record's trial as the records' run read it, checked against its records' gaps.
fn read_trial(file: &str, rs: &[(usize, &Rec)]) -> Result<Trial, String> {
    let corpus = FILES
        .iter()
        .find(|f| f.3 == file)
        .map(|f| f.2)
        .ok_or("not in the corpus list")?;
    let root = corpus::roots()
        .get(corpus)
        .cloned()
        .flatten()
        .ok_or("corpus not on this machine")?;
    let path = root.join(file);
    let trial = if corpus::holds_fills(corpus) {
        load_recorded(&path)?
    } else {
        load(&path)?
    };
    matches(&trial, rs)?;
    Ok(trial)
}

/// Whether every record's gap lies where `trial` has its marker recorded (its frames held
/// the truth the gap was scored on).
fn matches(trial: &Trial, rs: &[(usize, &Rec)]) -> Result<(), String> {
    for (_, r) in rs {
        let (m, a, len) = (r.g.marker, r.g.first, r.g.gap_len);
        if m >= trial.markers()
            || a + len > trial.frames()
            || !trial.valid[m][a..a + len].iter().all(|&v| v)
        {
            return Err(format!(
                "marker {m}'s gap at frame {a} is not recorded in the trial as read now"
            ));
        }
    }
    Ok(())
}

/// The measures of every record of one trial, read as the records' run read it.
fn measure_trial<'a>(
    file: &str,
    rs: &[(usize, &'a Rec)],
) -> Result<Vec<(usize, Measured<'a>)>, String> {
    let trial = read_trial(file, rs)?;
    Ok(rs
        .iter()
        .map(|&(i, r)| {
            let scored = r.g.evidence.map_or(0.0, |d| d.scored);
            let v = measure(&trial, r.g.marker, r.g.first, r.g.gap_len, scored);
            (i, (r, v))
        })
        .collect())
}

/// The measures of marker `m`'s gap over frames `a..a + len`, scored `scored`.
fn measure(t: &Trial, m: usize, a: usize, len: usize, scored: f64) -> [Option<f64>; NM] {
    let n = t.frames();
    let ok = |f: usize| t.valid[m][f] && !(a..a + len).contains(&f);
    let p = |f: usize| t.xyz[m][f];
    let w = len.max(10);
    let beside: Vec<usize> = (a.saturating_sub(w)..a)
        .chain(a + len..(a + len + w).min(n))
        .collect();
    let step = |f: usize| (f >= 1 && ok(f) && ok(f - 1)).then(|| dist(p(f), p(f - 1)));
    let acc = |f: usize| {
        (f >= 1 && f + 1 < n && ok(f - 1) && ok(f) && ok(f + 1)).then(|| {
            let (q0, q1, q2) = (p(f - 1), p(f), p(f + 1));
            dist(
                [q2[0] - q1[0], q2[1] - q1[1], q2[2] - q1[2]],
                [q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]],
            )
        })
    };
    let step_b = mean(beside.iter().filter_map(|&f| step(f)));
    let acc_b = mean(beside.iter().filter_map(|&f| acc(f)));
    let peak_b = beside.iter().filter_map(|&f| acc(f)).reduce(f64::max);
    let step_t = mean((0..n).filter_map(step));
    let acc_t = mean((0..n).filter_map(acc));
    let acc_med = evals::stats::median((0..n).filter_map(acc));
    // The gap's place in the marker's range: its anchors' midpoint against the marker's
    // middle (the median of each coordinate), over the marker's median distance from it.
    let rec: Vec<usize> = (0..n).filter(|&f| ok(f)).collect();
    let mid: Option<[f64; 3]> = (!rec.is_empty()).then(|| {
        std::array::from_fn(|c| evals::stats::median(rec.iter().map(|&f| p(f)[c])).unwrap_or(0.0))
    });
    let anchors: Vec<[f64; 3]> = [(0..a).rev().find(|&f| ok(f)), (a + len..n).find(|&f| ok(f))]
        .into_iter()
        .flatten()
        .map(p)
        .collect();
    let extreme = mid.and_then(|mid| {
        let usual = evals::stats::median(rec.iter().map(|&f| dist(p(f), mid)))?;
        let at: [f64; 3] = (!anchors.is_empty()).then(|| {
            std::array::from_fn(|c| {
                anchors.iter().map(|q| q[c]).sum::<f64>() / anchors.len() as f64
            })
        })?;
        (usual > 0.0).then(|| dist(at, mid) / usual)
    });
    let l = len as f64;
    let s = (scored > 0.0).then_some(scored);
    let ratio = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) if y > 0.0 => Some(x / y),
        _ => None,
    };
    [
        ratio(acc_b.map(|v| v * l * l), s),
        ratio(acc_b, acc_t),
        ratio(step_b, step_t),
        ratio(s, step_b),
        ratio(acc_b.map(|v| v * l), step_b),
        ratio(peak_b, acc_t),
        ratio(acc_t.map(|v| v * l * l), s),
        ratio(acc_t, step_t),
        ratio(acc_t, acc_med),
        ratio(acc_b, acc_med),
        extreme,
        Some(rec.len() as f64 / l),
    ]
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
