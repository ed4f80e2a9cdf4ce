//! Serial chains of revolute joints described by Denavit–Hartenberg
//! parameters in the convention of J. J. Craig's "Introduction to
//! Robotics" (the "modified" parameters LinuxCNC's genserkins uses): link
//! `i` is a turn `alpha` about X, a shift `a` along X, the joint's turn
//! `theta` about the new Z, and a shift `d` along that Z.
//!
//! Used by genserkins (forward kinematics and the Jacobian of its
//! iterative inverse) and pumakins (its forward kinematics).

use super::math::{add, column, cross, mat_mul, mat_vec, rot_x, rot_z, sub, Mat3, Vec3, IDENTITY};

/// Joints (links) of a chain.
pub const LINKS: usize = 6;

/// One link's parameters; `alpha` in radians, lengths in machine units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DhLink {
    /// Distance along the previous X between the joint axes.
    pub a: f64,
    /// Twist about the previous X between the joint axes (radians).
    pub alpha: f64,
    /// Offset along this joint's axis.
    pub d: f64,
}

/// A rigid transform: rotate by `rot`, then shift by `pos`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Orientation; its columns are the frame's axes.
    pub rot: Mat3,
    /// Origin.
    pub pos: Vec3,
}

impl Frame {
    /// The base frame.
    pub const IDENTITY: Frame = Frame {
        rot: IDENTITY,
        pos: [0.0; 3],
    };

    /// `self` followed by `next` expressed in `self`.
    pub fn then(&self, next: &Frame) -> Frame {
        Frame {
            rot: mat_mul(&self.rot, &next.rot),
            pos: add(self.pos, mat_vec(&self.rot, next.pos)),
        }
    }

    /// The frame's Z axis (a joint's axis of rotation).
    pub fn z_axis(&self) -> Vec3 {
        column(&self.rot, 2)
    }
}

impl DhLink {
    /// The link's transform with its joint at `theta` radians.
    pub fn frame(&self, theta: f64) -> Frame {
        let (sa, ca) = self.alpha.sin_cos();
        Frame {
            rot: mat_mul(&rot_x(self.alpha), &rot_z(theta)),
            pos: [self.a, -sa * self.d, ca * self.d],
        }
    }
}

/// The pose of the last link with joints at `theta` (radians), and the
/// frame of every joint on the way (joint `i` turns about the Z of
/// `frames[i]`).
pub fn chain(links: &[DhLink; LINKS], theta: &[f64; LINKS]) -> (Frame, [Frame; LINKS]) {
    let mut frames = [Frame::IDENTITY; LINKS];
    let mut t = Frame::IDENTITY;
    for (i, (link, &q)) in links.iter().zip(theta).enumerate() {
        t = t.then(&link.frame(q));
        frames[i] = t;
    }
    (t, frames)
}

/// The Jacobian at `tool` of a chain whose joints have `frames`: column
/// `i` is the tool's linear (rows 0–2) and angular (rows 3–5) velocity,
/// in base coordinates, per unit speed of joint `i`.
pub fn jacobian(frames: &[Frame; LINKS], tool: Vec3) -> [[f64; LINKS]; 6] {
    let mut j = [[0.0; LINKS]; 6];
    for (i, f) in frames.iter().enumerate() {
        let z = f.z_axis();
        let v = cross(z, sub(tool, f.pos));
        for r in 0..3 {
            j[r][i] = v[r];
            j[r + 3][i] = z[r];
        }
    }
    j
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kins::math::norm;

    #[test]
    fn a_planar_arm_reaches_where_geometry_says() {
        // Two links of 3 and 2 in the XY plane (twists zero), the rest
        // of the chain stacked at the tip.
        let mut links = [DhLink::default(); LINKS];
        links[1].a = 3.0;
        links[2].a = 2.0;
        let q = std::f64::consts::FRAC_PI_2;
        let (t, _) = chain(&links, &[q, -q, 0.0, 0.0, 0.0, 0.0]);
        // Joint 0 turns everything 90°: link 1 points along Y, and joint
        // 1 turns link 2 back to X.
        assert!(norm(sub(t.pos, [2.0, 3.0, 0.0])) < 1e-12, "{:?}", t.pos);
    }

    #[test]
    fn the_jacobian_matches_finite_differences() {
        let mut links = [DhLink::default(); LINKS];
        for (i, l) in links.iter_mut().enumerate() {
            l.a = 0.3 * i as f64;
            l.alpha = 0.7 - 0.4 * i as f64;
            l.d = 1.0 - 0.2 * i as f64;
        }
        let q = [0.1, -0.4, 0.8, 0.3, -1.2, 0.5];
        let (t, frames) = chain(&links, &q);
        let j = jacobian(&frames, t.pos);
        let h = 1e-7;
        for i in 0..LINKS {
            let mut q2 = q;
            q2[i] += h;
            let (t2, _) = chain(&links, &q2);
            for (r, row) in j.iter().take(3).enumerate() {
                let numeric = (t2.pos[r] - t.pos[r]) / h;
                assert!((numeric - row[i]).abs() < 1e-5, "col {i} row {r}");
            }
        }
    }
}
