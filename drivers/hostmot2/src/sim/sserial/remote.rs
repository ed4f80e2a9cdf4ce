//! Simulated Smart Serial remote cards: the 7I76 (32 inputs, 16 outputs,
//! spindle DAC), the two channels of the 7I77 (I/O; six analog
//! outputs with enables) and the 8I20 drive.
//!
//! The 8I20 predates self-description: it names no tables, its globals
//! sit where LinuxCNC's built-in table ([`legacy`]) says, and its power
//! stage is modelled in [`super::eight_i20`].
//!
//! Each describes itself as a real card does: a unit number, a name, and
//! records in its memory (modes and globals in the GTOC, process data in
//! one PTOC per mode), laid out so that Mesa's own tool reads them as it
//! reads the cards (mesaflash `--sserial`, hostmot2-more.md 3.4):
//!
//! * every record is stored once; the PTOCs of the modes point at the
//!   same record for an element they share;
//! * each process-data element has its place in the card's memory
//!   (ParmAddr, from [`PROCESS_AT`] on), as a global has;
//! * the globals are `SwRevision` (16 bits), `NVUnitNumber` (32 bits)
//!   and the 16-bit `NVBaudRate` (an index into
//!   [`BAUD_RATES`](crate::sserial::BAUD_RATES), 2.5 Mbaud by default)
//!   and `NVWatchDogTimeout` (ms, 50 by default), each at an even
//!   address from [`PARAMS_AT`] on: mesaflash reads the last two as
//!   16-bit values and indexes its table of baud rates with the first;
//! * a unitless record says `None`, as the cards' records do (mesaflash
//!   looks for that word).
//!
//! Names and modes are the cards'; the widths and ranges of the process
//! data are chosen to fit 96 bits each way (no source read documents
//! them, hostmot2-more.md 2.10).
//!
//! | remote | modes | process data (mode-dependent part in brackets) |
//! |---|---|---|
//! | 7I76 | 0 `io_spin`, 1 `io_ana_spin`, 2 `io_enc_ana_spin_fv` | out: `Output` 16 bits, `SpinOut` 0..10 V (16 bits), `SpinEna`, `SpinDir`; in: `Input` 32 bits [1, 2: `AnalogIn0..3` 0..36 V (8 bits); 2: `FieldVoltage`, encoders `MPG0`, `MPG1` (8 bits)] |
//! | 7I77 I/O | 0 `input_output`, 1 `io_analog`, 2 `io_analog_fieldvoltage`, 3 `io_encoder_analog_fieldvoltage` | out: `Output` 16 bits; in: `Input` 32 bits [≥ 1: `AnalogIn0..3`; ≥ 2: `FieldVoltage`; 3: `MPG0`, `MPG1`] |
//! | 7I77 analog | 0 `analogout_enables` | out: `AnalogOut0..5` −10..10 V (13 bits signed), `AnalogEna`, `SpinEna` |
//!
//! The card's watchdog turns every output off when no process data came
//! for `NVWatchDogTimeout` while it runs, and reports it in its status
//! until it is started again. A card whose cable is pulled
//! ([`SimRemote::connected`] false) answers nothing.

use super::eight_i20::EightI20;
mod eight_i20_card;

use crate::sserial::data;
use crate::sserial::legacy;
use crate::sserial::records::{data_type as t, dir, encode_table, DataRecord, ModeRecord};
use crate::sserial::{remote_type, status};

/// Which card.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RemoteKind {
    /// 7I76.
    SevenI76,
    /// 7I77, its I/O channel.
    SevenI77Io,
    /// 7I77, its analog channel.
    SevenI77Analog,
    /// 8I20 drive (no self-description: [`legacy`]).
    EightI20,
}

/// A remote card on a port's channel, for a firmware description.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RemoteSpec {
    /// The Smart Serial port (instance).
    pub port: u8,
    /// The channel.
    pub channel: u8,
    /// The card.
    pub kind: RemoteKind,
    /// Its unit (serial) number, low 24 bits.
    pub unit: u32,
}

