//! Opening what the parameters describe: each bus's port (raw port I/O,
//! or a simulated port with `sim=`), the scan for its boards, the
//! per-board options checked against what was found, and the boards
//! set up (counters cleared, outputs off, one board driving the latch
//! strobe, further estop boards made slaves). Nothing is exported yet.

use std::sync::Arc;

use hal_driver::bus::{IopermPorts, PortBus, PortRange};
use hal_driver::sim::SimBoard;
use hal_parport::cfg::{Mode, PortSpec};
use hal_parport::regs as port;
use hal_parport::select::{choose_all, sim_base, Choice, SysPaths};

use crate::epp::Epp;
use crate::error::PpmcError;
use crate::params::{Config, Options, PortAddr, SlotCode};
use crate::regs::{dac, dio, enc, pwm, stepgen, uxc, ID_OFFSET, SLOT_SIZE};
use crate::scan::{scan, Found, Kind};
use crate::sim::{PpmcPort, SimSpec};

/// What a USC/UPC's extra port drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExtraUse {
    /// Nothing.
    None,
    /// The 8-bit spindle DAC (`extradac`).
    Dac,
    /// Eight digital outputs (`extradout`).
    Douts,
}

/// A board found, with its options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Planned {
    /// Where and what.
    pub found: Found,
    /// The extra port's use.
    pub extra: ExtraUse,
    /// Velocity from timestamps.
    pub timestamp: bool,
    /// The encoder filter clock code, when set.
    pub enc_clock: Option<u8>,
    /// This board makes the bus's counter latch strobe (the first board
    /// with counters).
    pub strobe: bool,
    /// This board has the bus's estop circuit (the first board with
    /// digital I/O); later ones are its slaves.
    pub estop_master: bool,
}

/// One bus, opened and set up.
#[derive(Debug)]
pub struct OpenedBus {
    /// Its number (`ppmc.<number>`).
    pub number: usize,
    /// The port.
    pub epp: Epp,
    /// Its boards in slot order.
    pub boards: Vec<Planned>,
    /// The simulated port, when it is one.
    pub sim: Option<Arc<SimBoard<PpmcPort>>>,
}

/// Opens every bus of `cfg`, scans it, checks the options and sets the
/// boards up. An option naming a board that lacks the feature, or no
/// board at all, fails the whole load.
pub fn open(cfg: &Config) -> Result<Vec<OpenedBus>, PpmcError> {
    let mut used = Used::default();
    let mut buses = Vec::new();
    let mut real = choose_ports(cfg)?.into_iter();
    for b in &cfg.buses {
        let (bus, base, base_hi, sim) = match &b.sim {
            Some(spec) => sim_port(b.port, spec),
            None => raw_port(b.number, real.next().flatten())?,
        };
        let epp = Epp::new(bus, base, b.turn_for_reads);
        epp.set_up(base_hi);
        let found = scan(|slot| {
            let id = epp.select_read(slot as u8 * SLOT_SIZE + ID_OFFSET);
            epp.clear_timeout();
            id
        })?;
        if found.is_empty() {
            return Err(PpmcError::NoBoards {
                bus: b.number,
                port: base,
            });
        }
        let boards = plan(b.number, &found, &cfg.options, &mut used)?;
        buses.push(OpenedBus {
            number: b.number,
            epp,
            boards,
            sim,
        });
    }
    used.check(&cfg.options)?;
    for b in &buses {
        set_up(&b.epp, &b.boards);
    }
    Ok(buses)
}

/// The port of bus `b`: its bus, base, ECR block and simulator.
type PortOf = (
    Arc<dyn PortBus>,
    u16,
    Option<u16>,
    Option<Arc<SimBoard<PpmcPort>>>,
);

/// A real port's base and ECR block addresses.
type RawAt = (u16, Option<u16>);

