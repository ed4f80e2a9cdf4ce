//! Helpers the kinematics modules' unit tests share.

use super::{Kinematics, KinsError, KinsFlags, Pose};

/// The first `J` joints for a pose whose first axes are `axes`, solved
/// from joints at `start`.
pub(crate) fn inverse<const J: usize>(
    k: &dyn Kinematics,
    axes: &[f64],
    start: [f64; J],
) -> Result<[f64; J], KinsError> {
    let mut pose = Pose::ZERO;
    pose.0[..axes.len()].copy_from_slice(axes);
    let mut j = start;
    k.inverse(&pose, &mut j, &mut KinsFlags::default())
        .map(|()| j)
}

/// The first `A` axes of the pose of `joints`, from a zero guess.
pub(crate) fn forward<const A: usize>(
    k: &dyn Kinematics,
    joints: &[f64],
) -> Result<[f64; A], KinsError> {
    let mut pose = Pose::ZERO;
    k.forward(joints, &mut pose, &mut KinsFlags::default())?;
    Ok(*pose.0.first_chunk().expect("at most nine axes"))
}
