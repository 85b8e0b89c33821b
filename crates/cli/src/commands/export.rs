//! `c3dfix export`: point data (and analog) as CSV, TRC or JSON; the force plates' ground
//! reaction as an OpenSim motion file (MOT).

use crate::commands::info::read_c3d;
use crate::console::{errln, out, outln};
use crate::output::{refuse_input, write_all, write_atomic, Content, Output};
use crate::plates::{metres_per, Axes};
use anyhow::{bail, Result};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum ExportFormat {
    Csv,
    Trc,
    Json,
    /// OpenSim's ground reaction motion file: per plate force (N), point (m) and free torque
    /// (N·m), one row per analog sample, time from 0; unloaded rows are 0 at the plate centre.
    Mot,
}

#[derive(clap::Args)]
pub struct Args {
    pub file: PathBuf,
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output file (default: standard output). For CSV with analog data, the analog samples
    /// go to a second file beside it, `<name>.analog.csv`.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Replace existing output files.
    #[arg(long)]
    pub force: bool,
    /// The lab axes as the output's X,Y,Z (TRC and MOT only), a rotation: e.g. `x,z,-y` for
    /// OpenSim's Y-up frame from a Z-up lab (X = lab x, Y = lab z, Z = −lab y). Default: the
    /// lab's axes as they are.
    #[arg(long)]
    pub axes: Option<String>,
}

pub fn run(a: Args) -> Result<i32> {
    if let Some(out) = &a.output {
        refuse_input(out, &[&a.file], "output")?;
    }
    let axes = match (&a.axes, a.format) {
        (None, _) => Axes::default(),
        (Some(spec), ExportFormat::Trc | ExportFormat::Mot) => Axes::parse(spec)?,
        (Some(_), _) => bail!("--axes applies to --format trc and mot only"),
    };
    let c = read_c3d(&a.file)?;
    match a.format {
        ExportFormat::Csv => {
            let pts = points_csv(&c);
            let ana = (c.analog().channels() > 0).then(|| analog_csv(&c));
            match &a.output {
                Some(out) => {
                    let ana_path = out.with_extension("analog.csv");
                    let mut outs = vec![Output {
                        path: out,
                        bytes: Content::Bytes(pts.as_bytes()),
                        replace: a.force,
                    }];
                    if let Some(text) = &ana {
                        refuse_input(&ana_path, &[&a.file], "analog output")?;
                        outs.push(Output {
                            path: &ana_path,
                            bytes: Content::Bytes(text.as_bytes()),
                            replace: a.force,
                        });
                    }
                    write_all(&outs)?;
                }
                None => {
                    out!("{pts}")?;
                    if let Some(text) = ana {
                        outln!()?;
                        out!("{text}")?;
                    }
                }
            }
        }
        ExportFormat::Trc => {
            let (text, changed) = trc(&c, &a.file, &axes);
            emit(&a.output, text, a.force)?;
            for l in changed {
                errln!("c3dfix: warning: {}: label {l:?} holds a tab or line break, which TRC cannot; written with spaces", a.file.display());
            }
        }
        ExportFormat::Json => emit(&a.output, json(&c)?, a.force)?,
        ExportFormat::Mot => {
            let fp = crate::plates::compute(&c)?;
            for w in &fp.warnings {
                errln!("c3dfix: warning: {}: {w}", a.file.display());
            }
            let text = mot(&fp, &a.file, &axes)?;
            emit(&a.output, text, a.force)?;
        }
    }
    Ok(0)
}

fn emit(out: &Option<PathBuf>, text: String, force: bool) -> Result<()> {
    match out {
        Some(p) => write_atomic(p, text.as_bytes(), force),
        None => {
            out!("{text}")?;
            Ok(())
        }
    }
}

fn time_of(c: &c3d::C3d, f: usize) -> f64 {
    let r = c.point_rate() as f64;
    if r > 0.0 {
        f as f64 / r
    } else {
        0.0
    }
}

/// A CSV field as RFC 4180 writes it: in double quotes, with quotes doubled, when it holds
/// a comma, a quote or a line break; as it is otherwise.
fn csv_field(f: &str) -> std::borrow::Cow<'_, str> {
    if f.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", f.replace('"', "\"\"")).into()
    } else {
        f.into()
    }
}

