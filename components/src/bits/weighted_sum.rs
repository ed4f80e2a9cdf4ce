//! `weighted_sum`: groups of bit inputs summed with a weight each (by
//! default 2^n, so a group reads as a binary number) plus an offset. A
//! group holds its sum while `hold` is TRUE.
//!
//! `loadrt weighted_sum wsum_sizes=4,3` makes groups `wsum.0` (4 bits)
//! and `wsum.1` (3), up to 8 groups of 1 to 16 bits, all computed by the
//! one function `process_wsums`.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Param, Pin, Result, Rw};

/// Most groups.
pub const MAX_SUMMERS: usize = 8;
/// Most bits in a group.
pub const MAX_SUM_BITS: i64 = 16;

/// The sum of the weights of the bits that are TRUE, plus `offset`
/// (wrapping, as LinuxCNC's int arithmetic).
pub fn weighted_sum(offset: i32, bits: impl Iterator<Item = (bool, i32)>) -> i32 {
    bits.filter(|&(b, _)| b)
        .fold(offset, |s, (_, w)| s.wrapping_add(w))
}

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "wsum_sizes",
    kind: ParamKind::IntArray(MAX_SUMMERS),
    help: "number of bits of each summer (1 to 16), comma separated",
}];

/// The `weighted_sum` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "weighted_sum",
    params: PARAMS,
    help: "convert a group of bits to an integer",
    load,
};

/// One group's pins and params.
struct Group {
    sum: Pin<i32, Out>,
    hold: Pin<bool, In>,
    offset: Param<i32, Rw>,
    bits: Vec<(Pin<bool, In>, Param<i32, Rw>)>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let sizes = args.int_array("wsum_sizes");
    // Entries not given are -1 (none) in LinuxCNC.
    let sizes: Vec<i64> = sizes.iter().copied().take_while(|&n| n != -1).collect();
    let bad = |reason: String| HalError::ModuleParam {
        module: "weighted_sum".into(),
        param: "wsum_sizes".into(),
        reason,
    };
    if sizes.is_empty() {
        return Err(bad("no summers specified".into()));
    }
    if let Some(n) = sizes.iter().find(|&&n| !(1..=MAX_SUM_BITS).contains(&n)) {
        return Err(bad(format!("{n} bits: must be 1 to {MAX_SUM_BITS}")));
    }
    let mut b = host.new_rt_component("weighted_sum")?;
    let c = b.component();
    let mut groups = Vec::with_capacity(sizes.len());
    for (g, &n) in sizes.iter().enumerate() {
        let base = format!("wsum.{g}");
        let offset = c.param(&format!("{base}.offset"), 0)?;
        let sum = c.pin(&format!("{base}.sum"))?;
        let hold = c.pin(&format!("{base}.hold"))?;
        let mut bits = Vec::with_capacity(n as usize);
        for i in 0..n {
            bits.push((
                c.pin(&format!("{base}.bit.{i}.in"))?,
                c.param(&format!("{base}.bit.{i}.weight"), 1i32 << i)?,
            ));
        }
        groups.push(Group {
            sum,
            hold,
            offset,
            bits,
        });
    }
    b.funct("process_wsums", true, move |_| {
        for g in &groups {
            if !g.hold.get() {
                let s = weighted_sum(
                    g.offset.get(),
                    g.bits.iter().map(|(p, w)| (p.get(), w.get())),
                );
                g.sum.set(s);
            }
        }
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, S32};

    #[test]
    fn sums_the_weights_of_true_bits() {
        let bits = [(true, 1), (false, 2), (true, 4)];
        assert_eq!(weighted_sum(10, bits.into_iter()), 15);
        assert_eq!(weighted_sum(i32::MAX, [(true, 1)].into_iter()), i32::MIN);
    }

    #[test]
    fn pins_params_and_a_run() {
        let mut h = TestHost::new("wsum");
        for bad in [
            &[][..],
            &["wsum_sizes=17"],
            &["wsum_sizes=2,0"],
            &["count=1"],
        ] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(&MODULE, &["wsum_sizes=2,3"]).unwrap();
        h.check_pins(
            "wsum.0",
            &[
                "sum s32 out 0",
                "hold bit in 0",
                "bit.0.in bit in 0",
                "bit.1.in bit in 0",
            ],
        );
        h.check_params(
            "wsum.1",
            &[
                "offset s32 rw 0",
                "bit.0.weight s32 rw 1",
                "bit.1.weight s32 rw 2",
                "bit.2.weight s32 rw 4",
            ],
        );
        assert_eq!(h.functs(), ["process_wsums"]);
        h.thread(&["process_wsums"]);
        h.set("wsum.1.bit.2.in", Bit(true));
        h.setp("wsum.1.offset", S32(-1));
        h.expect(&[], "wsum.1.sum", S32(3));
        h.set("wsum.1.hold", Bit(true));
        h.expect(&[("wsum.1.bit.0.in", Bit(true))], "wsum.1.sum", S32(3));
    }
}
