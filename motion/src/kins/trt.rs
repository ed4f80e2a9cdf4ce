//! `xyzac-trt-kins` and `xyzbc-trt-kins`: five-axis mills with a tilting
//! rotary table, with tool-centre-point control. Both are switchable
//! (type 0 the table kinematics, type 1 identity, type 2 user; see
//! [`super::switchkins`]; `sparm=identityfirst` swaps types 0 and 1).
//!
//! The table tilts about X (A, xyzac) or Y (B, xyzbc); the rotary C is
//! mounted on the tilting part. The world pose is the tool tip in the
//! coordinates of the workpiece on the table, the joints are the
//! machine's slides and the two table angles (degrees). With the tilt
//! axis offset `d` from the rotary axis and both turned about the rotary
//! axis' point `r`:
//!
//! ```text
//! forward:  P = Rz(s·C) · (Rt(s·T) · (J − r − d) + d) + r
//! inverse:  J = Rt(−s·T) · (Rz(−s·C) · (P − r) − d) + d + r
//! ```
//!
//! where `Rt` turns about the tilt axis and `s` is −1 (LinuxCNC's default:
//! the table turns opposite to the conventional axis directions) or +1
//! with `conventional-directions` set. The angles themselves pass through.
//!
//! Joints follow `coordinates=` (default `xyzac` / `xyzbc`) as in
//! trivkins: it must contain the five letters, may repeat letters (a
//! gantry's second joint gets the same value) and may add others (U V W
//! and the unused rotary), which map one to one.
//!
//! Pins (float in, LinuxCNC's names, default 0): `<module>.x-rot-point`,
//! `.y-rot-point`, `.z-rot-point` (the rotary axis' point), `.x-offset`
//! (xyzbc: X from the rotary axis to the tilt axis), `.y-offset` (xyzac:
//! Y likewise), `.z-offset` (Z likewise), `.tool-offset` (the tool
//! length, added to `z-offset`), and `.conventional-directions` (bit in,
//! default false). Both modules export all seven float pins.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Pin, Result};

use super::loader::float_in;
use super::math::{add, finite, mat_vec, rad, rot_x, rot_y, rot_z, sub, Mat3, Vec3};
use super::switchkins::{self, SwitchSpec};
use super::trivkins::{Trivkins, MAX_JOINTS};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The `xyzac-trt-kins` module.
pub static XYZAC_MODULE: ModuleDef = ModuleDef {
    name: "xyzac-trt-kins",
    params: switchkins::PARAMS,
    help: "tilting (A) rotary (C) table with tool centre point (switchable)",
    load: load_xyzac,
};

/// The `xyzbc-trt-kins` module.
pub static XYZBC_MODULE: ModuleDef = ModuleDef {
    name: "xyzbc-trt-kins",
    params: switchkins::PARAMS,
    help: "tilting (B) rotary (C) table with tool centre point (switchable)",
    load: load_xyzbc,
};

/// Which way the table tilts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tilt {
    /// About X: the A axis (xyzac-trt-kins).
    A,
    /// About Y: the B axis (xyzbc-trt-kins).
    B,
}

impl Tilt {
    /// The pose index of the tilt angle.
    fn axis(self) -> usize {
        match self {
            Tilt::A => 3,
            Tilt::B => 4,
        }
    }

    fn turn(self, angle: f64) -> Mat3 {
        match self {
            Tilt::A => rot_x(angle),
            Tilt::B => rot_y(angle),
        }
    }

    fn module(self) -> &'static str {
        match self {
            Tilt::A => "xyzac-trt-kins",
            Tilt::B => "xyzbc-trt-kins",
        }
    }
}

/// The table's geometry (the pins' values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Table {
    /// Which way the table tilts.
    pub tilt: Tilt,
    /// A point of the rotary axis (`x-rot-point` … `z-rot-point`).
    pub rot_point: Vec3,
    /// `x-offset` (used by xyzbc).
    pub x_offset: f64,
    /// `y-offset` (used by xyzac).
    pub y_offset: f64,
    /// `z-offset`.
    pub z_offset: f64,
    /// `tool-offset`.
    pub tool_offset: f64,
    /// `conventional-directions`.
    pub conventional: bool,
}

impl Table {
    /// A table with every offset zero and LinuxCNC's default directions.
    pub fn new(tilt: Tilt) -> Table {
        Table {
            tilt,
            rot_point: [0.0; 3],
            x_offset: 0.0,
            y_offset: 0.0,
            z_offset: 0.0,
            tool_offset: 0.0,
            conventional: false,
        }
    }

    /// From the rotary axis to the tilt axis (with the tool length).
    fn offset(&self) -> Vec3 {
        let z = self.z_offset + self.tool_offset;
        match self.tilt {
            Tilt::A => [0.0, self.y_offset, z],
            Tilt::B => [self.x_offset, 0.0, z],
        }
    }

    fn sign(&self) -> f64 {
        if self.conventional {
            1.0
        } else {
            -1.0
        }
    }

    fn check(&self) -> std::result::Result<(), KinsError> {
        finite(&self.rot_point)?;
        finite(&self.offset())
    }

    /// The tool tip on the workpiece for slides at `j`, tilt `t` and
    /// rotary `c` (degrees).
    pub fn to_world(&self, j: Vec3, t: f64, c: f64) -> Vec3 {
        let (r, d, s) = (self.rot_point, self.offset(), self.sign());
        let tilted = add(mat_vec(&self.tilt.turn(s * rad(t)), sub(sub(j, r), d)), d);
        add(mat_vec(&rot_z(s * rad(c)), tilted), r)
    }

