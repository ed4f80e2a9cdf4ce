//! A register-level simulator of a PC parallel port (hardware.md 2.5).
//!
//! The model keeps the output latches and resolves the 17 signal lines of
//! the DB-25 connector from three kinds of sources:
//!
//! * the port's own drivers: data pins 2..9 are push-pull outputs while
//!   control bit 5 is clear; control pins 1, 14, 16, 17 are open-collector
//!   (they only pull low; a released line floats high) or push-pull,
//!   chosen at construction;
//! * the outside world ("plant"): [`SimPort::drive`] pulls a pin high or
//!   low, or leaves it floating;
//! * an optional loopback [`Plug`] that joins pins into nets.
//!
//! A net is low if anything on it pulls low, else high if anything drives
//! it high, else high (the port's pull-ups). Registers read as hardware
//! does: data returns the latch in output mode and the line levels in input
//! mode; status bits 3..7 are pins 15, 13, 12, 10 and NOT 11, bits 0..2
//! read 1; control returns the latch, except that with open-collector lines
//! bits 0..3 encode the actual line levels (so `x` mode can read them).
//! EPP registers (`base+3..7`) and the ECP window (`base_hi+0..2`) store
//! what is written without side effects.
//!
//! The model is a [`PortModel`] inside the driver layer's [`SimBoard`],
//! so [`SimPort`] reaches it through the same port bus as the raw
//! backend. Every register write is logged in the board's [`AccessLog`]
//! with a timestamp from the port's [`Clock`], so tests can check that
//! the driver writes only on change and that `reset` writes no earlier
//! than `reset-time` after `write`. The log keeps the newest writes in a
//! buffer allocated up front; accessors never allocate, and the model's
//! lock is the board's (uncontended: only tests and tools take it
//! besides the driver).

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;

use hal_driver::bus::PortBus;
use hal_driver::sim::{AccessLog, BoardModel, PortModel, SimBoard, Width};

use crate::clock::Clock;
use crate::port::{PortAt, PortError, PortIo};
use crate::regs::{self, PinReg};

/// What the outside world does to one pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    /// Nothing connected.
    Floating,
    /// Driven high.
    High,
    /// Pulled low.
    Low,
}
/// A loopback plug: wires that join connector pins.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plug {
    wires: Vec<(u8, u8)>,
}

impl Plug {
    /// A plug with the given wires (pin pairs, 1..17).
    pub fn new(wires: &[(u8, u8)]) -> Plug {
        Plug {
            wires: wires.to_vec(),
        }
    }

    /// The hal_parport test plug, used by the `simloop` backend:
    ///
    /// | wires | purpose |
    /// |---|---|
    /// | 2–15, 3–13, 4–12, 5–10, 6–11 | the common 25-pin loopback wiring: data D0..D4 to the five status inputs (`out` mode reads its own data back) |
    /// | 7–1, 8–14, 9–16, 6–17 | this project's extension: data D5..D7 and D4 to the four control lines, so `x` mode reads data outputs on its control inputs and `in` mode reads the control outputs on data inputs |
    ///
    /// The control lines share nets with data outputs, so this plug needs
    /// open-collector control lines (as `x` mode does); the simulator
    /// always builds `simloop` ports that way.
    pub fn loopback() -> Plug {
        Plug::new(&[
            (2, 15),
            (3, 13),
            (4, 12),
            (5, 10),
            (6, 11),
            (7, 1),
            (8, 14),
            (9, 16),
            (6, 17),
        ])
    }

    /// The wires.
    pub fn wires(&self) -> &[(u8, u8)] {
        &self.wires
    }
}

/// How to build a simulated port.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// Base I/O address (the data register).
    pub base: u16,
    /// Address of the ECP registers, normally `base + 0x400`.
    pub base_hi: Option<u16>,
    /// Whether control lines are open-collector (needed by `x` mode).
    pub open_collector: bool,
    /// A loopback plug in the connector.
    pub plug: Option<Plug>,
    /// How many register writes the log keeps (the newest).
    pub log_capacity: usize,
}