/// Where the records and tables start in the card's memory.
const RECORDS_AT: u16 = 0x10;
/// Where the process-data values live in the card's memory.
pub const PROCESS_AT: u16 = 0x500;
/// Where the global values live in the card's memory.
pub const PARAMS_AT: u16 = 0x600;
/// Size of the card's memory.
const MEMORY: usize = 0x800;
/// `NVBaudRate` of a new card: index 9 of
/// [`BAUD_RATES`](crate::sserial::BAUD_RATES), 2.5 Mbaud, the rate Mesa's
/// cards ship with.
pub const DEFAULT_BAUD_INDEX: u32 = 9;
/// "No unit", as the cards spell it.
const NO_UNIT: &str = "None";

fn rec(bits: u8, ty: u8, d: u8, min: f32, max: f32, unit: &str, name: &str) -> DataRecord {
    DataRecord {
        bits,
        data_type: ty,
        dir: d,
        min,
        max,
        addr: 0,
        unit: unit.into(),
        name: name.into(),
    }
}

fn analog_ins() -> Vec<DataRecord> {
    (0..4)
        .map(|k| {
            rec(
                8,
                t::UNSIGNED,
                dir::IN,
                0.0,
                36.0,
                "V",
                &format!("AnalogIn{k}"),
            )
        })
        .collect()
}

fn field_voltage() -> DataRecord {
    rec(8, t::UNSIGNED, dir::IN, 0.0, 36.0, "V", "FieldVoltage")
}

fn mpgs() -> Vec<DataRecord> {
    (0..2)
        .map(|k| {
            rec(
                8,
                t::ENCODER,
                dir::IN,
                0.0,
                1.0,
                "count",
                &format!("MPG{k}"),
            )
        })
        .collect()
}

impl RemoteKind {
    /// The card's type code and name.
    fn identity(self) -> (u8, [u8; 4]) {
        match self {
            RemoteKind::SevenI76 => (remote_type::SEVEN_I76, *b"7I76"),
            RemoteKind::SevenI77Io => (remote_type::SEVEN_I77_IO, *b"7I77"),
            RemoteKind::SevenI77Analog => (remote_type::SEVEN_I77_ANALOG, *b"7I77"),
            RemoteKind::EightI20 => (0, legacy::EIGHT_I20),
        }
    }

    /// Its software modes.
    pub fn modes(self) -> &'static [&'static str] {
        match self {
            RemoteKind::SevenI76 => &["io_spin", "io_ana_spin", "io_enc_ana_spin_fv"],
            RemoteKind::SevenI77Io => &[
                "input_output",
                "io_analog",
                "io_analog_fieldvoltage",
                "io_encoder_analog_fieldvoltage",
            ],
            RemoteKind::SevenI77Analog => &["analogout_enables"],
            RemoteKind::EightI20 => &[],
        }
    }

    /// The process data of `mode`, in wire order.
    pub fn process_data(self, mode: u8) -> Vec<DataRecord> {
        let mut v = Vec::new();
        match self {
            RemoteKind::EightI20 => {
                let raw = u32::from_le_bytes(legacy::EIGHT_I20);
                v = legacy::built_in(raw).map(|b| b.process).unwrap_or_default();
            }
            RemoteKind::SevenI76 => {
                v.push(rec(16, t::BITS, dir::OUT, 0.0, 0.0, NO_UNIT, "Output"));
                v.push(rec(16, t::UNSIGNED, dir::OUT, 0.0, 10.0, "V", "SpinOut"));
                v.push(rec(1, t::BOOLEAN, dir::OUT, 0.0, 0.0, NO_UNIT, "SpinEna"));
                v.push(rec(1, t::BOOLEAN, dir::OUT, 0.0, 0.0, NO_UNIT, "SpinDir"));
                v.push(rec(32, t::BITS, dir::IN, 0.0, 0.0, NO_UNIT, "Input"));
                if mode >= 1 {
                    v.extend(analog_ins());
                }
                if mode >= 2 {
                    v.push(field_voltage());
                    v.extend(mpgs());
                }
            }
            RemoteKind::SevenI77Io => {
                v.push(rec(16, t::BITS, dir::OUT, 0.0, 0.0, NO_UNIT, "Output"));
                v.push(rec(32, t::BITS, dir::IN, 0.0, 0.0, NO_UNIT, "Input"));
                if mode >= 1 {
                    v.extend(analog_ins());
                }
                if mode >= 2 {
                    v.push(field_voltage());
                }
                if mode >= 3 {
                    v.extend(mpgs());
                }
            }
            RemoteKind::SevenI77Analog => {
                for k in 0..6 {
                    v.push(rec(
                        13,
                        t::SIGNED,
                        dir::OUT,
                        -10.0,
                        10.0,
                        "V",
                        &format!("AnalogOut{k}"),
                    ));
                }
                v.push(rec(1, t::BOOLEAN, dir::OUT, 0.0, 0.0, NO_UNIT, "AnalogEna"));
                v.push(rec(1, t::BOOLEAN, dir::OUT, 0.0, 0.0, NO_UNIT, "SpinEna"));
            }
        }
        v
    }
}

