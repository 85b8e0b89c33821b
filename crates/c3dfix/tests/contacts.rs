//! Contacts on every corpus trial with plates: a plate's load is the push of a foot, its
//! unloaded level removed, so a contact is a footfall — it starts at the file's own Foot
//! Strike and ends at its Foot Off where the file marks them, and no walking plate is "in
//! contact" for a whole trial because of an offset.

use c3dfix::{force_platforms, ForceOptions};
use std::path::PathBuf;

/// Every corpus C3D file (the three corpora of `testkit::all_c3d_files` and `c3d-more`).
fn corpus() -> Vec<PathBuf> {
    let mut files = testkit::all_c3d_files();
    if let Some(d) = testkit::c3d_more() {
        files.extend(testkit::files_with_ext(&d, "c3d"));
    }
    files
}

/// Trials where a plate carries a subject from the first sample to the last: static poses
/// and a jump that starts standing. There a contact over the whole trial is the truth.
const LOADED_THROUGHOUT: [&str; 5] = [
    "Static Pose.c3d",
    "standing.C3D",
    "Sample_Jump2.c3d",
    "btkdata_Res16bits.c3d",
    // ANALOG:USED disagrees with the stored data: the channels are read shifted.
    "MotionMonitorC3D.c3d",
];

/// No contact spans a whole trial unless the plate carries a load throughout; and a plate
/// whose contact spans the whole trial had no unloaded stretch to remove (the warning says
/// so), never an offset read as a load.
#[test]
fn no_walking_plate_is_in_contact_for_the_whole_trial() {
    let (mut trials, mut plates) = (0, 0);
    for f in corpus() {
        let Ok(c) = c3dfix::open(&f) else { continue };
        let fp = force_platforms(&c, &ForceOptions::default()).expect("default options");
        if fp.platforms.is_empty() {
            continue;
        }
        trials += 1;
        let name = testkit::short(&f);
        let exempt = LOADED_THROUGHOUT.iter().any(|n| name.ends_with(n));
        for p in &fp.platforms {
            plates += 1;
            let n = p.push.len();
            for k in &p.contacts {
                let whole = k.first_sample == 0 && k.last_sample + 1 == n;
                assert!(
                    !whole || exempt,
                    "{name} plate {}: one contact over the whole trial (baseline {:?})",
                    p.index,
                    p.baseline
                );
            }
        }
    }
    eprintln!("{trials} trials, {plates} plates");
    if !corpus().is_empty() {
        assert!(trials >= 55, "{trials} trials with plates");
    }
}

/// Where the file marks a footfall (a Foot Strike within 10 frames of a contact's start, a
/// Foot Off within 10 frames of its end), the contact's ends are within 6 frames of those
/// events: c3dfix finds the first sample a foot pushes 10 N, a lab's events may come from the
/// markers or a higher threshold (sample_04's strike is 6 frames after the plate reads 10 N,
/// the plate rising slowly through 20 N as the heel lands).
#[test]
fn contacts_start_at_foot_strikes_and_end_at_foot_offs() {
    const NEAR: f64 = 10.0;
    const WITHIN: f64 = 6.0;
    let (mut starts, mut ends, mut worst) = (0, 0, 0.0f64);
    for f in corpus() {
        let Ok(c) = c3dfix::open(&f) else { continue };
        let events = c.events();
        let rate = c.point_rate() as f64;
        let times = |word: &str| -> Vec<f64> {
            events
                .iter()
                .filter(|e| e.label.to_ascii_lowercase().contains(word))
                .map(|e| e.time)
                .collect()
        };
        let (strikes, offs) = (times("strike"), times("off"));
        if strikes.is_empty() && offs.is_empty() {
            continue;
        }
        let fp = force_platforms(&c, &ForceOptions::default()).expect("default options");
        let name = testkit::short(&f);
        let nearest = |list: &[f64], at: f64| {
            list.iter()
                .map(|e| (at - e) * rate)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        };
        for p in &fp.platforms {
            for k in &p.contacts {
                for (list, at, what, count) in [
                    (&strikes, k.first_time, "start", &mut starts),
                    (&offs, k.last_time, "end", &mut ends),
                ] {
                    let Some(d) = nearest(list, at) else { continue };
                    if d.abs() > NEAR {
                        continue; // no event marks this end of the footfall
                    }
                    *count += 1;
                    worst = worst.max(d.abs());
                    assert!(
                        d.abs() <= WITHIN,
                        "{name} plate {}: contact {what} at {at:.3} s is {d:.1} frames from the file's event",
                        p.index
                    );
                }
            }
        }
    }
    eprintln!("{starts} starts, {ends} ends checked against events; worst {worst:.1} frames");
    if !corpus().is_empty() {
        assert!(starts >= 15 && ends >= 15, "{starts} starts, {ends} ends");
    }
}

