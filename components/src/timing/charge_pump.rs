//! `charge_pump`: a square wave at half the thread rate (plus 1/2 and 1/4
//! of that) to keep a charge-pump watchdog on external hardware alive.
//!
//! A singleton: `loadrt charge_pump` takes no `count=`/`names=` and makes
//! exactly one instance with prefix `charge-pump`.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Out, Pin, Result};

/// The instance prefix (and function name).
pub const PREFIX: &str = "charge-pump";

/// The counter behind the outputs.
#[derive(Debug, Clone, Default)]
pub struct ChargePump {
    acc: i32,
}

impl ChargePump {
    /// One call: returns (`out`, `out-2`, `out-4`). While disabled all
    /// three are FALSE and the counter keeps its value.
    pub fn step(&mut self, enable: bool) -> (bool, bool, bool) {
        if enable {
            self.acc = self.acc.wrapping_add(1);
            (self.acc & 1 != 0, self.acc & 2 != 0, self.acc & 4 != 0)
        } else {
            (false, false, false)
        }
    }
}

/// The `charge_pump` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "charge_pump",
    params: &[],
    help: "square wave for a charge-pump watchdog",
    load,
};

fn load(host: &Host, _args: &ModuleArgs) -> Result<()> {
    let mut b = host.new_rt_component("charge_pump")?;
    let c = b.component();
    let out: Pin<bool, Out> = c.pin(&format!("{PREFIX}.out"))?;
    let out_2: Pin<bool, Out> = c.pin(&format!("{PREFIX}.out-2"))?;
    let out_4: Pin<bool, Out> = c.pin(&format!("{PREFIX}.out-4"))?;
    let enable: Pin<bool, In> = c.pin_init(&format!("{PREFIX}.enable"), true)?;
    let mut logic = ChargePump::default();
    b.funct(PREFIX, false, move |_| {
        let (o1, o2, o4) = logic.step(enable.get());
        out.set(o1);
        out_2.set(o2);
        out_4.set(o4);
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    #[test]
    fn counts_in_binary_while_enabled() {
        let mut p = ChargePump::default();
        let seq: Vec<_> = (0..8).map(|_| p.step(true)).collect();
        assert_eq!(seq[0], (true, false, false));
        assert_eq!(seq[1], (false, true, false));
        assert_eq!(seq[2], (true, true, false));
        assert_eq!(seq[3], (false, false, true));
        assert_eq!(seq[7], (false, false, false));
        assert_eq!(p.step(false), (false, false, false));
        // The counter kept its value (8): the next call shows 9.
        assert_eq!(p.step(true), (true, false, false));
    }

    #[test]
    fn counter_wraps() {
        let mut p = ChargePump { acc: i32::MAX };
        assert_eq!(p.step(true), (false, false, false));
        assert_eq!(p.step(true), (true, false, false));
    }

    #[test]
    fn is_a_singleton() {
        let host = testing::host();
        assert!(testing::load(&host, &MODULE, &["count=2"]).is_err());
        testing::load(&host, &MODULE, &[]).unwrap();
        assert_eq!(
            testing::pin_names(&host),
            [
                "charge-pump.enable",
                "charge-pump.out",
                "charge-pump.out-2",
                "charge-pump.out-4",
                "charge-pump.time"
            ]
        );
        assert_eq!(testing::funct_names(&host), ["charge-pump"]);
    }
}
