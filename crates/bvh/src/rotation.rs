//! Rotations: Euler angles in any axis order ↔ unit quaternions ↔ 3×3 matrices, and slerp.
//!
//! Convention (the BVH one): Euler angles are in degrees and *intrinsic*, applied in the order
//! listed, so the order `[a, b, c]` means `R = R_a(θ1) · R_b(θ2) · R_c(θ3)` acting on column
//! vectors.

use crate::skeleton::Vec3;

/// A 3×3 rotation matrix, row-major, acting on column vectors.
pub type Mat3 = [[f64; 3]; 3];

/// A unit quaternion `w + xi + yj + zk`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quat {
    pub w: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl Quat {
    pub const IDENTITY: Quat = Quat {
        w: 1.0,
        x: 0.0,
        y: 0.0,
        z: 0.0,
    };

    /// Rotation by `radians` about coordinate axis `axis` (0 = X, 1 = Y, 2 = Z).
    pub fn about_axis(axis: usize, radians: f64) -> Quat {
        let (s, c) = (radians * 0.5).sin_cos();
        let mut v = [0.0; 3];
        v[axis] = s;
        Quat {
            w: c,
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }

    pub fn dot(self, o: Quat) -> f64 {
        self.w * o.w + self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// The inverse rotation (for unit quaternions).
    pub fn conj(self) -> Quat {
        Quat {
            w: self.w,
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }

    pub fn normalized(self) -> Quat {
        let n = self.dot(self).sqrt();
        if n > 0.0 {
            Quat {
                w: self.w / n,
                x: self.x / n,
                y: self.y / n,
                z: self.z / n,
            }
        } else {
            Quat::IDENTITY
        }
    }

    /// Rotate a vector.
    #[inline]
    pub fn rotate(self, v: Vec3) -> Vec3 {
        // v' = v + 2w (u × v) + 2 u × (u × v), with u the vector part.
        let u = [self.x, self.y, self.z];
        let t = scale(cross(u, v), 2.0);
        let c = cross(u, t);
        [
            v[0] + self.w * t[0] + c[0],
            v[1] + self.w * t[1] + c[1],
            v[2] + self.w * t[2] + c[2],
        ]
    }

    pub fn to_matrix(self) -> Mat3 {
        let Quat { w, x, y, z } = self;
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }

    /// From a rotation matrix (Shepperd's method: pick the largest diagonal term for stability).
    pub fn from_matrix(m: &Mat3) -> Quat {
        let tr = m[0][0] + m[1][1] + m[2][2];
        let q = if tr > 0.0 {
            let s = (tr + 1.0).sqrt() * 2.0;
            Quat {
                w: 0.25 * s,
                x: (m[2][1] - m[1][2]) / s,
                y: (m[0][2] - m[2][0]) / s,
                z: (m[1][0] - m[0][1]) / s,
            }
        } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
            let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
            Quat {
                w: (m[2][1] - m[1][2]) / s,
                x: 0.25 * s,
                y: (m[0][1] + m[1][0]) / s,
                z: (m[0][2] + m[2][0]) / s,
            }
        } else if m[1][1] > m[2][2] {
            let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
            Quat {
                w: (m[0][2] - m[2][0]) / s,
                x: (m[0][1] + m[1][0]) / s,
                y: 0.25 * s,
                z: (m[1][2] + m[2][1]) / s,
            }
        } else {
            let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
            Quat {
                w: (m[1][0] - m[0][1]) / s,
                x: (m[0][2] + m[2][0]) / s,
                y: (m[1][2] + m[2][1]) / s,
                z: 0.25 * s,
            }
        };
        q.normalized()
    }
}

impl std::ops::Mul for Quat {
    type Output = Quat;

    /// Hamilton product `self · o` (apply `o` first, then `self`).
    #[inline]
    fn mul(self, o: Quat) -> Quat {
        Quat {
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
        }
    }
}

impl std::ops::Neg for Quat {
    type Output = Quat;

    /// The same rotation, on the other side of the double cover.
    fn neg(self) -> Quat {
        Quat {
            w: -self.w,
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Matrix product `a · b`.
pub fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    r
}

/// Matrix times column vector.
pub fn mat_vec(m: &Mat3, v: Vec3) -> Vec3 {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// Rotation matrix about one coordinate axis.
pub fn axis_matrix(axis: usize, radians: f64) -> Mat3 {
    let (s, c) = radians.sin_cos();
    match axis {
        0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

/// Intrinsic Euler angles (degrees, applied in `order`) to a quaternion.
pub fn euler_to_quat(order: [usize; 3], degrees: Vec3) -> Quat {
    let mut q = Quat::IDENTITY;
    for (axis, deg) in order.iter().zip(degrees) {
        q = q * Quat::about_axis(*axis, deg.to_radians());
    }
    q
}

/// Intrinsic Euler angles (degrees, applied in `order`) to a matrix.
pub fn euler_to_matrix(order: [usize; 3], degrees: Vec3) -> Mat3 {
    let mut m = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for (axis, deg) in order.iter().zip(degrees) {
        m = mat_mul(&m, &axis_matrix(*axis, deg.to_radians()));
    }
    m
}

/// A matrix to intrinsic Euler angles (degrees) in `order`, which must name three distinct
/// axes. The middle angle is in [-90°, 90°]; at gimbal lock the last angle is set to zero.
pub fn matrix_to_euler(order: [usize; 3], m: &Mat3) -> Vec3 {
    let [i, j, k] = order;
    // +1 for cyclic orders (XYZ, YZX, ZXY), -1 for the others.
    let s = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
    let sb = (s * m[i][k]).clamp(-1.0, 1.0);
    let b = sb.asin();
    let (a, c) = if sb.abs() < 1.0 - 1e-12 {
        ((-s * m[j][k]).atan2(m[k][k]), (-s * m[i][j]).atan2(m[i][i]))
    } else {
        // R = R_i(a) R_j(b): column j is R_i(a) e_j = cos a e_j + s sin a e_k.
        ((s * m[k][j]).atan2(m[j][j]), 0.0)
    };
    [a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

/// A quaternion to intrinsic Euler angles (degrees) in `order`.
pub fn quat_to_euler(order: [usize; 3], q: Quat) -> Vec3 {
    matrix_to_euler(order, &q.to_matrix())
}

/// Spherical linear interpolation from `a` (t = 0) to `b` (t = 1) along the shorter arc:
/// `q` and `-q` are the same rotation, so `b` is negated when that brings it closer to `a`.
///
/// Computed as `a · (a⁻¹ b)^t`, which stays exact for tiny angles (no switch to a normalised
/// lerp), so that stepping by `(a⁻¹ b)^(1/n)` frame after frame gives the same rotations.
pub fn slerp(a: Quat, b: Quat, t: f64) -> Quat {
    a * pow(shortest_relative(a, b), t)
}

/// `a⁻¹ b`, negated if needed so that it rotates by at most 180°.
pub fn shortest_relative(a: Quat, b: Quat) -> Quat {
    let r = a.conj() * b;
    if r.w < 0.0 {
        -r
    } else {
        r
    }
}

/// `q^t` for a unit quaternion: the same axis, `t` times the angle.
pub fn pow(q: Quat, t: f64) -> Quat {
    let s = (q.x * q.x + q.y * q.y + q.z * q.z).sqrt();
    let half = s.atan2(q.w);
    // sin(t·φ)/sin(φ) tends to t as φ → 0.
    let k = if s > 1e-12 { (t * half).sin() / s } else { t };
    Quat {
        w: (t * half).cos(),
        x: q.x * k,
        y: q.y * k,
        z: q.z * k,
    }
}
