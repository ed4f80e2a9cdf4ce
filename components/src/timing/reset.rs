//! `reset`: on an edge of `trigger` (rising, falling or both, as chosen),
//! writes the `reset-*` values onto the I/O pins `out-*`, which other
//! components or `sets` otherwise drive.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Whether a call with `trigger` after `last` resets, given the edges
/// chosen.
pub fn triggered(trigger: bool, last: bool, rising: bool, falling: bool) -> bool {
    ((rising && trigger) || (falling && !trigger)) && trigger != last
}

/// The `reset` component.
pub struct Reset;
impl HalComp for Reset {
    const NAME: &'static str = "reset";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let trigger = inst.pin_in::<bool>("trigger")?;
        let out_u32 = inst.pin_io::<u32>("out-u32", 0)?;
        let reset_u32 = inst.pin_in::<u32>("reset-u32")?;
        let out_s32 = inst.pin_io::<i32>("out-s32", 0)?;
        let reset_s32 = inst.pin_in::<i32>("reset-s32")?;
        let out_float = inst.pin_io::<f64>("out-float", 0.0)?;
        let reset_float = inst.pin_in::<f64>("reset-float")?;
        let out_bit = inst.pin_io::<bool>("out-bit", false)?;
        let reset_bit = inst.pin_in::<bool>("reset-bit")?;
        // Declared by LinuxCNC, not used by its function.
        let _retriggerable = inst.pin_in_init::<bool>("retriggerable", true)?;
        let rising = inst.pin_in_init::<bool>("rising", true)?;
        let falling = inst.pin_in::<bool>("falling")?;
        let mut last = false;
        inst.funct("_", true, move |_| {
            let t = trigger.get();
            if triggered(t, last, rising.get(), falling.get()) {
                out_u32.set(reset_u32.get());
                out_s32.set(reset_s32.get());
                out_float.set(reset_float.get());
                out_bit.set(reset_bit.get());
            }
            last = t;
        })
    }
}
halcomp_module!(pub MODULE, Reset, "resets an IO signal");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, S32, U32};

    #[test]
    fn edges() {
        assert!(triggered(true, false, true, false));
        assert!(!triggered(true, true, true, false), "level is no edge");
        assert!(!triggered(false, true, true, false));
        assert!(triggered(false, true, false, true));
        assert!(triggered(false, true, true, true) && triggered(true, false, true, true));
        assert!(!triggered(true, false, false, true));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("reset");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "reset.0",
            &[
                "trigger bit in 0",
                "out-u32 u32 io 0",
                "reset-u32 u32 in 0",
                "out-s32 s32 io 0",
                "reset-s32 s32 in 0",
                "out-float float io 0",
                "reset-float float in 0",
                "out-bit bit io 0",
                "reset-bit bit in 0",
                "retriggerable bit in 1",
                "rising bit in 1",
                "falling bit in 0",
            ],
        );
        h.thread(&["reset.0"]);
        h.set("reset.0.out-float", Float(9.0));
        h.set("reset.0.out-s32", S32(9));
        h.set("reset.0.reset-u32", U32(4));
        h.set("reset.0.reset-bit", Bit(true));
        h.expect(&[], "reset.0.out-float", Float(9.0));
        h.expect(
            &[("reset.0.trigger", Bit(true))],
            "reset.0.out-float",
            Float(0.0),
        );
        assert_eq!(h.get("reset.0.out-s32"), S32(0));
        assert_eq!(h.get("reset.0.out-u32"), U32(4));
        assert_eq!(h.get("reset.0.out-bit"), Bit(true));
    }
}
