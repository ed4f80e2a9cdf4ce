//! `maxkins`: Chris Radek's tabletop five-axis mill "max", LinuxCNC's
//! example of a tilting head (B) with a rotary table (C), plus U V W
//! motion in the head's tilted frame.
//!
//! The joints are fixed, one per axis: joint *j* is axis *j* of
//! X Y Z A B C U V W (a configuration with fewer joints reads the missing
//! ones as 0). The head pivots about a point `pivot-length` above the
//! spindle nose; W extends the tool along its axis, U moves it across the
//! axis in the tilt plane, V along Y. With `L = pivot-length`, `b`, `c`
//! the B and C angles:
//!
//! ```text
//! inverse:  (x', y') = Rz(−c) · (X, Y)
//!           j0 = x' − (L + W)·sin b + U·cos b
//!           j1 = y' + V
//!           j2 = Z + (L + W)·cos b + U·sin b − L
//! forward:  the exact inverse of that: the head corrections are taken
//!           off in the machine frame, then the table is turned by +c
//! ```
//!
//! The angles and U V W pass through. The inverse is LinuxCNC's, term
//! for term; LinuxCNC's forward adds the head corrections after turning
//! by C and gives U's Z term the other sign, so it only undoes its
//! inverse at C = 0 with U = 0. Here the forward undoes the inverse
//! everywhere (the round trip the tests check), and agrees with
//! LinuxCNC's wherever LinuxCNC's round-trips.
//!
//! Pin (float io, LinuxCNC's name): `maxkins.pivot-length` (default
//! 0.666). The type is KINEMATICS_BOTH.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, Io, Pin, Result};

use super::loader::{float_io, register};
use super::math::{finite, rad};
use super::pinned::{PinGeometry, Pinned};
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose, NUM_AXES};

/// The `maxkins` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "maxkins",
    params: &[],
    help: "tilting head (B) and rotary table (C) mill with U V W in the head's frame",
    load,
};

/// LinuxCNC's default `maxkins.pivot-length`.
pub const DEFAULT_PIVOT_LENGTH: f64 = 0.666;

/// The mill with a fixed pivot length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Max {
    /// From the B pivot to the spindle nose.
    pub pivot_length: f64,
}

impl Default for Max {
    fn default() -> Self {
        Max {
            pivot_length: DEFAULT_PIVOT_LENGTH,
        }
    }
}

impl Max {
    /// The tool tip's offset from the head's joints in the machine's X
    /// and Z, for tilt `b` (radians), tool extension `w` and cross
    /// motion `u`.
    fn head_offset(&self, b: f64, u: f64, w: f64) -> (f64, f64) {
        let reach = self.pivot_length + w;
        let (sin, cos) = b.sin_cos();
        (
            reach * sin - u * cos,
            self.pivot_length - reach * cos - u * sin,
        )
    }
}

impl Kinematics for Max {
    fn name(&self) -> &str {
        "maxkins"
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
        let mut j = [0.0; NUM_AXES];
        let n = joints.len().min(NUM_AXES);
        j[..n].copy_from_slice(&joints[..n]);
        finite(&j)?;
        finite(&[self.pivot_length])?;
        let [j0, j1, j2, a, b, c, u, v, w] = j;
        let (dx, dz) = self.head_offset(rad(b), u, w);
        // The tip in the machine frame, then turned with the table.
        let (mx, my) = (j0 + dx, j1 - v);
        let (sin, cos) = rad(c).sin_cos();
        let out = [
            mx * cos - my * sin,
            mx * sin + my * cos,
            j2 + dz,
            a,
            b,
            c,
            u,
            v,
            w,
        ];
        finite(&out)?;
        pose.0 = out;
        Ok(())
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        finite(&pose.0)?;
        finite(&[self.pivot_length])?;
        let [x, y, z, a, b, c, u, v, w] = pose.0;
        let (dx, dz) = self.head_offset(rad(b), u, w);
        let (sin, cos) = rad(c).sin_cos();
        // The workpiece point turned back into the machine frame.
        let (mx, my) = (x * cos + y * sin, y * cos - x * sin);
        let out = [mx - dx, my + v, z - dz, a, b, c, u, v, w];
        finite(&out)?;
        for (slot, value) in joints.iter_mut().zip(out) {
            *slot = value;
        }
        Ok(())
    }
}

/// The module's kinematics: the pivot length read from its pin at every
/// call.
struct Maxkins {
    pivot_length: Pin<f64, Io>,
}

impl PinGeometry for Maxkins {
    const NAME: &'static str = "maxkins";
    type Geometry = Max;

