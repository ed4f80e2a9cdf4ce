//! `loadrt ads1115`: up to four analog inputs per chip.
//!
//! | parameter | meaning | default |
//! |---|---|---|
//! | `address`, `bus`, `backend` | see [`super`] | 0x48, 1, dev |
//! | `range` | full scale, mV: 6144, 4096, 2048, 1024, 512 or 256 | 4096 |
//! | `rate` | samples per second: 8, 16, 32, 64, 128, 250, 475 or 860 | 860 |
//! | `channels` | inputs converted, 1..4 (AIN0..; 1..2 with `diff`) | 4 (2 with `diff`) |
//! | `diff` | 1: differential, channel 0 = AIN0 − AIN1, channel 1 = AIN2 − AIN3 | 0 |
//!
//! Per chip N, channel K: a canonical analog input
//! `ads1115.N.adcin.K.value` (`scale`, `offset`, `bit_weight` = full
//! scale / 32768 V, `hw_offset` 0), the status pins, and the function
//! `ads1115.N.read`. Channels are converted one after another, each
//! taking 1 / rate: every channel is new every `channels / rate`
//! seconds (4.7 ms for four channels at 860 samples/s), plus the
//! transfers.

use canonical::{AdcIn, ChannelNames};
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::Result;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::Params;

use super::{export_chips, prepare_all, read_common, ChipAt, Prepared, StatusPins};
use crate::chips::{AdcSettings, Ads1115Chip};
use crate::regs::ads1115::{dr_for_sps, pga_for_mv, ADDRESSES};
use crate::sim::Ads1115;

/// The module's and component's name.
pub const NAME: &str = "ads1115";

/// ads1115's module parameters, the one table both hosts read.
#[macro_export]
macro_rules! ads1115_params {
    ($($then:tt)*) => { $crate::__i2c_params! { [$($then)*]
        range: IntArray($crate::hal::MAX_CHIPS) =
            "full scale of each chip, mV: 6144|4096|2048|1024|512|256 (default 4096)",
        rate: IntArray($crate::hal::MAX_CHIPS) =
            "samples/s of each chip: 8|16|32|64|128|250|475|860 (default 860)",
        channels: IntArray($crate::hal::MAX_CHIPS) =
            "inputs converted by each chip, 1..4 (default 4, 2 with diff)",
        diff: IntArray($crate::hal::MAX_CHIPS) = "1: differential inputs AIN0-AIN1, AIN2-AIN3",
    } };
}

/// The `ads1115` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalAds1115;

/// The `ads1115` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalAds1115>();

/// The chips, set up, with each one's conversion settings.
pub struct OpenedChips {
    prepared: Vec<(Prepared<Ads1115Chip>, ChipAt)>,
    settings: Vec<AdcSettings>,
}

impl DriverModule for HalAds1115 {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "TI ADS1115 16-bit 4-input ADC on I2C (or simulated)";
    const PARAMS: &'static [ParamDecl] = ads1115_params!(hal_driver::param_table);
    type Opened = OpenedChips;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> Result<OpenedChips> {
        open_chips(args, env)
    }

    fn export<H: DriverHost>(o: OpenedChips, ex: &mut Exporter<'_, H>) -> Result<()> {
        let settings = o.settings;
        export_chips(ex, NAME, o.prepared, |ex, comp, i, name, ends| {
            let c = ex.pins(comp);
            let s = settings[i];
            let names = ChannelNames::canonical::<AdcIn>(NAME, i, s.channels);
            let adcs = (0..s.channels)
                .map(|ch| AdcIn::<H>::export(c, &names, ch, s.lsb_volts(), 0.0))
                .collect::<Result<Vec<_>>>()?;
            let status = StatusPins::<H>::export(c, name)?;
            let mut st = ends.status;
            ex.funct(comp, &format!("{name}.read"), true, move |_| {
                let sample = status.update(&mut st).sample;
                for (ch, a) in adcs.iter().enumerate() {
                    a.update_counts(sample.counts[ch] as i64);
                }
            })
        })
    }
}

/// Reads the parameters and sets every chip up.
fn open_chips(args: &ModuleArgs, env: &LoadEnv) -> Result<OpenedChips> {
    let p = Params::new(NAME, args);
    let (backend, chips) = read_common(&p, args, ADDRESSES, 0x48).map_err(|e| e.into_hal(NAME))?;
    let n = chips.len();
    let err = |e: hal_driver::DriverError| e.into_hal(NAME);
    let ranges = p.ints_per("range", n, 4096, 0..=i64::MAX).map_err(err)?;
    let rates = p.ints_per("rate", n, 860, 0..=i64::MAX).map_err(err)?;
    let diff = super::flags_per(&p, "diff", n).map_err(err)?;
    let given = p.ints_per("channels", n, 0, 0..=4).map_err(err)?;
    let mut settings = Vec::with_capacity(n);
    for i in 0..n {
        let item = |param: &str, v: i64, why: &str| {
            p.item_error(param, i, &v.to_string(), why).into_hal(NAME)
        };
        let pga = pga_for_mv(ranges[i]).ok_or_else(|| {
            item(
                "range",
                ranges[i],
                "not one of 6144, 4096, 2048, 1024, 512, 256 (mV)",
            )
        })?;
        let dr = dr_for_sps(rates[i]).ok_or_else(|| {
            item(
                "rate",
                rates[i],
                "not one of 8, 16, 32, 64, 128, 250, 475, 860",
            )
        })?;
        let max = if diff[i] { 2 } else { 4 };
        let channels = if given[i] == 0 {
            max
        } else {
            given[i] as usize
        };
        if channels > max {
            return Err(item(
                "channels",
                given[i],
                "differential inputs make at most 2 channels",
            ));
        }
        settings.push(AdcSettings {
            channels,
            differential: diff[i],
            pga,
            dr,
        });
    }
    let prepared = prepare_all(
        env.instance(),
        backend,
        NAME,
        &chips,
        || Box::new(Ads1115::new()),
        |i, at| Ok((Ads1115Chip::new(at.addr, settings[i]), ())),
    )?;
    Ok(OpenedChips { prepared, settings })
}