/// A process-data field's place and value.
#[derive(Debug, Clone)]
struct Field {
    record: DataRecord,
    /// Physical value (bit fields: the bits as an integer).
    value: f64,
    /// Encoders: the count.
    count: i64,
}

/// One mode's process data.
#[derive(Debug, Clone)]
struct Mode {
    ptoc: u16,
    fields: Vec<Field>,
}

impl Mode {
    /// A mode at `ptoc` moving `records`, every value 0.
    fn new(ptoc: u16, records: Vec<DataRecord>) -> Mode {
        Mode {
            ptoc,
            fields: records
                .into_iter()
                .map(|record| Field {
                    record,
                    value: 0.0,
                    count: 0,
                })
                .collect(),
        }
    }
}

/// A simulated remote card.
#[derive(Debug, Clone)]
pub struct SimRemote {
    kind: RemoteKind,
    unit: u32,
    memory: Vec<u8>,
    gtoc: u16,
    modes: Vec<Mode>,
    mode: Option<u8>,
    running: bool,
    nonvolatile: bool,
    /// Setup-mode accesses go to the flash (flash access mode).
    flash_mode: bool,
    /// Its firmware flash.
    pub flash: super::flash::SimFlash,
    /// Each global: name, address, bits.
    params: Vec<(String, u16, u8)>,
    quiet_ns: u64,
    tripped: bool,
    /// The cable: a card not connected answers nothing.
    pub connected: bool,
    /// Transfers of process data received.
    pub transfers: u64,
    /// Writes to its EEPROM.
    pub eeprom_writes: u64,
    /// A card that answers every setup start with these words.
    fixed_ids: Option<[u32; 3]>,
    /// An 8I20's power stage.
    pub drive: Option<EightI20>,
}

/// The card's globals: (record, initial value).
fn globals(unit: u32) -> Vec<(DataRecord, u32)> {
    let nv = |bits, max, unit, name| rec(bits, t::NV_UNSIGNED, dir::BOTH, 0.0, max, unit, name);
    vec![
        (
            rec(
                16,
                t::UNSIGNED,
                dir::IN,
                0.0,
                65535.0,
                NO_UNIT,
                "SwRevision",
            ),
            22,
        ),
        (nv(32, 0.0, NO_UNIT, "NVUnitNumber"), unit),
        (nv(16, 11.0, NO_UNIT, "NVBaudRate"), DEFAULT_BAUD_INDEX),
        (nv(16, 65535.0, "ms", "NVWatchDogTimeout"), 50),
    ]
}

/// The card's memory as it is being laid out: records and tables from
/// [`RECORDS_AT`] upward, each record once.
struct Layout {
    memory: Vec<u8>,
    at: usize,
    /// Where each process-data record went, by name.
    placed: Vec<(String, u16)>,
}

