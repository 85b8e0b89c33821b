//! The library's exports on real corpus trials: TRC rows whole (NaN for missing), frame
//! numbers and times on the file's own base, markers without model outputs; MOT timed on
//! the same base; the OpenSim pair turned so that the lab's up is Y.

use c3dfix::export::{self, OpenSimOptions, Points};
use c3dfix::{Axes, ForceOptions};
use std::path::PathBuf;

fn more(name: &str) -> Option<PathBuf> {
    testkit::c3d_more().map(|d| d.join(name))
}

/// A Plug-in Gait trial cropped in the capture software (first frame 134) whose markers go
/// missing: every row has all its fields, model outputs are out, times start at 1.33 s.
#[test]
fn trc_rows_are_whole_and_on_the_files_time_base() {
    let Some(path) = more("martinfelis__puppeteer__testdata.c3d") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    assert_eq!(c.first_frame(), 134);
    let markers = Points::Markers.indices(&c).unwrap();
    let outputs = c.model_output_labels();
    assert!(outputs.len() >= 26);
    assert_eq!(markers.len(), c.point_count() - outputs.len());
    let t = export::trc(&c, "testdata.c3d", &markers, &Axes::default()).unwrap();
    let lines: Vec<&str> = t.text.lines().collect();
    assert_eq!(lines.len(), 6 + c.frames());
    assert!(lines[2].starts_with(&format!("100\t100\t{}\t{}\tmm", c.frames(), markers.len())));
    assert!(!lines[3].contains("LHipAngles") && lines[3].contains("\tLKNE\t"));
    let mut nan_rows = 0;
    for (f, row) in lines[6..].iter().enumerate() {
        let fields: Vec<&str> = row.split('\t').collect();
        assert_eq!(fields.len(), 2 + 3 * markers.len(), "frame {f}");
        assert_eq!(fields[0], (134 + f).to_string());
        let time: f64 = fields[1].parse().unwrap();
        assert!((time - (133 + f) as f64 / 100.0).abs() < 1e-9, "{time}");
        for (k, &i) in markers.iter().enumerate() {
            let xyz = &fields[2 + 3 * k..5 + 3 * k];
            if c.points().is_valid(f, i) {
                let v = c.points().xyz[c.points().index(f, i)];
                for a in 0..3 {
                    assert_eq!(xyz[a].parse::<f32>().unwrap(), v[a]);
                }
            } else {
                assert_eq!(xyz, ["NaN", "NaN", "NaN"]);
                nan_rows += 1;
            }
        }
    }
    assert!(nan_rows > 0, "the trial has gaps");
}

/// MOT rows on the same base as the TRC (first analog sample of frame 833 at 3.328 s), and
/// the OpenSim pair turned so that the plates' up (+z) is Y and the walk (+x here) is X.
#[test]
fn mot_and_opensim_share_the_time_base_and_stand_up() {
    let Some(path) = more("keenon__nimblephysics__JA1Gait35.c3d") else {
        return;
    };
    let c = c3dfix::open(&path).unwrap();
    assert_eq!(c.first_frame(), 833);
    let fp = c3dfix::force_platforms(&c, &ForceOptions::default()).unwrap();
    let mot = export::mot(&c, &fp, &path, &Axes::default()).unwrap();
    let rows: Vec<&str> = mot.lines().skip(7).collect();
    assert_eq!(rows.len(), fp.samples());
    assert!(rows[0].starts_with("3.328000\t"), "{}", rows[0]);
    let rate = c.analog_rate() as f64;
    let t1: f64 = rows[1].split('\t').next().unwrap().parse().unwrap();
    assert!((t1 - (3.328 + 1.0 / rate)).abs() < 1e-6);

    let up = c3dfix::axes::up(&c).unwrap();
    assert_eq!(up.up.to_string(), "+z");
    assert_eq!(up.source, c3dfix::UpSource::Plates);
    let dir = tempfile::tempdir().unwrap();
    let done = export::opensim(&c, &path, dir.path(), &OpenSimOptions::default()).unwrap();
    assert_eq!(done.axes.apply([0.0, 0.0, 1.0]), [0.0, 1.0, 0.0]);
    let trc = std::fs::read_to_string(&done.trc).unwrap();
    let mot = std::fs::read_to_string(done.mot.as_ref().unwrap()).unwrap();
    let trc_t: f64 = trc
        .lines()
        .nth(6)
        .unwrap()
        .split('\t')
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    let mot_t: f64 = mot
        .lines()
        .nth(7)
        .unwrap()
        .split('\t')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(trc_t, mot_t);
    // Written again only with force.
    assert!(export::opensim(&c, &path, dir.path(), &OpenSimOptions::default()).is_err());
    let again = OpenSimOptions {
        force: true,
        ..OpenSimOptions::default()
    };
    assert!(export::opensim(&c, &path, dir.path(), &again).is_ok());
}

/// An unknown POINT:UNITS is refused by the exports that must state SI units, with a typed
/// error naming the file, the parameter and the unit, and nothing written.
#[test]
fn an_unknown_unit_is_refused_for_opensim() {
    let Some(path) = more("keenon__nimblephysics__JA1Gait35.c3d") else {
        return;
    };
    let mut c = c3dfix::open(&path).unwrap();
    c.parameters
        .set_strings("POINT", "UNITS", &["furlong".to_string()])
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let e = export::opensim(&c, &path, dir.path(), &OpenSimOptions::default()).unwrap_err();
    match &e {
        c3dfix::Error::Unit {
            parameter, source, ..
        } => {
            assert_eq!(parameter, "POINT:UNITS");
            assert_eq!(source.unit, "furlong");
        }
        other => panic!("{other}"),
    }
    assert!(
        e.to_string()
            .contains("JA1Gait35.c3d: POINT:UNITS \"furlong\" is no length unit"),
        "{e}"
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    assert_eq!(c3dfix::units::metres_per(" M "), Ok(1.0));
}
