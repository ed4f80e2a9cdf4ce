//! `threadtest`: a counter for testing thread order and rates; `increment`
//! adds one, `reset` clears it.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// `threadtest`.
pub struct ThreadTest;
impl HalComp for ThreadTest {
    const NAME: &'static str = "threadtest";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let count = inst.pin_out::<u32>("count")?;
        let reset = count.clone();
        inst.funct("increment", false, move |_| {
            count.set(count.get().wrapping_add(1))
        })?;
        inst.funct("reset", false, move |_| reset.set(0))
    }
}
halcomp_module!(pub MODULE, ThreadTest, "counter incremented and reset by functions in different threads");
