//! A registered board: its modules, TRAM and transport, and the cycle
//! functions `read`, `write`, `read_gpio`, `write_gpio` (hardware.md 5.7
//! steps 11 to 14, 5.10).

use hal_core::{HalHost, HostParam, Ours, PinFactory, Rw};
use hal_driver::fault::{Fault, FaultLatch};

use crate::config::Config;
use crate::error::{Hm2Error, Result};
use crate::firmware::Firmware;
use crate::llio::Llio;
use crate::log::{Level, MessageLog};
use crate::modules::encoder::Encoders;
use crate::modules::ioport::IoPort;
use crate::modules::led::Leds;
use crate::modules::pwmgen::Pwmgens;
use crate::modules::raw::Raw;
use crate::modules::sserial::Sserial;
use crate::modules::stepgen::Stepgens;
use crate::modules::watchdog::{Watchdog, WatchdogEvent};
use crate::modules::{Export, Notify};
use crate::pktuart::links::Links;
use crate::pktuart::{PktUartInstance, PktUartLink};
use crate::regs::gtag;
use crate::tram::Tram;
use crate::transport::{TransferStats, Transport, TransportError};

/// A board the driver runs.
pub struct Board<H: HalHost = Ours> {
    llio: Llio,
    fw: Firmware,
    transport: Box<dyn Transport>,
    tram: Tram,
    io_error: H::Param<bool, Rw>,
    ioport: IoPort<H>,
    watchdog: Option<Watchdog<H>>,
    encoder: Option<Encoders<H>>,
    stepgen: Option<Stepgens<H>>,
    pwmgen: Option<Pwmgens<H>>,
    led: Option<Leds<H>>,
    sserial: Option<Sserial<H>>,
    raw: Option<Raw<H>>,
    /// PktUARTs whose traffic rides in the bursts (`hm2_modbus`).
    links: Links,
    /// What the transport was sized for without links.
    reserved: (usize, usize, usize, usize),
    say: Notify,
    latch: FaultLatch,
    recover: bool,
    requested: bool,
    started: bool,
}

/// A transfer of the cycle's reads failed.
static READ_FAILED: Fault = Fault::new(
    1,
    "error reading from the board: io_error set, board stopped (its watchdog releases the outputs)",
);
/// A transfer of the cycle's writes failed.
static WRITE_FAILED: Fault = Fault::new(
    2,
    "error writing to the board: io_error set, board stopped (its watchdog releases the outputs)",
);
/// More writes in one cycle than the transport was sized for (a bug).
static QUEUE_FULL: Fault = Fault::new(
    3,
    "too many register writes in one cycle: io_error set, board stopped",
);
/// `read_gpio` or `write_gpio` failed.
static GPIO_FAILED: Fault = Fault::new(
    4,
    "error transferring GPIO: io_error set, board stopped (its watchdog releases the outputs)",
);
/// A network board lost too many packets.
static PACKET_ERRORS: Fault = Fault::new(
    5,
    "packet-error-limit reached: io_error set, board stopped, outputs made safe (clear io_error to resume)",
);