impl SimConfig {
    /// A port at `base` with its ECR at `base + 0x400`, open-collector
    /// control lines, no plug, a 4096-entry log.
    pub fn new(base: u16) -> SimConfig {
        SimConfig {
            base,
            base_hi: base.checked_add(regs::HI_OFFSET),
            open_collector: true,
            plug: None,
            log_capacity: 4096,
        }
    }

    /// The same with the [`Plug::loopback`] plug.
    pub fn with_loopback(mut self) -> SimConfig {
        self.plug = Some(Plug::loopback());
        self.open_collector = true;
        self
    }
}

/// One logged register write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteRecord {
    /// When, on the port's clock (ns).
    pub time_ns: u64,
    /// The absolute I/O address written.
    pub addr: u16,
    /// The byte written.
    pub value: u8,
}

/// Number of pin slots (index = DB-25 pin number, 0 unused).
const PINS: usize = 18;

/// The port's registers and connector: the board model.
#[derive(Debug)]
pub struct ParportModel {
    at: PortAt,
    open_collector: bool,
    /// `net[p]`: the smallest pin number joined to pin `p` (itself if none).
    net: [u8; PINS],
    data: u8,
    control: u8,
    epp: [u8; 5],
    hi: [u8; 3],
    drive: [Drive; PINS],
    reads: [u64; 3],
}

/// Joins the nets of `plug`'s wires: `net[p]` becomes the smallest pin
/// on `p`'s net.
fn nets(plug: Option<&Plug>) -> [u8; PINS] {
    let mut net: [u8; PINS] = std::array::from_fn(|i| i as u8);
    let Some(plug) = plug else { return net };
    // Join nets until nothing changes (few wires, done at build).
    loop {
        let mut changed = false;
        for &(a, b) in plug.wires() {
            let (a, b) = (a as usize, b as usize);
            if a >= PINS || b >= PINS {
                continue;
            }
            let (na, nb) = (net[a], net[b]);
            let m = na.min(nb);
            for n in net.iter_mut() {
                if (*n == na || *n == nb) && *n != m {
                    *n = m;
                    changed = true;
                }
            }
        }
        if !changed {
            return net;
        }
    }
}

impl ParportModel {
    fn new(cfg: &SimConfig) -> ParportModel {
        ParportModel {
            at: PortAt {
                base: cfg.base,
                base_hi: cfg.base_hi,
            },
            open_collector: cfg.open_collector,
            net: nets(cfg.plug.as_ref()),
            data: 0,
            control: 0,
            epp: [0; 5],
            hi: [0; 3],
            drive: [Drive::Floating; PINS],
            reads: [0; 3],
        }
    }

    /// The electrical level of `pin` (true = high); ground pins read low.
    fn level(&self, pin: u8) -> bool {
        if !(1..=17).contains(&pin) {
            return false;
        }
        let n = self.net[pin as usize];
        // Anything pulling low wins; a driven-high or floating net is high.
        for p in 1..PINS as u8 {
            if self.net[p as usize] == n
                && (self.drive[p as usize] == Drive::Low || self.own_drive(p) == Some(false))
            {
                return false;
            }
        }
        true
    }

    /// What the port itself does to `pin`: Some(level) if it drives it.
    fn own_drive(&self, pin: u8) -> Option<bool> {
        match regs::pin_reg(pin)? {
            PinReg::Data(b) => {
                (self.control & regs::CONTROL_DIR_IN == 0).then(|| self.data & (1 << b) != 0)
            }
            PinReg::Control(b) => {
                let bit = self.control & (1 << b) != 0;
                let physical = bit != (regs::CONTROL_INVERTED & (1 << b) != 0);
                if self.open_collector {
                    (!physical).then_some(false)
                } else {
                    Some(physical)
                }
            }
            PinReg::Status(_) => None,
        }
    }

