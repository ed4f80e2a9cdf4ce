//! `sample_hold`: passes `in` to `out` while `hold` is FALSE, keeps the
//! last value while it is TRUE.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// One call: the new `out`, or `None` while holding.
pub fn sample_hold(input: i32, hold: bool) -> Option<i32> {
    (!hold).then_some(input)
}

/// The `sample_hold` component.
pub struct SampleHoldComp;
impl HalComp for SampleHoldComp {
    const NAME: &'static str = "sample_hold";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<i32>("in")?;
        let hold = inst.pin_in::<bool>("hold")?;
        let out = inst.pin_out::<i32>("out")?;
        inst.funct("_", false, move |_| {
            if let Some(v) = sample_hold(input.get(), hold.get()) {
                out.set(v);
            }
        })
    }
}
halcomp_module!(pub MODULE, SampleHoldComp, "sample and hold of an s32");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    #[test]
    fn holds_while_hold_is_true() {
        assert_eq!(sample_hold(-7, false), Some(-7));
        assert_eq!(sample_hold(9, true), None);
    }

    #[test]
    fn prefix_uses_dashes() {
        let host = testing::host();
        testing::load(&host, &MODULE, &["count=2"]).unwrap();
        assert_eq!(
            testing::funct_names(&host),
            ["sample-hold.0", "sample-hold.1"]
        );
    }
}