/// The fault a failed transfer trips.
fn fault_of(e: &TransportError, otherwise: &'static Fault) -> &'static Fault {
    match e {
        TransportError::QueueFull { .. } => &QUEUE_FULL,
        TransportError::PacketErrors { .. } => &PACKET_ERRORS,
        _ => otherwise,
    }
}

impl<H: HalHost> Board<H> {
    /// Exports the board's HAL objects on `comp`, writes its whole
    /// configuration, and runs a first read and write (LinuxCNC's
    /// `hm2_register` after the descriptors are parsed).
    pub fn register(
        comp: &impl PinFactory<H>,
        llio: Llio,
        fw: Firmware,
        config: &Config,
        transport: Box<dyn Transport>,
        say: Notify,
        log: &mut MessageLog,
    ) -> Result<Board<H>> {
        Board::register_with(comp, llio, fw, config, transport, say, log, false)
    }

    /// [`register`](Self::register), naming Smart Serial cards by unit
    /// number when `serial_numbers` (hostmot2's `use_serial_numbers`).
    #[allow(clippy::too_many_arguments)]
    pub fn register_with(
        comp: &impl PinFactory<H>,
        llio: Llio,
        fw: Firmware,
        config: &Config,
        transport: Box<dyn Transport>,
        say: Notify,
        log: &mut MessageLog,
        serial_numbers: bool,
    ) -> Result<Board<H>> {
        let prefix = llio.name.clone();
        let io_error = comp.param(&format!("{prefix}.io_error"), false)?;
        let mut tram = Tram::default();
        let mut x = Export {
            comp,
            prefix: &prefix,
            tram: &mut tram,
        };
        // IOPort's regions come first, then the modules in descriptor order.
        let ioport = IoPort::export(&mut x, &fw.ioport, &fw.pins)?;
        let (mut watchdog, mut encoder, mut stepgen, mut pwmgen, mut led) =
            (None, None, None, None, None);
        let mut sserial = None;
        for md in &fw.mds {
            match md.gtag {
                gtag::WATCHDOG => {
                    if let Some(m) = fw.watchdog.filter(|m| m.md.index == md.index) {
                        watchdog = Some(Watchdog::export(&mut x, &m)?);
                    }
                }
                gtag::ENCODER => {
                    if let Some(m) = fw.encoder.filter(|m| m.md.index == md.index) {
                        encoder = Some(Encoders::export(&mut x, &m)?);
                    }
                }
                gtag::STEPGEN => {
                    if let Some(m) = fw.stepgen.filter(|m| m.md.index == md.index) {
                        stepgen = Some(Stepgens::export(&mut x, &m)?);
                    }
                }
                gtag::PWMGEN => {
                    if let Some(m) = fw.pwmgen.filter(|m| m.md.index == md.index) {
                        pwmgen = Some(Pwmgens::export(&mut x, &m)?);
                    }
                }
                gtag::LED => {
                    if let Some(m) = fw.led.filter(|m| m.md.index == md.index) {
                        led = Some(Leds::export(&mut x, &m)?);
                    }
                }
                gtag::SSERIAL => {
                    if let Some(f) = fw.sserial.as_ref().filter(|f| f.md.index == md.index) {
                        sserial = Some(Sserial::export(&mut x, f, serial_numbers)?);
                    }
                }
                _ => {}
            }
        }
        let raw = if config.enable_raw {
            Some(Raw::export(&mut x)?)
        } else {
            None
        };
        let mut transport = transport;
        let (reads, read_words, writes, write_words) = tram.sizes();
        // Configuration writes of one cycle: at most a few per instance,
        // plus a stepgen table (17 writes) per stepgen.
        let instances: usize = [fw.encoder, fw.stepgen, fw.pwmgen, fw.led]
            .iter()
            .flatten()
            .map(|m| m.instances as usize)
            .sum::<usize>()
            + fw.ioport.instances as usize;
        let config_writes = 64 + 24 * instances;
        let reserved = (
            reads,
            read_words,
            writes + config_writes,
            write_words + config_writes,
        );
        transport.reserve(reserved.0, reserved.1, reserved.2, reserved.3);
        let mut board = Board {
            llio,
            fw,
            transport,
            tram,
            io_error,
            ioport,
            watchdog,
            encoder,
            stepgen,
            pwmgen,
            led,
            sserial,
            raw,
            links: Links::default(),
            reserved,
            latch: FaultLatch::new(format!("hm2/{prefix}")).with_log(say.log().clone()),
            say,
            recover: false,
            requested: false,
            started: false,
        };
        board.initialize().map_err(|e| {
            log.err(format!("{e}"));
            Hm2Error::CommErrors
        })?;
        log.info("registered");
        Ok(board)
    }

    /// Reads the firmware's description over `transport` and registers
    /// the board (`firmware::load`, then [`register`](Self::register)):
    /// what LinuxCNC's `hm2_register` does once the llio is known. The
    /// messages of both steps go to `log`, also when it fails.
    pub fn open(
        comp: &impl PinFactory<H>,
        llio: Llio,
        config: &Config,
        debug: crate::firmware::Debug,
        mut transport: Box<dyn Transport>,
        say: Notify,
        log: &mut MessageLog,
    ) -> Result<Board<H>> {
        let fw = crate::firmware::load(&llio, config, debug, transport.as_mut(), log)?;
        Board::register_with(
            comp,
            llio,
            fw,
            config,
            transport,
            say,
            log,
            debug.use_serial_numbers,
        )
    }

    /// Force-write, first TRAM read, first TRAM write (zeros).
    fn initialize(&mut self) -> Result<(), TransportError> {
        self.force_write()?;
        self.transport.send_queued_writes()?;
        self.tram.request_reads(self.transport.as_mut())?;
        self.tram.receive_reads(self.transport.as_mut())?;
        if let Some(e) = &mut self.encoder {
            e.init_from_read(&self.tram.read_buf);
        }
        if let Some(s) = &mut self.stepgen {
            s.init_from_read(&self.tram.read_buf);
        }
        self.tram.write_buf.fill(0);
        self.tram.queue_writes(self.transport.as_mut())?;
        self.transport.send_queued_writes()
    }

    /// Queues every module's whole configuration (`hm2_force_write`).
    fn force_write(&mut self) -> Result<(), TransportError> {
        let t = self.transport.as_mut();
        if let Some(w) = &mut self.watchdog {
            w.force_write(t)?;
        }
        self.ioport.force_write(t)?;
        if let Some(e) = &mut self.encoder {
            e.force_write(t)?;
        }
        if let Some(p) = &mut self.pwmgen {
            p.force_write(t, &self.say)?;
        }
        if let Some(s) = &mut self.stepgen {
            s.force_write(t, &self.say)?;
        }
        if let Some(l) = &mut self.led {
            l.force_write(t)?;
        }
        Ok(())
    }

    /// The board's name (`hm2_5i25.0`).
    pub fn name(&self) -> &str {
        &self.llio.name
    }

    /// Runs `job` on the Smart Serial module's registers directly
    /// (`setsserial`), then puts its ports back to idle; false if the
    /// board has no such module.
    pub(crate) fn sserial_setup(
        &mut self,
        job: &mut dyn FnMut(
            &mut dyn Transport,
            &crate::modules::sserial::discovery::SserialFirmware,
        ),
    ) -> bool {
        let Some(found) = self.fw.sserial.as_ref() else {
            return false;
        };
        job(self.transport.as_mut(), found);
        if let Some(s) = &mut self.sserial {
            s.restart_after_setup();
        }
        true
    }

    /// The board's transport, for another module's direct register
    /// access at load time (`hm2_modbus` setting its PktUART up); in
    /// realtime such a module uses a link ([`attach_pktuart`](Self::attach_pktuart)).
    pub(crate) fn transport_mut(&mut self) -> &mut dyn Transport {
        self.transport.as_mut()
    }

    /// Carries the PktUART `inst`'s traffic in this board's bursts from
    /// the next cycle on (load time: sizes the buffers and the
    /// transport's queues); the link's id.
    pub fn attach_pktuart(&mut self, inst: &PktUartInstance) -> Result<usize> {
        let id = self.links.attach(inst, self.tram.read_buf.len())?;
        let (r, rw, w, ww) = self.reserved;
        let (lr, lrw, lw, lww) = self.links.reserve_sizes();
        self.transport.reserve(r + lr, rw + lrw, w + lw, ww + lww);
        Ok(id)
    }

    /// Stops carrying link `id` (load time).
    pub fn detach_pktuart(&mut self, id: usize) {
        self.links.detach(id);
    }

    /// Link `id`, for its user's realtime function (between this board's
    /// `read` and `write`).
    #[inline]
    pub fn pktuart_link(&mut self, id: usize) -> Option<&mut PktUartLink> {
        self.links.get(id)
    }

    /// What the driver learned from the firmware.
    pub fn firmware(&self) -> &Firmware {
        &self.fw
    }

    /// Transfers so far.
    pub fn stats(&self) -> TransferStats {
        self.transport.stats()
    }

    /// Whether the transport splits reads (LinuxCNC's `read-request`).
    pub fn split_read(&self) -> bool {
        self.transport.split_read()
    }

    /// Whether `read_gpio`/`write_gpio` may run in another thread.
    pub fn threadsafe(&self) -> bool {
        self.transport.threadsafe()
    }

    /// Stops the board after a failed transfer: `io_error` goes TRUE (the
    /// cycle functions then do nothing until the user clears it) and the
    /// reason is said once. The outputs are made safe at once, as far as
    /// the board can still be reached; with writes stopped its watchdog
    /// bites and the firmware releases every output anyway.
    fn fail(&mut self, fault: &'static Fault) {
        self.io_error.set(true);
        if self.latch.trip(fault) {
            self.go_safe();
        }
        self.requested = false;
    }

    /// Whether the cycle functions may run: not while `io_error` is set;
    /// once the user clears it after a failure, the next `write` rewrites
    /// the whole configuration first.
    #[inline]
    fn usable(&mut self) -> bool {
        if self.io_error.get() {
            return false;
        }
        if self.latch.reset().is_some() {
            self.recover = true;
            self.transport.recover();
        }
        true
    }

    /// `read-request`: sends this cycle's read request.
    pub fn read_request(&mut self) {
        if !self.usable() {
            return;
        }
        if let Some(raw) = &self.raw {
            let (start, addr) = raw.target();
            self.tram.retarget_read(start, addr);
        }
        let t = self.transport.as_mut();
        let queued = self.tram.queue_reads(t).and_then(|()| {
            self.links.queue_reads(t);
            t.send_queued_reads()
        });
        match queued {
            // A request that could not leave is counted; `read` skips.
            Ok(()) | Err(TransportError::Lost) => self.requested = true,
            Err(e) => {
                self.links.lost();
                self.fail(fault_of(&e, &READ_FAILED));
            }
        }
    }

    /// `read`: every input pin from one burst of reads.
    pub fn read(&mut self) {
        if !self.usable() {
            return;
        }
        if !self.requested {
            self.read_request();
            if !self.requested {
                return;
            }
        }
        self.requested = false;
        let t = self.transport.as_mut();
        let received = if self.links.carrying() {
            self.links.receive(t, &mut self.tram.read_buf)
        } else {
            self.tram.receive_reads(t)
        };
        match received {
            Ok(()) => {}
            // A tolerated packet error: this cycle's inputs stay as they were.
            Err(TransportError::Lost) => return,
            Err(e) => {
                self.fail(fault_of(&e, &READ_FAILED));
                return;
            }
        }
        let buf = &self.tram.read_buf;
        if let Some(w) = &mut self.watchdog {
            if w.process_read(buf, &self.say) == WatchdogEvent::Bit {
                // The firmware released every output; keep reading so the
                // user sees the inputs, and wait for has_bit to be reset.
            }
        }
        self.ioport.process_read(buf);
        if let Some(e) = &mut self.encoder {
            e.process_read(buf);
        }
        if let Some(s) = &mut self.stepgen {
            s.process_read(buf);
        }
        if let Some(s) = &mut self.sserial {
            s.process_read(buf, &self.say);
        }
        if let Some(r) = &self.raw {
            r.process_read(buf);
        }
    }

    /// `write`: every output from one burst of writes, plus the
    /// configuration registers whose pins or params changed.
    pub fn write(&mut self, period_ns: i64) {
        if !self.usable() {
            return;
        }
        self.transport.set_cycle_period(period_ns);
        match self.write_cycle(period_ns) {
            Ok(()) | Err(TransportError::Lost) => {}
            Err(e) => self.fail(fault_of(&e, &WRITE_FAILED)),
        }
    }

    fn write_cycle(&mut self, period_ns: i64) -> Result<(), TransportError> {
        let bitten = self.watchdog.as_ref().is_some_and(|w| w.wants_recovery());
        if bitten || self.recover {
            self.say.say(
                Level::Err,
                format_args!("trying to recover from IO error or Watchdog bite"),
            );
            if let Some(w) = &mut self.watchdog {
                w.recovered(self.transport.as_mut())?;
            }
            self.force_write()?;
            self.recover = false;
        } else if self.transport.take_resync() {
            // Packets were lost: write the whole configuration again,
            // quietly (LinuxCNC's soft reset).
            self.force_write()?;
        }
        if !self.started {
            // Module outputs are driven from the first write on.
            self.ioport.start();
            self.started = true;
        }
        let buf = &mut self.tram.write_buf;
        if let Some(w) = &self.watchdog {
            w.prepare_write(buf);
        }
        self.ioport.prepare_write(buf);
        if let Some(p) = &mut self.pwmgen {
            p.prepare_write(buf);
        }
        if let Some(s) = &mut self.stepgen {
            s.prepare_write(buf, period_ns);
        }
        if let Some(s) = &mut self.sserial {
            s.prepare_write(buf, period_ns, &self.say);
        }
        let t = self.transport.as_mut();
        self.tram.queue_writes(t)?;
        self.ioport.write_config(t)?;
        if let Some(w) = &mut self.watchdog {
            w.write_config(t, period_ns, &self.say)?;
        }
        if let Some(e) = &mut self.encoder {
            e.write_config(t)?;
        }
        if let Some(p) = &mut self.pwmgen {
            p.write_config(t, &self.say)?;
        }
        if let Some(s) = &mut self.stepgen {
            s.write_config(t, &self.say)?;
        }
        if let Some(l) = &mut self.led {
            l.write_config(t)?;
        }
        if let Some(s) = &mut self.sserial {
            s.write_config(t)?;
        }
        let dump = match &self.raw {
            Some(r) => r.write(t)?,
            None => false,
        };
        self.links.queue_writes(t);
        t.send_queued_writes()?;
        if dump {
            self.dump_state();
        }
        Ok(())
    }

    /// `read_gpio`: the GPIO inputs only, outside TRAM.
    pub fn read_gpio(&mut self) {
        if !self.usable() {
            return;
        }
        if self.ioport.read_gpio(self.transport.as_mut()).is_err() {
            self.fail(&GPIO_FAILED);
        }
    }

    /// `write_gpio`: the GPIO outputs and their configuration only, plus
    /// a pet of the watchdog, outside TRAM.
    pub fn write_gpio(&mut self, period_ns: i64) {
        if !self.usable() {
            return;
        }
        let t = self.transport.as_mut();
        let r = self.ioport.write_gpio(t).and_then(|()| {
            if let Some(w) = &mut self.watchdog {
                w.write_config(t, period_ns, &self.say)?;
            }
            t.send_queued_writes()
        });
        if r.is_err() {
            self.fail(&GPIO_FAILED);
        }
    }

    /// Whether a Smart Serial port is stopped by faults.
    pub fn sserial_faulted(&self) -> bool {
        self.sserial.as_ref().is_some_and(|s| s.faulted())
    }

    /// Whether the board has a watchdog (LinuxCNC exports `pet_watchdog`
    /// then).
    pub fn has_watchdog(&self) -> bool {
        self.watchdog.is_some()
    }

    /// `pet_watchdog`: pets the watchdog outside TRAM, for a thread that
    /// runs more often than `write` (or when `write` runs slower than the
    /// watchdog's timeout).
    pub fn pet_watchdog(&mut self) {
        if !self.usable() {
            return;
        }
        if let Some(w) = &self.watchdog {
            if w.pet_now(self.transport.as_mut()).is_err() {
                self.fail(&WRITE_FAILED);
            }
        }
    }

    /// Says what `raw.dump_state` asks for: a summary of the board.
    fn dump_state(&self) {
        let s = self.transport.stats();
        self.say.say(
            Level::Info,
            format_args!(
                "dump_state: {} words read in {} bursts, {} written in {} bursts; \
                 TRAM {} read words, {} write words; io_error {}",
                s.words_read,
                s.read_bursts,
                s.words_written,
                s.write_bursts,
                self.tram.read_buf.len(),
                self.tram.write_buf.len(),
                self.io_error.get()
            ),
        );
    }

    /// Safe state (after a fault, at unload and at exit): PWM disabled
    /// and at 0, step rates 0, the watchdog made to bite at once, and
    /// every pin made an input (what the bite does, done directly too).
    pub fn go_safe(&mut self) {
        let t = self.transport.as_mut();
        if let Some(p) = &mut self.pwmgen {
            let _ = p.go_safe(t);
        }
        if let Some(s) = &mut self.stepgen {
            let _ = s.go_safe(t);
        }
        if let Some(s) = &mut self.sserial {
            let _ = s.go_safe(t);
        }
        if let Some(w) = &mut self.watchdog {
            let _ = w.bite_now(t);
        }
        // The bite takes a clock tick; release the pins now as well.
        let _ = self.ioport.go_safe(t);
        // Module outputs are driven again from the next write on.
        self.started = false;
    }
}
