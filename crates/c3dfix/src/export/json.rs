//! The whole trial as one JSON document.

use crate::error::{Error, Result};

/// Per-point arrays (null for missing samples) of `points` (indices), each saying whether it
/// is a model output, and per-channel analog arrays in physical units.
pub fn json(c: &c3d::C3d, points: &[usize]) -> Result<String> {
    let p = c.points();
    let labels = c.point_labels();
    let outputs = crate::markers::model_outputs(c);
    let markers: Vec<_> = points
        .iter()
        .map(|&i| {
            let xyz: Vec<Option<[f32; 3]>> = (0..p.frames())
                .map(|f| p.is_valid(f, i).then(|| p.xyz[p.index(f, i)]))
                .collect();
            let label = labels.get(i).cloned().unwrap_or_default();
            let mut v = serde_json::json!({"label": label, "xyz": xyz, "residual": p.residuals(i)});
            if outputs.contains(&label) {
                v["model_output"] = serde_json::Value::Bool(true);
            }
            v
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
            serde_json::json!({"label": l, "units": units.get(ch), "values": v})
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
    serde_json::to_string(&v)
        .map(|s| s + "\n")
        .map_err(|e| Error::Output(format!("cannot encode the trial as JSON: {e}")))
}
