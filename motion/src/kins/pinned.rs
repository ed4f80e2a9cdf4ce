//! Kinematics whose geometry lives in HAL pins: every call reads the pins
//! into a plain geometry value and lets it compute, so a `setp` takes
//! effect on the next servo cycle (as LinuxCNC's modules read their pins
//! in every call).

use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// A module's pins, and the geometry value they describe.
pub(crate) trait PinGeometry: Send + Sync + 'static {
    /// The module's name.
    const NAME: &'static str;
    /// The fixed-geometry kinematics the pins describe.
    type Geometry: Kinematics;
    /// The geometry on the pins now.
    fn geometry(&self) -> Self::Geometry;
}

/// The kinematics of a module whose pins are `P`.
pub(crate) struct Pinned<P>(pub P);

impl<P: PinGeometry> Kinematics for Pinned<P> {
    fn name(&self) -> &str {
        P::NAME
    }

    fn kins_type(&self) -> KinematicsType {
        self.0.geometry().kins_type()
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        flags: &mut KinsFlags,
    ) -> Result<(), KinsError> {
        self.0.geometry().forward(joints, pose, flags)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> Result<(), KinsError> {
        self.0.geometry().inverse(pose, joints, flags)
    }

    fn home(
        &self,
        pose: &mut Pose,
        joints: &mut [f64],
        flags: &mut KinsFlags,
    ) -> Result<(), KinsError> {
        self.0.geometry().home(pose, joints, flags)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.0.geometry().has_axis(axis)
    }
}
