//! The large generated trial of the memory and speed measurements of long recordings:
//! 100 000 frames × 100 markers of float data with 4 analog channels (about 162 MB). Shared
//! by `examples/make_big.rs`, the read/write bench and the memory test (through `#[path]`).
//!
//! The markers sit in clusters of four on 25 rigid segments that move smoothly (so gap
//! fills have donors to work with), carry 0.3 mm of noise, and lose sight of the cameras in
//! gaps of 5–60 frames, about 1.5 % of the samples, stored as the C3D manual says (fourth
//! word −1). The content is reproducible byte for byte.

use c3d::{Analog, C3d, NumberFormat, Parameters, Points, Processor, Value};

pub const FRAMES: usize = 100_000;
pub const MARKERS: usize = 100;
const CHANNELS: usize = 4;
const RATE: f32 = 100.0;

#[path = "rng.rs"]
mod rng;
use rng::Rng;

/// Position of marker `i` at time `t` (s): segment `i / 4` translates and turns about z.
fn marker(i: usize, t: f64) -> [f64; 3] {
    let seg = (i / 4) as f64;
    let w = 0.7 + 0.05 * seg;
    let centre = [
        300.0 * (w * t).sin() + 40.0 * seg,
        200.0 * (0.5 * w * t + seg).cos(),
        900.0 + 20.0 * seg + 50.0 * (2.0 * w * t).sin(),
    ];
    let a = 0.6 * (0.8 * w * t + seg).sin();
    let local = [
        [60.0, 0.0, 0.0],
        [0.0, 60.0, 0.0],
        [-50.0, -20.0, 30.0],
        [10.0, -40.0, -60.0],
    ][i % 4];
    let (s, c) = a.sin_cos();
    [
        centre[0] + c * local[0] - s * local[1],
        centre[1] + s * local[0] + c * local[1],
        centre[2] + local[2],
    ]
}

/// The trial's bytes.
pub fn big_trial() -> Result<Vec<u8>, c3d::Error> {
    let mut rng = Rng(0xB16_C3D);
    let mut pts = Points::new(FRAMES, MARKERS);
    for f in 0..FRAMES {
        let t = f as f64 / RATE as f64;
        for i in 0..MARKERS {
            let k = pts.index(f, i);
            let p = marker(i, t);
            let mut noise = || 0.3 * (rng.next() + rng.next() + rng.next() - 1.5) * 2.0;
            pts.xyz[k] = [
                (p[0] + noise()) as f32,
                (p[1] + noise()) as f32,
                (p[2] + noise()) as f32,
            ];
            pts.residual[k] = 0.5;
            pts.camera_mask[k] = 0b101_0110;
        }
    }
    // Gaps: each marker loses sight about once every 2 000 frames, for 5–60 frames.
    for i in 0..MARKERS {
        let mut f = (rng.next() * 2000.0) as usize;
        while f < FRAMES {
            let len = 5 + (rng.next() * 56.0) as usize;
            for g in f..(f + len).min(FRAMES) {
                let k = pts.index(g, i);
                pts.xyz[k] = [0.0; 3];
                pts.residual[k] = -1.0;
                pts.camera_mask[k] = 0;
            }
            f += len + 1000 + (rng.next() * 2000.0) as usize;
        }
    }
    let mut analog = Analog::new(FRAMES, CHANNELS, 1);
    for (j, v) in analog.raw.iter_mut().enumerate() {
        let (f, ch) = (j / CHANNELS, j % CHANNELS);
        *v = (100.0 * ((f as f64) * 0.01 * (ch + 1) as f64).sin()) as f32;
    }
    let mut ps = Parameters::new();
    let labels: Vec<String> = (1..=MARKERS).map(|i| format!("M{i:03}")).collect();
    let alabels: Vec<String> = (1..=CHANNELS).map(|i| format!("EMG{i}")).collect();
    let set = ps
        .set_f32("POINT", "RATE", RATE)
        .and_then(|_| ps.set_strings("POINT", "LABELS", &labels))
        .and_then(|_| ps.set_strings("POINT", "UNITS", &["mm".to_string()]))
        .and_then(|_| ps.set_f32("ANALOG", "RATE", RATE))
        .and_then(|_| ps.set_strings("ANALOG", "LABELS", &alabels))
        .and_then(|_| ps.set_f32("ANALOG", "GEN_SCALE", 1.0))
        .and_then(|_| {
            let n = CHANNELS as u8;
            ps.set(
                "ANALOG",
                "SCALE",
                vec![n],
                Value::Float(vec![1.0; CHANNELS]),
            )?;
            ps.set("ANALOG", "OFFSET", vec![n], Value::Int(vec![0; CHANNELS]))?;
            ps.set_strings("ANALOG", "UNITS", &vec!["V".to_string(); CHANNELS])
        });
    set.and_then(|_| {
        C3d::new(pts, analog, ps, Processor::Intel, -0.1).convert(
            Processor::Intel,
            NumberFormat::Float,
            None,
        )
    })
}
