//! Finding the remote cards on each Smart Serial port at load
//! (hostmot2-more.md 2.4), with plain register reads and writes:
//!
//! 1. the port's channel pins are given to the module (so the channels
//!    reach their cards), the processor is reset and its revision read;
//! 2. every channel not disabled with `x` is started in setup mode in
//!    its configured mode; a card answers with its unit number, name and
//!    the addresses of its tables;
//! 3. each card's tables and records are read one byte per transfer, and
//!    its globals' values;
//! 4. every port is stopped and the pins given back: pin allocation then
//!    gives the channels that have a card to the module, the others stay
//!    GPIO. The ports start at the first `write`.
//!
//! The 8I20 and 7I64 name no tables: their process data and globals are
//! the driver's own ([`legacy`]), and an 8I20's current is scaled to the
//! maximum current it keeps in its memory.
//!
//! With hostmot2's `sserial_baudrate=115200` discovery is in setup mode
//! (LinuxCNC's choice, for reflashing remotes with `setsserial`): a card
//! counts when the second character of its name is `I` (any Mesa card),
//! none of its records is read, and its port gets no HAL objects and is
//! never started; its channel pins still go to the module so that
//! `setsserial` reaches it.
//!
//! Everything a card says is checked: a table without end, a record
//! that is not one, process data wider than the module's registers or of
//! a type the driver cannot move are refused with the port, channel and
//! reason.

use std::time::{Duration, Instant};

use crate::config::Config;
use crate::error::{Hm2Error, Result};
use crate::log::MessageLog;
use crate::md::ModuleDescriptor;
use crate::pins::PinDescriptor;
use crate::regs::{gtag, ioport as io};
use crate::sserial::legacy;
use crate::sserial::records::{self, data_type as dt, DataRecord, ModeRecord, Record, RecordError};
use crate::sserial::{
    cmd, lbp, local, reg, remote_name, status, PinRole, MAX_CHANNELS, MAX_DATA_BITS,
};
use crate::transport::Transport;

/// A card found on a channel.
#[derive(Debug, Clone, PartialEq)]
pub struct RemoteFound {
    /// The channel.
    pub channel: u8,
    /// The mode it runs in.
    pub mode: u8,
    /// Interface 0 after the setup start: type in bits 31..24, unit number.
    pub unit: u32,
    /// Interface 1: the four-character name.
    pub raw_name: u32,
    /// Its process data, in wire order.
    pub process: Vec<DataRecord>,
    /// Its globals with the values read at load.
    pub globals: Vec<(DataRecord, u64)>,
    /// Its modes.
    pub modes: Vec<ModeRecord>,
    /// Its tables are the driver's own ([`legacy`]): it names no tables.
    pub built_in: bool,
}

impl RemoteFound {
    /// The name in HAL names (`7i76`).
    pub fn name(&self) -> String {
        remote_name(self.raw_name)
    }

    /// A record's name in HAL names: lower-cased as LinuxCNC keeps the
    /// names it reads from a card, as written for the built-in tables.
    pub fn hal_name(&self, r: &DataRecord) -> String {
        if self.built_in {
            r.name.clone()
        } else {
            r.hal_name()
        }
    }

    /// Bits the host receives and sends.
    pub fn widths(&self) -> (usize, usize) {
        let in_bits = self
            .process
            .iter()
            .filter(|r| r.is_in())
            .map(|r| r.bits as usize)
            .sum();
        let out_bits = self
            .process
            .iter()
            .filter(|r| r.is_out())
            .map(|r| r.bits as usize)
            .sum();
        (in_bits, out_bits)
    }
}

/// A port after discovery.
#[derive(Debug, Clone, PartialEq)]
pub struct PortFound {
    /// The port (module instance).
    pub index: u8,
    /// Its channels (from the pin descriptors).
    pub channels: u8,
    /// The processor's minor revision.
    pub revision: u8,
    /// The cards found, by channel.
    pub remotes: Vec<RemoteFound>,
    /// Found in setup mode (hostmot2's `sserial_baudrate=115200`): the
    /// cards are only named, for `setsserial`; the port gets no HAL
    /// objects and is never started in normal mode.
    pub setup: bool,
}

