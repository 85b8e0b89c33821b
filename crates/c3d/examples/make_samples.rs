//! Generates the demo trials in `sample_c3d/` with the project's own writer:
//! `cargo run -p c3d --example make_samples -- sample_c3d`.
//!
//! A synthetic walking trial with Plug-in Gait marker names: a pelvis walking forward at
//! 1.2 m/s, legs and arms swinging at 0.9 strides per second, markers fixed on their
//! segments. `walk_truth.c3d` holds the clean motion; `walk_int.c3d` and `walk_float.c3d` the
//! same motion with 0.4 mm noise, a few spikes, and gaps marked by residual −1 — the defects
//! c3dfix repairs, with the truth beside them to measure the repair against.

use c3d::{Analog, C3d, NumberFormat, Parameters, Points, Processor, Value};
use std::f64::consts::PI;

const RATE: f64 = 100.0;
const FRAMES: usize = 400;
const ANALOG_SPF: usize = 10;
/// The EMG-like analog channels of every trial.
const EMG_CHANNELS: usize = 4;

#[path = "common/rng.rs"]
mod rng;
use rng::Rng;

type V3 = [f64; 3];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Rotate `v` about the medio-lateral (y) axis by `a` radians (sagittal-plane flexion).
fn rot_y(v: V3, a: f64) -> V3 {
    let (s, c) = a.sin_cos();
    [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]]
}

