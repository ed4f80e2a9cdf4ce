//! Segment geometry: where a line, an arc (circle, helix or spiral) or a
//! blend arc is at arc length `s`, its direction there, and the per-axis
//! factors the limit budget needs.
//!
//! Lines are straight in all nine axes at once; a line's length is its
//! XYZ length if it moves XYZ, else its UVW length, else its ABC length
//! (LinuxCNC's rule), and every axis moves in proportion. Arcs turn in XYZ
//! about a centre and a normal (right-hand rule), may climb along the
//! normal (helix) and change radius linearly with the angle (spiral); the
//! other six axes move in proportion to the arc length.

use crate::kins::{Pose, NUM_AXES};

/// A vector in XYZ.
pub(crate) type V3 = [f64; 3];

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn scale(a: V3, k: f64) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}

pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// `a` scaled to length 1; `None` for a (nearly) zero vector.
pub(crate) fn unit(a: V3) -> Option<V3> {
    let n = norm(a);
    (n > 1e-12).then(|| scale(a, 1.0 / n))
}

/// The XYZ part of a pose.
pub(crate) fn xyz(p: &Pose) -> V3 {
    [p.0[0], p.0[1], p.0[2]]
}

/// Lengths below this are zero: such a move is not queued.
pub const MIN_LENGTH: f64 = 1e-9;

/// The length LinuxCNC gives a straight move of `delta`: XYZ if it moves
/// XYZ, else UVW, else ABC.
pub(crate) fn line_length(delta: &[f64; NUM_AXES]) -> f64 {
    let part = |r: std::ops::Range<usize>| delta[r].iter().map(|d| d * d).sum::<f64>().sqrt();
    let xyz = part(0..3);
    if xyz > MIN_LENGTH {
        return xyz;
    }
    let uvw = part(6..9);
    if uvw > MIN_LENGTH {
        return uvw;
    }
    part(3..6)
}

/// The shape of one segment as a function of its arc length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Path {
    /// Straight in all nine axes: `start + delta · s / len`.
    Line { start: Pose, delta: [f64; NUM_AXES] },
    /// A turn in XYZ; the other axes move from `start` by `delta`.
    Arc(Arc),
}

/// A circle, helix or spiral in XYZ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Arc {
    /// Centre (on the start's plane).
    pub center: V3,
    /// Unit vector from the centre towards the start.
    pub e1: V3,
    /// `normal × e1`: the direction of travel at the start.
    pub e2: V3,
    /// Unit normal; the arc turns counter-clockwise about it.
    pub normal: V3,
    /// Radius at the start.
    pub r0: f64,
    /// Radius change from start to end (a spiral when not zero).
    pub dr: f64,
    /// Angle turned, radians, > 0 (full turns included).
    pub angle: f64,
    /// Travel along the normal from start to end (a helix when not zero).
    pub helix: f64,
    /// Pose at the start (the A B C U V W start values).
    pub start: Pose,
    /// Change of every axis from start to end (only A B C U V W used).
    pub delta: [f64; NUM_AXES],
}

impl Arc {
    /// The XYZ point at angle `phi` from the start.
    fn xyz_at(&self, phi: f64) -> V3 {
        let f = phi / self.angle;
        let r = self.r0 + self.dr * f;
        let (s, c) = phi.sin_cos();
        let radial = add(scale(self.e1, c), scale(self.e2, s));
        add(
            add(self.center, scale(radial, r)),
            scale(self.normal, self.helix * f),
        )
    }

    /// `d xyz / d phi` at angle `phi`.
    fn dxyz_dphi(&self, phi: f64) -> V3 {
        let f = phi / self.angle;
        let r = self.r0 + self.dr * f;
        let rp = self.dr / self.angle;
        let (s, c) = phi.sin_cos();
        let radial = add(scale(self.e1, c), scale(self.e2, s));
        let tangential = add(scale(self.e1, -s), scale(self.e2, c));
        add(
            add(scale(tangential, r), scale(radial, rp)),
            scale(self.normal, self.helix / self.angle),
        )
    }