    /// Bits of `pins`' levels, pin `pins[i]` on bit i.
    fn levels(&self, pins: &[u8]) -> u8 {
        pins.iter()
            .enumerate()
            .fold(0, |v, (i, &p)| if self.level(p) { v | 1 << i } else { v })
    }

    /// Whether the port decodes `addr` (its `base` or `base_hi` window).
    fn decodes(at: PortAt, addr: u16) -> bool {
        addr.wrapping_sub(at.base) < regs::BASE_SPAN
            || at
                .base_hi
                .is_some_and(|h| addr.wrapping_sub(h) < regs::HI_SPAN)
    }

    fn inb(&mut self, addr: u16) -> u8 {
        let off = addr.wrapping_sub(self.at.base);
        if off < regs::BASE_SPAN {
            return match off {
                regs::DATA => {
                    self.reads[0] += 1;
                    if self.control & regs::CONTROL_DIR_IN == 0 {
                        self.data
                    } else {
                        self.levels(&regs::DATA_PINS)
                    }
                }
                regs::STATUS => {
                    self.reads[1] += 1;
                    let mut v = regs::STATUS_UNUSED;
                    for (i, &p) in regs::STATUS_PINS.iter().enumerate() {
                        if self.level(p) {
                            v |= 1 << (i as u32 + regs::STATUS_FIRST_BIT);
                        }
                    }
                    v ^ regs::STATUS_INVERTED
                }
                regs::CONTROL => {
                    self.reads[2] += 1;
                    if self.open_collector {
                        let lines = self.levels(&regs::CONTROL_PINS) ^ regs::CONTROL_INVERTED;
                        (self.control & !regs::CONTROL_LINES) | lines
                    } else {
                        self.control
                    }
                }
                o => self.epp[(o - regs::EPP_ADDR) as usize],
            };
        }
        if let Some(hi) = self.at.base_hi {
            let off = addr.wrapping_sub(hi);
            if off < regs::HI_SPAN {
                return self.hi[off as usize];
            }
        }
        0xFF
    }

    fn outb(&mut self, addr: u16, v: u8) {
        let off = addr.wrapping_sub(self.at.base);
        if off < regs::BASE_SPAN {
            match off {
                regs::DATA => self.data = v,
                regs::STATUS => {}
                regs::CONTROL => self.control = v,
                o => self.epp[(o - regs::EPP_ADDR) as usize] = v,
            }
        } else if let Some(hi) = self
            .at
            .base_hi
            .filter(|h| addr.wrapping_sub(*h) < regs::HI_SPAN)
        {
            self.hi[(addr - hi) as usize] = v;
        }
    }
}

/// The parallel port is timeless: its lines follow the latches and the
/// plant at once.
impl BoardModel for ParportModel {
    fn describe(&self) -> String {
        format!("simulated parallel port at {:#x}", self.at.base)
    }
}

/// Byte registers; a wider access touches consecutive ports, low byte
/// first, as on an 8-bit ISA device.
impl PortModel for ParportModel {
    fn read(&mut self, port: u16, width: Width) -> u32 {
        if width == Width::Byte {
            return self.inb(port) as u32;
        }
        let mut v = 0;
        for i in 0..width.bytes() {
            v |= (self.inb(port.wrapping_add(i)) as u32) << (8 * i);
        }
        v
    }

    fn write(&mut self, port: u16, width: Width, value: u32) {
        for i in 0..width.bytes() {
            self.outb(port.wrapping_add(i), (value >> (8 * i)) as u8);
        }
    }
}

/// A simulated parallel port: the model on a [`SimBoard`], and the
/// [`PortIo`] the driver uses.
pub struct SimPort {
    at: PortAt,
    plug: Option<Plug>,
    board: SimBoard<ParportModel>,
    claimed: AtomicBool,
}