impl PortFound {
    /// Channels with a card, as a bit mask.
    pub fn mask(&self) -> u8 {
        self.remotes.iter().fold(0, |m, r| m | 1 << r.channel)
    }
}

/// What discovery found on every port in use.
#[derive(Debug, Clone, PartialEq)]
pub struct SserialFirmware {
    /// The module's descriptor.
    pub md: ModuleDescriptor,
    /// The ports in use (the first `num_sserials`), in order.
    pub ports: Vec<PortFound>,
}

impl SserialFirmware {
    /// Channels with a card on each port (for pin allocation).
    pub fn masks(&self) -> [u8; crate::sserial::MAX_PORTS] {
        let mut m = [0u8; crate::sserial::MAX_PORTS];
        for p in &self.ports {
            if let Some(slot) = m.get_mut(p.index as usize) {
                *slot = p.mask();
            }
        }
        m
    }
}

/// How long each kind of command may take (LinuxCNC's budgets).
mod budget {
    use std::time::Duration;
    pub const RESET: Duration = Duration::from_millis(1007);
    pub const STOP: Duration = Duration::from_millis(51);
    pub const START: Duration = Duration::from_millis(8000);
    pub const LOCAL: Duration = Duration::from_millis(22);
    pub const DOIT: Duration = Duration::from_millis(51);
}

/// An error of discovery, before the port and channel are added.
enum Fail {
    Hm2(Hm2Error),
    Record(RecordError),
}

impl From<Hm2Error> for Fail {
    fn from(e: Hm2Error) -> Fail {
        Fail::Hm2(e)
    }
}

impl From<RecordError> for Fail {
    fn from(e: RecordError) -> Fail {
        Fail::Record(e)
    }
}

/// One port's registers.
struct Port<'a> {
    t: &'a mut dyn Transport,
    md: ModuleDescriptor,
    index: u8,
}

impl Port<'_> {
    fn addr(&self, r: usize, chan: usize) -> u32 {
        self.md.inst_reg(r, self.index as usize) + 4 * chan as u32
    }

    fn read(&mut self, addr: u32) -> Result<u32> {
        let mut w = [0u32];
        self.t
            .read(addr, &mut w)
            .map_err(|source| Hm2Error::Transport {
                op: format!(
                    "error reading Smart Serial port {} (at 0x{addr:04X})",
                    self.index
                ),
                source,
            })?;
        Ok(w[0])
    }

    fn write(&mut self, addr: u32, v: u32) -> Result<()> {
        self.t
            .write(addr, &[v])
            .map_err(|source| Hm2Error::Transport {
                op: format!(
                    "error writing Smart Serial port {} (at 0x{addr:04X})",
                    self.index
                ),
                source,
            })
    }

    /// Writes a command and waits until the register reads 0.
    fn command(&mut self, c: u32, budget: Duration) -> Result<()> {
        let at = self.addr(reg::COMMAND, 0);
        self.write(at, c)?;
        let start = Instant::now();
        loop {
            if self.read(at)? == 0 {
                return Ok(());
            }
            if start.elapsed() > budget {
                return Err(Hm2Error::Sserial {
                    port: self.index,
                    channel: None,
                    reason: format!("command 0x{c:04X} not done after {} ms", budget.as_millis()),
                });
            }
            std::thread::sleep(Duration::from_micros(50));
        }
    }

    fn data(&mut self) -> Result<u32> {
        let at = self.addr(reg::DATA, 0);
        self.read(at)
    }

    fn read_local(&mut self, byte: u16) -> Result<u8> {
        self.command(cmd::READ_LOCAL | byte as u32, budget::LOCAL)?;
        Ok(self.data()? as u8)
    }

    /// One transfer on channel `c` in setup mode with CS = `op` << 24 |
    /// `addr` and interface 0 = `arg`; returns interfaces 0 and 1.
    fn transfer(&mut self, c: u8, op: u8, addr: u16, arg: u64) -> Result<u64> {
        let cs = self.addr(reg::CS, c as usize);
        self.write(cs, (op as u32) << 24 | addr as u32)?;
        if op & !3 == lbp::WRITE || op == lbp::NONVOLATILE {
            let i0 = self.addr(reg::INTERFACE0, c as usize);
            let i1 = self.addr(reg::INTERFACE0 + 1, c as usize);
            self.write(i0, arg as u32)?;
            self.write(i1, (arg >> 32) as u32)?;
        }
        self.command(cmd::DOIT | 1 << c, budget::DOIT)?;
        if self.data()? & (1 << c) != 0 {
            let st = self.read(cs)?;
            return Err(Hm2Error::Sserial {
                port: self.index,
                channel: Some(c),
                reason: format!(
                    "the card does not answer (status 0x{st:08X}: {})",
                    describe_status(st)
                ),
            });
        }
        let i0 = self.addr(reg::INTERFACE0, c as usize);
        let i1 = self.addr(reg::INTERFACE0 + 1, c as usize);
        Ok(self.read(i0)? as u64 | (self.read(i1)? as u64) << 32)
    }

    fn remote_byte(&mut self, c: u8, addr: u16) -> Result<u8> {
        Ok(self.transfer(c, lbp::READ_BYTE, addr, 0)? as u8)
    }
}

