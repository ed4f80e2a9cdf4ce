//! `supply`: pins set from params, for testing (deprecated in LinuxCNC,
//! kept for old configurations): `q` and `_q` follow the bit param `d`
//! and its inverse, `variable` and `_variable` the float param `value`
//! and its negative.
//!
//! `loadrt supply num_chan=N [period=ns]`: channels `supply.1` to
//! `supply.N` (1 to 16, numbered from 1), each with an `update`
//! function; a non-zero `period` also creates the thread
//! `supply.thread`.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, Result};

/// Most channels.
pub const MAX_CHAN: i64 = 16;

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "num_chan",
        kind: ParamKind::Int,
        help: "number of channels (1 to 16)",
    },
    ParamDecl {
        name: "period",
        kind: ParamKind::Long,
        help: "period of a thread to create (ns), 0 for none",
    },
];

/// The `supply` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "supply",
    params: PARAMS,
    help: "set output pins with values from parameters (deprecated)",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let n = args.int("num_chan").unwrap_or(1);
    if !(1..=MAX_CHAN).contains(&n) {
        return Err(HalError::ModuleParam {
            module: "supply".into(),
            param: "num_chan".into(),
            reason: format!("{n} is out of range 1-{MAX_CHAN}"),
        });
    }
    let mut b = host.new_rt_component("supply")?;
    for num in 1..=n {
        let c = b.component();
        let p = format!("supply.{num}");
        let q: hal_core::Pin<bool, hal_core::Out> = c.pin(&format!("{p}.q"))?;
        let nq: hal_core::Pin<bool, hal_core::Out> = c.pin_init(&format!("{p}._q"), true)?;
        let variable: hal_core::Pin<f64, hal_core::Out> = c.pin(&format!("{p}.variable"))?;
        let nvariable: hal_core::Pin<f64, hal_core::Out> = c.pin(&format!("{p}._variable"))?;
        let d: hal_core::Param<bool, hal_core::Rw> = c.param(&format!("{p}.d"), false)?;
        let value: hal_core::Param<f64, hal_core::Rw> = c.param(&format!("{p}.value"), 0.0)?;
        b.funct(&format!("{p}.update"), true, move |_| {
            q.set(d.get());
            nq.set(!d.get());
            variable.set(value.get());
            nvariable.set(-value.get());
        })?;
    }
    b.ready()?;
    let period = args.int("period").unwrap_or(0);
    if period > 0 {
        host.create_thread("supply.thread", period, true, None)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn channels_count_from_one() {
        let mut h = TestHost::new("supply");
        for bad in [&["num_chan=0"][..], &["num_chan=17"], &["period=x"]] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(&MODULE, &["num_chan=2"]).unwrap();
        h.check_pins(
            "supply.2",
            &[
                "q bit out 0",
                "_q bit out 1",
                "variable float out 0",
                "_variable float out 0",
            ],
        );
        h.check_params("supply.2", &["d bit rw 0", "value float rw 0"]);
        assert_eq!(h.functs(), ["supply.1.update", "supply.2.update"]);
        h.thread(&["supply.1.update"]);
        h.setp("supply.1.d", Bit(true));
        h.setp("supply.1.value", Float(2.5));
        h.expect(&[], "supply.1._variable", Float(-2.5));
        assert_eq!(h.get("supply.1._q"), Bit(false));
    }

    #[test]
    fn period_makes_a_thread() {
        let h = TestHost::new("supply-thread");
        h.load(&MODULE, &["period=1000000"]).unwrap();
        let threads = h.instance().threads().unwrap();
        assert!(threads.iter().any(|t| t.name == "supply.thread"));
    }
}