impl std::fmt::Debug for SimPort {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimPort")
            .field("base", &format_args!("{:#x}", self.at.base))
            .field("data", &self.data_latch())
            .field("control", &self.control_latch())
            .finish()
    }
}

impl SimPort {
    /// Builds a port; its log uses `clock`.
    pub fn new(cfg: SimConfig, clock: Arc<dyn Clock>) -> SimPort {
        let board = SimBoard::new(ParportModel::new(&cfg))
            .with_log(AccessLog::writes_only(cfg.log_capacity.max(1)))
            .stamp_log_with(clock);
        SimPort {
            at: PortAt {
                base: cfg.base,
                base_hi: cfg.base_hi,
            },
            plug: cfg.plug,
            board,
            claimed: AtomicBool::new(false),
        }
    }

    /// The base address.
    pub fn base_addr(&self) -> u16 {
        self.at.base
    }

    /// The plug in the connector, if any.
    pub fn plug(&self) -> Option<&Plug> {
        self.plug.as_ref()
    }

    /// The board the port lives on (the model, its log).
    pub fn board(&self) -> &SimBoard<ParportModel> {
        &self.board
    }

    // ---- plant side -------------------------------------------------

    /// Makes the outside world drive `pin` (1..17; others are ignored).
    pub fn drive(&self, pin: u8, d: Drive) {
        if (1..=17).contains(&pin) {
            self.board.with(|m| m.drive[pin as usize] = d);
        }
    }

    /// Drives `pin` high or low.
    pub fn set_input(&self, pin: u8, high: bool) {
        self.drive(pin, if high { Drive::High } else { Drive::Low });
    }

    /// Lets every pin float again.
    pub fn release_all(&self) {
        self.board.with(|m| m.drive = [Drive::Floating; PINS]);
    }

    /// The electrical level of `pin` on the connector (true = high).
    /// Ground pins (18..25) read low.
    pub fn level(&self, pin: u8) -> bool {
        self.board.with(|m| m.level(pin))
    }

    /// The data output latch.
    pub fn data_latch(&self) -> u8 {
        self.board.with(|m| m.data)
    }

    /// The control register latch.
    pub fn control_latch(&self) -> u8 {
        self.board.with(|m| m.control)
    }

    /// The last byte written to the ECR (`base_hi + 2`).
    pub fn ecr(&self) -> u8 {
        self.board.with(|m| m.hi[regs::ECR as usize])
    }

    /// Whether a driver holds the port.
    pub fn is_claimed(&self) -> bool {
        self.claimed.load(Relaxed)
    }

    /// How many times register `offset` (0..2) was read.
    pub fn reads(&self, offset: u16) -> u64 {
        self.board
            .with(|m| m.reads.get(offset as usize).copied().unwrap_or(0))
    }

    // ---- bus side ---------------------------------------------------

    /// Reads the byte at absolute I/O address `addr` (0xFF outside the
    /// port's windows, as an empty ISA bus reads).
    pub fn inb(&self, addr: u16) -> u8 {
        self.board.inb(addr)
    }

    /// Writes `v` at absolute I/O address `addr` (ignored, and not
    /// logged, outside the port's windows; the read-only status register
    /// ignores it).
    pub fn outb(&self, addr: u16, v: u8) {
        if ParportModel::decodes(self.at, addr) {
            self.board.outb(addr, v);
        }
    }

    // ---- log --------------------------------------------------------

    /// The logged writes since the last [`clear_log`](Self::clear_log),
    /// oldest first (at most the log's capacity).
    pub fn writes(&self) -> Vec<WriteRecord> {
        self.board
            .accesses()
            .iter()
            .map(|a| WriteRecord {
                time_ns: a.time_ns,
                addr: a.addr as u16,
                value: a.value as u8,
            })
            .collect()
    }

    /// The logged writes to base-relative register `offset`.
    pub fn writes_to(&self, offset: u16) -> Vec<WriteRecord> {
        let addr = self.at.base.wrapping_add(offset);
        self.writes()
            .into_iter()
            .filter(|w| w.addr == addr)
            .collect()
    }

