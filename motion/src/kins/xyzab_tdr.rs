//! `xyzab_tdr_kins`: a five-axis mill with a dual rotary table, a rotary
//! A carrying a rotary B, switchable between type 0 (identity, the
//! startup type) and type 1 (tool-centre-point control); see
//! [`super::twotype`].
//!
//! Joints 0 to 4 are X Y Z A B (angles in degrees); C U V W are always
//! 0. In type 1 the world pose is the tool tip in the coordinates of the
//! workpiece on the table. The B axis passes through `r + t`, the A axis
//! through `r + t + d`, with `r` the rotation point, `t = (0, 0,
//! tool-offset-z)` and `d = (x-offset, 0, z-offset)`:
//!
//! ```text
//! forward:  P = Rx(A) · (Ry(B) · (J − r − t) − d) + r + t + d
//! inverse:  J = Ry(−B) · (Rx(−A) · (P − r − t − d) + d) + r + t
//! ```
//!
//! (LinuxCNC writes the same out term by term; in its forward the two
//! `x-offset` terms cancel, so it does not read that pin.)
//!
//! Pins (LinuxCNC's names, float in, default 0):
//! `xyzab_tdr_kins.tool-offset-z`, `.x-offset`, `.z-offset`,
//! `.x-rot-point`, `.y-rot-point`, `.z-rot-point`; the switch's
//! `kinstype.is-0` and `kinstype.is-1`; and per halcompile instance
//! `xyzab-tdr-kins.N.dummy` (s32 out, 0), which the template needs and
//! nothing uses. LinuxCNC creates the kinematics pins when motion first
//! asks for the kinematics type; here `loadrt` creates them.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Out, Pin, Result};

use super::loader::float_in;
use super::math::{add, finite, mat_vec, rad, rot_x, rot_y, sub, Vec3};
use super::twotype::{self, TwoTypes};
use super::{KinsError, Pose};

/// The module's name.
const NAME: &str = "xyzab_tdr_kins";

/// The `xyzab_tdr_kins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: hal_core::instances::INSTANCE_PARAMS,
    help: "dual rotary table (A carrying B), identity or tool centre point (switchable)",
    load,
};

/// Joints the kinematics use.
const JOINTS: usize = 5;

/// The table's geometry (the pins' values).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DualTable {
    /// `x-rot-point`, `y-rot-point`, `z-rot-point`.
    pub rot_point: Vec3,
    /// `x-offset`: X from the B axis to the A axis.
    pub x_offset: f64,
    /// `z-offset`: Z from the B axis to the A axis.
    pub z_offset: f64,
    /// `tool-offset-z`: the tool length.
    pub tool_offset_z: f64,
}

impl DualTable {
    /// The point the B axis passes through, and from it to the A axis.
    fn centres(&self) -> (Vec3, Vec3) {
        let b = add(self.rot_point, [0.0, 0.0, self.tool_offset_z]);
        (b, [self.x_offset, 0.0, self.z_offset])
    }

    fn check(&self) -> std::result::Result<(), KinsError> {
        finite(&self.rot_point)?;
        finite(&[self.x_offset, self.z_offset, self.tool_offset_z])
    }

    /// The tool tip on the workpiece for slides at `j` and table angles
    /// `a`, `b` (degrees).
    pub fn to_world(&self, j: Vec3, a: f64, b: f64) -> Vec3 {
        let (cb, d) = self.centres();
        let turned_b = sub(mat_vec(&rot_y(rad(b)), sub(j, cb)), d);
        add(add(mat_vec(&rot_x(rad(a)), turned_b), cb), d)
    }

    /// The slides that put the tool tip at `p` on the workpiece with
    /// table angles `a`, `b` (degrees).
    pub fn to_joints(&self, p: Vec3, a: f64, b: f64) -> Vec3 {
        let (cb, d) = self.centres();
        let back_a = add(mat_vec(&rot_x(rad(-a)), sub(sub(p, cb), d)), d);
        add(mat_vec(&rot_y(rad(-b)), back_a), cb)
    }
}

impl TwoTypes for DualTable {
    const NAME: &'static str = NAME;

    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        let j: &[f64; JOINTS] = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(j)?;
        self.check()?;
        let [x, y, z, a, b] = *j;
        let xyz = if kins_type == 1 {
            self.to_world([x, y, z], a, b)
        } else {
            [x, y, z]
        };
        finite(&xyz)?;
        *pose = Pose::ZERO;
        pose.0[..JOINTS].copy_from_slice(&[xyz[0], xyz[1], xyz[2], a, b]);
        Ok(())
    }

    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        let slots: &mut [f64; JOINTS] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        let [x, y, z, a, b, ..] = pose.0;
        finite(&[x, y, z, a, b])?;
        self.check()?;
        let j = if kins_type == 1 {
            self.to_joints([x, y, z], a, b)
        } else {
            [x, y, z]
        };
        finite(&j)?;
        *slots = [j[0], j[1], j[2], a, b];
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

/// The module's pins, read at every call.
struct TdrPins {
    rot_point: [Pin<f64, In>; 3],
    x_offset: Pin<f64, In>,
    z_offset: Pin<f64, In>,
    tool_offset_z: Pin<f64, In>,
}