/// The real ports of `cfg`'s buses, chosen as hal_parport chooses an
/// epp-mode port (raw I/O at the address Linux lists, or the one given),
/// with its check that no port is given twice; one entry per real bus,
/// in order.
fn choose_ports(cfg: &Config) -> Result<Vec<Option<RawAt>>, PpmcError> {
    let real: Vec<(usize, PortSpec)> = cfg
        .buses
        .iter()
        .filter(|b| b.sim.is_none())
        .map(|b| {
            let spec = PortSpec {
                addr: b.port,
                mode: Mode::Epp,
                backend: None,
            };
            (b.number, spec)
        })
        .collect();
    let specs: Vec<PortSpec> = real.iter().map(|(_, s)| *s).collect();
    let choices =
        choose_all(&specs, &SysPaths::system()).map_err(|(i, source)| PpmcError::PortChoice {
            bus: real.get(i).map_or(i, |(n, _)| *n),
            source,
        })?;
    // An epp-mode port is always raw I/O (ppdev cannot reach the ECR).
    Ok(choices
        .into_iter()
        .map(|c| match c {
            Choice::Raw { base, base_hi, .. } => Some((base, base_hi)),
            Choice::Ppdev { .. } | Choice::Sim { .. } => None,
        })
        .collect())
}

/// A simulated port at `addr` with the boards of `spec`.
fn sim_port(addr: PortAddr, spec: &SimSpec) -> PortOf {
    let base = match addr {
        PortAddr::Address(a) => a,
        PortAddr::Number(n) => sim_base(n),
    };
    let hi = base.wrapping_add(port::HI_OFFSET);
    let sim = Arc::new(SimBoard::new(PpmcPort::new(base, hi, spec)));
    (sim.clone(), base, Some(hi), Some(sim))
}

/// Raw I/O on the port hal_parport's choice named. The port is not
/// claimed through ppdev (a claim blocks while another holder has it).
fn raw_port(bus: usize, choice: Option<RawAt>) -> Result<PortOf, PpmcError> {
    let (base, base_hi) = choice.ok_or_else(|| PpmcError::BadOption {
        param: "port_addr",
        code: bus as i64,
        reason: "hal_parport chose no raw I/O for this epp-mode port".into(),
    })?;
    let wrap = |source| PpmcError::Port { port: base, source };
    let mut ranges = vec![PortRange::new(base, port::BASE_SPAN).map_err(wrap)?];
    if let Some(hi) = base_hi {
        ranges.push(PortRange::new(hi, port::HI_SPAN).map_err(wrap)?);
    }
    let ports = IopermPorts::open(&ranges).map_err(wrap)?;
    Ok((Arc::new(ports), base, base_hi, None))
}

/// Which option items a board took.
#[derive(Debug, Default)]
struct Used {
    extradac: Vec<usize>,
    extradout: Vec<usize>,
    timestamp: Vec<usize>,
    enc_clock: Vec<usize>,
}

