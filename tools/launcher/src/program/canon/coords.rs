//! Task's canon between program and machine: lengths in program units
//! to machine units (through millimetres, as LinuxCNC's canon converts),
//! and positions through the XY rotation and the G5x, G92 and tool
//! length offsets, both ways.

use rs274ngc::Pose;

use super::TaskCanon;

impl TaskCanon {
    /// Whether axis `i` (X Y Z A B C U V W) is a length (A B C are
    /// angles, taken as they are).
    pub(super) fn is_length(i: usize) -> bool {
        !(3..6).contains(&i)
    }

    /// A length in program units in machine units: to millimetres first,
    /// then to machine units, two roundings as LinuxCNC's canon has them
    /// (one factor made of the two would be off by a bit: 0.2 inch on an
    /// inch machine would come out 0.19999999999999998).
    pub(super) fn length_to_machine(&self, v: f64) -> f64 {
        v * self.units.mm_per_unit() * self.user_per_mm
    }

    /// A length in machine units in program units (the way back, the
    /// same two steps).
    pub(super) fn length_to_program(&self, v: f64) -> f64 {
        v / self.user_per_mm / self.units.mm_per_unit()
    }

    pub(super) fn pose_to_array(p: &Pose) -> [f64; 9] {
        [p.x, p.y, p.z, p.a, p.b, p.c, p.u, p.v, p.w]
    }

    pub(super) fn array_to_pose(a: [f64; 9]) -> Pose {
        Pose {
            x: a[0],
            y: a[1],
            z: a[2],
            a: a[3],
            b: a[4],
            c: a[5],
            u: a[6],
            v: a[7],
            w: a[8],
        }
    }

    /// A program-units vector (no offsets) in machine units.
    pub(super) fn scaled(&self, p: &Pose) -> [f64; 9] {
        let mut a = Self::pose_to_array(p);
        for (i, v) in a.iter_mut().enumerate() {
            if Self::is_length(i) {
                *v = self.length_to_machine(*v);
            }
        }
        a
    }

    /// A machine-units vector (no offsets) in program units.
    pub(super) fn unscaled(&self, mut a: [f64; 9]) -> Pose {
        for (i, v) in a.iter_mut().enumerate() {
            if Self::is_length(i) {
                *v = self.length_to_program(*v);
            }
        }
        Self::array_to_pose(a)
    }

    /// A program position in machine coordinates: scaled, rotated about
    /// the work origin, offset.
    pub(super) fn to_machine(&self, p: &Pose) -> [f64; 9] {
        let mut a = self.scaled(p);
        let (s, c) = self.rotation_deg.to_radians().sin_cos();
        let (x, y) = (a[0], a[1]);
        a[0] = x * c - y * s;
        a[1] = x * s + y * c;
        for (i, v) in a.iter_mut().enumerate() {
            *v += self.g5x[i] + self.g92[i] + self.tool_offset[i];
        }
        a
    }

    /// A machine position in program coordinates.
    pub(super) fn to_program(&self, m: [f64; 9]) -> Pose {
        let mut a = m;
        for (i, v) in a.iter_mut().enumerate() {
            *v -= self.g5x[i] + self.g92[i] + self.tool_offset[i];
        }
        let (s, c) = self.rotation_deg.to_radians().sin_cos();
        let (x, y) = (a[0], a[1]);
        a[0] = x * c + y * s;
        a[1] = -x * s + y * c;
        self.unscaled(a)
    }

    /// The feed rate in machine units per second.
    pub(super) fn feed_per_second(&self) -> f64 {
        self.feed * self.units.mm_per_unit() * self.user_per_mm / 60.0
    }
}
