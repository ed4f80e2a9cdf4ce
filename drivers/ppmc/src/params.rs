//! The `loadrt` parameters: which ports (`port_addr`), the per-board
//! options (`extradac`, `extradout`, `timestamp`, `enc_clock`), the
//! EPP direction handling (`epp_dir`) and the simulator (`sim`).
//!
//! Per-board options name a board by a bus/slot code `0xBS`: `B` the
//! bus (the position of its port in `port_addr`, 0..2), `S` the board's
//! first slot (0..f). `enc_clock` puts the filter clock in MHz before
//! it: `0x503` is 5 MHz for the encoder board in slot 3 of bus 0. An
//! item of -1 is unused, as in LinuxCNC's defaults. Whether a code names
//! a board that has the feature is checked after the scan
//! ([`crate::open`]).

use hal_core::module::ModuleArgs;
use hal_driver::params::Params;
use hal_driver::DriverError;

use crate::regs::enc;
use crate::sim::SimSpec;

/// Buses (ports) one load drives.
pub const MAX_BUS: usize = 3;
/// Items of each per-board option.
pub const MAX_OPTIONS: usize = MAX_BUS * 8;
/// The first port's address when `port_addr` is not given.
pub const DEFAULT_PORT: i64 = 0x378;

/// Where a bus's port is: hal_parport's `port_addr` item (an I/O
/// address, or a port number Linux registered).
pub use hal_parport::cfg::PortAddr;

/// One bus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BusConfig {
    /// Its number: the item's position in `port_addr` (`ppmc.<number>`).
    pub number: usize,
    /// Its port.
    pub port: PortAddr,
    /// `epp_dir=0`: turn the data lines for each read.
    pub turn_for_reads: bool,
    /// The simulated boards, with `sim=`.
    pub sim: Option<SimSpec>,
}

/// A board named by bus and slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlotCode {
    /// The bus (0..2).
    pub bus: usize,
    /// The board's first slot (0..15).
    pub slot: usize,
    /// The item as given, for messages.
    pub given: i64,
}

/// The per-board options.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Options {
    /// Boards whose extra port drives the 8-bit spindle DAC.
    pub extradac: Vec<SlotCode>,
    /// Boards whose extra port is 8 more digital outputs.
    pub extradout: Vec<SlotCode>,
    /// Boards whose counters' timestamps give the velocity.
    pub timestamp: Vec<SlotCode>,
    /// Encoder boards' filter clocks: the board and the [`enc::CLOCK`]
    /// register's code.
    pub enc_clock: Vec<(SlotCode, u8)>,
}

/// The parsed parameters.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    /// The buses, in `port_addr` order.
    pub buses: Vec<BusConfig>,
    /// The per-board options.
    pub options: Options,
}

/// Reads every parameter.
pub fn parse(args: &ModuleArgs) -> Result<Config, DriverError> {
    let p = Params::new(crate::hal::NAME, args);
    let sims = args.str_array("sim");
    let mut addrs: Vec<(usize, i64)> = args
        .int_array("port_addr")
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, v)| *v != -1)
        .collect();
    if args.int_array("port_addr").is_empty() {
        addrs = (0..sims.len().max(1))
            .map(|i| (i, [DEFAULT_PORT, 0x278, 0x3BC][i.min(2)]))
            .collect();
    }
    if !sims.is_empty() && sims.len() != addrs.len() {
        return Err(p.error(
            "sim",
            format!(
                "{} item(s) for {} port(s): give one board set per port in port_addr (every \
                 bus is simulated, or none)",
                sims.len(),
                addrs.len()
            ),
        ));
    }
    let dirs = args.int_array("epp_dir");
    let buses = addrs
        .iter()
        .enumerate()
        .map(|(k, &(i, v))| {
            let port = port_addr(&p, i, v)?;
            let turn_for_reads = match dirs.get(k).copied().unwrap_or(0) {
                0 => true,
                1 => false,
                d => return Err(p.item_error("epp_dir", k, &d.to_string(), "must be 0 or 1")),
            };
            let sim = match sims.get(k) {
                Some(s) => Some(SimSpec::parse(s).map_err(|e| p.item_error("sim", k, s, e))?),
                None => None,
            };
            Ok(BusConfig {
                number: i,
                port,
                turn_for_reads,
                sim,
            })
        })
        .collect::<Result<Vec<_>, DriverError>>()?;
    let options = Options {
        extradac: slot_codes(&p, args, "extradac")?,
        extradout: slot_codes(&p, args, "extradout")?,
        timestamp: slot_codes(&p, args, "timestamp")?,
        enc_clock: clocks(&p, args)?,
    };
    for (list, name) in [
        (&options.extradac, "extradac"),
        (&options.extradout, "extradout"),
        (&options.timestamp, "timestamp"),
    ] {
        if let Some(c) = list
            .iter()
            .find(|c| !buses.iter().any(|b| b.number == c.bus))
        {
            return Err(no_such_bus(&p, name, c));
        }
    }
    let clock_codes = options.enc_clock.iter().map(|(c, _)| c);
    if let Some(c) = clock_codes
        .clone()
        .find(|c| !buses.iter().any(|b| b.number == c.bus))
    {
        return Err(no_such_bus(&p, "enc_clock", c));
    }
    Ok(Config { buses, options })
}

fn no_such_bus(p: &Params<'_>, name: &str, c: &SlotCode) -> DriverError {
    p.error(
        name,
        format!(
            "{:#x} names bus {}, but port_addr gives no port {}",
            c.given, c.bus, c.bus
        ),
    )
}