    fn geometry(&self) -> Max {
        Max {
            pivot_length: self.pivot_length.get(),
        }
    }
}

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let b = host.new_rt_component("maxkins")?;
    let pivot_length = float_io(b.component(), "maxkins.pivot-length", DEFAULT_PIVOT_LENGTH)?;
    register(
        host,
        b,
        "maxkins",
        Arc::new(Pinned(Maxkins { pivot_length })),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fwd(k: &Max, j: [f64; 9]) -> std::result::Result<[f64; 9], KinsError> {
        crate::kins::testing::forward(k, &j)
    }

    fn inv(k: &Max, p: [f64; 9]) -> std::result::Result<[f64; 9], KinsError> {
        crate::kins::testing::inverse(k, &p, [0.0; 9])
    }

    /// max5kins.ini's `[MAX]B_PIVOT_LENGTH`.
    const SAMPLE: Max = Max { pivot_length: 50.8 };

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
    }

    #[test]
    fn upright_head_and_square_table_is_identity() {
        let p = [1.0, 2.0, 3.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        assert!(close(&fwd(&SAMPLE, p).unwrap(), &p, 1e-12));
        assert!(close(&inv(&SAMPLE, p).unwrap(), &p, 1e-12));
    }

    #[test]
    fn tilting_the_head_swings_the_tip_about_the_pivot() {
        // B = 90°: the tip, L below the pivot, swings out to +X at the
        // pivot's height (LinuxCNC's unconventional B direction).
        let j = [0.0, 0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0, 0.0];
        let p = fwd(&SAMPLE, j).unwrap();
        assert!(close(&p[..3], &[50.8, 0.0, 50.8], 1e-9), "{p:?}");
        // W lengthens the tool along its tilted axis.
        let p = fwd(&SAMPLE, [0.0, 0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0, 2.0]).unwrap();
        assert!(close(&p[..3], &[52.8, 0.0, 50.8], 1e-9), "{p:?}");
    }

    #[test]
    fn the_inverse_is_linuxcncs() {
        // LinuxCNC's inverse, written out for one pose.
        let (x, y, z, b, c, u, v, w) = (10.0f64, -4.0f64, 3.0, 30.0f64, 50.0f64, 1.5, 0.5, 2.0);
        let l = SAMPLE.pivot_length;
        let (br, cr) = (b.to_radians(), c.to_radians());
        let r = x.hypot(y);
        let t = y.atan2(x) - cr;
        let want = [
            r * t.cos() - (l + w) * br.sin() + u * br.cos(),
            r * t.sin() + v,
            z + (l + w) * br.cos() + u * br.sin() - l,
        ];
        let j = inv(&SAMPLE, [x, y, z, 0.0, b, c, u, v, w]).unwrap();
        assert!(close(&j[..3], &want, 1e-9), "{j:?} vs {want:?}");
        assert_eq!(j[3..], [0.0, b, c, u, v, w]);
    }

    #[test]
    fn missing_joints_read_as_zero_and_non_numbers_are_refused() {
        let mut pose = Pose::ZERO;
        let mut flags = KinsFlags::default();
        SAMPLE
            .forward(&[1.0, 2.0, 3.0, 0.0, 0.0, 0.0], &mut pose, &mut flags)
            .unwrap();
        assert!(close(
            &pose.0,
            &[1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            1e-12
        ));
        let mut six = [0.0; 6];
        pose.0[8] = 1.0;
        SAMPLE.inverse(&pose, &mut six, &mut flags).unwrap();
        // W = 1 lengthens the tool: the head rises to keep the tip at Z = 3.
        assert!(close(&six[..3], &[1.0, 2.0, 4.0], 1e-12), "{six:?}");
        pose.0[4] = f64::NAN;
        assert_eq!(
            SAMPLE.inverse(&pose, &mut six, &mut flags),
            Err(KinsError::NoSolution)
        );
        assert_eq!(
            fwd(
                &SAMPLE,
                [f64::INFINITY, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
            ),
            Err(KinsError::NoSolution)
        );
    }

    proptest! {
        #[test]
        fn round_trips_everywhere(
            xyz in prop::array::uniform3(-300.0f64..300.0),
            b in -120.0f64..120.0, c in -720.0f64..720.0,
            uvw in prop::array::uniform3(-50.0f64..50.0),
            pivot in 0.0f64..200.0,
        ) {
            let k = Max { pivot_length: pivot };
            let p = [xyz[0], xyz[1], xyz[2], 7.0, b, c, uvw[0], uvw[1], uvw[2]];
            let back = fwd(&k, inv(&k, p).unwrap()).unwrap();
            prop_assert!(close(&back, &p, 1e-9), "{:?} vs {:?}", back, p);
        }
    }
}
