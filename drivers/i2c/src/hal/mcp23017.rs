//! `loadrt mcp23017`: 16 digital inputs and outputs per chip.
//!
//! | parameter | meaning | default |
//! |---|---|---|
//! | `address`, `bus`, `backend` | see [`super`] | 0x20, 1, dev |
//! | `dir` | directions, pin n on bit n (GPA0..7 = 0..7, GPB0..7 = 8..15); 1 = input, as the chip's IODIR | 0xFFFF (all inputs) |
//! | `pullup` | the 100 kΩ pull-ups of input pins | 0 |
//! | `gp7_input` | 1: read GPA7/GPB7 when they are inputs (older silicon only) | 0 |
//!
//! Per chip N, for each pin NN (two digits): a canonical digital input
//! `mcp23017.N.digin.NN.in`/`in-not` or a canonical digital output
//! `mcp23017.N.digout.NN.out` with its `invert` parameter; the status
//! pins; functions `mcp23017.N.read` and `mcp23017.N.write`. The safe
//! state of an output is `out` FALSE (the level of its `invert`); the
//! outputs are at that level from the set-up on.
//!
//! GPA7 and GPB7 are outputs only on current silicon (newer data sheet
//! revisions withdrew their input function, so an input there may read
//! anything): left as inputs (as by the default `dir`), they stay
//! high-impedance and get no pins, unless `gp7_input=1` says the chip is
//! an older one that reads them. A pull-up on an output pin is refused
//! at load (it would do nothing).

use canonical::{ChannelNames, DigIn, DigOut};
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{Host, Result};
use hal_driver::params::Params;

use super::{build, per_chip, prepare_all, read_common, StatusPins, COMMON_PARAMS};
use crate::chips::{DioCmd, Mcp23017Chip};
use crate::regs::mcp23017::{ADDRESSES, OUTPUT_ONLY_PINS};
use crate::sim::Mcp23017;

/// The module's and component's name.
pub const NAME: &str = "mcp23017";

/// Pins per chip.
pub const PINS: usize = 16;

const PARAMS: &[ParamDecl] = &[
    COMMON_PARAMS[0],
    COMMON_PARAMS[1],
    per_chip(
        "dir",
        "directions of each chip, bit n = pin n, 1 = input (default 0xffff)",
    ),
    per_chip("pullup", "pull-ups of each chip's input pins (default 0)"),
    per_chip(
        "gp7_input",
        "1: read GPA7/GPB7 as inputs (older chips only)",
    ),
    COMMON_PARAMS[2],
];

/// The `mcp23017` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: PARAMS,
    help: "Microchip MCP23017 16-bit I/O expander on I2C (or simulated)",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let p = Params::new(NAME, args);
    let (backend, chips) = read_common(&p, args, ADDRESSES, 0x20).map_err(|e| e.into_hal(NAME))?;
    let n = chips.len();
    let err = |e: hal_driver::DriverError| e.into_hal(NAME);
    let dirs = p.ints_per("dir", n, 0xFFFF, 0..=0xFFFF).map_err(err)?;
    let pullups = p.ints_per("pullup", n, 0, 0..=0xFFFF).map_err(err)?;
    let gp7 = super::flags_per(&p, "gp7_input", n).map_err(err)?;
    let prepared = prepare_all(
        host,
        backend,
        NAME,
        &chips,
        || Box::new(Mcp23017::new()),
        |i, at| {
            let (dir, pullup) = (dirs[i] as u16, pullups[i] as u16);
            if pullup & !dir != 0 {
                return Err(p
                    .item_error(
                        "pullup",
                        i,
                        &format!("{pullup:#06x}"),
                        format_args!(
                            "pull-ups on output pins ({:#06x}) do nothing",
                            pullup & !dir
                        ),
                    )
                    .into_hal(NAME));
            }
            Ok((Mcp23017Chip::new(at.addr, dir, pullup), DioCmd::default()))
        },
    )?;
    build(host, NAME, prepared, |b, i, name, ends| {
        let c = b.component();
        let dir = dirs[i] as u16;
        let in_names = ChannelNames::canonical::<DigIn>(NAME, i, PINS);
        let out_names = ChannelNames::canonical::<DigOut>(NAME, i, PINS);
        let mut inputs = Vec::new();
        let mut outputs = Vec::new();
        for pin in 0..PINS {
            let bit = 1u16 << pin;
            if dir & bit == 0 {
                outputs.push((pin, DigOut::export(c, &out_names, pin)?));
            } else if bit & OUTPUT_ONLY_PINS == 0 || gp7[i] {
                inputs.push((pin, DigIn::export(c, &in_names, pin)?));
            }
        }
        let status = StatusPins::export(c, name)?;
        let (mut cmd, mut st) = (ends.cmd, ends.status);
        b.funct(&format!("{name}.read"), false, move |_| {
            let bits = status.update(&mut st).sample;
            for (pin, d) in &inputs {
                d.update(bits & (1 << pin) != 0);
            }
        })?;
        b.funct(&format!("{name}.write"), false, move |_| {
            let mut out = DioCmd::default();
            for (pin, d) in &outputs {
                out.out |= (d.level() as u16) << pin;
                out.safe |= (d.safe_level() as u16) << pin;
            }
            cmd.publish(out);
        })
    })
}
