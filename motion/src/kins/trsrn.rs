//! `xyzacb_trsrn` and `xyzbca_trsrn`: six-axis machines with a rotary
//! table and a universal spindle head whose secondary axis is inclined
//! ("nutating") by a fixed angle, from LinuxCNC 2.10 (halcompile
//! components on the userkins template). Three types, switched through
//! `motion.switchkins-type` (see [`super::twotype`]): 0 identity (the
//! startup type), 1 TCP (tool centre point: the tool tip follows the
//! table and the head), 2 TOOL (coordinates in a tilted work plane).
//!
//! Joints are X Y Z and three angles (degrees), passed through to A B C
//! in every type. The head turns the tool first about its secondary
//! axis, the unit vector `n` inclined `nut-angle` from Z, by `s`, then
//! about Z by the primary angle `p`; the table turns the workpiece by
//! `w` about X (xyzacb) or Y (xyzbca):
//!
//! | module | table `w` | secondary `s` | primary `p` | `n` | pivot |
//! |---|---|---|---|---|---|
//! | xyzacb_trsrn | joint 3 about X | joint 4 | joint 5 | (0, sin ν, cos ν) | `y-pivot` along −Y |
//! | xyzbca_trsrn | joint 4 about Y | joint 3 | joint 5 | (sin ν, 0, cos ν) | `x-pivot` along −X |
//!
//! With `v` the tool tip from the head's pivot (the pivot offset and
//! `z-pivot + tool-offset-z` down), `d` = (`x-offset`, `y-offset`, 0),
//! `h` = Rz(p)·(Rn(s)·v − d) the tip from the slides' point, `c` the
//! table axis' point (`y-rot-axis`/`x-rot-axis` and `z-rot-axis` less
//! the pivot and offsets) and `e` the tip at zero angles less the
//! slides' point:
//!
//! ```text
//! TCP:   world  = Rt(w)·(P + h − c) + c + e
//!        P      = Rt(−w)·(world − c − e) + c − h
//! TOOL:  world  = K·(Rz(−p)·(P + o) − d) + Rz(−τ)·(−pivot, −z-pivot)
//!        with K = Rz(−τ)·Rn(−s), p and s from `primary-angle` and
//!        `secondary-angle`, τ = `pre-rot`, o the pivot offsets
//! ```
//!
//! These are LinuxCNC's formulas (its sources expand them term by term),
//! with one difference: LinuxCNC's TCP inverse takes the angles from
//! the joints' previous values, which only undoes its forward while the
//! angles stand still; here it takes them from the pose, whose angles
//! become the joints', so the forward kinematics undo the inverse always.
//! `pre-rot` is read in radians, as LinuxCNC reads it.
//!
//! HAL items, LinuxCNC's names (prefix `xyzacb_trsrn_kins.` or
//! `xyzbca_trsrn_kins.`): `in` (u32 in) copied to `out` (u32 out) at every
//! inverse call; float in, default 0: `tool-offset-z`, `y-pivot` or
//! `x-pivot`, `z-pivot`, `x-offset`, `y-offset`, `y-rot-axis` or
//! `x-rot-axis`, `z-rot-axis`, `pre-rot`, `nut-angle`, `primary-angle`,
//! `secondary-angle`; the switch's `kinstype.is-0` … `is-2`; per
//! halcompile instance `xyzacb-trsrn.N.fpin` (s32 out) and the function
//! `xyzacb-trsrn.N.fdemo` counting its runs. The type is
//! KINEMATICS_BOTH.

use std::sync::atomic::{AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Out, Pin, Result};

use super::loader::float_in;
use super::math::{
    add, finite, mat_mul, mat_vec, rad, rot_x, rot_y, rot_z, sub, transpose, Mat3, Vec3,
};
use super::twotype::{self, TwoTypes};
use super::{KinsError, Pose};

/// The `xyzacb_trsrn` module.
pub static XYZACB_MODULE: ModuleDef = ModuleDef {
    name: "xyzacb_trsrn",
    params: hal_core::instances::INSTANCE_PARAMS,
    help: "rotary table (A) with a nutating universal spindle head, TCP and TOOL (switchable)",
    load: load_xyzacb,
};

