//! `multiswitch`: steps through a number of output bits, one on at a
//! time, on rising edges of `up` and `down` (wrapping at both ends).
//!
//! `loadrt multiswitch cfg=4,6` makes one instance `multiswitch.<i>` per
//! entry, with that many positions (one instance of 4 when none is
//! given).

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, Out, Pin, Result};

use crate::halcomp::{hal_name, load_instances, Inst};

/// Most entries in `cfg=`.
pub const MAX_COUNT: usize = 32;
/// Most positions an instance may have.
pub const MAX_POSITIONS: i64 = 32;

/// The switch's state between calls.
#[derive(Debug, Clone, Default)]
pub struct Multiswitch {
    old_up: bool,
    old_down: bool,
}

impl Multiswitch {
    /// One call: the new `position` from the old one and `top-position`.
    pub fn step(&mut self, up: bool, down: bool, position: i32, top: u32) -> i32 {
        let mut p = position;
        if up && !self.old_up {
            p = p.wrapping_add(1);
        }
        if down && !self.old_down {
            p = p.wrapping_sub(1);
        }
        self.old_up = up;
        self.old_down = down;
        if p < 0 {
            p = top as i32;
        }
        if p as u32 > top {
            p = 0;
        }
        p
    }
}

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "cfg",
        kind: ParamKind::IntArray(MAX_COUNT),
        help: "number of positions of each switch, comma separated",
    },
    crate::halcomp::PERSONALITY,
];

/// The `multiswitch` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "multiswitch",
    params: PARAMS,
    help: "toggle between a specified number of output bits",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let mut sizes: Vec<i64> = args
        .int_array("cfg")
        .iter()
        .copied()
        .take_while(|&n| n != 0)
        .collect();
    if sizes.is_empty() {
        sizes.push(4);
    }
    if let Some(bad) = sizes.iter().find(|&&n| !(1..=MAX_POSITIONS).contains(&n)) {
        return Err(HalError::ModuleParam {
            module: "multiswitch".into(),
            param: "cfg".into(),
            reason: format!("{bad} positions: must be 1 to {MAX_POSITIONS}"),
        });
    }
    let base = hal_name(MODULE.name);
    let instances = sizes
        .iter()
        .enumerate()
        .map(|(i, &n)| (format!("{base}.{i}"), n))
        .collect();
    load_instances(host, MODULE.name, instances, |inst, _| build(inst))
}

fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
    let n = inst.personality as usize;
    let up = inst.pin_in::<bool>("up")?;
    let down = inst.pin_in::<bool>("down")?;
    let top = inst.param_rw::<u32>("top-position", n as u32 - 1)?;
    let position = inst.param_rw::<i32>("position", 0)?;
    let bits: Vec<Pin<bool, Out>> = (0..n)
        .map(|i| inst.pin_out(&format!("bit-{i:02}")))
        .collect::<Result<_>>()?;
    let mut s = Multiswitch::default();
    inst.funct("_", true, move |_| {
        let p = s.step(up.get(), down.get(), position.get(), top.get());
        position.set(p);
        for (i, b) in bits.iter().enumerate() {
            b.set(i as i32 == p);
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, S32};

    #[test]
    fn steps_on_edges_and_wraps() {
        let mut s = Multiswitch::default();
        assert_eq!(s.step(true, false, 0, 2), 1);
        assert_eq!(s.step(true, false, 1, 2), 1, "held: no edge");
        assert_eq!(s.step(false, false, 1, 2), 1);
        assert_eq!(s.step(true, false, 1, 2), 2);
        s.step(false, false, 2, 2);
        assert_eq!(s.step(true, false, 2, 2), 0, "past the top wraps to 0");
        assert_eq!(s.step(false, true, 0, 2), 2, "below 0 wraps to the top");
        assert_eq!(s.step(false, false, 7, 2), 0, "an out-of-range position");
    }

    #[test]
    fn instances_follow_cfg() {
        let h = TestHost::new("multiswitch");
        h.load(&MODULE, &["cfg=2,3"]).unwrap();
        h.check_pins(
            "multiswitch.0",
            &[
                "up bit in 0",
                "down bit in 0",
                "bit-00 bit out 0",
                "bit-01 bit out 0",
            ],
        );
        h.check_params(
            "multiswitch.1",
            &["top-position u32 rw 2", "position s32 rw 0"],
        );
        assert_eq!(h.functs(), ["multiswitch.0", "multiswitch.1"]);
        let h = TestHost::new("multiswitch-default");
        h.load(&MODULE, &[]).unwrap();
        assert_eq!(h.items("multiswitch.0.bit-03").len(), 1, "4 by default");
        for bad in [&["cfg=33"][..], &["cfg=2,-1"], &["count=2"]] {
            h.check_load_fails(&MODULE, bad);
        }
    }

    #[test]
    fn runs_in_a_thread() {
        let mut h = TestHost::new("multiswitch-run");
        h.load(&MODULE, &["cfg=3"]).unwrap();
        h.thread(&["multiswitch.0"]);
        h.expect(&[], "multiswitch.0.bit-00", Bit(true));
        h.expect(
            &[("multiswitch.0.up", Bit(true))],
            "multiswitch.0.bit-01",
            Bit(true),
        );
        assert_eq!(h.getp("multiswitch.0.position"), S32(1));
    }
}
