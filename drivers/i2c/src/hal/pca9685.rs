//! `loadrt pca9685`: 16 PWM outputs per chip.
//!
//! | parameter | meaning | default |
//! |---|---|---|
//! | `address`, `bus`, `backend` | see [`super`] | 0x40, 1, dev |
//! | `freq` | PWM frequency, Hz (24..1526; set through PRE_SCALE, so the chip runs at the nearest it can) | 1000 |
//! | `invert` | 1: outputs inverted (MODE2.INVRT) | 0 |
//! | `opendrain` | 1: open-drain outputs (else totem pole) | 0 |
//!
//! Per chip N: canonical PWM outputs `pca9685.N.pwmgen.00` .. `.15`
//! (`value`, `enable`, `scale`; duty = value / scale, clipped to 0..1, as
//! the chip has no direction output: a negative duty is off), the status
//! pins, functions `pca9685.N.read` and `pca9685.N.write`. A disabled
//! channel, and every channel in the safe state, is full off.

use canonical::{ChannelNames, Pwm};
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::Result;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;

use super::{export_chips, prepare_all, read_common, ChipAt, Prepared, StatusPins};
use crate::chips::{Pca9685Chip, PwmCmd};
use crate::regs::pca9685::{prescale_for, ADDRESSES, CHANNELS};
use crate::sim::Pca9685;

/// The module's and component's name.
pub const NAME: &str = "pca9685";

/// The PWM frequency when none is given, Hz.
pub const DEFAULT_FREQ: i64 = 1000;

/// pca9685's module parameters, the one table both hosts read.
#[macro_export]
macro_rules! pca9685_params {
    ($($then:tt)*) => { $crate::__i2c_params! { [$($then)*]
        freq: IntArray($crate::hal::MAX_CHIPS) =
            "PWM frequency of each chip, Hz (24..1526, default 1000)",
        invert: IntArray($crate::hal::MAX_CHIPS) = "1: invert the chip's outputs",
        opendrain: IntArray($crate::hal::MAX_CHIPS) = "1: open-drain outputs (default totem pole)",
    } };
}

/// The `pca9685` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalPca9685;

/// The `pca9685` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalPca9685>();

impl DriverModule for HalPca9685 {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "NXP PCA9685 16-channel PWM outputs on I2C (or simulated)";
    const PARAMS: &'static [ParamDecl] = pca9685_params!(hal_driver::param_table);
    type Opened = Vec<(Prepared<Pca9685Chip>, ChipAt)>;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> Result<Self::Opened> {
        let p = Params::new(NAME, args);
        let (backend, chips) =
            read_common(&p, args, ADDRESSES, 0x40).map_err(|e| e.into_hal(NAME))?;
        let n = chips.len();
        let freqs = p
            .ints_per("freq", n, DEFAULT_FREQ, 1..=100_000)
            .map_err(|e| e.into_hal(NAME))?;
        let invert = super::flags_per(&p, "invert", n).map_err(|e| e.into_hal(NAME))?;
        let open_drain = super::flags_per(&p, "opendrain", n).map_err(|e| e.into_hal(NAME))?;
        prepare_all(
            env.instance(),
            backend,
            NAME,
            &chips,
            || Box::new(Pca9685::new()),
            |i, at| {
                let prescale = prescale_for(freqs[i] as f64).ok_or_else(|| {
                    p.item_error(
                        "freq",
                        i,
                        &freqs[i].to_string(),
                        "the chip runs at 24..1526 Hz",
                    )
                    .into_hal(NAME)
                })?;
                let chip = Pca9685Chip::new(at.addr, prescale, invert[i], open_drain[i]);
                Ok((chip, PwmCmd::default()))
            },
        )
    }

    fn export<H: DriverHost>(prepared: Self::Opened, ex: &mut Exporter<'_, H>) -> Result<()> {
        export_chips(ex, NAME, prepared, |ex, comp, i, name, ends| {
            let c = ex.pins(comp);
            let names = ChannelNames::canonical::<Pwm>(NAME, i, CHANNELS);
            let pwm = (0..CHANNELS)
                .map(|ch| Pwm::<H>::export(c, &names, ch))
                .collect::<Result<Vec<_>>>()?;
            let status = StatusPins::<H>::export(c, name)?;
            let (mut cmd, mut st) = (ends.cmd, ends.status);
            ex.funct(comp, &format!("{name}.read"), false, move |_| {
                status.update(&mut st);
            })?;
            ex.funct(comp, &format!("{name}.write"), true, move |_| {
                let mut out = PwmCmd::default();
                for (k, ch) in pwm.iter().enumerate() {
                    out.counts[k] = PwmCmd::counts_for(ch.duty().unwrap_or(0.0));
                }
                cmd.publish(out);
            })
        })
    }
}
