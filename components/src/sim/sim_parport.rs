//! `sim_parport`: the pins of `hal_parport` (both directions of every
//! pin) without a port, so a configuration written for a parallel port
//! runs on other I/O or in simulation. `read` copies each `pin-NN-in-fake`
//! to `pin-NN-in` (and its inverse to `pin-NN-in-invert`); `write` copies
//! each `pin-NN-out` (xor its `-invert` param) to `pin-NN-out-fake`;
//! `reset` does nothing. Load it with `names=parport.0` to get the real
//! names.

use hal_core::{In, Out, Param, Pin, Result, Rw};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The output pin numbers.
pub const OUT_PINS: [u32; 12] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 14, 16, 17];
/// The input pin numbers.
pub const IN_PINS: [u32; 13] = [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 15];

/// One output pin.
struct OutPin {
    pin: Pin<bool, In>,
    fake: Pin<bool, Out>,
    invert: Param<bool, Rw>,
    _reset: Param<bool, Rw>,
}

/// One input pin.
struct InPin {
    pin: Pin<bool, Out>,
    fake: Pin<bool, In>,
    invert: Pin<bool, Out>,
}

/// The `sim_parport` component.
pub struct SimParport;
impl HalComp for SimParport {
    const NAME: &'static str = "sim_parport";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let mut outs = Vec::with_capacity(OUT_PINS.len());
        for n in OUT_PINS {
            outs.push(OutPin {
                pin: inst.pin_in(&format!("pin-{n:02}-out"))?,
                fake: inst.pin_out(&format!("pin-{n:02}-out-fake"))?,
                invert: inst.param_rw(&format!("pin-{n:02}-out-invert"), false)?,
                _reset: inst.param_rw(&format!("pin-{n:02}-out-reset"), false)?,
            });
        }
        let mut ins = Vec::with_capacity(IN_PINS.len());
        for n in IN_PINS {
            ins.push(InPin {
                pin: inst.pin_out(&format!("pin-{n:02}-in"))?,
                fake: inst.pin_in(&format!("pin-{n:02}-in-fake"))?,
                invert: inst.pin_out(&format!("pin-{n:02}-in-invert"))?,
            });
        }
        let _reset_time = inst.pin_in::<f64>("reset-time")?;
        inst.funct("read", false, move |_| {
            for p in &ins {
                let v = p.fake.get();
                p.pin.set(v);
                p.invert.set(!v);
            }
        })?;
        inst.funct("write", false, move |_| {
            for p in &outs {
                p.fake.set(p.pin.get() != p.invert.get());
            }
        })?;
        inst.funct("reset", false, |_| {})
    }
}
halcomp_module!(pub MODULE, SimParport, "simulate the pins of the hal_parport component");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Bit;

    #[test]
    fn pins_functions_and_pass_through() {
        let mut h = TestHost::new("sim-parport");
        h.load(&MODULE, &["names=parport.0"]).unwrap();
        let mut want = vec!["reset-time float in 0".to_string()];
        for n in OUT_PINS {
            want.push(format!("pin-{n:02}-out bit in 0"));
            want.push(format!("pin-{n:02}-out-fake bit out 0"));
        }
        for n in IN_PINS {
            want.push(format!("pin-{n:02}-in bit out 0"));
            want.push(format!("pin-{n:02}-in-fake bit in 0"));
            want.push(format!("pin-{n:02}-in-invert bit out 0"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("parport.0", &want);
        assert_eq!(h.params().len(), 2 * OUT_PINS.len());
        assert_eq!(
            h.functs(),
            ["parport.0.read", "parport.0.reset", "parport.0.write"]
        );
        h.thread(&["parport.0.read", "parport.0.write"]);
        h.expect(
            &[("parport.0.pin-15-in-fake", Bit(true))],
            "parport.0.pin-15-in",
            Bit(true),
        );
        assert_eq!(h.get("parport.0.pin-15-in-invert"), Bit(false));
        h.setp("parport.0.pin-16-out-invert", Bit(true));
        h.expect(&[], "parport.0.pin-16-out-fake", Bit(true));
    }
}