    /// The XYZ length (Simpson's rule on the speed; exact for circles and
    /// helices, whose speed is constant).
    pub fn xyz_length(&self) -> f64 {
        if self.dr == 0.0 {
            return ((self.r0 * self.angle).powi(2) + self.helix * self.helix).sqrt();
        }
        const N: usize = 64;
        let h = self.angle / N as f64;
        let mut sum = 0.0;
        for k in 0..=N {
            let w = if k == 0 || k == N {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += w * norm(self.dxyz_dphi(k as f64 * h));
        }
        sum * h / 3.0
    }

    /// The largest radius along the arc.
    pub fn r_max(&self) -> f64 {
        self.r0.max(self.r0 + self.dr)
    }
}

impl Path {
    /// The length of the path as the planner measures it.
    pub fn length(&self) -> f64 {
        match self {
            Path::Line { delta, .. } => line_length(delta),
            Path::Arc(a) => {
                let l = a.xyz_length();
                if l > MIN_LENGTH {
                    l
                } else {
                    line_length(&a.delta)
                }
            }
        }
    }

    /// The pose at arc length `s` of a path `len` long.
    pub fn point(&self, s: f64, len: f64) -> Pose {
        let f = if len > 0.0 { s / len } else { 1.0 };
        match self {
            Path::Line { start, delta } => {
                let mut p = *start;
                for (v, d) in p.0.iter_mut().zip(delta) {
                    *v += d * f;
                }
                p
            }
            Path::Arc(a) => {
                let mut p = a.start;
                for i in 3..NUM_AXES {
                    p.0[i] += a.delta[i] * f;
                }
                let q = a.xyz_at(a.angle * f);
                p.0[..3].copy_from_slice(&q);
                p
            }
        }
    }

    /// `d pose / d s` at arc length `s`: how far each axis moves per unit
    /// of path.
    pub fn derivative(&self, s: f64, len: f64) -> [f64; NUM_AXES] {
        let mut d = [0.0; NUM_AXES];
        if len <= 0.0 {
            return d;
        }
        match self {
            Path::Line { delta, .. } => {
                for (o, v) in d.iter_mut().zip(delta) {
                    *o = v / len;
                }
            }
            Path::Arc(a) => {
                let w = a.angle / len;
                let t = a.dxyz_dphi(a.angle * s / len);
                for (i, o) in d.iter_mut().enumerate() {
                    *o = if i < 3 { t[i] * w } else { a.delta[i] / len };
                }
            }
        }
        d
    }

    /// `d² pose / d s²` at arc length `s`: the curvature part of each
    /// axis's acceleration (zero for straight moves).
    pub fn second_derivative(&self, s: f64, len: f64) -> [f64; NUM_AXES] {
        let mut d = [0.0; NUM_AXES];
        if let Path::Arc(a) = self {
            if len > 0.0 {
                let w = a.angle / len;
                let phi = a.angle * s / len;
                let r = a.r0 + a.dr * phi / a.angle;
                let rp = a.dr / a.angle;
                let (sn, cs) = phi.sin_cos();
                for (i, o) in d.iter_mut().take(3).enumerate() {
                    let radial = cs * a.e1[i] + sn * a.e2[i];
                    let tangential = -sn * a.e1[i] + cs * a.e2[i];
                    *o = w * w * (-r * radial + 2.0 * rp * tangential);
                }
            }
        }
        d
    }

    /// The unit XYZ direction of travel at arc length `s`, if it moves in
    /// XYZ there.
    pub fn xyz_direction(&self, s: f64, len: f64) -> Option<V3> {
        let d = self.derivative(s, len);
        unit([d[0], d[1], d[2]])
    }

    /// Whether any of A B C U V W moves.
    pub fn moves_other_axes(&self) -> bool {
        let delta = match self {
            Path::Line { delta, .. } => delta,
            Path::Arc(a) => &a.delta,
        };
        delta[3..].iter().any(|d| d.abs() > MIN_LENGTH)
    }