/// A label for a TRC header, where tabs separate fields and line breaks separate rows: those
/// characters become spaces. Also whether anything was replaced.
fn trc_label(l: &str) -> (String, bool) {
    let clean: String = l
        .chars()
        .map(|ch| {
            if matches!(ch, '\t' | '\n' | '\r') {
                ' '
            } else {
                ch
            }
        })
        .collect();
    let changed = clean != l;
    (clean, changed)
}

/// One row per frame: frame number, time, then X/Y/Z per marker; invalid samples are empty.
fn points_csv(c: &c3d::C3d) -> String {
    let p = c.points();
    let labels = c.point_labels();
    let mut s = String::from("Frame,Time");
    for l in &labels {
        for axis in ["X", "Y", "Z"] {
            let _ = write!(s, ",{}", csv_field(&format!("{l}_{axis}")));
        }
    }
    s.push('\n');
    let first = c.first_frame();
    for f in 0..p.frames() {
        let _ = write!(s, "{},{:.6}", first + f, time_of(c, f));
        for i in 0..p.count() {
            if p.is_valid(f, i) {
                let [x, y, z] = p.xyz[p.index(f, i)];
                let _ = write!(s, ",{x},{y},{z}");
            } else {
                s.push_str(",,,");
            }
        }
        s.push('\n');
    }
    s
}

/// One row per analog sample, in physical units.
fn analog_csv(c: &c3d::C3d) -> String {
    let a = c.analog();
    let labels = c.analog_labels();
    let units = c.analog_units();
    let phys = c.analog_physical();
    let rate = c.analog_rate() as f64;
    let mut s = String::from("Sample,Time");
    for (l, u) in labels.iter().zip(&units) {
        let name = if u.is_empty() {
            l.clone()
        } else {
            format!("{l} ({u})")
        };
        let _ = write!(s, ",{}", csv_field(&name));
    }
    s.push('\n');
    for k in 0..a.samples() {
        let t = if rate > 0.0 { k as f64 / rate } else { 0.0 };
        let _ = write!(s, "{},{t:.6}", k + 1);
        for ch in 0..a.channels() {
            let _ = write!(s, ",{}", phys[k * a.channels() + ch]);
        }
        s.push('\n');
    }
    s
}

/// The Motion Analysis TRC text format (PathFileType 4, X/Y/Z); invalid samples are empty.
/// Also the labels that had to be changed to fit it.
fn trc(c: &c3d::C3d, path: &Path, axes: &Axes) -> (String, Vec<String>) {
    let p = c.points();
    let labels = c.point_labels();
    let rate = c.point_rate();
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let (name, _) = trc_label(&name);
    let units = trc_label(&c.point_units()).0;
    let mut changed = Vec::new();
    let mut s = format!("PathFileType\t4\t(X/Y/Z)\t{name}\n");
    s.push_str("DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n");
    let first = c.first_frame();
    let _ = writeln!(
        s,
        "{rate}\t{rate}\t{}\t{}\t{}\t{rate}\t{first}\t{}",
        p.frames(),
        p.count(),
        units,
        p.frames()
    );
    s.push_str("Frame#\tTime");
    for l in &labels {
        let (clean, was_changed) = trc_label(l);
        if was_changed {
            changed.push(l.clone());
        }
        let _ = write!(s, "\t{clean}\t\t");
    }
    s.push_str("\n\t");
    for i in 1..=p.count() {
        let _ = write!(s, "\tX{i}\tY{i}\tZ{i}");
    }
    s.push_str("\n\n");
    for f in 0..p.frames() {
        let _ = write!(s, "{}\t{:.6}", first + f, time_of(c, f));
        for i in 0..p.count() {
            if p.is_valid(f, i) {
                let [x, y, z] = axes.apply_f32(p.xyz[p.index(f, i)]);
                let _ = write!(s, "\t{x}\t{y}\t{z}");
            } else {
                s.push_str("\t\t\t");
            }
        }
        s.push('\n');
    }
    (s, changed)
}

