//! The committed demo trials in `sample_c3d/` are exactly what the generator makes, and hold
//! what their README says.

#[path = "../examples/make_samples.rs"]
mod make_samples;

#[test]
fn committed_samples_match_the_generator() {
    let dir = testkit::workspace_root().join("sample_c3d");
    for &(name, defects, scale, processor) in make_samples::TRIALS {
        let made = make_samples::trial_bytes(defects, scale, processor).unwrap();
        let committed = std::fs::read(dir.join(name)).unwrap();
        assert!(
            made == committed,
            "{name} differs from the generator's output: regenerate it"
        );
    }
}

#[test]
fn samples_hold_the_described_defects() {
    let dir = testkit::workspace_root().join("sample_c3d");
    let truth = c3d::read_file(dir.join("walk_truth.c3d")).unwrap();
    let int = c3d::read_file(dir.join("walk_int.c3d")).unwrap();
    for c in [&truth, &int] {
        assert_eq!((c.points().frames(), c.points().count()), (400, 35));
        assert_eq!(c.analog().channels(), 4);
        assert_eq!(c.analog_rate(), 1000.0);
        assert_eq!(c.events().len(), 7);
        assert!(c.warnings().is_empty(), "{:?}", c.warnings());
        assert_eq!(c.point_labels()[0], "LASI");
        assert_eq!(
            c.param("point", "rate").map(|p| p.as_f32s()),
            Some(vec![100.0])
        );
        assert_eq!(
            c.param("ANALOG", "USED").map(|p| p.as_i32s()),
            Some(vec![4])
        );
        assert_eq!(
            c.param("EVENT", "CONTEXTS")
                .map(|p| p.as_strings()[1].clone()),
            Some("Left".into())
        );
    }
    let gaps: usize = (0..35).map(|i| int.points().gaps(i).len()).sum();
    assert_eq!(gaps, 9);
    assert_eq!(
        (0..35).map(|i| truth.points().gaps(i).len()).sum::<usize>(),
        0
    );
    let rkne = int.point_index("RKNE").unwrap();
    assert_eq!(int.points().gaps(rkne), vec![(330, 389)]);
    // Noise and quantization keep valid samples within ~2 mm of the truth, spikes aside.
    let lkne = int.point_index("LKNE").unwrap();
    let k = int.points().index(75, lkne);
    let d = (int.points().xyz[k][0] - truth.points().xyz[k][0]).abs();
    assert!((33.0..37.0).contains(&d), "spike of {d} mm");
}
