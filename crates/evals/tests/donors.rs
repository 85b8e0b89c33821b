//! The donors `auto`'s fills choose for a gap, as `repair::fill::gap_donors` opens them to
//! the evaluation (`fill_eval --donors` measures what they do around a gap), on a real
//! trial: a marker of a rigid cluster leans on its own cluster.

use evals::corpus;

use repair::fill::gap_donors;
use repair::FillOptions;

#[test]
fn a_shank_cluster_markers_gap_leans_on_its_own_cluster() {
    let Some(root) = testkit::c3d_samples() else {
        return;
    };
    let path = root.join("sample_01/Eb015pr.c3d");
    let mut trial = corpus::load(&path).expect("Eb015pr.c3d reads");
    let labels = c3d::read_file(&path)
        .expect("Eb015pr.c3d reads")
        .point_labels();
    assert_eq!(labels.len(), trial.markers(), "every point is a marker");
    let at = |l: &str| labels.iter().position(|x| x == l).expect("label");
    let m = at("RSK1");
    trial.valid[m][200..220].iter_mut().for_each(|v| *v = false);
    let d = gap_donors(&trial, m, 200, 219, &FillOptions::default());
    let names = |v: &[usize]| v.iter().map(|&j| labels[j].as_str()).collect::<Vec<_>>();
    // The rigid fill's three donors: the two shank markers whose distance to RSK1 varies
    // least around the gap, and a foot marker (the shank's skin moves RSK2 more).
    assert_eq!(names(&d.rigid), ["RSK3", "RFT3", "RSK4"]);
    assert_eq!(d.pattern.map(|j| labels[j].as_str()), Some("RSK3"));
    // The PCA fill's eight neighbours, nearest first: the rest of the shank cluster, then
    // the thigh and the foot, their weights falling with distance (0.94 to 0.46).
    let pca: Vec<usize> = d.pca.iter().map(|p| p.0).collect();
    assert_eq!(
        names(&pca),
        ["RSK3", "RSK2", "RSK4", "RTH3", "RTH4", "RFT2", "RTH1", "RTH2"]
    );
    assert!(d.pca.windows(2).all(|w| w[0].1 >= w[1].1));
    assert!((d.pca[0].1 - 0.944).abs() < 1e-3 && (d.pca[7].1 - 0.456).abs() < 1e-3);
    // Every donor is recorded through the gap and its anchors.
    for &j in d.rigid.iter().chain(&pca) {
        assert!(j != m && trial.valid[j][199..=220].iter().all(|&v| v));
    }
}