impl Used {
    /// Fails on the first item no board took.
    fn check(&self, o: &Options) -> Result<(), PpmcError> {
        let lists: [(&'static str, Vec<&SlotCode>, &Vec<usize>, &str); 4] = [
            (
                "extradac",
                o.extradac.iter().collect(),
                &self.extradac,
                "a USC or UPC",
            ),
            (
                "extradout",
                o.extradout.iter().collect(),
                &self.extradout,
                "a USC or UPC",
            ),
            (
                "timestamp",
                o.timestamp.iter().collect(),
                &self.timestamp,
                "an encoder board or UPC",
            ),
            (
                "enc_clock",
                o.enc_clock.iter().map(|(c, _)| c).collect(),
                &self.enc_clock,
                "an encoder board",
            ),
        ];
        for (param, codes, used, wanted) in lists {
            if let Some((_, c)) = codes.iter().enumerate().find(|(i, _)| !used.contains(i)) {
                return Err(PpmcError::BadOption {
                    param,
                    code: c.given,
                    reason: format!(
                        "no board starts at slot {} of bus {} (it should be {wanted})",
                        c.slot, c.bus
                    ),
                });
            }
        }
        Ok(())
    }
}

/// The options of each board found on bus `bus`, checked, and which
/// board strobes the counters and holds the estop circuit.
fn plan(
    bus: usize,
    found: &[Found],
    o: &Options,
    used: &mut Used,
) -> Result<Vec<Planned>, PpmcError> {
    let (mut strobe_taken, mut estop_taken) = (false, false);
    let mut planned = Vec::with_capacity(found.len());
    for &f in found {
        let (extra, timestamp, enc_clock) = options_of(bus, f, o, used)?;
        let counters = f.id.kind.has_encoders();
        let dio = f.id.kind.is_uxc() || f.id.kind == Kind::Dio;
        planned.push(Planned {
            found: f,
            extra,
            timestamp,
            enc_clock,
            strobe: counters && !strobe_taken,
            estop_master: dio && !estop_taken,
        });
        strobe_taken |= counters;
        estop_taken |= dio;
    }
    Ok(planned)
}

/// The first item of `list` that names board `f` of bus `bus`; every
/// such item's index goes into `used`.
fn take(
    list: impl Iterator<Item = SlotCode>,
    bus: usize,
    f: Found,
    used: &mut Vec<usize>,
) -> Option<SlotCode> {
    let mut first = None;
    for (i, c) in list.enumerate() {
        if c.bus == bus && c.slot == f.slot {
            used.push(i);
            first = first.or(Some(c));
        }
    }
    first
}

/// Board `f`'s extra port use, timestamps and filter clock, from the
/// options that name it; an option it cannot take is an error.
fn options_of(
    bus: usize,
    f: Found,
    o: &Options,
    used: &mut Used,
) -> Result<(ExtraUse, bool, Option<u8>), PpmcError> {
    let bad = |param: &'static str, c: SlotCode, reason: String| PpmcError::BadOption {
        param,
        code: c.given,
        reason,
    };
    let what = format!(
        "the board at slot {} of bus {bus} is a {} revision {}",
        f.slot, f.id.kind, f.id.rev
    );
    let xdac = take(o.extradac.iter().copied(), bus, f, &mut used.extradac);
    let xdout = take(o.extradout.iter().copied(), bus, f, &mut used.extradout);
    let extra = match (xdac, xdout) {
        (Some(c), Some(_)) => {
            let why = "extradout names the same board: its extra port is one or the other";
            return Err(bad("extradac", c, why.into()));
        }
        (Some(c), None) | (None, Some(c)) if !f.id.has_extra_port() => {
            let param = if xdac.is_some() {
                "extradac"
            } else {
                "extradout"
            };
            let why = "which has no extra port (every USC has one; a UPC from revision 2)";
            return Err(bad(param, c, format!("{what}, {why}")));
        }
        (Some(_), None) => ExtraUse::Dac,
        (None, Some(_)) => ExtraUse::Douts,
        (None, None) => ExtraUse::None,
    };
    let timestamp = match take(o.timestamp.iter().copied(), bus, f, &mut used.timestamp) {
        Some(c) if !f.id.has_timestamps() || !f.id.has_index() => {
            let why = "whose firmware has no encoder timestamps (an encoder board or UPC of \
                       revision 4 or later has them)";
            return Err(bad("timestamp", c, format!("{what}, {why}")));
        }
        found => found.is_some(),
    };
    let clocks = o.enc_clock.iter().map(|(c, _)| *c);
    let enc_clock = match take(clocks, bus, f, &mut used.enc_clock) {
        Some(c) if !f.id.has_filter_clock() => {
            let why = "whose filter clock cannot be set (an encoder board of revision 4 or later)";
            return Err(bad("enc_clock", c, format!("{what}, {why}")));
        }
        Some(c) => o.enc_clock.iter().find(|(k, _)| *k == c).map(|(_, r)| *r),
        None => None,
    };
    Ok((extra, timestamp, enc_clock))
}