/// The `xyzbca_trsrn` module.
pub static XYZBCA_MODULE: ModuleDef = ModuleDef {
    name: "xyzbca_trsrn",
    params: hal_core::instances::INSTANCE_PARAMS,
    help: "rotary table (B) with a nutating universal spindle head, TCP and TOOL (switchable)",
    load: load_xyzbca,
};

/// Joints the kinematics use.
pub const JOINTS: usize = 6;

/// Which of the two machines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// Table about X (joint 3), head pivot along Y.
    Acb,
    /// Table about Y (joint 4), head pivot along X.
    Bca,
}

impl Layout {
    /// The pins' prefix.
    fn prefix(self) -> &'static str {
        match self {
            Layout::Acb => "xyzacb_trsrn_kins",
            Layout::Bca => "xyzbca_trsrn_kins",
        }
    }

    /// The names of the pivot and table-axis pins' first letter.
    fn letter(self) -> char {
        match self {
            Layout::Acb => 'y',
            Layout::Bca => 'x',
        }
    }
}

/// The machine's geometry (the pins' values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Head {
    /// Which machine.
    pub layout: Layout,
    /// `tool-offset-z`.
    pub tool: f64,
    /// `y-pivot` (xyzacb) or `x-pivot` (xyzbca).
    pub pivot: f64,
    /// `z-pivot`.
    pub z_pivot: f64,
    /// `x-offset`.
    pub x_offset: f64,
    /// `y-offset`.
    pub y_offset: f64,
    /// `y-rot-axis` (xyzacb) or `x-rot-axis` (xyzbca).
    pub rot_axis: f64,
    /// `z-rot-axis`.
    pub z_rot_axis: f64,
    /// `pre-rot` (radians).
    pub pre_rot: f64,
    /// `nut-angle` (degrees).
    pub nut_angle: f64,
    /// `primary-angle` (degrees, TOOL type).
    pub primary: f64,
    /// `secondary-angle` (degrees, TOOL type).
    pub secondary: f64,
}

impl Head {
    /// A machine with every pin at its default (0).
    pub fn new(layout: Layout) -> Head {
        Head {
            layout,
            tool: 0.0,
            pivot: 0.0,
            z_pivot: 0.0,
            x_offset: 0.0,
            y_offset: 0.0,
            rot_axis: 0.0,
            z_rot_axis: 0.0,
            pre_rot: 0.0,
            nut_angle: 0.0,
            primary: 0.0,
            secondary: 0.0,
        }
    }

    fn values(&self) -> [f64; 11] {
        [
            self.tool,
            self.pivot,
            self.z_pivot,
            self.x_offset,
            self.y_offset,
            self.rot_axis,
            self.z_rot_axis,
            self.pre_rot,
            self.nut_angle,
            self.primary,
            self.secondary,
        ]
    }

    /// Turn by `angle` radians about the secondary axis.
    fn secondary_turn(&self, angle: f64) -> Mat3 {
        let (sv, cv) = rad(self.nut_angle).sin_cos();
        let n = match self.layout {
            Layout::Acb => [0.0, sv, cv],
            Layout::Bca => [sv, 0.0, cv],
        };
        let (s, c) = angle.sin_cos();
        let k = 1.0 - c;
        let [x, y, z] = n;
        [
            [c + k * x * x, k * x * y - s * z, k * x * z + s * y],
            [k * x * y + s * z, c + k * y * y, k * y * z - s * x],
            [k * x * z - s * y, k * y * z + s * x, c + k * z * z],
        ]
    }

    /// The table's turn by `angle` radians.
    fn table_turn(&self, angle: f64) -> Mat3 {
        match self.layout {
            Layout::Acb => rot_x(angle),
            Layout::Bca => rot_y(angle),
        }
    }

    /// The pivot offset as a vector, `down` below it.
    fn pivot_vec(&self, down: f64) -> Vec3 {
        match self.layout {
            Layout::Acb => [0.0, -self.pivot, -down],
            Layout::Bca => [-self.pivot, 0.0, -down],
        }
    }

