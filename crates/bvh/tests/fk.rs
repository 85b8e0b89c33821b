//! Forward kinematics of a hand-built skeleton, against numbers worked out by hand.

const TWO_JOINTS: &str = "HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Upper Arm
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 5 0 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
1 2 3 0 0 0 0 0 0
1 2 3 90 0 0 0 90 0
";

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-9)
}

#[test]
fn rest_pose_adds_offsets() {
    let bvh = bvh::parse(TWO_JOINTS).expect("parses");
    assert_eq!(bvh.skeleton.joints[1].name, "Upper Arm");
    let pose = bvh::fk::forward(&bvh, 0);
    assert!(close(pose.positions[0], [1.0, 2.0, 3.0]));
    assert!(close(pose.positions[1], [1.0, 12.0, 3.0]));
    assert!(close(
        pose.end_sites[1].expect("end site"),
        [6.0, 12.0, 3.0]
    ));
}

#[test]
fn rotated_pose_matches_hand_computation() {
    let bvh = bvh::parse(TWO_JOINTS).expect("parses");
    let pose = bvh::fk::forward(&bvh, 1);
    // Root: Rz(90) maps (x, y, z) to (-y, x, z). The arm's offset (0, 10, 0) becomes (-10, 0, 0).
    assert!(close(pose.positions[1], [1.0 - 10.0, 2.0, 3.0]));
    // Arm: local Rx(90) is the second listed channel; it maps the End Site's (5, 0, 0) to
    // itself, then the root's Rz(90) maps it to (0, 5, 0).
    assert!(close(
        pose.end_sites[1].expect("end site"),
        [-9.0, 7.0, 3.0]
    ));
    // Check a case where the arm rotation matters: Yrotation 90 would map (5,0,0) to (0,0,-5).
    let text = TWO_JOINTS.replace("1 2 3 90 0 0 0 90 0", "1 2 3 90 0 0 0 0 90");
    let bvh = bvh::parse(&text).expect("parses");
    let pose = bvh::fk::forward(&bvh, 1);
    // Arm: Ry(90)·(5,0,0) = (0,0,-5); root Rz(90) keeps it: end = (-9, 2, -2).
    assert!(close(
        pose.end_sites[1].expect("end site"),
        [-9.0, 2.0, -2.0]
    ));
}

#[test]
fn listed_order_matters() {
    // Root rotations Z then X (listed order): R = Rz(90)·Rx(90). Applied to the arm offset
    // (0, 10, 0): Rx(90) gives (0, 0, 10), Rz(90) keeps it. In the other order it would be
    // Rx(90)·Rz(90)·(0,10,0) = Rx(90)·(-10,0,0) = (-10, 0, 0).
    let text = TWO_JOINTS.replace("1 2 3 90 0 0 0 90 0", "0 0 0 90 90 0 0 0 0");
    let bvh = bvh::parse(&text).expect("parses");
    let pose = bvh::fk::forward(&bvh, 1);
    assert!(
        close(pose.positions[1], [0.0, 0.0, 10.0]),
        "{:?}",
        pose.positions[1]
    );
}

#[test]
fn position_channels_on_a_child_replace_its_offset() {
    let text = TWO_JOINTS
        .replace(
            "CHANNELS 3 Zrotation Xrotation Yrotation",
            "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        )
        .replace("1 2 3 0 0 0 0 0 0", "1 2 3 0 0 0 0 7 0 0 0 0")
        .replace("1 2 3 90 0 0 0 90 0", "1 2 3 0 0 0 4 0 0 0 0 0");
    let bvh = bvh::parse(&text).expect("parses");
    assert!(close(
        bvh::fk::forward(&bvh, 0).positions[1],
        [1.0, 9.0, 3.0]
    ));
    assert!(close(
        bvh::fk::forward(&bvh, 1).positions[1],
        [5.0, 2.0, 3.0]
    ));
}

#[test]
fn all_positions_give_every_point_and_bone_per_frame() {
    let bvh = bvh::parse(TWO_JOINTS).expect("parses");
    let p = bvh::fk::all_positions(&bvh);
    assert_eq!(p.labels, ["Hips", "Upper Arm", "Upper Arm_End"]);
    assert_eq!(p.bones, [(0, 1), (1, 2)]);
    assert_eq!(p.end_sites, [2]);
    assert_eq!(p.xyz.len(), 2 * 3);
    let want = [
        [1.0, 2.0, 3.0],
        [1.0, 12.0, 3.0],
        [6.0, 12.0, 3.0],
        [1.0, 2.0, 3.0],
        [-9.0, 2.0, 3.0],
        [-9.0, 7.0, 3.0],
    ];
    for (got, want) in p.xyz.iter().zip(want) {
        assert!(close(*got, want), "{got:?} vs {want:?}");
    }
}
