//! Filter designs and filtfilt against scipy's numbers (reference/make_reference.py).

use serde_json::Value;
use signal::Iir;

fn reference() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference/filters.json");
    let text = std::fs::read_to_string(path).expect("reference/filters.json is committed");
    serde_json::from_str(&text).expect("valid JSON")
}

fn vec_of(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

fn design(c: &Value) -> Iir {
    let order = c["order"].as_u64().expect("order") as usize;
    let cutoff = c["cutoff_hz"].as_f64().expect("cutoff");
    let fs = c["fs"].as_f64().expect("fs");
    match c["kind"].as_str() {
        Some("butter") => Iir::butterworth(order, cutoff, fs).expect("valid design"),
        Some("cheby2") => {
            let atten = c["atten_db"].as_f64().expect("atten");
            Iir::cheby2(order, cutoff, atten, fs).expect("valid design")
        }
        k => panic!("unknown kind {k:?}"),
    }
}

/// Largest difference relative to the largest reference magnitude.
fn rel_err(got: &[f64], want: &[f64]) -> f64 {
    assert_eq!(got.len(), want.len());
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    got.iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn coefficients_match_scipy() {
    let r = reference();
    let designs = r["designs"].as_array().expect("designs");
    assert!(designs.len() > 100);
    let mut worst = 0.0f64;
    for c in designs {
        let f = design(c);
        let (b, a) = (vec_of(&c["b"]), vec_of(&c["a"]));
        let e = rel_err(&f.b, &b).max(rel_err(&f.a, &a));
        assert!(e < 1e-9, "{c:?}: rel err {e}");
        worst = worst.max(e);
    }
    eprintln!("worst coefficient rel error {worst:e}");
}

#[test]
fn filtfilt_matches_scipy() {
    let r = reference();
    let cases = r["filtfilt"].as_array().expect("filtfilt");
    let mut worst = 0.0f64;
    for c in cases {
        let f = design(c);
        let mut x = vec_of(&c["x"]);
        let y = vec_of(&c["y"]);
        f.filtfilt(&mut x).expect("long enough");
        let e = rel_err(&x, &y);
        assert!(
            e < 1e-9,
            "{} order {} {}: rel err {e}",
            c["kind"],
            c["order"],
            c["signal"]
        );
        worst = worst.max(e);
    }
    eprintln!(
        "worst filtfilt rel error {worst:e} over {} cases",
        cases.len()
    );
}

#[test]
fn filtfilt_refuses_padlen_samples() {
    let f = Iir::butterworth(4, 6.0, 100.0).unwrap();
    assert_eq!(f.padlen(), 15);
    let mut x = vec![1.0; 15];
    assert!(matches!(
        f.filtfilt(&mut x),
        Err(signal::FilterError::TooShort {
            len: 15,
            padlen: 15
        })
    ));
    let mut x = vec![1.0; 16];
    f.filtfilt(&mut x).unwrap();
    assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-12));
}
