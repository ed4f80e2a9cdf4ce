//! Fixed-size geometry for the kinematics modules: 3-vectors, rotation
//! matrices, roll-pitch-yaw angles, a 6×6 linear solver and the
//! intersection of three spheres. Everything lives on the stack, so the
//! modules stay allocation-free in the servo thread.

use super::KinsError;

/// A vector in space.
pub type Vec3 = [f64; 3];

/// A 3×3 matrix, row-major: `m[row][col]`. As a rotation its columns are
/// the rotated frame's axes.
pub type Mat3 = [[f64; 3]; 3];

/// The identity matrix.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Degrees to radians.
pub fn rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// Radians to degrees.
pub fn deg(rad: f64) -> f64 {
    rad.to_degrees()
}

/// `a + b`.
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a - b`.
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a · s`.
pub fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// The dot product.
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product `a × b`.
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The length of `a`.
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

/// `a` scaled to length 1, or `None` for a (nearly) zero vector.
pub fn unit(a: Vec3) -> Option<Vec3> {
    let n = norm(a);
    (n > 1e-300 && n.is_finite()).then(|| scale(a, 1.0 / n))
}

/// `m · v`.
pub fn mat_vec(m: &Mat3, v: Vec3) -> Vec3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// `a · b`.
pub fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut out = [[0.0; 3]; 3];
    for (r, row) in out.iter_mut().enumerate() {
        for (c, cell) in row.iter_mut().enumerate() {
            *cell = a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c];
        }
    }
    out
}

/// The transpose (for a rotation, its inverse).
pub fn transpose(m: &Mat3) -> Mat3 {
    let mut t = [[0.0; 3]; 3];
    for (r, row) in m.iter().enumerate() {
        for (c, &v) in row.iter().enumerate() {
            t[c][r] = v;
        }
    }
    t
}

/// Column `c` of `m` (for a rotation, the rotated frame's axis `c`).
pub fn column(m: &Mat3, c: usize) -> Vec3 {
    [m[0][c], m[1][c], m[2][c]]
}

/// Rotation by `a` radians about X.
pub fn rot_x(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

/// Rotation by `a` radians about Y.
pub fn rot_y(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

/// Rotation by `a` radians about Z.
pub fn rot_z(a: f64) -> Mat3 {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// The derivative of an elementary rotation matrix about `axis` with
/// respect to its angle.
pub fn turn_derivative(m: &Mat3, axis: usize) -> Mat3 {
    // The derivative of a turn is the turn followed by the generator:
    // for rotation about X, dR = R · [x]×, and the same for Y and Z.
    let mut g = [[0.0; 3]; 3];
    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
    g[b][a] = 1.0;
    g[a][b] = -1.0;
    mat_mul(m, &g)
}

/// The rotation of roll, pitch and yaw angles (radians), LinuxCNC's
/// convention for the A, B and C of a pose: roll about X first, then
/// pitch about Y, then yaw about Z, all about fixed axes
/// (`Rz(yaw) · Ry(pitch) · Rx(roll)`).
pub fn rpy_matrix(roll: f64, pitch: f64, yaw: f64) -> Mat3 {
    mat_mul(&rot_z(yaw), &mat_mul(&rot_y(pitch), &rot_x(roll)))
}

/// Roll, pitch and yaw (radians) of a rotation, the inverse of
/// [`rpy_matrix`]: pitch in [-π/2, π/2], roll and yaw in (-π, π]. At
/// pitch ±π/2 roll and yaw turn about the same axis; the yaw is then
/// taken as zero.
pub fn matrix_rpy(m: &Mat3) -> Vec3 {
    let cos_pitch = m[0][0].hypot(m[1][0]);
    let pitch = (-m[2][0]).atan2(cos_pitch);
    if cos_pitch > 1e-12 {
        [m[2][1].atan2(m[2][2]), pitch, m[1][0].atan2(m[0][0])]
    } else if pitch > 0.0 {
        [m[0][1].atan2(m[1][1]), pitch, 0.0]
    } else {
        [(-m[0][1]).atan2(m[1][1]), pitch, 0.0]
    }
}

/// The rotation vector (axis times angle, radians) of rotation `m`: the
/// turn that takes the identity to `m`.
pub fn rotation_vector(m: &Mat3) -> Vec3 {
    let cos_angle = ((m[0][0] + m[1][1] + m[2][2] - 1.0) / 2.0).clamp(-1.0, 1.0);
    let angle = cos_angle.acos();
    let skew = [m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]];
    if angle < 1e-6 {
        // sin(angle) ≈ angle: the skew part is twice the vector.
        return scale(skew, 0.5);
    }
    if std::f64::consts::PI - angle > 1e-6 {
        return scale(skew, angle / (2.0 * angle.sin()));
    }
    // Near a half turn the skew part vanishes: the axis is the column of
    // (m + I) / 2 with the largest diagonal, its sign from the skew part.
    let k = (0..3)
        .max_by(|&a, &b| m[a][a].total_cmp(&m[b][b]))
        .unwrap_or(0);
    let mut axis = [0.0; 3];
    for (r, a) in axis.iter_mut().enumerate() {
        *a = (m[r][k] + if r == k { 1.0 } else { 0.0 }) / 2.0;
    }
    let axis = unit(axis).unwrap_or([1.0, 0.0, 0.0]);
    let sign = if dot(axis, skew) < 0.0 { -1.0 } else { 1.0 };
    scale(axis, sign * angle)
}

/// An angle in degrees brought into (-180, 180].
pub fn wrap_degrees(a: f64) -> f64 {
    let w = a.rem_euclid(360.0);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}

/// The difference `a - b` of two angles in radians, in (-π, π].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let d = (a - b).rem_euclid(TAU);
    if d > PI {
        d - TAU
    } else {
        d
    }
}

/// `Ok` if every value is a finite number: what the modules check on
/// their inputs and outputs so that a NaN never reaches a motor.
pub fn finite(values: &[f64]) -> Result<(), KinsError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(KinsError::NoSolution)
    }
}