/// The words of the status bits set in `st`.
pub fn describe_status(st: u32) -> String {
    let words: Vec<&str> = (0..32)
        .filter(|b| st & (1 << b) != 0)
        .filter_map(status::describe)
        .collect();
    if words.is_empty() {
        "no error bit".into()
    } else {
        words.join(", ")
    }
}

/// The size code (0..3 for 1, 2, 4, 8 bytes) of a value of `bits`.
fn size_code(bits: u8) -> u8 {
    match bits {
        0..=8 => 0,
        9..=16 => 1,
        17..=32 => 2,
        _ => 3,
    }
}

/// Checks a card's process data: what the driver can move, and that it
/// fits the module's registers.
fn check_process(r: &RemoteFound) -> std::result::Result<(), Hm2Error> {
    for p in &r.process {
        let ok = match p.data_type {
            dt::PAD | dt::BITS | dt::BOOLEAN => p.bits > 0,
            dt::UNSIGNED | dt::SIGNED | dt::STREAM | dt::ENCODER => (1..=32).contains(&p.bits),
            dt::FLOAT => p.bits == 32 || p.bits == 64,
            dt::ENCODER_HIGH | dt::ENCODER_LOW => {
                return Err(Hm2Error::SplitEncoder {
                    record: p.name.clone(),
                })
            }
            t if records::data_type::is_nonvolatile(t) => {
                return Err(Hm2Error::NonVolatileInPtoc {
                    record: p.name.clone(),
                })
            }
            t => {
                return Err(Hm2Error::UnknownDataType {
                    record: p.name.clone(),
                    data_type: t,
                });
            }
        };
        if !ok {
            return Err(Hm2Error::BadRecordWidth {
                record: p.name.clone(),
                bits: p.bits,
            });
        }
    }
    let (i, o) = r.widths();
    if i > MAX_DATA_BITS || o > MAX_DATA_BITS {
        return Err(Hm2Error::ProcessTooWide {
            inputs: i,
            outputs: o,
            registers: reg::INTERFACES,
        });
    }
    Ok(())
}

