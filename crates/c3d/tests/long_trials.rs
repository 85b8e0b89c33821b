//! Trials beyond 65 535 frames: the header cannot count them, the parameters do.

use c3d::{Analog, C3d, NumberFormat, Parameters, Points, Processor};

#[test]
fn seventy_thousand_frames_round_trip() {
    let frames = 70_000;
    let mut pts = Points::new(frames, 2);
    for f in 0..frames {
        for i in 0..2 {
            let k = pts.index(f, i);
            pts.xyz[k] = [f as f32 * 0.01, i as f32, -(f as f32) * 0.02];
            pts.residual[k] = if f % 1000 == 7 { -1.0 } else { 0.5 };
        }
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 1000.0).unwrap();
    ps.set_strings("POINT", "LABELS", &["A".into(), "B".into()])
        .unwrap();
    for (proc_, fmt, scale) in [
        (Processor::Intel, NumberFormat::Float, -0.01f32),
        (Processor::Sgi, NumberFormat::Integer, 0.1f32),
    ] {
        let c = C3d::new(
            pts.clone(),
            Analog::new(frames, 0, 1),
            ps.clone(),
            proc_,
            scale,
        );
        let bytes = c.convert(proc_, fmt, Some(scale)).unwrap();
        let back = c3d::read(bytes.clone()).unwrap();
        assert_eq!(back.points().frames(), frames);
        assert_eq!(back.header.last_frame, 65535);
        assert_eq!(back.first_frame(), 1);
        let end = back
            .parameters
            .get("TRIAL", "ACTUAL_END_FIELD")
            .unwrap()
            .as_u16s();
        assert_eq!(end[0] as usize + ((end[1] as usize) << 16), frames);
        assert!(back.warnings().is_empty(), "{:?}", back.warnings());
        let k = back.points().index(69_999, 1);
        let want = pts.xyz[k];
        for (got, want) in back.points().xyz[k].iter().zip(want) {
            assert!((got - want).abs() <= scale.abs() / 2.0 + 1e-3);
        }
        assert!(!back.points().is_valid(69_007, 0));
        // And it rewrites byte for byte.
        assert!(back.to_bytes().unwrap() == bytes);
    }
}

#[test]
fn point_frames_is_read_unsigned() {
    // 40 000 frames: POINT:FRAMES holds 40000 as int16 (-25536) and the header holds it too.
    let frames = 40_000;
    let pts = Points::new(frames, 1);
    let c = C3d::new(
        pts,
        Analog::new(frames, 0, 1),
        Parameters::new(),
        Processor::Intel,
        -1.0,
    );
    let back = c3d::read(c.to_bytes().unwrap()).unwrap();
    assert_eq!(back.points().frames(), frames);
    assert_eq!(back.parameters.get_u16("POINT", "FRAMES"), Some(40_000));
    assert_eq!(back.parameters.get_i32("POINT", "FRAMES"), Some(-25_536));
}
