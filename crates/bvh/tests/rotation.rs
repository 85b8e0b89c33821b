//! Rotation conversions and slerp against values known by hand.

use bvh::rotation::{euler_to_matrix, euler_to_quat, matrix_to_euler, quat_to_euler, slerp, Quat};

const ORDERS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < tol)
}

/// A small fixed-seed generator, so the "random" angles are the same on every run.
struct XorShift(u64);
impl XorShift {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

#[test]
fn ninety_degrees_about_z_maps_x_to_y() {
    let q = euler_to_quat([2, 1, 0], [90.0, 0.0, 0.0]);
    assert!(close(q.rotate([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], 1e-12));
    let m = euler_to_matrix([2, 1, 0], [90.0, 0.0, 0.0]);
    assert!(close(
        bvh::rotation::mat_vec(&m, [1.0, 0.0, 0.0]),
        [0.0, 1.0, 0.0],
        1e-12
    ));
    // 90° about X maps Y to Z; 90° about Y maps Z to X.
    let qx = euler_to_quat([0, 1, 2], [90.0, 0.0, 0.0]);
    assert!(close(qx.rotate([0.0, 1.0, 0.0]), [0.0, 0.0, 1.0], 1e-12));
    let qy = euler_to_quat([1, 0, 2], [90.0, 0.0, 0.0]);
    assert!(close(qy.rotate([0.0, 0.0, 1.0]), [1.0, 0.0, 0.0], 1e-12));
}

#[test]
fn intrinsic_order_applies_listed_rotations_left_to_right() {
    // ZYX with Z = 90°, Y = 90°: R = Rz(90)·Ry(90). Ry(90) takes X to -Z; Rz leaves -Z alone.
    let q = euler_to_quat([2, 1, 0], [90.0, 90.0, 0.0]);
    assert!(close(q.rotate([1.0, 0.0, 0.0]), [0.0, 0.0, -1.0], 1e-12));
    // Z to X by Ry, then X to Y by Rz.
    assert!(close(q.rotate([0.0, 0.0, 1.0]), [0.0, 1.0, 0.0], 1e-12));
}

#[test]
fn euler_quat_matrix_round_trip_all_orders() {
    let mut rng = XorShift(0x5eed_1234_abcd_0042);
    for order in ORDERS {
        for _ in 0..200 {
            // Middle angle away from ±90° (gimbal lock), where the split is not unique.
            let e = [
                rng.range(-179.0, 179.0),
                rng.range(-80.0, 80.0),
                rng.range(-179.0, 179.0),
            ];
            let q = euler_to_quat(order, e);
            let back = quat_to_euler(order, q);
            assert!(close(back, e, 1e-9), "{order:?} {e:?} -> {back:?}");
            let m = euler_to_matrix(order, e);
            let qm = Quat::from_matrix(&m);
            assert!(q.dot(qm).abs() > 1.0 - 1e-12, "{order:?} {e:?}");
            assert!(close(matrix_to_euler(order, &m), e, 1e-9));
        }
    }
}

#[test]
fn gimbal_lock_still_gives_the_same_rotation() {
    for order in ORDERS {
        for b in [90.0, -90.0] {
            let e = [30.0, b, 20.0];
            let m = euler_to_matrix(order, e);
            let back = matrix_to_euler(order, &m);
            let m2 = euler_to_matrix(order, back);
            for i in 0..3 {
                assert!(close(m[i], m2[i], 1e-9), "{order:?} {e:?} -> {back:?}");
            }
        }
    }
}

#[test]
fn slerp_halfway_and_shortest_arc() {
    let a = Quat::IDENTITY;
    let b = euler_to_quat([2, 1, 0], [90.0, 0.0, 0.0]);
    let h = slerp(a, b, 0.5);
    let e = quat_to_euler([2, 1, 0], h);
    assert!(close(e, [45.0, 0.0, 0.0], 1e-9), "{e:?}");
    // -b is the same rotation: the sign fix must still go the short way (45°, not -135°).
    let h2 = slerp(a, -b, 0.5);
    let e2 = quat_to_euler([2, 1, 0], h2);
    assert!(close(e2, [45.0, 0.0, 0.0], 1e-9), "{e2:?}");
    // Between 170° and -170° about Z the short way passes through 180°, not 0°.
    let p = euler_to_quat([2, 1, 0], [170.0, 0.0, 0.0]);
    let q = euler_to_quat([2, 1, 0], [-170.0, 0.0, 0.0]);
    let m = slerp(p, q, 0.5);
    assert!(close(m.rotate([1.0, 0.0, 0.0]), [-1.0, 0.0, 0.0], 1e-9));
    // Endpoints are reproduced.
    assert!(slerp(p, q, 0.0).dot(p).abs() > 1.0 - 1e-12);
    assert!(slerp(p, q, 1.0).dot(q).abs() > 1.0 - 1e-12);
}