/// Reads card `c`'s tables, records and globals.
fn read_card(
    p: &mut Port,
    found: &mut RemoteFound,
    ptoc: u16,
    gtoc: u16,
) -> std::result::Result<(), Fail> {
    let c = found.channel;
    let mut byte = |a: u16| -> std::result::Result<u8, Fail> { Ok(p.remote_byte(c, a)?) };
    for at in records::read_table(ptoc, &mut byte)? {
        match records::read_record(at, &mut byte)? {
            Record::Data(d) => found.process.push(d),
            Record::Mode(_) => {}
        }
    }
    let mut globals = Vec::new();
    if gtoc != 0 {
        for at in records::read_table(gtoc, &mut byte)? {
            match records::read_record(at, &mut byte)? {
                Record::Data(d) => {
                    if !found
                        .process
                        .iter()
                        .any(|pd| pd.addr == d.addr && d.addr != 0)
                    {
                        globals.push(d);
                    }
                }
                Record::Mode(m) => found.modes.push(m),
            }
        }
    }
    read_globals(p, found, globals)
}

/// Reads the values of card `found`'s `globals` (the non-volatile ones
/// from its EEPROM) into it.
fn read_globals(
    p: &mut Port,
    found: &mut RemoteFound,
    globals: Vec<DataRecord>,
) -> std::result::Result<(), Fail> {
    let c = found.channel;
    for g in globals {
        let nv = records::data_type::is_nonvolatile(g.data_type);
        if nv {
            p.transfer(c, lbp::NONVOLATILE, 0, 1)?;
        }
        let raw = p.transfer(c, lbp::READ + size_code(g.bits), g.addr, 0);
        if nv {
            p.transfer(c, lbp::NONVOLATILE, 0, 0)?;
        }
        let bits = g.bits.min(64) as u32;
        let mask = if bits >= 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        found.globals.push((g, raw? & mask));
    }
    Ok(())
}

/// Takes the built-in tables of a card that does not describe itself
/// and reads its globals; an 8I20's current scale is its own maximum
/// current, read from its memory.
fn read_built_in(
    p: &mut Port,
    found: &mut RemoteFound,
    mut b: legacy::BuiltIn,
) -> std::result::Result<(), Fail> {
    if found.raw_name.to_le_bytes() == legacy::EIGHT_I20 {
        let c = found.channel;
        let raw = p.transfer(c, lbp::READ + 1, legacy::EIGHT_I20_MAX_CURRENT_AT, 0)? as u16;
        let amps = raw as f32 * 0.01;
        if let Some(current) = b.process.get_mut(legacy::EIGHT_I20_CURRENT) {
            current.min = -amps;
            current.max = amps;
        }
    }
    found.process = b.process;
    found.built_in = true;
    read_globals(p, found, b.globals)
}

/// The I/O pins of `port`'s enabled channels: (io, is output).
fn channel_pins(
    pins: &[PinDescriptor],
    port: u8,
    modes: &[Option<u8>; MAX_CHANNELS],
) -> Vec<(usize, bool)> {
    pins.iter()
        .enumerate()
        .filter(|(_, d)| d.sec_tag == gtag::SSERIAL && d.sec_unit == port)
        .filter_map(|(io, d)| {
            let role = PinRole::of(d.sec_pin)?;
            let c = role.channel() as usize;
            (c < MAX_CHANNELS && modes[c].is_some()).then_some((io, d.is_output()))
        })
        .collect()
}

/// The channels of `port`: the highest channel any of its pins serves.
pub fn channels_of(pins: &[PinDescriptor], port: u8) -> u8 {
    pins.iter()
        .filter(|d| d.sec_tag == gtag::SSERIAL && d.sec_unit == port)
        .filter_map(|d| PinRole::of(d.sec_pin))
        .map(|r| r.channel() + 1)
        .max()
        .unwrap_or(0)
        .min(MAX_CHANNELS as u8)
}

/// Writes `ALT_SOURCE` and `DDR` of every IOPort instance: the pins in
/// `route` to the module, its outputs as outputs (or all zero).
fn route_pins(
    t: &mut dyn Transport,
    ioport: &ModuleDescriptor,
    port_width: u32,
    route: &[(usize, bool)],
) -> Result<()> {
    let n = ioport.instances as usize;
    let mut alt = vec![0u32; n];
    let mut ddr = vec![0u32; n];
    for &(pin, output) in route {
        let (k, bit) = (pin / port_width as usize, pin % port_width as usize);
        if k < n && bit < 32 {
            alt[k] |= 1 << bit;
            if output {
                ddr[k] |= 1 << bit;
            }
        }
    }
    let op = |what: &str| format!("error routing the Smart Serial pins ({what})");
    t.write(ioport.reg(io::ALT_SOURCE), &alt)
        .map_err(|source| Hm2Error::Transport {
            op: op("AltSource"),
            source,
        })?;
    t.write(ioport.reg(io::DDR), &ddr)
        .map_err(|source| Hm2Error::Transport {
            op: op("DDR"),
            source,
        })
}

