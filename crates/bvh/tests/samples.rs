//! Every file of the shared BVH corpus parses to the counts its README gives, round-trips
//! through the writer, and goes through forward kinematics.

use std::path::Path;

struct Expect {
    file: &'static str,
    joints: usize,
    end_sites: usize,
    /// Channels of the root, then of every other joint.
    root_channels: usize,
    other_channels: usize,
    order: [usize; 3],
    frames: usize,
    frame_time: f64,
}

const X: usize = 0;
const Y: usize = 1;
const Z: usize = 2;

const EXPECTED: &[Expect] = &[
    Expect {
        file: "fairmotion_cmu_01_01.bvh",
        joints: 31,
        end_sites: 7,
        root_channels: 6,
        other_channels: 3,
        order: [Z, Y, X],
        frames: 2752,
        frame_time: 0.0083333,
    },
    Expect {
        file: "fairmotion_sinusoidal.bvh",
        joints: 4,
        end_sites: 0,
        root_channels: 6,
        other_channels: 3,
        order: [X, Y, Z],
        frames: 120,
        frame_time: 0.016666666666666666,
    },
    Expect {
        file: "fairmotion_pfnn_hierarchy.bvh",
        joints: 31,
        end_sites: 7,
        root_channels: 6,
        other_channels: 3,
        order: [Z, Y, X],
        frames: 60,
        frame_time: 0.0333333,
    },
    Expect {
        file: "bvhpython_test_freebvh.bvh",
        joints: 55,
        end_sites: 15,
        root_channels: 6,
        other_channels: 3,
        order: [Z, Y, X],
        frames: 69,
        frame_time: 0.0333333,
    },
    Expect {
        file: "bvhtoolbox_walk01.bvh",
        joints: 19,
        end_sites: 5,
        root_channels: 6,
        other_channels: 3,
        order: [Z, X, Y],
        frames: 101,
        frame_time: 0.0416667,
    },
    Expect {
        file: "bandai_dataset-1_bow_active_001.bvh",
        joints: 22,
        end_sites: 5,
        root_channels: 6,
        other_channels: 6,
        order: [Z, X, Y],
        frames: 128,
        frame_time: 0.0333333,
    },
    Expect {
        file: "bandai_dataset-2_wave-left-hand_active_011.bvh",
        joints: 22,
        end_sites: 5,
        root_channels: 6,
        other_channels: 6,
        order: [Z, X, Y],
        frames: 19,
        frame_time: 0.0333333,
    },
];

fn check(dir: &Path, e: &Expect) {
    let path = dir.join(e.file);
    let bvh = bvh::read(&path).unwrap_or_else(|err| panic!("{err}"));
    let s = &bvh.skeleton;
    assert_eq!(s.joints.len(), e.joints, "{}", e.file);
    assert_eq!(s.end_site_count(), e.end_sites, "{}", e.file);
    assert_eq!(s.root_count(), 1, "{}", e.file);
    for (i, j) in s.joints.iter().enumerate() {
        let want = if i == 0 {
            e.root_channels
        } else {
            e.other_channels
        };
        assert_eq!(j.channels.len(), want, "{} joint {}", e.file, j.name);
        assert_eq!(
            j.euler_order(),
            Some(e.order),
            "{} joint {}",
            e.file,
            j.name
        );
    }
    let channels = e.root_channels + (e.joints - 1) * e.other_channels;
    assert_eq!(s.channel_count(), channels, "{}", e.file);
    assert_eq!(bvh.motion.channels, channels, "{}", e.file);
    assert_eq!(bvh.motion.frames(), e.frames, "{}", e.file);
    assert_eq!(bvh.motion.values.len(), e.frames * channels, "{}", e.file);
    assert_eq!(bvh.motion.frame_time, e.frame_time, "{}", e.file);

    // Writer round trip is exact.
    let again = bvh::parse(&bvh::write(&bvh)).unwrap_or_else(|err| panic!("{err}"));
    assert_eq!(again, bvh, "{}", e.file);

    // Forward kinematics of the first frame: the root sits at its position channels, and each
    // child is its (rotated) offset away from its parent.
    let pose = bvh::fk::forward(&bvh, 0);
    let f0 = bvh.motion.frame(0);
    assert!((pose.positions[0][0] - f0[0]).abs() < 1e-9, "{}", e.file);
    for (i, j) in s.joints.iter().enumerate().skip(1) {
        let p = j.parent.expect("non-root joints have parents");
        let d: f64 = (0..3)
            .map(|k| (pose.positions[i][k] - pose.positions[p][k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let local = bvh::fk::local_pose(s, f0).translations[i];
        let len = local.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(
            (d - len).abs() < 1e-6 * (1.0 + len),
            "{} joint {}",
            e.file,
            j.name
        );
    }
}

#[test]
fn every_sample_parses_with_readme_counts() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    let files = testkit::files_with_ext(&dir, "bvh");
    assert_eq!(files.len(), EXPECTED.len(), "corpus changed: {files:?}");
    for e in EXPECTED {
        check(&dir, e);
    }
}

#[test]
fn bandai_position_channels_replace_offsets() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    let bvh = bvh::read(&dir.join("bandai_dataset-1_bow_active_001.bvh")).expect("parses");
    let s = &bvh.skeleton;
    let j = &s.joints[1];
    let f0 = bvh.motion.frame(0);
    let local = bvh::fk::local_pose(s, f0);
    for k in 0..3 {
        assert_eq!(local.translations[1][k], f0[j.first_channel + k]);
    }
}