/// Solves `a · x = b` for a 6×6 system: [`solve_linear`] for six
/// unknowns.
pub fn solve6(a: [[f64; 6]; 6], b: [f64; 6]) -> Option<[f64; 6]> {
    solve_linear(a, b)
}

/// Solves `a · x = b` for an N×N system by Gaussian elimination with
/// partial pivoting; `None` when `a` is singular (a pivot smaller than
/// 1e-12 of its largest entry) or holds non-finite values.
pub fn solve_linear<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    let largest =
        a.iter().flatten().fold(
            0.0f64,
            |m, v| if v.is_nan() { f64::NAN } else { m.max(v.abs()) },
        );
    if !largest.is_finite() || largest == 0.0 {
        return None;
    }
    let tiny = largest * 1e-12;
    for col in 0..N {
        let pivot = (col..N).max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))?;
        if a[pivot][col].abs() <= tiny {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let pivot_row = a[col];
        for row in col + 1..N {
            let f = a[row][col] / pivot_row[col];
            if f == 0.0 {
                continue;
            }
            for (x, p) in a[row][col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; N];
    for row in (0..N).rev() {
        let mut s = b[row];
        for k in row + 1..N {
            s -= a[row][k] * x[k];
        }
        x[row] = s / a[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The limits of an iterative forward solution (LinuxCNC's
/// `convergence-criterion`, `limit-iterations` and `max-error` pins).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonLimits {
    /// Largest residual of a converged solution.
    pub convergence_criterion: f64,
    /// Most iterations of one solution.
    pub limit_iterations: u32,
    /// Total residual beyond which the iteration gives up.
    pub max_error: f64,
}

/// Newton's method on N equations in N unknowns from `start`:
/// `linearise` gives the residuals at a point and their Jacobian (`None`
/// where they cannot be computed). Returns the first point whose
/// residuals are all within the criterion, with the iterations it took;
/// refuses when the summed residuals pass `max_error`, the iterations
/// the limit, or the Jacobian cannot be solved.
pub fn newton<const N: usize>(
    limits: &NewtonLimits,
    start: [f64; N],
    mut linearise: impl FnMut(&[f64; N]) -> Option<([[f64; N]; N], [f64; N])>,
) -> Result<([f64; N], u32), KinsError> {
    let mut x = start;
    let mut iterations = 0;
    loop {
        iterations += 1;
        if iterations > limits.limit_iterations {
            return Err(KinsError::NotConverged);
        }
        let (jac, error) = linearise(&x).ok_or(KinsError::NoSolution)?;
        let total: f64 = error.iter().map(|e| e.abs()).sum();
        if total.is_nan() || total > limits.max_error {
            return Err(KinsError::NotConverged);
        }
        if error
            .iter()
            .all(|e| e.abs() <= limits.convergence_criterion)
        {
            return Ok((x, iterations));
        }
        let delta = solve_linear(jac, error).ok_or(KinsError::NoSolution)?;
        for (v, d) in x.iter_mut().zip(delta) {
            *v -= d;
        }
    }
}

/// Whether `p` lies below the plane through the three `points` (on the
/// side of smaller Z); `false` for a vertical plane or points in line.
/// Of the two points equally far from three centers, the lower one is
/// below their plane.
pub fn below_plane(p: Vec3, points: [Vec3; 3]) -> bool {
    let n = cross(sub(points[1], points[0]), sub(points[2], points[0]));
    let side = dot(sub(p, points[0]), n);
    if n[2] > 0.0 {
        side < 0.0
    } else if n[2] < 0.0 {
        side > 0.0
    } else {
        false
    }
}

/// The lower of the two points at distance `radius` from all three
/// `centers` (lower = smaller Z), or `None` when the spheres do not meet
/// in two points: centers that coincide or lie on one line, or spheres
/// too far apart (or only touching, a singular configuration).
pub fn lower_sphere_intersection(centers: [Vec3; 3], radius: f64) -> Option<Vec3> {
    let [p1, p2, p3] = centers;
    let ex = unit(sub(p2, p1))?;
    let d = norm(sub(p2, p1));
    let p13 = sub(p3, p1);
    let i = dot(ex, p13);
    let ey = unit(sub(p13, scale(ex, i)))?;
    let j = dot(ey, p13);
    // The centers must span a triangle of some size, not a sliver.
    let span = d.max(norm(p13));
    if j.abs() <= span * 1e-9 {
        return None;
    }
    let ez = cross(ex, ey);
    let r2 = radius * radius;
    // Equal radii: the sphere equations reduce to a point on the plane
    // of the centers plus a height along its normal.
    let x = d / 2.0;
    let y = (i * i + j * j) / (2.0 * j) - i * x / j;
    let h2 = r2 - x * x - y * y;
    if h2.is_nan() || h2 <= r2 * 1e-14 {
        return None;
    }
    let h = h2.sqrt();
    let base = add(p1, add(scale(ex, x), scale(ey, y)));
    let a = add(base, scale(ez, h));
    let b = sub(base, scale(ez, h));
    let lower = if a[2] <= b[2] { a } else { b };
    lower.iter().all(|v| v.is_finite()).then_some(lower)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_derivative_of_a_turn() {
        let a = 0.3;
        let h = 1e-7;
        for (axis, turn) in [(0, rot_x as fn(f64) -> Mat3), (1, rot_y), (2, rot_z)] {
            let d = turn_derivative(&turn(a), axis);
            let (m1, m0) = (turn(a + h), turn(a));
            for r in 0..3 {
                for c in 0..3 {
                    assert!(((m1[r][c] - m0[r][c]) / h - d[r][c]).abs() < 1e-6);
                }
            }
        }
    }
    use proptest::prelude::*;

    fn close(a: &Mat3, b: &Mat3, tol: f64) -> bool {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| (x - y).abs() < tol)
    }

    #[test]
    fn rpy_follows_linuxcnc_fixed_axis_order() {
        // A quarter turn of yaw takes X to Y; of pitch, Z to X; of roll,
        // Y to Z.
        let q = std::f64::consts::FRAC_PI_2;
        let m = rpy_matrix(0.0, 0.0, q);
        assert!(close(
            &[[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            &m,
            1e-15
        ));
        let v = mat_vec(&rpy_matrix(0.0, q, 0.0), [0.0, 0.0, 1.0]);
        assert!((v[0] - 1.0).abs() < 1e-15);
        let v = mat_vec(&rpy_matrix(q, 0.0, 0.0), [0.0, 1.0, 0.0]);
        assert!((v[2] - 1.0).abs() < 1e-15);
        // Roll first: a roll then a yaw differs from a yaw then a roll.
        let m = rpy_matrix(q, 0.0, q);
        assert!(close(&m, &mat_mul(&rot_z(q), &rot_x(q)), 1e-15));
    }

    #[test]
    fn rpy_at_gimbal_lock_keeps_the_rotation() {
        for pitch in [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2] {
            let m = rpy_matrix(0.3, pitch, 0.2);
            let [r, p, y] = matrix_rpy(&m);
            assert_eq!(y, 0.0);
            assert!(close(&rpy_matrix(r, p, y), &m, 1e-12));
        }
    }

    #[test]
    fn rotation_vector_near_a_half_turn() {
        let m = rot_y(std::f64::consts::PI - 1e-9);
        let v = rotation_vector(&m);
        assert!((v[1] - (std::f64::consts::PI - 1e-9)).abs() < 1e-6, "{v:?}");
        assert_eq!(rotation_vector(&IDENTITY), [0.0; 3]);
    }

    #[test]
    fn wraps_angles() {
        assert_eq!(wrap_degrees(190.0), -170.0);
        assert_eq!(wrap_degrees(-180.0), 180.0);
        assert_eq!(wrap_degrees(540.0), 180.0);
        assert!((angle_diff(0.1, -0.1 + std::f64::consts::TAU) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn solver_refuses_singular_systems() {
        let mut a = [[0.0; 6]; 6];
        for (i, row) in a.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        a[5] = a[4];
        assert_eq!(solve6(a, [1.0; 6]), None);
        a[0][0] = f64::NAN;
        assert_eq!(solve6(a, [1.0; 6]), None);
        assert_eq!(solve6([[0.0; 6]; 6], [1.0; 6]), None);
    }

    #[test]
    fn spheres_that_do_not_meet_have_no_intersection() {
        let c = [[0.0, 1.0, 0.0], [-0.9, -0.5, 0.0], [0.9, -0.5, 0.0]];
        assert!(lower_sphere_intersection(c, 0.5).is_none());
        let p = lower_sphere_intersection(c, 2.0).unwrap();
        assert!(p[2] < 0.0);
        let line = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert!(lower_sphere_intersection(line, 5.0).is_none());
    }

    proptest! {
        #[test]
        fn rpy_round_trips(r in -3.1f64..3.1, p in -1.5f64..1.5, y in -3.1f64..3.1) {
            let [r2, p2, y2] = matrix_rpy(&rpy_matrix(r, p, y));
            prop_assert!((r - r2).abs() < 1e-9 && (p - p2).abs() < 1e-9 && (y - y2).abs() < 1e-9);
        }

        #[test]
        fn rotation_vector_is_the_axis_angle(
            ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0, angle in 0.0f64..3.1,
        ) {
            let Some(axis) = unit([ax, ay, az]) else { return Ok(()) };
            // Rodrigues' formula builds the rotation from axis and angle.
            let (s, c) = angle.sin_cos();
            let [x, y, z] = axis;
            let t = 1.0 - c;
            let m = [
                [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
            ];
            let v = rotation_vector(&m);
            let want = scale(axis, angle);
            prop_assert!(norm(sub(v, want)) < 1e-6, "{:?} vs {:?}", v, want);
        }

        #[test]
        fn solver_solves(seed in prop::array::uniform32(-1.0f64..1.0), x in prop::array::uniform6(-5.0f64..5.0)) {
            let mut a = [[0.0; 6]; 6];
            for (i, row) in a.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = seed[(i * 6 + j) % 32] + if i == j { 4.0 } else { 0.0 };
                }
            }
            let mut b = [0.0; 6];
            for i in 0..6 {
                b[i] = (0..6).map(|j| a[i][j] * x[j]).sum();
            }
            let got = solve6(a, b).unwrap();
            for i in 0..6 {
                prop_assert!((got[i] - x[i]).abs() < 1e-9);
            }
        }

        #[test]
        fn sphere_intersection_is_at_the_radius(
            z in prop::array::uniform3(-2.0f64..2.0), r in 3.0f64..10.0,
        ) {
            let c = [[0.0, 1.0, z[0]], [-0.9, -0.5, z[1]], [0.9, -0.5, z[2]]];
            if let Some(p) = lower_sphere_intersection(c, r) {
                for ci in c {
                    prop_assert!((norm(sub(p, ci)) - r).abs() < 1e-9);
                }
                // The other solution is the mirror image across the
                // centers' plane: it must not be lower.
                let n = unit(cross(sub(c[1], c[0]), sub(c[2], c[0]))).unwrap();
                let mirror = sub(p, scale(n, 2.0 * dot(sub(p, c[0]), n)));
                prop_assert!(p[2] <= mirror[2] + 1e-12);
            }
        }
    }
}
