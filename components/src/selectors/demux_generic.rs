//! `demux_generic`: routes one input, of a type chosen per instance, to
//! one of several outputs (of the same or another type), selected by
//! `sel-int` plus the select bits, with optional debounce. The mirror of
//! mux_generic, with the same format strings (`config="bf8,uu4"`: input
//! type, number of outputs, optional output type) and conversions.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, In, Out, Pin, RawPin, Result};

use super::mux_generic::{convert, parse_configs, select_value, Selection, MAX_INSTANCES};

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "config",
    kind: ParamKind::StrArray(MAX_INSTANCES),
    help: "format of each instance: input type, number of outputs, output type (e.g. bf8,uu4)",
}];

/// The `demux_generic` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "demux_generic",
    params: PARAMS,
    help: "route a single input signal to one of multiple outputs",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let cfgs = parse_configs(MODULE.name, "bf8,uu4", args)?;
    let mut b = host.new_rt_component(MODULE.name)?;
    for (n, cfg) in cfgs.into_iter().enumerate() {
        let prefix = format!("demux-gen.{n:02}");
        let (tin, tout) = (cfg.in_type.name(), cfg.out_type.name());
        let c = b.component();
        let sel_bits: Vec<Pin<bool, In>> = (0..cfg.select_bits())
            .map(|i| c.pin(&format!("{prefix}.sel-bit-{i:02}")))
            .collect::<Result<_>>()?;
        let sel_int: Pin<u32, In> = c.pin(&format!("{prefix}.sel-int"))?;
        let input: RawPin<In> = c.pin_raw(&format!("{prefix}.in-{tin}"), cfg.in_type)?;
        let suppress: Pin<bool, In> = c.pin(&format!("{prefix}.suppress-no-input"))?;
        let debounce_us: Pin<u32, In> = c.pin(&format!("{prefix}.debounce-us"))?;
        let elapsed: hal_core::Param<u32, hal_core::Ro> =
            c.param(&format!("{prefix}.elapsed"), 0)?;
        let selected: hal_core::Param<u32, hal_core::Ro> =
            c.param(&format!("{prefix}.selected"), 0)?;
        let outputs: Vec<RawPin<Out>> = (0..cfg.size)
            .map(|i| c.pin_raw(&format!("{prefix}.out-{tout}-{i:02}"), cfg.out_type))
            .collect::<Result<_>>()?;
        b.funct(&prefix, true, move |ctx| {
            let s = select_value(sel_bits.iter().map(Pin::get), sel_int.get());
            let mut st = Selection {
                selected: selected.get(),
                elapsed: elapsed.get(),
            };
            let pick = st.update(s, suppress.get(), debounce_us.get(), ctx.period(), cfg.size);
            selected.set(st.selected);
            elapsed.set(st.elapsed);
            if let Some(k) = pick {
                outputs[k].set_bits(convert(input.value(), cfg.out_type).to_bits());
            }
        })?;
    }
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, U32};

    #[test]
    fn pins_and_routing() {
        let mut h = TestHost::new("demux-gen");
        for bad in [&[][..], &["config=b1"], &["config=x4"], &["config=bfs4"]] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(&MODULE, &["config=bf4,uu3"]).unwrap();
        h.check_pins(
            "demux-gen.00",
            &[
                "sel-bit-00 bit in 0",
                "sel-bit-01 bit in 0",
                "sel-int u32 in 0",
                "in-bit bit in 0",
                "suppress-no-input bit in 0",
                "debounce-us u32 in 0",
                "out-float-00 float out 0",
                "out-float-01 float out 0",
                "out-float-02 float out 0",
                "out-float-03 float out 0",
            ],
        );
        h.check_params("demux-gen.00", &["elapsed u32 ro 0", "selected u32 ro 0"]);
        // Three outputs: 2^1 + 1, one select bit.
        assert_eq!(h.items("demux-gen.01.sel-bit-00").len(), 1);
        assert!(h.items("demux-gen.01.sel-bit-01").is_empty());
        assert_eq!(h.functs(), ["demux-gen.00", "demux-gen.01"]);

        h.thread(&["demux-gen.00", "demux-gen.01"]);
        h.set("demux-gen.00.in-bit", Bit(true));
        h.set("demux-gen.00.sel-bit-01", Bit(true));
        h.expect(&[], "demux-gen.00.out-float-02", Float(1.0));
        assert_eq!(h.get("demux-gen.00.out-float-00"), Float(0.0));
        // A selection past the end goes to the last output.
        h.set("demux-gen.01.in-u32", U32(7));
        h.expect(
            &[("demux-gen.01.sel-int", U32(9))],
            "demux-gen.01.out-u32-02",
            U32(7),
        );
    }
}