    /// The slides that put the tool tip at `p` on the workpiece with tilt
    /// `t` and rotary `c` (degrees).
    pub fn to_joints(&self, p: Vec3, t: f64, c: f64) -> Vec3 {
        let (r, d, s) = (self.rot_point, self.offset(), self.sign());
        let untwisted = sub(mat_vec(&rot_z(-s * rad(c)), sub(p, r)), d);
        add(add(mat_vec(&self.tilt.turn(-s * rad(t)), untwisted), d), r)
    }

    /// Forward kinematics through the joint map `map`.
    fn forward(
        &self,
        map: &Trivkins,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        self.check()?;
        finite(&joints[..joints.len().min(map.axis_of_joint().len())])?;
        // The joints as letters, then the tool tip from X Y Z and angles.
        let mut jp = *pose;
        map.forward(joints, &mut jp, &mut KinsFlags::default())?;
        let t = jp.0[self.tilt.axis()];
        let [x, y, z, .., c, _, _, _] = jp.0;
        finite(&[x, y, z, t, c])?;
        let w = self.to_world([x, y, z], t, c);
        finite(&w)?;
        jp.0[..3].copy_from_slice(&w);
        *pose = jp;
        Ok(())
    }

    /// Inverse kinematics through the joint map `map`.
    fn inverse(
        &self,
        map: &Trivkins,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        self.check()?;
        let mut jp = *pose;
        let t = pose.0[self.tilt.axis()];
        let [x, y, z, .., c, _, _, _] = pose.0;
        finite(&[x, y, z, t, c])?;
        let j = self.to_joints([x, y, z], t, c);
        finite(&j)?;
        jp.0[..3].copy_from_slice(&j);
        for &a in map.axis_of_joint() {
            finite(&[jp.0[a]])?;
        }
        map.inverse(&jp, joints, &mut KinsFlags::default())
    }
}

/// A tilting rotary table of fixed geometry with its joint map.
#[derive(Debug, Clone, PartialEq)]
pub struct TableKins {
    /// The geometry.
    pub table: Table,
    map: Trivkins,
}

impl TableKins {
    /// The table kinematics with joints mapped by `coordinates` (which
    /// must contain X Y Z, the tilt letter and C); a refused map is the
    /// error `loadrt` would give for it.
    pub fn new(table: Table, coordinates: &str) -> Result<TableKins> {
        let map = switchkins::identity_map(&spec(table.tilt), Some(coordinates))?;
        Ok(TableKins { table, map })
    }
}

impl Kinematics for TableKins {
    fn name(&self) -> &str {
        self.table.tilt.module()
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Both
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.table.forward(&self.map, joints, pose)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.table.inverse(&self.map, pose, joints)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.map.has_axis(axis)
    }
}

/// The module's own kinematics: the geometry read from the pins at every
/// call.
pub struct Trtkins {
    tilt: Tilt,
    map: Trivkins,
    rot_point: [Pin<f64, In>; 3],
    offsets: [Pin<f64, In>; 4],
    conventional: Pin<bool, In>,
}

impl Trtkins {
    fn export(c: &Component, tilt: Tilt, map: &Trivkins) -> Result<Trtkins> {
        let m = tilt.module();
        let p = |name: &str| float_in(c, &format!("{m}.{name}"), 0.0);
        Ok(Trtkins {
            tilt,
            map: map.clone(),
            rot_point: [p("x-rot-point")?, p("y-rot-point")?, p("z-rot-point")?],
            offsets: [
                p("x-offset")?,
                p("y-offset")?,
                p("z-offset")?,
                p("tool-offset")?,
            ],
            conventional: c.pin(&format!("{m}.conventional-directions"))?,
        })
    }

    /// The geometry on the pins now.
    pub fn geometry(&self) -> Table {
        let [x_offset, y_offset, z_offset, tool_offset] = self.offsets.each_ref().map(|p| p.get());
        Table {
            tilt: self.tilt,
            rot_point: self.rot_point.each_ref().map(|p| p.get()),
            x_offset,
            y_offset,
            z_offset,
            tool_offset,
            conventional: self.conventional.get(),
        }
    }
}

impl Kinematics for Trtkins {
    fn name(&self) -> &str {
        self.tilt.module()
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Both
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.geometry().forward(&self.map, joints, pose)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.geometry().inverse(&self.map, pose, joints)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.map.has_axis(axis)
    }
}

/// How the table modules switch: the five letters required, duplicates
/// and extra letters allowed, `sparm=identityfirst` honoured.
pub const fn spec(tilt: Tilt) -> SwitchSpec {
    SwitchSpec {
        module: match tilt {
            Tilt::A => "xyzac-trt-kins",
            Tilt::B => "xyzbc-trt-kins",
        },
        required: match tilt {
            Tilt::A => "xyzac",
            Tilt::B => "xyzbc",
        },
        requires_letters: true,
        allow_duplicates: true,
        max_joints: MAX_JOINTS,
        honours_identity_first: true,
        forward_iterates: false,
        gui_pins: false,
    }
}

fn load_xyzac(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, spec(Tilt::A), |c, map| {
        Trtkins::export(c, Tilt::A, map)
    })
}

fn load_xyzbc(host: &Host, args: &ModuleArgs) -> Result<()> {
    switchkins::load(host, args, spec(Tilt::B), |c, map| {
        Trtkins::export(c, Tilt::B, map)
    })
}

#[cfg(test)]
mod tests;