impl Layout {
    fn new() -> Layout {
        Layout {
            memory: vec![0u8; MEMORY],
            at: RECORDS_AT as usize,
            placed: Vec::new(),
        }
    }

    /// Stores `bytes` at the next free address, returning it.
    fn place(&mut self, bytes: &[u8]) -> u16 {
        let here = self.at;
        self.memory[here..here + bytes.len()].copy_from_slice(bytes);
        self.at += bytes.len();
        here as u16
    }

    /// The address of process-data record `r`, stored on first use.
    fn place_shared(&mut self, r: &DataRecord) -> u16 {
        if let Some((_, a)) = self.placed.iter().find(|(n, _)| *n == r.name) {
            return *a;
        }
        let a = self.place(&r.encode());
        self.placed.push((r.name.clone(), a));
        a
    }
}

/// Gives each process-data element of every mode its place in the
/// card's memory: an element the modes share has one place.
fn place_process_data(modes: &mut [Vec<DataRecord>]) {
    let mut places: Vec<(String, u16)> = Vec::new();
    let mut next = PROCESS_AT;
    for r in modes.iter_mut().flatten() {
        r.addr = match places.iter().find(|(n, _)| *n == r.name) {
            Some((_, a)) => *a,
            None => {
                let a = next;
                next += (r.bits as u16).div_ceil(8).max(1);
                places.push((r.name.clone(), a));
                a
            }
        };
    }
}

impl SimRemote {
    /// A card of `kind` with unit number `unit` (low 24 bits).
    pub fn new(kind: RemoteKind, unit: u32) -> SimRemote {
        let (code, _) = kind.identity();
        let unit = (code as u32) << 24 | (unit & 0x00FF_FFFF);
        if kind == RemoteKind::EightI20 {
            return Self::eight_i20(unit);
        }
        let mut layout = Layout::new();
        // Globals and modes, then the GTOC; globals at even addresses.
        let mut gtoc_entries = Vec::new();
        let mut param_at = PARAMS_AT;
        let mut initial = Vec::new();
        let mut params = Vec::new();
        for (mut r, v) in globals(unit) {
            r.addr = param_at;
            initial.push((param_at, r.bits, v));
            params.push((r.name.clone(), param_at, r.bits));
            param_at += (r.bits as u16).div_ceil(8).next_multiple_of(2);
            gtoc_entries.push(layout.place(&r.encode()));
        }
        for (i, name) in kind.modes().iter().enumerate() {
            let m = ModeRecord {
                index: i as u8,
                software: true,
                name: name.to_string(),
            };
            gtoc_entries.push(layout.place(&m.encode()));
        }
        let gtoc = layout.place(&encode_table(&gtoc_entries));
        let mut per_mode: Vec<Vec<DataRecord>> = (0..kind.modes().len())
            .map(|i| kind.process_data(i as u8))
            .collect();
        place_process_data(&mut per_mode);
        let mut modes = Vec::new();
        for records in per_mode {
            let entries: Vec<u16> = records.iter().map(|r| layout.place_shared(r)).collect();
            let ptoc = layout.place(&encode_table(&entries));
            modes.push(Mode::new(ptoc, records));
        }
        let mut memory = layout.memory;
        for (a, bits, v) in initial {
            let n = (bits as usize).div_ceil(8);
            memory[a as usize..a as usize + n].copy_from_slice(&v.to_le_bytes()[..n]);
        }
        SimRemote {
            kind,
            unit,
            memory,
            gtoc,
            modes,
            mode: None,
            running: false,
            nonvolatile: false,
            flash_mode: false,
            flash: super::flash::SimFlash::default(),
            params,
            quiet_ns: 0,
            tripped: false,
            connected: true,
            transfers: 0,
            eeprom_writes: 0,
            fixed_ids: None,
            drive: None,
        }
    }