impl TdrPins {
    fn export(c: &Component) -> Result<TdrPins> {
        let p = |name: &str| float_in(c, &format!("{NAME}.{name}"), 0.0);
        Ok(TdrPins {
            tool_offset_z: p("tool-offset-z")?,
            x_offset: p("x-offset")?,
            z_offset: p("z-offset")?,
            rot_point: [p("x-rot-point")?, p("y-rot-point")?, p("z-rot-point")?],
        })
    }

    fn geometry(&self) -> DualTable {
        DualTable {
            rot_point: self.rot_point.each_ref().map(|p| p.get()),
            x_offset: self.x_offset.get(),
            z_offset: self.z_offset.get(),
            tool_offset_z: self.tool_offset_z.get(),
        }
    }
}

impl TwoTypes for TdrPins {
    const NAME: &'static str = NAME;

    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        self.geometry().forward(kins_type, joints, pose)
    }

    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        self.geometry().inverse(kins_type, pose, joints)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    twotype::load(
        host,
        args,
        |b, prefix| {
            b.component()
                .pin::<i32, Out>(&format!("{prefix}.dummy"))
                .map(drop)
        },
        TdrPins::export,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kins::twotype::TwoTypeKins;
    use crate::kins::{Kinematics, KinsFlags};
    use proptest::prelude::*;

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    fn tcp(table: DualTable) -> TwoTypeKins<DualTable> {
        let k = TwoTypeKins::new(table);
        k.switch_to(1).unwrap();
        k
    }

    fn fwd(k: &dyn Kinematics, j: [f64; 5]) -> [f64; 9] {
        let mut p = Pose::ZERO;
        k.forward(&j, &mut p, &mut KinsFlags::default()).unwrap();
        p.0
    }

    fn inv(k: &dyn Kinematics, p: [f64; 5]) -> [f64; 5] {
        crate::kins::testing::inverse(k, &p, [0.0; 5]).unwrap()
    }

    #[test]
    fn type_0_is_identity_and_type_1_turns_the_table() {
        let table = DualTable {
            rot_point: [1.0, 2.0, 3.0],
            x_offset: 4.0,
            z_offset: 5.0,
            tool_offset_z: 6.0,
        };
        let k = TwoTypeKins::new(table);
        assert_eq!(k.active_type(), 0);
        let j = [10.0, 20.0, 30.0, 40.0, 50.0];
        assert_eq!(fwd(&k, j)[..5], j);
        assert_eq!(inv(&k, j), j);
        let k = tcp(table);
        assert!(!close(&fwd(&k, j)[..3], &j[..3], 1.0));
        assert_eq!(k.switch_to(2), Err(KinsError::Unsupported));
        assert_eq!(k.active_type(), 1);
    }

    #[test]
    fn tcp_matches_linuxcncs_terms() {
        // LinuxCNC's type-1 forward, written out for one joint set.
        let t = DualTable {
            rot_point: [5.0, -7.0, 11.0],
            x_offset: 3.0,
            z_offset: -2.0,
            tool_offset_z: 40.0,
        };
        let (a, b) = (25.0f64.to_radians(), -35.0f64.to_radians());
        let (sa, ca, sb, cb) = (a.sin(), a.cos(), b.sin(), b.cos());
        let (dz, dt) = (t.z_offset, t.tool_offset_z);
        let j = [12.0, -9.0, 30.0];
        let px = j[0] - t.rot_point[0];
        let py = j[1] - t.rot_point[1];
        let pz = j[2] - t.rot_point[2] - dt;
        let want = [
            cb * px + sb * pz + t.rot_point[0],
            sa * sb * px + ca * py - cb * sa * pz + sa * dz + t.rot_point[1],
            -ca * sb * px + sa * py + ca * cb * pz - ca * dz + t.rot_point[2] + dz + dt,
        ];
        let got = t.to_world(j, 25.0, -35.0);
        assert!(close(&got, &want, 1e-9), "{got:?} vs {want:?}");
    }

    #[test]
    fn short_joint_sets_and_non_numbers_are_refused() {
        let k = tcp(DualTable::default());
        let mut p = Pose::ZERO;
        let mut flags = KinsFlags::default();
        assert_eq!(
            k.forward(&[0.0; 4], &mut p, &mut flags),
            Err(KinsError::Unsupported)
        );
        p.0[3] = f64::NAN;
        assert_eq!(
            k.inverse(&p, &mut [0.0; 5], &mut flags),
            Err(KinsError::NoSolution)
        );
        let bad = tcp(DualTable {
            x_offset: f64::INFINITY,
            ..DualTable::default()
        });
        assert_eq!(
            bad.inverse(&Pose::ZERO, &mut [0.0; 5], &mut flags),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn tcp_round_trips(
            rot in prop::array::uniform3(-200.0f64..200.0),
            offsets in prop::array::uniform3(-100.0f64..100.0),
            xyz in prop::array::uniform3(-300.0f64..300.0),
            a in -120.0f64..120.0, b in -360.0f64..360.0,
        ) {
            let k = tcp(DualTable {
                rot_point: rot,
                x_offset: offsets[0],
                z_offset: offsets[1],
                tool_offset_z: offsets[2],
            });
            let p = [xyz[0], xyz[1], xyz[2], a, b];
            let back = fwd(&k, inv(&k, p));
            prop_assert!(close(&back[..5], &p, 1e-9), "{:?} vs {:?}", back, p);
        }
    }
}