/// Per-marker arrays (null for invalid samples) and per-channel analog arrays.
fn json(c: &c3d::C3d) -> Result<String> {
    let p = c.points();
    let labels = c.point_labels();
    let markers: Vec<_> = (0..p.count())
        .map(|i| {
            let xyz: Vec<Option<[f32; 3]>> = (0..p.frames())
                .map(|f| p.is_valid(f, i).then(|| p.xyz[p.index(f, i)]))
                .collect();
            serde_json::json!({"label": labels[i], "xyz": xyz, "residual": p.residuals(i)})
        })
        .collect();
    let a = c.analog();
    let phys = c.analog_physical();
    let units = c.analog_units();
    let channels: Vec<_> = c
        .analog_labels()
        .into_iter()
        .enumerate()
        .map(|(ch, l)| {
            let v: Vec<f32> = phys
                .iter()
                .skip(ch)
                .step_by(a.channels().max(1))
                .copied()
                .collect();
            serde_json::json!({"label": l, "units": units[ch], "values": v})
        })
        .collect();
    let v = serde_json::json!({
        "point_rate": c.point_rate(),
        "first_frame": c.first_frame(),
        "frames": p.frames(),
        "units": c.point_units(),
        "markers": markers,
        "analog": {"rate": c.analog_rate(), "channels": channels},
        "events": c.events(),
    });
    Ok(serde_json::to_string(&v)? + "\n")
}

/// OpenSim's ground reaction motion file (the `.mot` its ExternalLoads read): `time`, then per
/// plate K (numbered as FORCE_PLATFORM numbers it) `ground_force_K_v{x,y,z}` in N,
/// `ground_force_K_p{x,y,z}` (the COP) in m and `ground_torque_K_{x,y,z}` (the free moment)
/// in N·m, one row per analog sample, time from 0 at ANALOG:RATE.
///
/// OpenSim takes no NaN: where a plate carries less than the threshold the COP is undefined,
/// and the row says "no load" — force and torque 0, the point at the plate's centre, so that
/// a force applied there is nothing.
fn mot(fp: &c3dfix::ForcePlatforms, path: &Path, axes: &Axes) -> Result<String> {
    let Some(first) = fp.platforms.first() else {
        bail!(
            "{}: no force platforms{}: nothing to write as MOT",
            path.display(),
            if fp.warnings.is_empty() {
                ""
            } else {
                " could be computed (see the warnings)"
            }
        );
    };
    let rate = first.rate;
    if !(rate > 0.0 && rate.is_finite()) {
        bail!(
            "{}: ANALOG:RATE is {rate}: MOT needs a time for each sample",
            path.display()
        );
    }
    let mut scales = Vec::new();
    for p in &fp.platforms {
        let m = match metres_per(&p.units.position) {
            Some(m) => m,
            None => bail!(
                "{}: POINT:UNITS {:?} is no length unit c3dfix knows (mm, cm, dm, m, in): cannot write metres",
                path.display(),
                p.units.position
            ),
        };
        scales.push(m);
    }
    let rows = fp.samples();
    let columns = 1 + 9 * fp.platforms.len();
    let stem = path
        .file_stem()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut s = format!(
        "name {}\nversion=1\nnRows={rows}\nnColumns={columns}\ninDegrees=yes\nendheader\ntime",
        trc_label(&stem).0
    );
    for p in &fp.platforms {
        let k = p.index;
        for q in ["vx", "vy", "vz", "px", "py", "pz"] {
            write!(s, "\tground_force_{k}_{q}")?;
        }
        for q in ["x", "y", "z"] {
            write!(s, "\tground_torque_{k}_{q}")?;
        }
    }
    s.push('\n');
    for i in 0..rows {
        write!(s, "{:.6}", i as f64 / rate)?;
        for (p, &m) in fp.platforms.iter().zip(&scales) {
            let at = |v: &[[f64; 3]]| v.get(i).copied().unwrap_or([f64::NAN; 3]);
            let (force, cop, torque) = (at(&p.force), at(&p.cop), at(&p.free_moment));
            let loaded = [force, cop, torque].iter().flatten().all(|x| x.is_finite());
            let (force, point, torque) = if loaded {
                (force, cop.map(|x| x * m), torque.map(|x| x * m))
            } else {
                ([0.0; 3], p.centre.map(|x| x * m), [0.0; 3])
            };
            for v in [force, point, torque] {
                for x in axes.apply(v) {
                    // A rotated 0 may be a negative zero: written as 0.
                    write!(s, "\t{:.6}", x + 0.0)?;
                }
            }
        }
        s.push('\n');
    }
    Ok(s)
}