/// One contact per footfall on the walking trials whose events name every footfall on the
/// plates: each plate that a foot strikes once has exactly one contact, at that strike.
#[test]
fn one_contact_per_step() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    for (file, contacts) in [
        (
            "HansUniVie__MuscleLength__test.c3d",
            [1, 1, 1, 1].as_slice(),
        ),
        ("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d", &[0, 1, 1, 0]),
        ("tsalemink__C3D-parser__RBWH_bfnd_w1.c3d", &[1, 1, 1]),
        (
            "keenon__nimblephysics__JA1Gait35.c3d",
            &[0, 1, 0, 1, 0, 0, 1, 1],
        ),
        ("opensim-org__opensim-core__walking2.c3d", &[1, 1]),
        ("pyomeca__ezc3d-testFiles__Qualisys.c3d", &[1, 1]),
    ] {
        let c = c3dfix::open(more.join(file)).expect(file);
        let fp = force_platforms(&c, &ForceOptions::default()).expect("plates");
        let got: Vec<usize> = fp.platforms.iter().map(|p| p.contacts.len()).collect();
        assert_eq!(got, contacts, "{file}");
    }
}

/// The user's trial: plates resting at a pull of 14 and 20 N (`walking2`) read no load
/// outside the footfall once the level is removed, and without the baseline the pull is still
/// no contact (a pull is never a load).
#[test]
fn an_offset_is_no_load() {
    let Some(more) = testkit::c3d_more() else {
        return;
    };
    let c = c3dfix::open(more.join("opensim-org__opensim-core__walking2.c3d")).expect("walking2");
    let fp = force_platforms(&c, &ForceOptions::default()).expect("plates");
    for p in &fp.platforms {
        let b = p.baseline.expect("a baseline");
        assert_eq!(b.source, c3dfix::BaselineSource::Quiet);
        assert!(b.level < -10.0 && b.level > -25.0, "{b:?}");
        let k = p.contacts[0];
        let outside = p.push[..k.first_sample]
            .iter()
            .chain(&p.push[k.last_sample + 1..]);
        assert!(outside.clone().all(|v| v.abs() < 10.0));
        assert!(p.cop[..k.first_sample].iter().all(|c| c[0].is_nan()));
    }
    let raw = force_platforms(
        &c,
        &ForceOptions {
            zero_baseline: false,
            ..ForceOptions::default()
        },
    )
    .expect("plates");
    for p in &raw.platforms {
        assert!(p.baseline.is_none());
        assert_eq!(p.contacts.len(), 1, "plate {}", p.index);
    }
}

/// Trials whose COP or frames cannot be placed under the markers, each for a reason the
/// file states: `sample_21`'s POINT:RATE and ANALOG:RATE are wrong (200 and 1000 Hz recorded,
/// 60 and 1020 stored: its readme), so samples fall in the wrong frames;
/// `btkdata_parameterOverflow`'s moment channels hold one value throughout (the warning
/// says so), so its COP is not measured.
const NO_TRUE_COP: [&str; 2] = ["sample21.c3d", "btkdata_parameterOverflow.c3d"];

/// The push is the foot's: at the middle of every contact of at least 0.1 s, the COP lies
/// under a foot marker (heel, toe or ankle) — within 250 mm of one, measured in the plate's
/// plane, a foot's length — on every trial whose markers name the feet.
#[test]
fn the_cop_of_a_contact_lies_under_a_foot() {
    const FOOT_MM: f64 = 250.0;
    let (mut checked, mut worst, mut far) = (0, 0.0f64, Vec::new());
    for f in corpus() {
        let Ok(c) = c3dfix::open(&f) else { continue };
        let labels = c.point_labels();
        let feet: Vec<usize> = labels
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                let l = l
                    .rsplit(':')
                    .next()
                    .unwrap_or(l)
                    .trim()
                    .to_ascii_uppercase();
                ["HEE", "TOE", "ANK"].iter().any(|k| l.contains(k))
                    && !l.contains("ANGLE")
                    && !l.contains("FORCE")
                    && !l.contains("MOMENT")
                    && !l.contains("POWER")
            })
            .map(|(i, _)| i)
            .collect();
        if feet.is_empty() {
            continue;
        }
        let name = testkit::short(&f);
        if NO_TRUE_COP.iter().any(|n| name.ends_with(n)) {
            continue;
        }
        let fp = force_platforms(&c, &ForceOptions::default()).expect("default options");
        let pts = c.points();
        let spf = fp.samples_per_frame;
        for p in &fp.platforms {
            let mm = c3d::mm_per_unit(&p.units.position);
            let k = p.corners;
            let d1: [f64; 3] = std::array::from_fn(|i| k[0][i] - k[2][i]);
            let d2: [f64; 3] = std::array::from_fn(|i| k[1][i] - k[3][i]);
            let n = [
                d1[1] * d2[2] - d1[2] * d2[1],
                d1[2] * d2[0] - d1[0] * d2[2],
                d1[0] * d2[1] - d1[1] * d2[0],
            ];
            let nn = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let n = n.map(|v| v / nn);
            for contact in &p.contacts {
                let len = contact.last_sample - contact.first_sample + 1;
                if (len as f64) < 0.1 * p.rate {
                    continue;
                }
                let mid = contact.first_sample + len / 2;
                let frame = mid / spf;
                let cop = p.cop[mid];
                if frame >= pts.frames() || cop[0].is_nan() {
                    continue;
                }
                let near = feet
                    .iter()
                    .filter(|&&i| pts.is_valid(frame, i))
                    .map(|&i| {
                        let m = pts.xyz[pts.index(frame, i)];
                        let d: [f64; 3] = std::array::from_fn(|a| m[a] as f64 - cop[a]);
                        let along = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                        let h: [f64; 3] = std::array::from_fn(|a| d[a] - along * n[a]);
                        (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt() * mm
                    })
                    .fold(f64::INFINITY, f64::min);
                if !near.is_finite() {
                    continue; // no foot marker seen in that frame
                }
                checked += 1;
                worst = worst.max(near);
                if near > FOOT_MM {
                    far.push(format!(
                        "{name} plate {}: the COP at {:.3} s is {near:.0} mm from the nearest foot marker",
                        p.index,
                        contact.first_time + (mid - contact.first_sample) as f64 / p.rate
                    ));
                }
            }
        }
    }
    eprintln!("{checked} contacts: COP under a foot marker, farthest {worst:.0} mm");
    assert!(far.is_empty(), "{far:#?}");
    if !corpus().is_empty() {
        assert!(checked >= 40, "{checked} contacts checked");
    }
}