/// Rotate `v` about the vertical (z) axis.
fn rot_z(v: V3, a: f64) -> V3 {
    let (s, c) = a.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

struct Leg {
    hip: V3,
    phase: f64,
    side: f64,
}

/// Marker positions of one leg at gait phase `t` (radians), relative to the pelvis.
fn leg(l: &Leg, t: f64) -> [(&'static str, V3); 6] {
    let p = t + l.phase;
    let hip = 0.45 * p.sin() + 0.1;
    let knee = -(0.55 * (1.0 - (p + 0.6).cos()) / 2.0 + 0.08);
    let ankle = 0.2 * (p - 0.8).sin();
    let thigh = |v: V3| add(l.hip, rot_y(v, hip));
    let knee_c = thigh([0.0, 0.0, -420.0]);
    let shank = |v: V3| add(knee_c, rot_y(v, hip + knee));
    let ankle_c = shank([0.0, 0.0, -400.0]);
    let foot = |v: V3| add(ankle_c, rot_y(v, hip + knee + ankle));
    let s = l.side;
    [
        ("THI", thigh([0.0, s * 70.0, -220.0])),
        ("KNE", thigh([0.0, s * 55.0, -420.0])),
        ("TIB", shank([0.0, s * 60.0, -200.0])),
        ("ANK", shank([0.0, s * 40.0, -400.0])),
        ("HEE", foot([-60.0, 0.0, -40.0])),
        ("TOE", foot([140.0, s * 10.0, -50.0])),
    ]
}

/// All markers (name, position in mm) at frame `f`.
fn markers(f: usize) -> Vec<(String, V3)> {
    let time = f as f64 / RATE;
    let t = 2.0 * PI * 0.9 * time;
    let pelvis = [1200.0 * time - 2400.0, 0.0, 950.0 + 12.0 * (2.0 * t).cos()];
    let yaw = 0.06 * t.sin();
    let on_pelvis = |v: V3| add(pelvis, rot_z(v, yaw));
    let mut out: Vec<(String, V3)> = Vec::new();
    for (n, v) in [
        ("LASI", [80.0, 120.0, 0.0]),
        ("RASI", [80.0, -120.0, 0.0]),
        ("LPSI", [-90.0, 50.0, 20.0]),
        ("RPSI", [-90.0, -50.0, 20.0]),
    ] {
        out.push((n.into(), on_pelvis(v)));
    }
    for (side, s, phase) in [("L", 1.0, PI), ("R", -1.0, 0.0)] {
        let l = Leg {
            hip: [0.0, s * 90.0, -80.0],
            phase,
            side: s,
        };
        for (n, v) in leg(&l, t) {
            out.push((format!("{side}{n}"), on_pelvis(v)));
        }
    }
    // Trunk, head and arms: rigid trunk leaning slightly, arms swinging against the legs.
    let trunk = |v: V3| on_pelvis(rot_y(v, 0.05 + 0.02 * (2.0 * t).sin()));
    for (n, v) in [
        ("C7", [-60.0, 0.0, 520.0]),
        ("T10", [-90.0, 0.0, 300.0]),
        ("CLAV", [80.0, 0.0, 470.0]),
        ("STRN", [110.0, 0.0, 330.0]),
        ("RBAK", [-80.0, -80.0, 400.0]),
        ("LFHD", [90.0, 60.0, 700.0]),
        ("RFHD", [90.0, -60.0, 700.0]),
        ("LBHD", [-60.0, 60.0, 680.0]),
        ("RBHD", [-60.0, -60.0, 680.0]),
    ] {
        out.push((n.into(), trunk(v)));
    }
    for (side, s, phase) in [("L", 1.0, 0.0), ("R", -1.0, PI)] {
        let sho = [0.0, s * 180.0, 500.0];
        let swing = 0.3 * (t + phase).sin();
        let elbow = -0.3 - 0.15 * (t + phase).sin();
        let upper = |v: V3| trunk(add(sho, rot_y(v, swing)));
        let elb = upper([0.0, 0.0, -290.0]);
        let wrist = |v: V3| add(elb, rot_y(v, swing + elbow));
        out.push((format!("{side}SHO"), trunk(sho)));
        out.push((format!("{side}ELB"), upper([-20.0, s * 30.0, -290.0])));
        out.push((format!("{side}WRA"), wrist([25.0, s * 20.0, -260.0])));
        out.push((format!("{side}WRB"), wrist([-25.0, s * 20.0, -260.0])));
        out.push((format!("{side}FIN"), wrist([0.0, s * 10.0, -340.0])));
    }
    out
}

/// (marker, first frame, length) of the gaps written into the defect trials.
const GAPS: &[(&str, usize, usize)] = &[
    ("LTOE", 40, 12),
    ("LTOE", 250, 30),
    ("RHEE", 120, 25),
    ("RTIB", 10, 8),
    ("LWRA", 300, 45),
    ("RFIN", 0, 15),
    ("LASI", 180, 6),
    ("RKNE", 330, 60),
    ("CLAV", 200, 20),
];

/// (marker, frame, displacement in mm along x, y, z) of the spikes.
const SPIKES: &[(&str, usize, V3)] = &[
    ("LKNE", 75, [35.0, 0.0, 0.0]),
    ("RANK", 150, [0.0, -40.0, 10.0]),
    ("STRN", 222, [0.0, 0.0, 50.0]),
];

fn build(defects: bool, scale: f32, processor: Processor) -> Result<C3d, c3d::Error> {
    let names: Vec<String> = markers(0).into_iter().map(|(n, _)| n).collect();
    let mut rng = Rng(0x00C3_DF1C);
    let pts = points(&names, defects, scale, &mut rng)?;
    let analog = analog(&mut rng);
    let ps = parameters(&names, scale, EMG_CHANNELS)?;
    let stride = 1.0 / 0.9;
    let mut c = C3d::new(pts, analog, ps, processor, scale);
    c.header.frame_rate = RATE as f32;
    c.header.first_frame = 1;
    c.header.event_count = 2;
    c.header.event_times[0] = 0.3;
    c.header.event_labels[0] = *b"RFS ";
    c.header.event_times[1] = 0.3 + (stride / 2.0) as f32;
    c.header.event_labels[1] = *b"LFS ";
    Ok(c)
}

/// The markers' samples: the motion, with noise, gaps and spikes in a defect trial, stored
/// as a file of `scale` holds them.
fn points(
    names: &[String],
    defects: bool,
    scale: f32,
    rng: &mut Rng,
) -> Result<Points, c3d::Error> {
    let n = names.len();
    let mut pts = Points::new(FRAMES, n);
    for f in 0..FRAMES {
        for (i, (_, p)) in markers(f).into_iter().enumerate() {
            let k = pts.index(f, i);
            let noise = if defects { 0.4 } else { 0.0 };
            let v = [
                p[0] + noise * rng.gauss(),
                p[1] + noise * rng.gauss(),
                p[2] + noise * rng.gauss(),
            ];
            pts.xyz[k] = [v[0] as f32, v[1] as f32, v[2] as f32];
            // Residual about 0.9 mm; seen by cameras 1, 2 and 4 (or 2, 3, 5).
            pts.residual[k] = (0.8 + 0.2 * rng.next()) as f32;
            pts.camera_mask[k] = if (f / 50 + i) % 2 == 0 {
                0b1011
            } else {
                0b10110
            };
        }
    }
    if defects {
        for &(m, first, len) in GAPS {
            let i = names
                .iter()
                .position(|x| x == m)
                .ok_or_else(|| c3d::Error::Misuse(format!("gap on unknown marker {m}")))?;
            for f in first..(first + len).min(FRAMES) {
                let k = pts.index(f, i);
                pts.xyz[k] = [0.0; 3];
                pts.residual[k] = -1.0;
                pts.camera_mask[k] = 0;
            }
        }
        for &(m, f, d) in SPIKES {
            if let Some(i) = names.iter().position(|x| x == m) {
                let k = pts.index(f, i);
                for (v, dv) in pts.xyz[k].iter_mut().zip(d) {
                    *v += dv as f32;
                }
            }
        }
    }
    if scale > 0.0 {
        // Quantize as the integer file stores it (the float variant keeps full precision).
        for k in 0..pts.xyz.len() {
            for a in 0..3 {
                pts.xyz[k][a] = (pts.xyz[k][a] / scale).round() * scale;
            }
            if pts.residual[k] >= 0.0 {
                pts.residual[k] = (pts.residual[k] / scale).round().clamp(0.0, 255.0) * scale;
            }
        }
    } else {
        for k in 0..pts.residual.len() {
            if pts.residual[k] >= 0.0 {
                pts.residual[k] =
                    (pts.residual[k] / scale.abs()).round().clamp(0.0, 255.0) * scale.abs();
            }
        }
    }
    Ok(pts)
}

/// Four EMG-like channels at 1000 Hz: bursts timed with the gait cycle, in raw ADC counts.
fn analog(rng: &mut Rng) -> Analog {
    let channels = EMG_CHANNELS;
    let mut analog = Analog::new(FRAMES, channels, ANALOG_SPF);
    for s in 0..FRAMES * ANALOG_SPF {
        let time = s as f64 / (RATE * ANALOG_SPF as f64);
        let t = 2.0 * PI * 0.9 * time;
        for c in 0..channels {
            let env = (0.5 + 0.5 * (t + c as f64 * PI / 2.0).sin()).powi(4);
            let v = 800.0 * env * rng.gauss() + 20.0 * rng.gauss();
            analog.raw[s * channels + c] = v.round().clamp(-32768.0, 32767.0) as f32;
        }
    }
    analog
}

/// The parameters: points, analog channels, trial range, subject, foot strikes, maker.
fn parameters(names: &[String], scale: f32, channels: usize) -> Result<Parameters, c3d::Error> {
    let n = names.len();
    let mut ps = Parameters::new();
    ps.set_i16("POINT", "USED", n as i16)?;
    ps.set_f32("POINT", "SCALE", scale)?;
    ps.set_f32("POINT", "RATE", RATE as f32)?;
    ps.set_i16("POINT", "DATA_START", 0)?;
    ps.set_i16("POINT", "FRAMES", FRAMES as i16)?;
    ps.set_strings("POINT", "LABELS", names)?;
    let desc: Vec<String> = names
        .iter()
        .map(|m| format!("Plug-in Gait marker {m}"))
        .collect();
    ps.set_strings("POINT", "DESCRIPTIONS", &desc)?;
    ps.set_strings("POINT", "UNITS", &["mm".into()])?;
    ps.set_i16("ANALOG", "USED", channels as i16)?;
    let alabels: Vec<String> = ["EMG_LTA", "EMG_LGAS", "EMG_RTA", "EMG_RGAS"]
        .map(String::from)
        .to_vec();
    ps.set_strings("ANALOG", "LABELS", &alabels)?;
    ps.set_strings(
        "ANALOG",
        "DESCRIPTIONS",
        &alabels
            .iter()
            .map(|l| format!("EMG {l}"))
            .collect::<Vec<_>>(),
    )?;
    ps.set(
        "ANALOG",
        "SCALE",
        vec![channels as u8],
        Value::Float(vec![0.000_305_2; channels]),
    )?;
    ps.set(
        "ANALOG",
        "OFFSET",
        vec![channels as u8],
        Value::Int(vec![0; channels]),
    )?;
    ps.set_strings("ANALOG", "UNITS", &vec!["V".to_string(); channels])?;
    ps.set_f32("ANALOG", "RATE", (RATE * ANALOG_SPF as f64) as f32)?;
    ps.set_f32("ANALOG", "GEN_SCALE", 1.0)?;
    ps.set_strings("ANALOG", "FORMAT", &["SIGNED".into()])?;
    ps.set_i16("ANALOG", "BITS", 16)?;
    ps.set(
        "TRIAL",
        "ACTUAL_START_FIELD",
        vec![2],
        Value::Int(vec![1, 0]),
    )?;
    ps.set(
        "TRIAL",
        "ACTUAL_END_FIELD",
        vec![2],
        Value::Int(vec![FRAMES as i16, 0]),
    )?;
    ps.set_strings("SUBJECTS", "NAMES", &["Synthetic".into()])?;
    ps.set_i16("SUBJECTS", "USES_PREFIXES", 0)?;
    // Foot strikes: left and right alternate every half stride (1 / 0.9 s per stride).
    let stride = 1.0 / 0.9;
    let mut times = Vec::new();
    let mut contexts = Vec::new();
    for k in 0..7 {
        let t = 0.3 + k as f64 * stride / 2.0;
        times.extend([0.0f32, t as f32]);
        contexts.push(if k % 2 == 0 { "Right" } else { "Left" }.to_string());
    }
    let ne = contexts.len();
    ps.set_i16("EVENT", "USED", ne as i16)?;
    ps.set("EVENT", "TIMES", vec![2, ne as u8], Value::Float(times))?;
    ps.set_strings("EVENT", "CONTEXTS", &contexts)?;
    ps.set_strings("EVENT", "LABELS", &vec!["Foot Strike".to_string(); ne])?;
    ps.set_strings("MANUFACTURER", "COMPANY", &["c3dfix".into()])?;
    ps.set_strings("MANUFACTURER", "SOFTWARE", &["c3dfix make_samples".into()])?;
    Ok(ps)
}

/// The trials: (file name, with defects, POINT:SCALE, processor).
pub const TRIALS: &[(&str, bool, f32, Processor)] = &[
    ("walk_truth.c3d", false, -0.1, Processor::Intel),
    ("walk_float.c3d", true, -0.1, Processor::Intel),
    ("walk_int.c3d", true, 0.1, Processor::Intel),
];

/// The bytes of one trial of [`TRIALS`].
pub fn trial_bytes(defects: bool, scale: f32, processor: Processor) -> Result<Vec<u8>, c3d::Error> {
    let c = build(defects, scale, processor)?;
    let fmt = if scale < 0.0 {
        NumberFormat::Float
    } else {
        NumberFormat::Integer
    };
    c.convert(processor, fmt, Some(scale))
}

#[allow(dead_code)] // unused when a test includes this file as a module
fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "sample_c3d".into());
    for &(name, defects, scale, processor) in TRIALS {
        match trial_bytes(defects, scale, processor) {
            Ok(b) => {
                let path = std::path::Path::new(&dir).join(name);
                if let Err(e) = std::fs::write(&path, b) {
                    eprintln!("{}: {e}", path.display());
                    std::process::exit(2);
                }
                println!("wrote {}", path.display());
            }
            Err(e) => {
                eprintln!("{name}: {e}");
                std::process::exit(2);
            }
        }
    }
}