    /// The per-axis factors of a path `len` long (see [`AxisFactors`]).
    pub fn factors(&self, len: f64) -> AxisFactors {
        let mut f = AxisFactors::default();
        if len <= 0.0 {
            return f;
        }
        match self {
            Path::Line { delta, .. } => {
                for (l, d) in f.lin.iter_mut().zip(delta) {
                    *l = d.abs() / len;
                }
            }
            Path::Arc(a) => {
                let w = a.angle / len;
                let rp = (a.dr / a.angle).abs();
                let r = a.r_max();
                for i in 0..3 {
                    let rho = (a.e1[i] * a.e1[i] + a.e2[i] * a.e2[i]).sqrt();
                    f.rot[i] = w * (r + rp) * rho;
                    f.lin[i] = (a.helix / len).abs() * a.normal[i].abs();
                }
                for i in 3..NUM_AXES {
                    f.lin[i] = a.delta[i].abs() / len;
                }
                f.omega = if r + rp > 0.0 {
                    w * (r + 2.0 * rp) / (r + rp)
                } else {
                    0.0
                };
                f.exact_circle = a.dr == 0.0;
            }
        }
        f
    }

    /// The smallest and largest value each axis takes along the path (for
    /// the limit check: an arc can bulge beyond both of its ends).
    pub fn extent(&self, len: f64) -> ([f64; NUM_AXES], [f64; NUM_AXES]) {
        let a = self.point(0.0, len);
        let b = self.point(len, len);
        let mut lo = [0.0; NUM_AXES];
        let mut hi = [0.0; NUM_AXES];
        for i in 0..NUM_AXES {
            lo[i] = a.0[i].min(b.0[i]);
            hi[i] = a.0[i].max(b.0[i]);
        }
        if let Path::Arc(arc) = self {
            // Each XYZ coordinate of the turning part is extreme where the
            // radial direction lines up with that axis; the climb and the
            // radius change are monotonic, so bounding the circle of the
            // largest radius at both heights covers them.
            let r = arc.r_max();
            let h = scale(arc.normal, arc.helix);
            for i in 0..3 {
                // x_i(phi) = c_i + r·rho·cos(phi − beta): extreme where
                // phi ≡ beta (mod π).
                let rho = (arc.e1[i] * arc.e1[i] + arc.e2[i] * arc.e2[i]).sqrt();
                if rho == 0.0 {
                    continue;
                }
                let beta = arc.e2[i].atan2(arc.e1[i]);
                let mut phi = beta.rem_euclid(std::f64::consts::PI);
                while phi <= arc.angle {
                    let (s, c) = phi.sin_cos();
                    let v = arc.center[i] + r * (c * arc.e1[i] + s * arc.e2[i]);
                    for extra in [0.0, h[i]] {
                        lo[i] = lo[i].min(v + extra);
                        hi[i] = hi[i].max(v + extra);
                    }
                    phi += std::f64::consts::PI;
                }
            }
        }
        (lo, hi)
    }
}

/// How fast each axis moves and accelerates for a given motion along a
/// path: with path speed `v` and tangential acceleration `a`, axis `i`
/// moves at most `v · (rot[i] + lin[i])` and accelerates at most
/// `rot[i] · √(a² + (v²·omega)²) + lin[i] · |a|` (exact circles and
/// helices) or `rot[i] · (|a| + v²·omega) + lin[i] · |a|` (spirals).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct AxisFactors {
    /// The turning part: axis travel per unit of path from the rotation.
    pub rot: [f64; NUM_AXES],
    /// The straight part: axis travel per unit of path.
    pub lin: [f64; NUM_AXES],
    /// Angle turned per unit of path, scaled for spirals' curvature.
    pub omega: f64,
    /// Whether the turning part is an exact circle (no spiral).
    pub exact_circle: bool,
}

impl AxisFactors {
    /// Axis travel per unit of path, at most.
    pub fn speed(&self, i: usize) -> f64 {
        self.rot[i] + self.lin[i]
    }

    /// The largest acceleration of axis `i` at path speed `v` and
    /// tangential acceleration `a`.
    pub fn accel(&self, i: usize, v: f64, a: f64) -> f64 {
        let a = a.abs();
        let n = v * v * self.omega;
        let turning = if self.exact_circle {
            (a * a + n * n).sqrt()
        } else {
            a + n
        };
        self.rot[i] * turning + self.lin[i] * a
    }

    /// The largest jerk of axis `i` at path speed `v`, tangential
    /// acceleration `a` and tangential jerk `j`.
    pub fn jerk(&self, i: usize, v: f64, a: f64, j: f64) -> f64 {
        let w = self.omega;
        self.rot[i] * (j.abs() + v * v * v * w * w + 3.0 * v * a.abs() * w) + self.lin[i] * j.abs()
    }
}

