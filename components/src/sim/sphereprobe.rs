//! `sphereprobe`: a simulated probe touching a hemisphere: `probe-out`
//! is TRUE when the position (raw encoder counts) is inside the sphere
//! of radius `r` around (`cx`, `cy`, `cz`), or below its centre outside
//! its footprint.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The probe output for position `p`, centre `c` and radius `r`, in
/// LinuxCNC's wrapping integer arithmetic.
pub fn sphereprobe(p: [i32; 3], c: [i32; 3], r: i32) -> bool {
    let d = |k: usize| p[k].wrapping_sub(c[k]).wrapping_abs() as i64 as u64;
    let (dx, dy, dz) = (d(0), d(1), d(2));
    let d2 = dx.wrapping_mul(dx).wrapping_add(dy.wrapping_mul(dy));
    let r2 = (i64::from(r) * i64::from(r)) as u64;
    if d2 > r2 {
        p[2] < c[2]
    } else {
        d2.wrapping_add(dz.wrapping_mul(dz)) <= r2
    }
}

/// The `sphereprobe` component.
pub struct Sphereprobe;
impl HalComp for Sphereprobe {
    const NAME: &'static str = "sphereprobe";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let p = [
            inst.pin_in::<i32>("px")?,
            inst.pin_in::<i32>("py")?,
            inst.pin_in::<i32>("pz")?,
        ];
        let c = [
            inst.pin_in::<i32>("cx")?,
            inst.pin_in::<i32>("cy")?,
            inst.pin_in::<i32>("cz")?,
        ];
        let r = inst.pin_in::<i32>("r")?;
        let probe_out = inst.pin_out::<bool>("probe-out")?;
        inst.funct("_", true, move |_| {
            probe_out.set(sphereprobe(
                std::array::from_fn(|k| p[k].get()),
                std::array::from_fn(|k| c[k].get()),
                r.get(),
            ))
        })
    }
}
halcomp_module!(pub MODULE, Sphereprobe, "probe a pretend hemisphere");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, S32};

    #[test]
    fn inside_the_sphere_or_below_outside_it() {
        let c = [0, 0, 0];
        assert!(sphereprobe([3, 4, 0], c, 5), "on the surface");
        assert!(!sphereprobe([3, 4, 1], c, 5));
        assert!(!sphereprobe([10, 0, 1], c, 5), "outside, above the centre");
        assert!(sphereprobe([10, 0, -1], c, 5), "outside, below: the table");
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("sphereprobe");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "sphereprobe.0",
            &[
                "px s32 in 0",
                "py s32 in 0",
                "pz s32 in 0",
                "cx s32 in 0",
                "cy s32 in 0",
                "cz s32 in 0",
                "r s32 in 0",
                "probe-out bit out 0",
            ],
        );
        h.thread(&["sphereprobe.0"]);
        h.expect(&[], "sphereprobe.0.probe-out", Bit(true));
        h.expect(
            &[("sphereprobe.0.pz", S32(1))],
            "sphereprobe.0.probe-out",
            Bit(false),
        );
    }
}