/// What discovery needs to know about the board.
pub struct Setup<'a> {
    /// The Smart Serial module's descriptor.
    pub md: ModuleDescriptor,
    /// Ports to use (the first ones).
    pub ports: u32,
    /// The IOPort module's descriptor (to route the channel pins).
    pub ioport: ModuleDescriptor,
    /// Pins per connector.
    pub port_width: u32,
    /// Every pin descriptor.
    pub pins: &'a [PinDescriptor],
    /// The config string (channel modes).
    pub config: &'a Config,
    /// A baud rate to set on every channel, if asked.
    pub baudrate: Option<u32>,
}

/// The baud rate that puts discovery in setup mode (LinuxCNC's choice:
/// the rate remote cards are reflashed at).
pub const SETUP_BAUD: u32 = 115_200;

/// A card found in setup mode: any Mesa card (an `I` as the second
/// character of its name), taken as it answers, with no records read.
fn setup_remote(
    port: u8,
    channel: u8,
    mode: u8,
    ids: [u32; 3],
    log: &mut MessageLog,
) -> Option<RemoteFound> {
    if ids[1].to_le_bytes()[1] != b'I' {
        return None;
    }
    let found = RemoteFound {
        channel,
        mode,
        unit: ids[0],
        raw_name: ids[1],
        process: Vec::new(),
        globals: Vec::new(),
        modes: Vec::new(),
        built_in: false,
    };
    log.info(format!(
        "Smart Serial port {port} channel {channel}: {} (unit 0x{:08X}) in setup mode: no pins made, the port is not started",
        found.name(),
        found.unit
    ));
    Some(found)
}

/// Finds the cards on the ports in use.
pub fn discover(t: &mut dyn Transport, s: &Setup, log: &mut MessageLog) -> Result<SserialFirmware> {
    let mut out = Vec::new();
    let md = s.md;
    for index in 0..s.ports.min(crate::sserial::MAX_PORTS as u32) as u8 {
        let modes = s.config.sserial_modes(index as usize);
        let channels = channels_of(s.pins, index);
        let route = channel_pins(s.pins, index, &modes);
        route_pins(t, &s.ioport, s.port_width, &route)?;
        let found = discover_port(t, &md, index, channels, &modes, s.baudrate, log);
        let stopped = Port { t, md, index }.command(cmd::STOP, budget::STOP);
        route_pins(t, &s.ioport, s.port_width, &[])?;
        let found = found?;
        stopped?;
        out.push(found);
    }
    Ok(SserialFirmware { md, ports: out })
}