    /// A card that says whatever `ids` and `memory` say (fuzzing the
    /// driver's discovery): unit, name, GTOC << 16 | PTOC, and the bytes
    /// its tables and records are read from (zeros past the end).
    pub fn hostile(ids: [u32; 3], memory: Vec<u8>) -> SimRemote {
        let mut r = SimRemote::new(RemoteKind::SevenI76, 0);
        r.memory = memory;
        r.fixed_ids = Some(ids);
        r
    }

    /// Which card it is.
    pub fn kind(&self) -> RemoteKind {
        self.kind
    }

    /// The interface registers after a setup start in `mode`: unit,
    /// name, GTOC << 16 | PTOC; `None` if the card has no such mode.
    pub fn identify(&mut self, mode: u8) -> Option<[u32; 3]> {
        if let Some(ids) = self.fixed_ids {
            return Some(ids);
        }
        let m = self.modes.get(mode as usize)?;
        self.mode = Some(mode);
        self.running = false;
        let (_, name) = self.kind.identity();
        Some([
            self.unit,
            u32::from_le_bytes(name),
            (self.gtoc as u32) << 16 | m.ptoc as u32,
        ])
    }

    /// Starts process data in `mode`; false if the card has no such mode.
    pub fn start(&mut self, mode: u8) -> bool {
        if (mode as usize) >= self.modes.len() {
            return false;
        }
        self.mode = Some(mode);
        self.running = true;
        self.tripped = false;
        self.quiet_ns = 0;
        if let Some(d) = self.drive.as_mut() {
            d.restart();
        }
        true
    }

    /// Stops process data (the watchdog keeps counting).
    pub fn stop(&mut self) {
        self.running = false;
    }

    /// Bytes of its memory (a setup-mode read).
    pub fn read_memory(&self, addr: u16, n: usize) -> u64 {
        if self.flash_mode {
            return self.flash.read(addr, n);
        }
        let mut v = [0u8; 8];
        for (i, b) in v.iter_mut().enumerate().take(n.min(8)) {
            *b = self.memory.get(addr as usize + i).copied().unwrap_or(0);
        }
        u64::from_le_bytes(v)
    }

    /// A setup-mode write of `n` bytes.
    pub fn write_memory(&mut self, addr: u16, n: usize, v: u64) {
        if self.flash_mode {
            return self.flash.write(addr, n, v);
        }
        if self.nonvolatile {
            self.eeprom_writes += 1;
        }
        for i in 0..n.min(8) {
            if let Some(b) = self.memory.get_mut(addr as usize + i) {
                *b = (v >> (8 * i)) as u8;
            }
        }
    }

    /// The non-volatile access command: setup-mode accesses go to RAM
    /// (0), the EEPROM (1) or the flash (2).
    pub fn set_nonvolatile(&mut self, which: u32) {
        self.nonvolatile = which == 1;
        self.flash_mode = which == 2;
    }

    /// A global's value, by the card's name of it.
    pub fn global(&self, name: &str) -> Option<u32> {
        let (_, addr, bits) = self.params.iter().find(|(n, _, _)| n == name)?;
        Some(self.read_memory(*addr, (*bits as usize).div_ceil(8)) as u32)
    }

    /// Sets a global, by the card's name of it (as a write to its
    /// EEPROM would); false if the card has no such global.
    pub fn set_global(&mut self, name: &str, v: u32) -> bool {
        let Some(&(_, addr, bits)) = self.params.iter().find(|(n, _, _)| n == name) else {
            return false;
        };
        let n = (bits as usize).div_ceil(8);
        for (i, b) in v.to_le_bytes().iter().enumerate().take(n) {
            if let Some(m) = self.memory.get_mut(addr as usize + i) {
                *m = *b;
            }
        }
        true
    }

    fn watchdog_ns(&self) -> u64 {
        self.global("NVWatchDogTimeout").unwrap_or(50) as u64 * 1_000_000
    }

    fn fields(&self) -> &[Field] {
        self.mode
            .and_then(|m| self.modes.get(m as usize))
            .map_or(&[], |m| &m.fields)
    }

