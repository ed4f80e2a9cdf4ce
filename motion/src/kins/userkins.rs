//! `userkins`: LinuxCNC's template for kinematics users build with
//! halcompile, as it ships unmodified: identity kinematics for an X Y Z
//! machine with three joints.
//!
//! ```text
//! X = j0   Y = j1   Z = j2   (A B C U V W are always 0)
//! ```
//!
//! HAL items, LinuxCNC's names and kinds: `userkins.in` (u32 in) copied
//! to `userkins.out` (u32 out) at every inverse call (the template's
//! example of pins the kinematics use), parameters `userkins.param-rw`
//! (float rw) and `userkins.param-ro` (float ro); per halcompile
//! instance (`count=`/`names=`, one instance by default)
//! `userkins.N.fpin` (s32 out) and the function `userkins.N.fdemo`,
//! which counts its runs on `fpin`. LinuxCNC creates the kinematics'
//! items when motion first asks for the kinematics type and prints a
//! line when `fdemo` first runs; here `loadrt` creates them and the
//! function is silent. The type is KINEMATICS_IDENTITY; the module is
//! not switchable.

use std::sync::atomic::{AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::instances::instance_names;
use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Out, Param, Pin, Result, Ro, Rw};

use super::loader::register;
use super::math::finite;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// The module's name.
const NAME: &str = "userkins";

/// The `userkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: hal_core::instances::INSTANCE_PARAMS,
    help: "LinuxCNC's user kinematics template, unmodified: identity X Y Z on three joints",
    load,
};

/// Joints the kinematics use.
pub const JOINTS: usize = 3;

/// The template's kinematics, without pins.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct UserXyz;

impl Kinematics for UserXyz {
    fn name(&self) -> &str {
        NAME
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Identity
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let j: &[f64; JOINTS] = joints.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(j)?;
        *pose = Pose::ZERO;
        pose.0[..JOINTS].copy_from_slice(j);
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        let slots: &mut [f64; JOINTS] = joints.first_chunk_mut().ok_or(KinsError::Unsupported)?;
        let p: &[f64; JOINTS] = pose.0.first_chunk().ok_or(KinsError::Unsupported)?;
        finite(p)?;
        *slots = *p;
        Ok(())
    }

    /// X Y Z.
    fn has_axis(&self, axis: usize) -> Option<bool> {
        Some(axis < JOINTS)
    }
}

/// The kinematics with the template's example items.
struct UserkinsPins {
    input: Pin<u32, In>,
    output: Pin<u32, Out>,
    _param_rw: Param<f64, Rw>,
    _param_ro: Param<f64, Ro>,
}

impl UserkinsPins {
    fn export(c: &Component) -> Result<UserkinsPins> {
        Ok(UserkinsPins {
            input: c.pin(&format!("{NAME}.in"))?,
            output: c.pin(&format!("{NAME}.out"))?,
            _param_rw: c.param(&format!("{NAME}.param-rw"), 0.0)?,
            _param_ro: c.param(&format!("{NAME}.param-ro"), 0.0)?,
        })
    }
}

impl Kinematics for UserkinsPins {
    fn name(&self) -> &str {
        NAME
    }

    fn kins_type(&self) -> KinematicsType {
        UserXyz.kins_type()
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        UserXyz.forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        UserXyz.inverse(pose, joints, flags)?;
        self.output.set(self.input.get());
        Ok(())
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        UserXyz.has_axis(axis)
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let prefixes = instance_names(NAME, args)?;
    let mut b = host.new_rt_component(NAME)?;
    for prefix in &prefixes {
        let fpin: Pin<i32, Out> = b.component().pin(&format!("{prefix}.fpin"))?;
        let runs = Arc::new(AtomicI32::new(0));
        b.funct(&format!("{prefix}.fdemo"), true, move |_| {
            let n = runs.load(Relaxed).wrapping_add(1);
            runs.store(n, Relaxed);
            fpin.set(n);
        })?;
    }
    let kins = UserkinsPins::export(b.component())?;
    register(host, b, NAME, Arc::new(kins))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn three_joints_are_x_y_z_and_the_rest_is_zero() {
        let mut pose = Pose([9.0; 9]);
        let mut flags = KinsFlags::default();
        UserXyz
            .forward(&[1.0, 2.0, 3.0, 4.0], &mut pose, &mut flags)
            .unwrap();
        assert_eq!(pose.0, [1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let mut j = [7.0; 4];
        pose.0[3] = 5.0;
        UserXyz.inverse(&pose, &mut j, &mut flags).unwrap();
        assert_eq!(j, [1.0, 2.0, 3.0, 7.0]);
        assert_eq!(UserXyz.has_axis(2), Some(true));
        assert_eq!(UserXyz.has_axis(3), Some(false));
    }

    #[test]
    fn short_joint_sets_and_non_numbers_are_refused() {
        let mut pose = Pose::ZERO;
        let mut flags = KinsFlags::default();
        assert_eq!(
            UserXyz.forward(&[0.0; 2], &mut pose, &mut flags),
            Err(KinsError::Unsupported)
        );
        assert_eq!(
            UserXyz.inverse(&pose, &mut [0.0; 2], &mut flags),
            Err(KinsError::Unsupported)
        );
        pose.0[1] = f64::NAN;
        let mut j = [4.0; 3];
        assert_eq!(
            UserXyz.inverse(&pose, &mut j, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(j, [4.0; 3]);
        assert_eq!(
            UserXyz.forward(&[0.0, f64::INFINITY, 0.0], &mut pose, &mut flags),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn round_trips_exactly(p in prop::array::uniform3(-1e6f64..1e6)) {
            let j: [f64; 3] = crate::kins::testing::inverse(&UserXyz, &p, [0.0; 3]).unwrap();
            let back: [f64; 9] = crate::kins::testing::forward(&UserXyz, &j).unwrap();
            prop_assert_eq!(&back[..3], &p[..]);
            prop_assert!(back[3..].iter().all(|&v| v == 0.0));
        }
    }
}