/// A `port_addr` item: a port number 0..15 or an I/O address.
fn port_addr(p: &Params<'_>, i: usize, v: i64) -> Result<PortAddr, DriverError> {
    match v {
        0..=15 => Ok(PortAddr::Number(v as u8)),
        0x10..=0xFFF8 => Ok(PortAddr::Address(v as u16)),
        _ => Err(p.item_error(
            "port_addr",
            i,
            &if v < 0 {
                v.to_string()
            } else {
                format!("{v:#x}")
            },
            "neither a port number (0..15) nor a port address (0x10..0xfff8); -1 leaves the \
             item unused",
        )),
    }
}

/// A bus/slot code `0xBS`.
fn slot_code(v: i64) -> Option<SlotCode> {
    (0..=0xFF).contains(&v).then_some(())?;
    let bus = (v >> 4) as usize;
    (bus < MAX_BUS).then_some(SlotCode {
        bus,
        slot: (v & 0xF) as usize,
        given: v,
    })
}

fn slot_codes(p: &Params<'_>, args: &ModuleArgs, name: &str) -> Result<Vec<SlotCode>, DriverError> {
    args.int_array(name)
        .iter()
        .enumerate()
        .filter(|(_, v)| **v != -1)
        .map(|(i, &v)| {
            slot_code(v).ok_or_else(|| {
                p.item_error(
                    name,
                    i,
                    &shown(v),
                    "not a bus/slot code 0xBS (B the bus 0..2, S the slot 0..f)",
                )
            })
        })
        .collect()
}

fn clocks(p: &Params<'_>, args: &ModuleArgs) -> Result<Vec<(SlotCode, u8)>, DriverError> {
    args.int_array("enc_clock")
        .iter()
        .enumerate()
        .filter(|(_, v)| **v != -1)
        .map(|(i, &v)| {
            let bad = |why: &str| p.item_error("enc_clock", i, &shown(v), why);
            if v < 0 {
                return Err(bad(
                    "not a code 0xFBS (F the clock in MHz: 1, 2 for 2.5, 5 or a for 10)",
                ));
            }
            let code = slot_code(v & 0xFF)
                .map(|c| SlotCode { given: v, ..c })
                .ok_or_else(|| {
                    bad("its low byte is not a bus/slot code 0xBS (B the bus 0..2, S the slot 0..f)")
                })?;
            let mhz = v >> 8;
            let reg = enc::CLOCKS
                .iter()
                .find(|(m, _)| *m as i64 == mhz)
                .map(|(_, r)| *r)
                .ok_or_else(|| {
                    bad("the clock (the digits before the bus/slot code) must be 1, 2 (2.5 MHz), \
                         5 or a (10 MHz)")
                })?;
            Ok((code, reg))
        })
        .collect()
}

fn shown(v: i64) -> String {
    if v < 0 {
        v.to_string()
    } else {
        format!("{v:#x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(args: &[&str]) -> hal_core::Result<Config> {
        let a = ModuleArgs::parse(crate::hal::NAME, crate::hal::PARAMS, args)?;
        parse(&a).map_err(|e| e.into_hal(crate::hal::NAME))
    }

    #[test]
    fn linuxcnc_parameters() {
        let c = cfg(&[]).unwrap();
        assert_eq!(c.buses.len(), 1);
        assert_eq!(c.buses[0].port, PortAddr::Address(0x378));
        assert!(c.buses[0].turn_for_reads && c.buses[0].sim.is_none());
        let c = cfg(&["port_addr=\"0x378\"", "timestamp=\"0x00\""]).unwrap();
        assert_eq!(
            c.options.timestamp,
            [SlotCode {
                bus: 0,
                slot: 0,
                given: 0
            }]
        );
        let c = cfg(&[
            "port_addr=0x378,0",
            "extradac=0x12",
            "enc_clock=0x503,0xa00",
            "epp_dir=1,0",
        ])
        .unwrap();
        assert_eq!(c.buses[1].port, PortAddr::Number(0));
        assert!(!c.buses[0].turn_for_reads && c.buses[1].turn_for_reads);
        assert_eq!(
            (c.options.extradac[0].bus, c.options.extradac[0].slot),
            (1, 2)
        );
        assert_eq!(c.options.enc_clock[0].1, 2);
        assert_eq!(c.options.enc_clock[1].1, 3);
    }

    #[test]
    fn bad_parameters_name_the_parameter() {
        for (args, want) in [
            (&["port_addr=0x10000"][..], "hal_ppmc: parameter 'port_addr': item 0 \"0x10000\": neither a port number (0..15) nor a port address (0x10..0xfff8); -1 leaves the item unused"),
            (&["extradac=0x30"], "hal_ppmc: parameter 'extradac': item 0 \"0x30\": not a bus/slot code 0xBS (B the bus 0..2, S the slot 0..f)"),
            (&["timestamp=0x10"], "hal_ppmc: parameter 'timestamp': 0x10 names bus 1, but port_addr gives no port 1"),
            (&["enc_clock=0x300"], "hal_ppmc: parameter 'enc_clock': item 0 \"0x300\": the clock (the digits before the bus/slot code) must be 1, 2 (2.5 MHz), 5 or a (10 MHz)"),
            (&["epp_dir=2"], "hal_ppmc: parameter 'epp_dir': item 0 \"2\": must be 0 or 1"),
            (&["port_addr=0x378", "sim=ppmc,upc"], "hal_ppmc: parameter 'sim': 2 item(s) for 1 port(s): give one board set per port in port_addr (every bus is simulated, or none)"),
            (&["sim=ppmc+foo"], "hal_ppmc: parameter 'sim': item 0 \"ppmc+foo\": 'foo' is not a simulated board (encoder, dac, dio, usc, upc, or ppmc for encoder+dac+dio; a revision may follow, as upc:2)"),
        ] {
            assert_eq!(cfg(args).unwrap_err().to_string(), want, "{args:?}");
        }
    }
}