    /// How many writes happened since the last clear (including any the
    /// log no longer holds).
    pub fn write_count(&self) -> u64 {
        self.board.access_count()
    }

    /// Forgets the log and the read counters.
    pub fn clear_log(&self) {
        self.board.clear_log();
        self.board.with(|m| m.reads = [0; 3]);
    }
}

impl PortIo for SimPort {
    #[inline]
    fn read_data(&self) -> u8 {
        self.at.read_data(&self.board)
    }
    #[inline]
    fn write_data(&self, v: u8) {
        self.at.write_data(&self.board, v)
    }
    #[inline]
    fn read_status(&self) -> u8 {
        self.at.read_status(&self.board)
    }
    #[inline]
    fn read_control(&self) -> u8 {
        self.at.read_control(&self.board)
    }
    #[inline]
    fn write_control(&self, v: u8) {
        self.at.write_control(&self.board, v)
    }
    fn has_ecr(&self) -> bool {
        self.at.base_hi.is_some()
    }
    fn write_ecr(&self, v: u8) -> Result<(), PortError> {
        if self.at.write_ecr(&self.board, v) {
            Ok(())
        } else {
            Err(PortError::Unsupported(format!(
                "simulated port {:#x} has no ECR",
                self.at.base
            )))
        }
    }
    fn claim(&self) -> Result<(), PortError> {
        if self.claimed.swap(true, Relaxed) {
            return Err(PortError::Unsupported(format!(
                "simulated port {:#x} is already claimed",
                self.at.base
            )));
        }
        Ok(())
    }
    fn release(&self) {
        self.claimed.store(false, Relaxed);
    }
    fn describe(&self) -> String {
        match self.plug {
            Some(_) => format!("simulator at {:#x} with loopback plug", self.at.base),
            None => format!("simulator at {:#x}", self.at.base),
        }
    }
    fn errors(&self) -> u64 {
        0
    }
}

/// The key a loaded port is published under: `parport.<num>` (the
/// driver layer's board registry, [`hal_driver::sim::publish`]), so tests
/// and tools in the same process can reach it while the module is loaded.
pub(crate) fn key(num: usize) -> String {
    format!("parport.{num}")
}

