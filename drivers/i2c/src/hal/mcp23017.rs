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
use hal_core::Result;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;

use super::{export_chips, prepare_all, read_common, ChipAt, Prepared, StatusPins};
use crate::chips::{DioCmd, Mcp23017Chip};
use crate::regs::mcp23017::{ADDRESSES, OUTPUT_ONLY_PINS};
use crate::sim::Mcp23017;

/// The module's and component's name.
pub const NAME: &str = "mcp23017";

/// Pins per chip.
pub const PINS: usize = 16;

/// mcp23017's module parameters, the one table both hosts read.
#[macro_export]
macro_rules! mcp23017_params {
    ($($then:tt)*) => { $crate::__i2c_params! { [$($then)*]
        dir: IntArray($crate::hal::MAX_CHIPS) =
            "directions of each chip, bit n = pin n, 1 = input (default 0xffff)",
        pullup: IntArray($crate::hal::MAX_CHIPS) = "pull-ups of each chip's input pins (default 0)",
        gp7_input: IntArray($crate::hal::MAX_CHIPS) =
            "1: read GPA7/GPB7 as inputs (older chips only)",
    } };
}

/// The `mcp23017` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalMcp23017;

/// The `mcp23017` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalMcp23017>();

/// The chips, set up, with each one's directions and GP7 choice.
pub struct OpenedChips {
    prepared: Vec<(Prepared<Mcp23017Chip>, ChipAt)>,
    dirs: Vec<u16>,
    gp7: Vec<bool>,
}

impl DriverModule for HalMcp23017 {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "Microchip MCP23017 16-bit I/O expander on I2C (or simulated)";
    const PARAMS: &'static [ParamDecl] = mcp23017_params!(hal_driver::param_table);
    type Opened = OpenedChips;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> Result<OpenedChips> {
        open_chips(args, env)
    }

    fn export<H: DriverHost>(o: OpenedChips, ex: &mut Exporter<'_, H>) -> Result<()> {
        let OpenedChips {
            prepared,
            dirs,
            gp7,
        } = o;
        export_chips(ex, NAME, prepared, |ex, comp, i, name, ends| {
            let c = ex.pins(comp);
            let dir = dirs[i];
            let in_names = ChannelNames::canonical::<DigIn>(NAME, i, PINS);
            let out_names = ChannelNames::canonical::<DigOut>(NAME, i, PINS);
            let mut inputs = Vec::new();
            let mut outputs = Vec::new();
            for pin in 0..PINS {
                let bit = 1u16 << pin;
                if dir & bit == 0 {
                    outputs.push((pin, DigOut::<H>::export(c, &out_names, pin)?));
                } else if bit & OUTPUT_ONLY_PINS == 0 || gp7[i] {
                    inputs.push((pin, DigIn::<H>::export(c, &in_names, pin)?));
                }
            }
            let status = StatusPins::<H>::export(c, name)?;
            let (mut cmd, mut st) = (ends.cmd, ends.status);
            ex.funct(comp, &format!("{name}.read"), false, move |_| {
                let bits = status.update(&mut st).sample;
                for (pin, d) in &inputs {
                    d.update(bits & (1 << pin) != 0);
                }
            })?;
            ex.funct(comp, &format!("{name}.write"), false, move |_| {
                let mut out = DioCmd::default();
                for (pin, d) in &outputs {
                    out.out |= (d.level() as u16) << pin;
                    out.safe |= (d.safe_level() as u16) << pin;
                }
                cmd.publish(out);
            })
        })
    }
}

/// Reads the parameters and sets every chip up.
fn open_chips(args: &ModuleArgs, env: &LoadEnv) -> Result<OpenedChips> {
    let p = Params::new(NAME, args);
    let (backend, chips) = read_common(&p, args, ADDRESSES, 0x20).map_err(|e| e.into_hal(NAME))?;
    let n = chips.len();
    let err = |e: hal_driver::DriverError| e.into_hal(NAME);
    let dirs = p.ints_per("dir", n, 0xFFFF, 0..=0xFFFF).map_err(err)?;
    let pullups = p.ints_per("pullup", n, 0, 0..=0xFFFF).map_err(err)?;
    let gp7 = super::flags_per(&p, "gp7_input", n).map_err(err)?;
    let prepared = prepare_all(
        env.instance(),
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
    Ok(OpenedChips {
        prepared,
        dirs: dirs.iter().map(|&d| d as u16).collect(),
        gp7,
    })
}