/// A blend arc between two straight XYZ moves meeting at `corner`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Blend {
    /// The arc.
    pub arc: Arc,
    /// How much of each line it replaces, measured from the corner.
    pub cut: f64,
}

/// The arc tangent to a line arriving at `corner` along `u1` and one
/// leaving along `u2` (unit XYZ vectors), cutting `cut` off each, with
/// the other axes held at `corner`'s values. `None` for a straight-through
/// or reversing corner, where no arc fits.
pub(crate) fn blend_arc(corner: &Pose, u1: V3, u2: V3, cut: f64) -> Option<Blend> {
    let cos_turn = dot(u1, u2).clamp(-1.0, 1.0);
    let turn = cos_turn.acos();
    if !(1e-6..std::f64::consts::PI - 1e-3).contains(&turn) || cut <= 0.0 {
        return None;
    }
    // Half the interior angle between the incoming and outgoing lines.
    let half = (std::f64::consts::PI - turn) / 2.0;
    let radius = cut * half.tan();
    let inward = unit(sub(u2, u1))?;
    let p = xyz(corner);
    let center = add(p, scale(inward, radius / half.sin()));
    let q1 = sub(p, scale(u1, cut));
    let normal = unit(cross(u1, u2))?;
    let e1 = unit(sub(q1, center))?;
    let e2 = cross(normal, e1);
    let mut start = *corner;
    start.0[..3].copy_from_slice(&q1);
    Some(Blend {
        arc: Arc {
            center,
            e1,
            e2,
            normal,
            r0: radius,
            dr: 0.0,
            angle: turn,
            helix: 0.0,
            start,
            delta: [0.0; NUM_AXES],
        },
        cut,
    })
}

/// How far from the corner a blend with half interior angle `half` may
/// cut so that the arc stays within `tolerance` of the corner.
pub(crate) fn cut_for_tolerance(u1: V3, u2: V3, tolerance: f64) -> f64 {
    let turn = dot(u1, u2).clamp(-1.0, 1.0).acos();
    let half = (std::f64::consts::PI - turn) / 2.0;
    tolerance * half.cos() / (1.0 - half.sin())
}