/// The simulated port `num` that `loadrt hal_parport` made in instance
/// `instance`, while that module is loaded.
pub fn find(instance: &str, num: usize) -> Option<Arc<SimPort>> {
    hal_driver::sim::find(instance, &key(num))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::SimClock;

    fn port(cfg: SimConfig) -> (SimPort, Arc<SimClock>) {
        let clock = Arc::new(SimClock::new(0, 10));
        (SimPort::new(cfg, clock.clone()), clock)
    }

    #[test]
    fn data_latch_drives_pins_in_output_mode_and_reads_levels_in_input_mode() {
        let (p, _) = port(SimConfig::new(0x378));
        p.outb(0x378, 0xA5);
        assert_eq!(p.inb(0x378), 0xA5);
        assert!(p.level(2) && !p.level(3) && p.level(9));
        p.set_input(3, true);
        assert!(!p.level(3), "a driven-low output beats an outside high");
        p.outb(0x37A, 0x20);
        p.release_all();
        p.set_input(2, false);
        p.set_input(5, false);
        assert_eq!(p.inb(0x378), 0xF6, "floating inputs read high");
    }

    #[test]
    fn status_bits_follow_pins_with_busy_inverted() {
        let (p, _) = port(SimConfig::new(0x378));
        assert_eq!(p.inb(0x379), 0x7F, "all high: bit 7 = NOT pin 11");
        for pin in [15, 13, 12, 10, 11] {
            p.set_input(pin, false);
        }
        assert_eq!(p.inb(0x379), 0x87);
        p.set_input(11, true);
        p.set_input(13, true);
        assert_eq!(p.inb(0x379), 0x17);
        assert_eq!(p.reads(regs::STATUS), 3);
        p.outb(0x379, 0);
        assert_eq!(p.inb(0x379), 0x17, "status is read-only");
    }

    #[test]
    fn control_lines_open_collector_and_push_pull() {
        let (oc, _) = port(SimConfig::new(0x378));
        oc.outb(0x37A, 0x04);
        assert!(oc.level(1) && oc.level(14) && oc.level(16) && oc.level(17));
        assert_eq!(oc.inb(0x37A), 0x04);
        oc.set_input(14, false);
        oc.set_input(16, false);
        assert_eq!(oc.inb(0x37A), 0x02, "pulled-low lines read as low levels");
        oc.outb(0x37A, 0x0B);
        assert!(!oc.level(1) && !oc.level(17));

        let mut cfg = SimConfig::new(0x278);
        cfg.open_collector = false;
        let (pp, _) = port(cfg);
        pp.outb(0x27A, 0x04);
        pp.set_input(14, false);
        assert_eq!(pp.inb(0x27A), 0x04, "push-pull reads the latch");
        assert!(
            !pp.level(14),
            "a line pulled low is low, even against a push-pull high"
        );
    }

    #[test]
    fn ecr_and_epp_registers_store_without_side_effects() {
        let (p, _) = port(SimConfig::new(0x378));
        p.outb(0x77A, 0x94);
        p.outb(0x37C, 0x55);
        assert_eq!(p.ecr(), 0x94);
        assert_eq!(p.inb(0x37C), 0x55);
        assert_eq!(p.data_latch(), 0);
        assert_eq!(p.inb(0x1234), 0xFF);
        p.outb(0x1234, 1);
        assert_eq!(p.write_count(), 2);
    }

    #[test]
    fn loopback_plug_joins_data_status_and_control() {
        let (p, _) = port(SimConfig::new(0x378).with_loopback());
        p.outb(0x37A, 0x04); // control released
        p.outb(0x378, 0b0001_0101); // D0, D2, D4 high
        let st = p.inb(0x379) ^ regs::STATUS_INVERTED;
        assert_eq!(st >> 3, 0b10101, "pins 15,13,12,10,11 = D0..D4");
        p.outb(0x378, 0b0110_0000); // D5, D6 high; D7, D4 low
        assert_eq!(
            p.inb(0x37A) ^ regs::CONTROL_INVERTED,
            0x03,
            "pins 1, 14 high; 16, 17 low"
        );
        // In input mode the control outputs reach the data inputs.
        p.outb(0x37A, 0x20 | (0b0101 ^ regs::CONTROL_INVERTED));
        let d = p.inb(0x378);
        assert_eq!(
            d >> 5 & 0b111,
            0b101,
            "D5 = pin 1, D6 = pin 14, D7 = pin 16"
        );
        assert_eq!(d >> 4 & 1, 0, "D4 = pin 17");
    }

    #[test]
    fn log_keeps_the_newest_writes_with_times() {
        let mut cfg = SimConfig::new(0x378);
        cfg.log_capacity = 3;
        let (p, clock) = port(cfg);
        for v in 0..5u8 {
            clock.advance(100);
            p.outb(0x378, v);
        }
        let w = p.writes();
        assert_eq!(w.iter().map(|r| r.value).collect::<Vec<_>>(), vec![2, 3, 4]);
        assert_eq!(w[0].time_ns, 320);
        assert_eq!(p.write_count(), 5);
        p.clear_log();
        assert!(p.writes().is_empty());
        p.outb(0x37A, 9);
        assert_eq!(p.writes_to(regs::CONTROL).len(), 1);
        assert!(p.writes_to(regs::DATA).is_empty());
    }

    #[test]
    fn claim_is_exclusive() {
        let (p, _) = port(SimConfig::new(0x378));
        p.claim().unwrap();
        assert!(p.claim().is_err());
        p.release();
        p.claim().unwrap();
    }
}