/// Sets the boards up: counters cleared and latched by the first board's
/// strobe, index clears off, outputs off, DACs at 0 V, slaves told so.
fn set_up(epp: &Epp, boards: &[Planned]) {
    for p in boards {
        let base = p.found.slot as u8 * SLOT_SIZE;
        let kind = p.found.id.kind;
        if kind.has_encoders() {
            epp.select_write(base + enc::CTRL, 0);
            let rate = if p.strobe { enc::RATE_MASTER } else { 0 };
            epp.select_write(base + enc::RATE, rate);
            epp.select_write(base + enc::LOAD, 0);
            epp.write_more(0);
            epp.write_more(0);
            epp.select_write(base + enc::CTRL, enc::CTRL_RESET_ALL);
            epp.select_write(base + enc::CTRL, 0);
            epp.select_write(base + enc::INDEX, 0);
            if let Some(code) = p.enc_clock {
                epp.select_write(base + enc::CLOCK, code);
            }
        }
        if kind.is_uxc() {
            epp.select_write(base + uxc::DOUT, 0);
            if !p.estop_master {
                epp.select_write(base + uxc::SLAVE, 1);
            }
        }
        if kind == Kind::Dio {
            epp.select_write(base + dio::DOUT, 0);
            if !p.estop_master {
                epp.select_write(base + dio::ESTOP_OUT, dio::SLAVE);
            }
        }
        if kind == Kind::Dac {
            zero_dacs(epp, base);
        }
    }
}

/// Every DAC of the DAC board at `base` to 0 V.
fn zero_dacs(epp: &Epp, base: u8) {
    let [lo, hi] = dac::ZERO.to_le_bytes();
    epp.select_write(base + dac::DAC0, lo);
    for i in 1..8 {
        epp.write_more(if i % 2 == 0 { lo } else { hi });
    }
}

/// The safe state of a bus: every board's estop output off first (the
/// boards' own estop circuits then hold their outputs off), then every
/// output register at its off value: step and PWM generators stopped,
/// DACs at 0 V (code 0x8000; LinuxCNC's unload wrote 0, which is -10
/// V), digital outputs and the extra port 0, index clears off.
pub fn go_safe(epp: &Epp, boards: &[Planned]) {
    for p in boards {
        let base = p.found.slot as u8 * SLOT_SIZE;
        match p.found.id.kind {
            Kind::Usc | Kind::Upc => epp.select_write(base + uxc::DOUT, 0),
            Kind::Dio => {
                epp.select_write(base + dio::DOUT, 0);
                let estop = if p.estop_master { 0 } else { dio::SLAVE };
                epp.select_write(base + dio::ESTOP_OUT, estop);
            }
            _ => {}
        }
    }
    for p in boards {
        let base = p.found.slot as u8 * SLOT_SIZE;
        let kind = p.found.id.kind;
        match kind {
            Kind::Usc => epp.select_write(base + stepgen::CTRL, 0),
            Kind::Upc => epp.select_write(base + pwm::CTRL, 0),
            Kind::Dac => zero_dacs(epp, base),
            _ => {}
        }
        if kind.is_uxc() {
            epp.select_write(base + uxc::EXTRA, 0);
        }
        if kind.has_encoders() && p.found.id.has_index() {
            epp.select_write(base + enc::INDEX, 0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::ModuleArgs;

    /// One port given twice is refused before any port is touched, as
    /// hal_parport refuses it: two buses would strobe the same boards.
    #[test]
    fn one_port_twice_is_refused() {
        let a = ModuleArgs::parse(
            crate::hal::NAME,
            crate::hal::PARAMS,
            &["port_addr=0x278,0x278"],
        )
        .unwrap();
        let cfg = crate::params::parse(&a).unwrap();
        match open(&cfg) {
            Err(e @ PpmcError::PortChoice { bus: 1, .. }) => {
                assert!(e.to_string().contains("port_addr item 1"), "{e}");
            }
            Err(e) => panic!("refused otherwise: {e}"),
            Ok(_) => panic!("two buses on one port"),
        }
    }
}
