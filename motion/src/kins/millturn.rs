//! `millturn`: a mill-turn machine with three slides and a rotary A,
//! switchable between type 0 (mill: joints 0 to 3 are X Y Z A, the
//! startup type) and type 1 (turn: the spindle along X, with the slides
//! renamed); see [`super::twotype`].
//!
//! ```text
//! type 0:  X = j0   Y = j1    Z = j2   A = j3
//! type 1:  X = j2   Y = −j1   Z = j0   A = j3
//! ```
//!
//! B C U V W are always 0.
//!
//! HAL items, LinuxCNC's names and kinds: `millturn.in` (u32 in) copied
//! to `millturn.out` (u32 out) at every inverse call (the template's
//! example of pins the kinematics use), parameters `millturn.param-rw`
//! (float rw) and `millturn.param-ro` (float ro), the switch's
//! `kinstype.is-0` and `kinstype.is-1`; per halcompile instance
//! `millturn.N.fpin` (s32 out) and the function `millturn.N.fdemo`,
//! which counts its runs on `fpin` (the template's example of a
//! function beside the kinematics). LinuxCNC creates the kinematics'
//! items when motion first asks for the kinematics type, and prints a
//! line when `fdemo` first runs; here `loadrt` creates them, and the
//! function is silent.

use std::sync::atomic::{AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Out, Param, Pin, Result, Ro, Rw};

use super::math::finite;
use super::twotype::{self, TwoTypes};
use super::{KinsError, Pose};

/// The module's name.
const NAME: &str = "millturn";

/// The `millturn` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: hal_core::instances::INSTANCE_PARAMS,
    help: "mill-turn machine: mill (XYZA) or turn (Z-YX) kinematics (switchable)",
    load,
};

/// Joints the kinematics use.
const JOINTS: usize = 4;

/// The two kinematics, without pins.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MillTurn;

/// The axes X Y Z A of joints `j` in type `kins_type`.
fn axes_of(kins_type: usize, j: [f64; JOINTS]) -> [f64; JOINTS] {
    let [j0, j1, j2, j3] = j;
    if kins_type == 1 {
        [j2, -j1, j0, j3]
    } else {
        j
    }
}

/// The joints of axes X Y Z A `p` in type `kins_type`.
fn joints_of(kins_type: usize, p: [f64; JOINTS]) -> [f64; JOINTS] {
    let [x, y, z, a] = p;
    if kins_type == 1 {
        [z, -y, x, a]
    } else {
        p
    }
}

impl TwoTypes for MillTurn {
    const NAME: &'static str = NAME;

    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        let j: &[f64; JOINTS] = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(j)?;
        *pose = Pose::ZERO;
        pose.0[..JOINTS].copy_from_slice(&axes_of(kins_type, *j));
        Ok(())
    }

    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        let slots: &mut [f64; JOINTS] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        let p: &[f64; JOINTS] = pose.0.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(p)?;
        *slots = joints_of(kins_type, *p);
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

/// The module's kinematics with the template's example items.
struct MillturnPins {
    input: Pin<u32, In>,
    output: Pin<u32, Out>,
    _param_rw: Param<f64, Rw>,
    _param_ro: Param<f64, Ro>,
}

impl MillturnPins {
    fn export(c: &Component) -> Result<MillturnPins> {
        Ok(MillturnPins {
            input: c.pin(&format!("{NAME}.in"))?,
            output: c.pin(&format!("{NAME}.out"))?,
            _param_rw: c.param(&format!("{NAME}.param-rw"), 0.0)?,
            _param_ro: c.param(&format!("{NAME}.param-ro"), 0.0)?,
        })
    }
}

impl TwoTypes for MillturnPins {
    const NAME: &'static str = NAME;

    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError> {
        MillTurn.forward(kins_type, joints, pose)
    }

    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError> {
        MillTurn.inverse(kins_type, pose, joints)?;
        self.output.set(self.input.get());
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        MillTurn.has_axis(axis)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
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
        MillturnPins::export,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kins::twotype::TwoTypeKins;
    use crate::kins::{Kinematics, KinsFlags};
    use proptest::prelude::*;

    fn fwd(k: &dyn Kinematics, j: [f64; 4]) -> [f64; 9] {
        let mut p = Pose::ZERO;
        k.forward(&j, &mut p, &mut KinsFlags::default()).unwrap();
        p.0
    }

    fn inv(k: &dyn Kinematics, p: [f64; 4]) -> [f64; 4] {
        crate::kins::testing::inverse(k, &p, [0.0; 4]).unwrap()
    }

    #[test]
    fn mill_is_identity_and_turn_renames_the_slides() {
        let k = TwoTypeKins::new(MillTurn);
        let j = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(fwd(&k, j)[..4], j);
        k.switch_to(1).unwrap();
        assert_eq!(fwd(&k, j)[..4], [3.0, -2.0, 1.0, 4.0]);
        assert_eq!(inv(&k, [3.0, -2.0, 1.0, 4.0]), j);
        assert_eq!(k.switch_to(-1), Err(KinsError::Unsupported));
        assert_eq!(k.active_type(), 1);
    }

    #[test]
    fn short_joint_sets_and_non_numbers_are_refused() {
        let k = TwoTypeKins::new(MillTurn);
        let mut p = Pose::ZERO;
        let mut flags = KinsFlags::default();
        assert_eq!(
            k.forward(&[0.0; 3], &mut p, &mut flags),
            Err(KinsError::Unsupported)
        );
        p.0[2] = f64::NAN;
        assert_eq!(
            k.inverse(&p, &mut [0.0; 4], &mut flags),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn both_types_round_trip(
            p in prop::array::uniform4(-1000.0f64..1000.0), turn in any::<bool>(),
        ) {
            let k = TwoTypeKins::new(MillTurn);
            k.switch_to(i32::from(turn)).unwrap();
            let back = fwd(&k, inv(&k, p));
            prop_assert_eq!(&back[..4], &p[..]);
            prop_assert!(back[4..].iter().all(|&v| v == 0.0));
        }
    }
}