/// An unloaded plate's .mot rows are zero, on every corpus trial with plates: wherever a
/// plate is in no contact (no foot pushes it the threshold), its row in the MOT that
/// `export --format mot` and the OpenSim pair write has force and torque exactly 0 and the
/// point at the plate's centre, so an ExternalLoads applies nothing there; and inside a
/// contact the row carries the plate's force.
#[test]
fn an_unloaded_plates_mot_rows_are_zero() {
    let (mut trials, mut unloaded_rows, mut loaded_rows) = (0usize, 0usize, 0usize);
    // Rows outside every contact whose push reached the threshold (runs too short for a
    // footfall): no load in the MOT, though the plate's COP is defined there.
    let mut blips = 0usize;
    for f in corpus() {
        let Ok(c) = c3dfix::open(&f) else { continue };
        let fp = force_platforms(&c, &ForceOptions::default()).expect("default options");
        if fp.platforms.is_empty() {
            continue;
        }
        let name = testkit::short(&f);
        let Ok(text) = c3dfix::export::mot(&c, &fp, &f, &c3dfix::Axes::default()) else {
            continue; // refused with a reason (no analog rate, a unit MOT cannot state)
        };
        trials += 1;
        let rows: Vec<Vec<f64>> = text
            .lines()
            .skip_while(|l| *l != "endheader")
            .skip(2)
            .map(|l| {
                l.split('\t')
                    .map(|x| x.parse().expect("a number"))
                    .collect()
            })
            .collect();
        assert_eq!(rows.len(), fp.samples(), "{name}");
        for (k, p) in fp.platforms.iter().enumerate() {
            let col = 1 + 9 * k;
            let mut inside = vec![false; rows.len()];
            for c in &p.contacts {
                inside[c.first_sample..=c.last_sample.min(rows.len() - 1)].fill(true);
            }
            let m = c3dfix::units::metres_per(&p.units.position).expect("a unit");
            for (i, row) in rows.iter().enumerate() {
                let force = &row[col..col + 3];
                let point = &row[col + 3..col + 6];
                let torque = &row[col + 6..col + 9];
                if inside[i] {
                    if p.push[i] >= 2.0 * ForceOptions::default().threshold {
                        assert!(
                            force.iter().any(|&x| x != 0.0),
                            "{name} plate {} row {i}",
                            p.index
                        );
                        loaded_rows += 1;
                    }
                    continue;
                }
                assert!(
                    force.iter().chain(torque).all(|&x| x == 0.0),
                    "{name} plate {}: row {i} (time {}) outside every contact carries {force:?} N, {torque:?} N·m (push {:.2} N)",
                    p.index,
                    row[0],
                    p.push[i]
                );
                for a in 0..3 {
                    assert!(
                        (point[a] - p.centre[a] * m).abs() < 1e-6,
                        "{name} plate {}: row {i}'s point {point:?} is not the centre",
                        p.index
                    );
                }
                unloaded_rows += 1;
                blips += usize::from(p.cop[i][0].is_finite());
            }
        }
    }
    eprintln!("{trials} trials: {unloaded_rows} unloaded rows zero ({blips} of them above the threshold for less than a footfall), {loaded_rows} loaded rows carry force");
    if !corpus().is_empty() {
        assert!(trials >= 55, "{trials} trials with plates");
    }
}
