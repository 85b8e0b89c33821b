//! A corpus trial's markers as a repair `Trial` in mm, shared by the `fill_eval` example
//! and the `fill_eval` bench.

use repair::Trial;

/// The file's markers (points that are not model outputs) as a trial in mm.
pub fn load(path: &std::path::Path) -> Result<Trial, String> {
    let c = c3d::read_file(path).map_err(|e| e.to_string())?;
    let outputs = c.model_output_labels();
    let k = c3d::mm_per_unit(&c.point_units());
    let p = c.points();
    let (mut xyz, mut valid) = (Vec::new(), Vec::new());
    for (i, l) in c.point_labels().iter().enumerate() {
        if outputs.contains(l) {
            continue;
        }
        let v: Vec<bool> = (0..p.frames()).map(|f| p.is_valid(f, i)).collect();
        if !v.iter().any(|&x| x) {
            continue;
        }
        xyz.push(
            p.trajectory(i)
                .iter()
                .map(|q| [q[0] as f64 * k, q[1] as f64 * k, q[2] as f64 * k])
                .collect(),
        );
        valid.push(v);
    }
    Trial::new(c.point_rate() as f64, xyz, valid).map_err(|e| e.to_string())
}