/// The arc of a G2/G3-style move from `start` to `end` about `center`
/// (XYZ; the start's height along `normal` is the arc's plane), turning
/// counter-clockwise about `normal` through `turns` extra full turns
/// (negative `turns`: clockwise, as LinuxCNC's SET_CIRCLE encodes it).
/// `None` when the start or end is on the centre's axis or the normal is
/// zero.
pub(crate) fn arc_move(
    start: &Pose,
    end: &Pose,
    center: V3,
    normal: V3,
    turns: i32,
) -> Option<Arc> {
    let mut n = unit(normal)?;
    let mut extra = turns;
    if turns < 0 {
        n = scale(n, -1.0);
        extra = -1 - turns;
    }
    let ps = xyz(start);
    let pe = xyz(end);
    // Project the centre onto the start's plane.
    let c = sub(center, scale(n, dot(sub(center, ps), n)));
    let rs = sub(ps, c);
    let r0 = norm(rs);
    let helix = dot(sub(pe, c), n);
    let re = sub(sub(pe, c), scale(n, helix));
    let r1 = norm(re);
    if r0 < MIN_LENGTH || r1 < MIN_LENGTH {
        return None;
    }
    let e1 = scale(rs, 1.0 / r0);
    let e2 = cross(n, e1);
    let mut angle = dot(re, e2).atan2(dot(re, e1));
    if angle <= 1e-12 {
        angle += 2.0 * std::f64::consts::PI;
    }
    angle += extra as f64 * 2.0 * std::f64::consts::PI;
    let mut delta = [0.0; NUM_AXES];
    for (i, d) in delta.iter_mut().enumerate() {
        *d = end.0[i] - start.0[i];
    }
    Some(Arc {
        center: c,
        e1,
        e2,
        normal: n,
        r0,
        dr: r1 - r0,
        angle,
        helix,
        start: *start,
        delta,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x: f64, y: f64, z: f64) -> Pose {
        let mut p = Pose::ZERO;
        p.0[0] = x;
        p.0[1] = y;
        p.0[2] = z;
        p
    }

    fn close(a: V3, b: V3) -> bool {
        norm(sub(a, b)) < 1e-9
    }

    #[test]
    fn a_quarter_circle_counter_clockwise_and_clockwise() {
        let a = arc_move(
            &pose(1.0, 0.0, 0.0),
            &pose(0.0, 1.0, 0.0),
            [0.0; 3],
            [0.0, 0.0, 1.0],
            0,
        )
        .unwrap();
        assert!((a.angle - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let p = Path::Arc(a);
        let len = p.length();
        assert!((len - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let mid = p.point(len / 2.0, len);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!(close(xyz(&mid), [h, h, 0.0]));
        assert!(close(xyz(&p.point(len, len)), [0.0, 1.0, 0.0]));
        // Clockwise the long way round: three quarters.
        let cw = arc_move(
            &pose(1.0, 0.0, 0.0),
            &pose(0.0, 1.0, 0.0),
            [0.0; 3],
            [0.0, 0.0, 1.0],
            -1,
        )
        .unwrap();
        assert!((cw.angle - 1.5 * std::f64::consts::PI).abs() < 1e-12);
        let p = Path::Arc(cw);
        let len = p.length();
        assert!(close(xyz(&p.point(len / 3.0, len)), [0.0, -1.0, 0.0]));
    }

    #[test]
    fn a_helix_climbs_and_its_derivative_has_unit_xyz_length() {
        let a = arc_move(
            &pose(2.0, 0.0, 0.0),
            &pose(2.0, 0.0, 3.0),
            [0.0; 3],
            [0.0, 0.0, 1.0],
            0,
        )
        .unwrap();
        assert!(
            (a.angle - 2.0 * std::f64::consts::PI).abs() < 1e-12,
            "full turn"
        );
        let p = Path::Arc(a);
        let len = p.length();
        for k in 0..10 {
            let s = len * k as f64 / 10.0;
            let d = p.derivative(s, len);
            assert!((norm([d[0], d[1], d[2]]) - 1.0).abs() < 1e-12);
        }
        assert!((p.point(len / 2.0, len).0[2] - 1.5).abs() < 1e-12);
        let (lo, hi) = p.extent(len);
        assert!((lo[0] + 2.0).abs() < 1e-9 && (hi[0] - 2.0).abs() < 1e-9);
        assert!((lo[1] + 2.0).abs() < 1e-9 && (hi[1] - 2.0).abs() < 1e-9);
        assert!((hi[2] - 3.0).abs() < 1e-9);
    }

    #[test]
    fn a_quarter_arc_extent_includes_only_the_bulge_it_passes() {
        let a = arc_move(
            &pose(1.0, 0.0, 0.0),
            &pose(-1.0, 0.0, 0.0),
            [0.0; 3],
            [0.0, 0.0, 1.0],
            0,
        )
        .unwrap();
        let p = Path::Arc(a);
        let (lo, hi) = p.extent(p.length());
        assert!((hi[1] - 1.0).abs() < 1e-9, "passes +Y");
        assert!(lo[1].abs() < 1e-9, "not -Y");
    }

    #[test]
    fn a_blend_arc_is_tangent_to_both_lines_within_tolerance() {
        let corner = pose(10.0, 0.0, 0.0);
        let u1 = [1.0, 0.0, 0.0];
        let u2 = [0.0, 1.0, 0.0];
        let tol = 0.1;
        let cut = cut_for_tolerance(u1, u2, tol);
        let b = blend_arc(&corner, u1, u2, cut).unwrap();
        let p = Path::Arc(b.arc);
        let len = p.length();
        assert!(close(xyz(&p.point(0.0, len)), [10.0 - cut, 0.0, 0.0]));
        assert!(close(xyz(&p.point(len, len)), [10.0, cut, 0.0]));
        assert!(close(p.xyz_direction(0.0, len).unwrap(), u1));
        assert!(close(p.xyz_direction(len, len).unwrap(), u2));
        let mid = xyz(&p.point(len / 2.0, len));
        let dev = norm(sub(mid, xyz(&corner)));
        assert!((dev - tol).abs() < 1e-9, "deviation {dev}");
    }
}