fn discover_port(
    t: &mut dyn Transport,
    md: &ModuleDescriptor,
    index: u8,
    channels: u8,
    modes: &[Option<u8>; MAX_CHANNELS],
    baudrate: Option<u32>,
    log: &mut MessageLog,
) -> Result<PortFound> {
    let mut p = Port { t, md: *md, index };
    p.command(cmd::RESET, budget::RESET)?;
    let mut revision = p.read_local(local::MINOR_REV)?;
    for _ in 0..10 {
        if revision != 0xAA {
            break;
        }
        revision = p.read_local(local::MINOR_REV)?;
    }
    log.info(format!("Smart Serial Firmware Version {revision}"));
    if let Some(baud) = baudrate {
        let start = p.read_local(local::CHANNEL_START)? as u16;
        let stride = p.read_local(local::CHANNEL_STRIDE)? as u16;
        for c in 0..channels as u16 {
            for (k, b) in baud.to_le_bytes().iter().enumerate() {
                let at = start + c * stride + local::BAUD_RATE + k as u16;
                let data = p.addr(reg::DATA, 0);
                p.write(data, *b as u32)?;
                p.command(cmd::WRITE_LOCAL | at as u32, budget::LOCAL)?;
            }
        }
        log.info(format!(
            "Smart Serial port {index}: baud rate set to {baud}"
        ));
    }
    let setup = baudrate == Some(SETUP_BAUD);
    p.command(cmd::STOP, budget::STOP)?;
    let mut mask = 0u32;
    for c in 0..channels {
        if let Some(m) = modes[c as usize] {
            let cs = p.addr(reg::CS, c as usize);
            p.write(cs, (m as u32) << 24)?;
            mask |= 1 << c;
        }
    }
    let mut remotes = Vec::new();
    if mask != 0 {
        p.command(cmd::START_SETUP | mask, budget::START)?;
        let failed = p.data()?;
        for c in (0..channels).filter(|c| mask & (1 << c) != 0) {
            let mode = modes[c as usize].unwrap_or(0);
            if failed & (1 << c) != 0 {
                let st = p.read(p.addr(reg::CS, c as usize))?;
                if st & status::ILLEGAL_MODE != 0 {
                    return Err(Hm2Error::Sserial {
                        port: index,
                        channel: Some(c),
                        reason: format!("the card has no mode {mode} (sserial_port_{index})"),
                    });
                }
                continue;
            }
            let mut ids = [0u32; 3];
            for (k, w) in ids.iter_mut().enumerate() {
                *w = p.read(p.addr(reg::INTERFACE0 + k, c as usize))?;
            }
            let (ptoc, gtoc) = (ids[2] as u16, (ids[2] >> 16) as u16);
            if setup {
                if let Some(found) = setup_remote(index, c, mode, ids, log) {
                    remotes.push(found);
                }
                continue;
            }
            let mut found = RemoteFound {
                channel: c,
                mode,
                unit: ids[0],
                raw_name: ids[1],
                process: Vec::new(),
                globals: Vec::new(),
                modes: Vec::new(),
                built_in: false,
            };
            let context = |reason: String| Hm2Error::Sserial {
                port: index,
                channel: Some(c),
                reason,
            };
            let built_in = (ptoc == 0 && gtoc == 0)
                .then(|| legacy::built_in(ids[1]))
                .flatten();
            let read = match built_in {
                Some(b) => read_built_in(&mut p, &mut found, b),
                None if ptoc == 0 => {
                    if ids[1] != 0 {
                        log.warn(format!(
                            "Smart Serial port {index} channel {c}: {} describes no process data and is not a card this driver knows: its pins stay GPIO",
                            found.name()
                        ));
                    }
                    continue;
                }
                None => read_card(&mut p, &mut found, ptoc, gtoc),
            };
            match read {
                Ok(()) => {}
                Err(Fail::Hm2(e)) => return Err(e),
                Err(Fail::Record(e)) => return Err(context(e.to_string())),
            }
            check_process(&found).map_err(|e| context(e.to_string()))?;
            log.info(format!(
                "Smart Serial port {index} channel {c}: {} (unit 0x{:08X}) in mode {mode}",
                found.name(),
                found.unit
            ));
            for m in &found.modes {
                log.info(format!(
                    "Board {} {} Mode {} = {}",
                    found.name(),
                    if m.software { "Software" } else { "Hardware" },
                    m.index,
                    m.name
                ));
            }
            if let Some((_, v)) = found
                .globals
                .iter()
                .find(|(g, _)| g.name.eq_ignore_ascii_case("swrevision"))
            {
                if *v < 14 {
                    log.warn(format!(
                        "Warning: sserial remote device {} on port {index} channel {c} has old firmware (revision {v}) that should be updated",
                        found.name()
                    ));
                }
            }
            remotes.push(found);
        }
    }
    Ok(PortFound {
        index,
        channels,
        revision,
        remotes,
        setup,
    })
}