    /// The slides' offsets `d`.
    fn offsets(&self) -> Vec3 {
        [self.x_offset, self.y_offset, 0.0]
    }

    /// The table axis' point `c` and the zero-angle tip offset `e`.
    fn table_points(&self) -> (Vec3, Vec3) {
        let down = self.z_pivot + self.tool;
        let e = sub(self.offsets(), self.pivot_vec(down));
        let c = match self.layout {
            Layout::Acb => [0.0, self.rot_axis - e[1], self.z_rot_axis - self.z_pivot],
            Layout::Bca => [self.rot_axis - e[0], 0.0, self.z_rot_axis - self.z_pivot],
        };
        (c, e)
    }

    /// The angles (table, secondary, primary; radians) of joints 3 to 5.
    fn angles(&self, j: [f64; 3]) -> (f64, f64, f64) {
        let [j3, j4, j5] = j.map(rad);
        match self.layout {
            Layout::Acb => (j3, j4, j5),
            Layout::Bca => (j4, j3, j5),
        }
    }

    /// The tool tip from the slides' point, `h`.
    fn head_offset(&self, s: f64, p: f64) -> Vec3 {
        let tip = mat_vec(
            &self.secondary_turn(s),
            self.pivot_vec(self.z_pivot + self.tool),
        );
        mat_vec(&rot_z(p), sub(tip, self.offsets()))
    }

    /// TCP: the tool tip on the workpiece for slides `p` and angles `a`.
    pub fn tcp_world(&self, slides: Vec3, a: [f64; 3]) -> Vec3 {
        let (w, s, p) = self.angles(a);
        let (c, e) = self.table_points();
        let h = self.head_offset(s, p);
        add(
            add(mat_vec(&self.table_turn(w), sub(add(slides, h), c)), c),
            e,
        )
    }

    /// TCP: the slides that put the tool tip at `world` with angles `a`.
    pub fn tcp_slides(&self, world: Vec3, a: [f64; 3]) -> Vec3 {
        let (w, s, p) = self.angles(a);
        let (c, e) = self.table_points();
        let h = self.head_offset(s, p);
        sub(
            add(mat_vec(&self.table_turn(-w), sub(sub(world, c), e)), c),
            h,
        )
    }

    /// TOOL: the plane's turn `K` and its shift.
    fn plane(&self) -> (Mat3, Vec3) {
        let pre = rot_z(-self.pre_rot);
        let k = mat_mul(&pre, &transpose(&self.secondary_turn(rad(self.secondary))));
        let shift = mat_vec(&pre, self.pivot_vec(self.z_pivot));
        (k, shift)
    }

    /// TOOL: the pivot offsets `o` added to the slides.
    fn plane_origin(&self) -> Vec3 {
        add(self.offsets(), sub([0.0; 3], self.pivot_vec(self.z_pivot)))
    }

    /// TOOL: the point in the work plane for slides `p`.
    pub fn tool_world(&self, slides: Vec3) -> Vec3 {
        let (k, shift) = self.plane();
        let turned = mat_vec(&rot_z(-rad(self.primary)), add(slides, self.plane_origin()));
        add(mat_vec(&k, sub(turned, self.offsets())), shift)
    }

    /// TOOL: the slides for point `world` in the work plane.
    pub fn tool_slides(&self, world: Vec3) -> Vec3 {
        let (k, shift) = self.plane();
        let back = add(mat_vec(&transpose(&k), sub(world, shift)), self.offsets());
        sub(
            mat_vec(&rot_z(rad(self.primary)), back),
            self.plane_origin(),
        )
    }
}