    fn fields_mut(&mut self) -> &mut [Field] {
        match self.mode {
            Some(m) => self
                .modes
                .get_mut(m as usize)
                .map_or(&mut [], |m| &mut m.fields),
            None => &mut [],
        }
    }

    /// A process-data field's value in the running mode (bit fields as
    /// integers, encoders as counts), by the card's name of it.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.fields()
            .iter()
            .find(|f| f.record.name == name)
            .map(|f| {
                if f.record.data_type == t::ENCODER {
                    f.count as f64
                } else {
                    f.value
                }
            })
    }

    /// Sets an input field (what the card senses), by name.
    pub fn set_value(&mut self, name: &str, v: f64) -> bool {
        match self.fields_mut().iter_mut().find(|f| f.record.name == name) {
            Some(f) => {
                if f.record.data_type == t::ENCODER {
                    f.count = v as i64;
                } else {
                    f.value = v;
                }
                true
            }
            None => false,
        }
    }

    /// Whether its watchdog turned the outputs off.
    pub fn watchdog_tripped(&self) -> bool {
        self.tripped
    }

    /// Its status bits (reported in the channel's CS register).
    pub fn status(&self) -> u32 {
        let drive = self.drive.as_ref().map_or(0, EightI20::cs_status);
        if self.tripped {
            status::WATCHDOG | status::REMOTE_FAULT | drive
        } else {
            drive
        }
    }

    /// One process-data transfer: takes the host's stream from `out`,
    /// answers with its own in `back`.
    pub fn transfer(&mut self, out: &[u32], back: &mut [u32]) {
        self.transfers += 1;
        self.quiet_ns = 0;
        let tripped = self.tripped;
        let mut at_out = 0;
        let mut at_in = 0;
        back.fill(0);
        for f in self.fields_mut() {
            let r = &f.record;
            let len = r.bits as usize;
            if r.is_out() {
                let raw = data::get_bits(out, at_out, len);
                at_out += len;
                if !tripped {
                    f.value = match r.data_type {
                        t::UNSIGNED => data::unsigned_value(raw, r.bits, r.max as f64),
                        t::SIGNED => data::signed_value(raw, r.bits, r.max as f64),
                        t::BOOLEAN => (raw != 0) as u8 as f64,
                        _ => raw as f64,
                    };
                }
            }
        }
        if !tripped {
            self.run_drive();
        }
        for f in self.fields_mut() {
            let r = &f.record;
            let len = r.bits as usize;
            if r.is_in() {
                let raw = match r.data_type {
                    t::UNSIGNED => data::unsigned_raw(
                        f.value,
                        r.bits,
                        r.max as f64,
                        r.min as f64,
                        r.max as f64,
                    ),
                    t::SIGNED => {
                        data::signed_raw(f.value, r.bits, r.max as f64, r.min as f64, r.max as f64)
                    }
                    t::ENCODER => f.count as u64,
                    t::BOOLEAN => (f.value != 0.0) as u64,
                    _ => f.value as u64,
                };
                data::put_bits(back, at_in, len, raw);
                at_in += len;
            }
        }
    }

    /// Lets `dt_ns` pass: without process data for the watchdog's time
    /// a running card turns every output off.
    pub fn advance(&mut self, dt_ns: u64) {
        if let Some(d) = self.drive.as_mut() {
            d.advance(dt_ns);
        }
        if self.mode.is_none() || self.tripped || !(self.running || self.transfers > 0) {
            return;
        }
        self.quiet_ns = self.quiet_ns.saturating_add(dt_ns);
        if self.quiet_ns > self.watchdog_ns() {
            self.tripped = true;
            for f in self.fields_mut() {
                if f.record.is_out() {
                    f.value = 0.0;
                }
            }
            if let Some(d) = self.drive.as_mut() {
                d.watchdog();
            }
            self.run_drive_report();
        }
    }
}

#[cfg(test)]
mod tests;
