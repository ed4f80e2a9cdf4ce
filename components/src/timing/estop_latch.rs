//! `estop_latch`: an e-stop latch with a watchdog output. It starts
//! faulted; a rising edge of `reset` while `ok-in` is TRUE and `fault-in`
//! FALSE makes it OK, and any fault drops it again.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

use super::write_changed;

/// The pin values one call of `estop_latch` reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EstopLatchVars {
    /// Pin `ok-in`.
    pub ok_in: bool,
    /// Pin `fault-in`.
    pub fault_in: bool,
    /// Pin `reset`.
    pub reset: bool,
    /// Pin `ok-out` (read back).
    pub ok_out: bool,
    /// Pin `fault-out`.
    pub fault_out: bool,
    /// Pin `watchdog` (read back).
    pub watchdog: bool,
}

/// Per-instance state of `estop_latch`.
#[derive(Debug, Clone, Default)]
pub struct EstopLatch {
    /// `reset` at the previous call.
    old_reset: bool,
}

impl EstopLatch {
    /// One call. A reset edge seen while a fault is present is lost.
    pub fn step(&mut self, v: &mut EstopLatchVars) {
        if v.ok_in && !v.fault_in {
            if v.reset && !self.old_reset {
                v.ok_out = true;
                v.fault_out = false;
            }
            if v.ok_out {
                v.watchdog = !v.watchdog;
            }
        } else {
            v.ok_out = false;
            v.fault_out = true;
        }
        self.old_reset = v.reset;
    }
}

/// The `estop_latch` component.
pub struct EstopLatchComp;
impl HalComp for EstopLatchComp {
    const NAME: &'static str = "estop_latch";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let ok_in = inst.pin_in_init::<bool>("ok-in", true)?;
        let fault_in = inst.pin_in::<bool>("fault-in")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let ok_out = inst.pin_out::<bool>("ok-out")?;
        let fault_out = inst.pin_out_init::<bool>("fault-out", true)?;
        let watchdog = inst.pin_out::<bool>("watchdog")?;
        let mut state = EstopLatch::default();
        inst.funct("_", false, move |_| {
            let old = EstopLatchVars {
                ok_in: ok_in.get(),
                fault_in: fault_in.get(),
                reset: reset.get(),
                ok_out: ok_out.get(),
                fault_out: fault_out.get(),
                watchdog: watchdog.get(),
            };
            let mut v = old;
            state.step(&mut v);
            write_changed(&ok_out, old.ok_out, v.ok_out);
            write_changed(&fault_out, old.fault_out, v.fault_out);
            write_changed(&watchdog, old.watchdog, v.watchdog);
        })
    }
}
halcomp_module!(pub MODULE, EstopLatchComp, "e-stop latch with watchdog");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    fn start() -> EstopLatchVars {
        EstopLatchVars {
            ok_in: true,
            fault_out: true,
            ..Default::default()
        }
    }

    #[test]
    fn starts_faulted_and_latches_ok_on_reset_edge() {
        let mut e = EstopLatch::default();
        let mut v = start();
        e.step(&mut v);
        assert!(!v.ok_out && v.fault_out && !v.watchdog);
        v.reset = true;
        e.step(&mut v);
        // The watchdog toggles in the reset call already.
        assert!(v.ok_out && !v.fault_out && v.watchdog);
        e.step(&mut v);
        assert!(v.ok_out && !v.watchdog);
        v.reset = false;
        e.step(&mut v);
        assert!(v.ok_out && v.watchdog);
    }

    #[test]
    fn fault_drops_and_reset_during_fault_is_lost() {
        let mut e = EstopLatch::default();
        let mut v = start();
        v.reset = true;
        e.step(&mut v);
        assert!(v.ok_out);
        v.reset = false;
        v.fault_in = true;
        e.step(&mut v);
        assert!(!v.ok_out && v.fault_out);
        let w = v.watchdog;
        // Reset edge while faulted: not remembered.
        v.reset = true;
        e.step(&mut v);
        v.fault_in = false;
        e.step(&mut v);
        assert!(!v.ok_out && v.fault_out);
        assert_eq!(v.watchdog, w, "watchdog stops while not OK");
        // ok-in FALSE is a fault too.
        v.reset = false;
        e.step(&mut v);
        v.reset = true;
        e.step(&mut v);
        assert!(v.ok_out);
        v.ok_in = false;
        e.step(&mut v);
        assert!(!v.ok_out && v.fault_out);
    }

    #[test]
    fn defaults() {
        let host = testing::host();
        testing::load(&host, &MODULE, &[]).unwrap();
        let i = host.instance();
        assert_eq!(
            i.pin_value("estop-latch.0.ok-in").unwrap(),
            hal_core::Value::Bit(true)
        );
        assert_eq!(
            i.pin_value("estop-latch.0.fault-out").unwrap(),
            hal_core::Value::Bit(true)
        );
    }
}
