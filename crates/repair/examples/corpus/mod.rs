//! A corpus trial's markers as a repair `Trial` in mm, shared by the `fill_eval` example
//! and the `fill_eval` bench.

use repair::Trial;

/// The file's markers (points that are not model outputs) as a trial in mm.
///
/// A sample at exactly (0, 0, 0) counts as missing here, whatever its residual says: no
/// marker sits on the lab's origin to the last bit, and the writers that store such samples
/// mean a lost one (ART-Human sets every point of a frame where the body was lost there;
/// Vicon's files hold them in virtual markers it could not compute). As the truth of an
/// artificial gap such a sample would score a fill against the origin: 206 of the 353 gaps
/// of `arthuman-sample.c3d` touched its one such frame, the only stretches there not
/// skipped as computed points (the frame breaks their constant distances).
pub fn load(path: &std::path::Path) -> Result<Trial, String> {
    load_with(path, false)
}

/// [`load`], with samples of residual 0 (the C3D manual's mark for processed points: the
/// capture software's fills) counted as missing when the file has any residual above 0.
#[allow(dead_code)]
pub fn load_recorded(path: &std::path::Path) -> Result<Trial, String> {
    load_with(path, true)
}

fn load_with(path: &std::path::Path, recorded: bool) -> Result<Trial, String> {
    let c = c3d::read_file(path).map_err(|e| e.to_string())?;
    let outputs = c.model_output_labels();
    let k = c3d::mm_per_unit(&c.point_units());
    let p = c.points();
    let markers: Vec<usize> = (0..c.point_labels().len())
        .filter(|&i| !outputs.contains(&c.point_labels()[i]))
        .collect();
    let drop_processed = recorded
        && markers.iter().any(|&i| {
            let r = p.residuals(i);
            (0..p.frames()).any(|f| p.is_valid(f, i) && r[f] > 0.0)
        });
    let (mut xyz, mut valid) = (Vec::new(), Vec::new());
    for (i, l) in c.point_labels().iter().enumerate() {
        if outputs.contains(l) {
            continue;
        }
        let r = p.residuals(i);
        let t = p.trajectory(i);
        let v: Vec<bool> = (0..p.frames())
            .map(|f| p.is_valid(f, i) && !(drop_processed && r[f] == 0.0) && t[f] != [0.0; 3])
            .collect();
        if !v.iter().any(|&x| x) {
            continue;
        }
        xyz.push(
            t.iter()
                .map(|q| [q[0] as f64 * k, q[1] as f64 * k, q[2] as f64 * k])
                .collect(),
        );
        valid.push(v);
    }
    Trial::new(c.point_rate() as f64, xyz, valid).map_err(|e| e.to_string())
}