impl TwoTypes for Head {
    const NAME: &'static str = "trsrn";
    const TYPES: usize = 3;

    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        let j: &[f64; JOINTS] = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(j)?;
        finite(&self.values())?;
        let [x, y, z, a0, a1, a2] = *j;
        let xyz = match kins_type {
            1 => self.tcp_world([x, y, z], [a0, a1, a2]),
            2 => self.tool_world([x, y, z]),
            _ => [x, y, z],
        };
        finite(&xyz)?;
        *pose = Pose::ZERO;
        pose.0[..3].copy_from_slice(&xyz);
        pose.0[3..6].copy_from_slice(&j[3..]);
        Ok(())
    }

    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        let slots: &mut [f64; JOINTS] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        let [x, y, z, a0, a1, a2, ..] = pose.0;
        finite(&[x, y, z, a0, a1, a2])?;
        finite(&self.values())?;
        let xyz = match kins_type {
            1 => self.tcp_slides([x, y, z], [a0, a1, a2]),
            2 => self.tool_slides([x, y, z]),
            _ => [x, y, z],
        };
        finite(&xyz)?;
        *slots = [xyz[0], xyz[1], xyz[2], a0, a1, a2];
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

/// The module's kinematics: the geometry read from the pins at every
/// call, and the template's `in`/`out` pins.
struct HeadPins<const ACB: bool> {
    geometry: [Pin<f64, In>; 11],
    input: Pin<u32, In>,
    output: Pin<u32, Out>,
}

impl<const ACB: bool> HeadPins<ACB> {
    const LAYOUT: Layout = if ACB { Layout::Acb } else { Layout::Bca };

    fn export(c: &Component) -> Result<HeadPins<ACB>> {
        let prefix = Self::LAYOUT.prefix();
        let l = Self::LAYOUT.letter();
        let input = c.pin(&format!("{prefix}.in"))?;
        let output = c.pin(&format!("{prefix}.out"))?;
        let names = [
            "tool-offset-z".to_string(),
            format!("{l}-pivot"),
            "z-pivot".into(),
            "x-offset".into(),
            "y-offset".into(),
            format!("{l}-rot-axis"),
            "z-rot-axis".into(),
            "pre-rot".into(),
            "nut-angle".into(),
            "primary-angle".into(),
            "secondary-angle".into(),
        ];
        let p = |i: usize| float_in(c, &format!("{prefix}.{}", names[i]), 0.0);
        Ok(HeadPins {
            geometry: [
                p(0)?,
                p(1)?,
                p(2)?,
                p(3)?,
                p(4)?,
                p(5)?,
                p(6)?,
                p(7)?,
                p(8)?,
                p(9)?,
                p(10)?,
            ],
            input,
            output,
        })
    }

    fn head(&self) -> Head {
        let [tool, pivot, z_pivot, x_offset, y_offset, rot_axis, z_rot_axis, pre_rot, nut_angle, primary, secondary] =
            self.geometry.each_ref().map(|p| p.get());
        Head {
            layout: Self::LAYOUT,
            tool,
            pivot,
            z_pivot,
            x_offset,
            y_offset,
            rot_axis,
            z_rot_axis,
            pre_rot,
            nut_angle,
            primary,
            secondary,
        }
    }
}

impl<const ACB: bool> TwoTypes for HeadPins<ACB> {
    const NAME: &'static str = if ACB { "xyzacb_trsrn" } else { "xyzbca_trsrn" };
    const TYPES: usize = 3;

    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        self.head().forward(kins_type, joints, pose)
    }

    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        self.head().inverse(kins_type, pose, joints)?;
        self.output.set(self.input.get());
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

fn load_module<const ACB: bool>(host: &Host, args: &ModuleArgs) -> Result<()> {
    twotype::load(
        host,
        args,
        |b, prefix| {
            let fpin: Pin<i32, Out> = b.component().pin(&format!("{prefix}.fpin"))?;
            let runs = Arc::new(AtomicI32::new(0));
            b.funct(&format!("{prefix}.fdemo"), true, move |_| {
                let n = runs.load(Relaxed).wrapping_add(1);
                runs.store(n, Relaxed);
                fpin.set(n);
            })
        },
        HeadPins::<ACB>::export,
    )
}

fn load_xyzacb(host: &Host, args: &ModuleArgs) -> Result<()> {
    load_module::<true>(host, args)
}

fn load_xyzbca(host: &Host, args: &ModuleArgs) -> Result<()> {
    load_module::<false>(host, args)
}

#[cfg(test)]
mod tests;
