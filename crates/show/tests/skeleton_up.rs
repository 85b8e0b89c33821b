//! A BVH skeleton stands on the up the library's marker rule gives its joints
//! (`c3dfix::axes::points_up`), the one rule C3D trials without plates use too.

/// The page's `"up":A,"up_positive":B` for a BVH file of the corpus.
fn page_up(name: &str) -> Option<String> {
    let dir = testkit::bvh_samples()?;
    let b = bvh::read(&dir.join(name)).unwrap();
    let html = show::view::skeleton::page((&b, name), None).unwrap();
    let at = html.find("\"up\":")?;
    let end = html[at..].find(",\"fills_marked\"")?;
    Some(html[at..at + end].to_string())
}

#[test]
fn the_corpus_skeletons_stand_on_plus_y_but_one() {
    // (file, axis): 1 is y. fairmotion_pfnn_hierarchy's joints spread furthest along x, and
    // no floor shows, so the rule says x (as the viewer's own spread rule said before).
    let names = [
        ("bandai_dataset-1_bow_active_001.bvh", 1),
        ("bandai_dataset-2_wave-left-hand_active_011.bvh", 1),
        ("bvhpython_test_freebvh.bvh", 1),
        ("bvhtoolbox_walk01.bvh", 1),
        ("fairmotion_cmu_01_01.bvh", 1),
        ("fairmotion_pfnn_hierarchy.bvh", 0),
        ("fairmotion_sinusoidal.bvh", 1),
    ];
    if testkit::bvh_samples().is_none() {
        testkit::skipped("skeleton_up: bvh-samples not found");
        return;
    }
    for (n, axis) in names {
        let want = format!("\"up\":{axis},\"up_positive\":true");
        assert_eq!(page_up(n), Some(want), "{n}");
    }
}
