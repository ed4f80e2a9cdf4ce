//! The register-level model of a HostMot2 board: a 64 KiB window serving
//! a firmware's identification, IDROM and descriptors, with its modules
//! running in simulated time and its connectors wired to a [`World`].
//!
//! Addresses that no module decodes read 0 and ignore writes. Time moves
//! only through [`Hm2Model::advance`]; each step runs the watchdog, the
//! step generators, the outputs into the world, then the counters from
//! what the world did.

use super::encoder::{Counter, SimEncoders};
use super::ioport::SimIoPort;
use super::pktuart::{SimPktUart, SimPktUarts};
use super::pwm::SimPwms;
use super::sserial::SimSserial;
use super::stepgen::{Gen, SimStepgens};
use super::watchdog::SimWatchdog;
use super::world::{Bench, EncoderIn, Inputs, Outputs, PwmOut, StepOut, World};
use crate::image::{FirmwareSpec, WINDOW_WORDS};
use crate::pins::PinDescriptor;
use crate::regs::{self, gtag};

/// What a register word belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    Nothing,
    Static,
    IoPort(u8, u8),
    Watchdog(u8),
    Encoder(u8, u8),
    Stepgen(u8, u8),
    Pwm(u8, u8),
    Led,
    /// Smart Serial register, port, channel.
    Sserial(u8, u8, u8),
    /// PktUART half (false TX, true RX), register, instance.
    PktUart(bool, u8, u8),
}

/// The I/O pins of one module instance, by function.
#[derive(Debug, Clone, Copy, Default)]
struct FunctionPins([Option<usize>; 9]);

impl FunctionPins {
    fn get(&self, f: u8) -> Option<usize> {
        self.0.get(f as usize).copied().flatten()
    }
}

/// A simulated HostMot2 board.
pub struct Hm2Model {
    spec: FirmwareSpec,
    image: Vec<u32>,
    map: Vec<Target>,
    clock_low: u64,
    clock_high: u32,
    ioport: SimIoPort,
    watchdog: Option<SimWatchdog>,
    encoders: SimEncoders,
    stepgens: SimStepgens,
    pwms: SimPwms,
    sserial: SimSserial,
    pktuarts: SimPktUarts,
    /// Per Smart Serial port, the I/O pin of each channel's TX.
    sserial_tx: Vec<[Option<usize>; crate::sserial::MAX_CHANNELS]>,
    led: u32,
    world: Box<dyn World>,
    enc_pins: Vec<FunctionPins>,
    sg_pins: Vec<FunctionPins>,
    sg_in_pins: Vec<FunctionPins>,
    pwm_pins: Vec<FunctionPins>,
    enc_in: Vec<EncoderIn>,
    external: Vec<Option<bool>>,
    driven: Vec<Option<bool>>,
    pwm_out: Vec<PwmOut>,
    step_out: Vec<StepOut>,
    emitted: Vec<i64>,
    rem_ns: u128,
    time_ns: u64,
    /// Pin levels per port, as the Data registers read them.
    levels: Vec<u32>,
    /// Whether `levels` must be recomputed (a register was written or
    /// time passed).
    stale: bool,
}

impl std::fmt::Debug for Hm2Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hm2Model")
            .field("board", &self.spec.board)
            .field("time_ns", &self.time_ns)
            .finish()
    }
}

fn instances(spec: &FirmwareSpec, tag: u8) -> usize {
    spec.module(tag).map_or(0, |m| m.instances as usize)
}

/// Per instance, the pins of each function of module `tag` in one
/// direction.
fn function_pins(pins: &[PinDescriptor], tag: u8, n: usize, outputs: bool) -> Vec<FunctionPins> {
    let mut v = vec![FunctionPins::default(); n];
    for (io, p) in pins.iter().enumerate() {
        if p.sec_tag != tag || p.is_output() != outputs {
            continue;
        }
        let f = p.function() as usize;
        let units: Vec<usize> = if p.is_global() {
            (0..n).collect()
        } else {
            vec![p.sec_unit as usize]
        };
        for u in units {
            if let Some(slot) = v.get_mut(u).and_then(|fp| fp.0.get_mut(f)) {
                slot.get_or_insert(io);
            }
        }
    }
    v
}

impl Hm2Model {
    /// A board running `spec` with nothing connected.
    pub fn new(spec: FirmwareSpec) -> Hm2Model {
        Hm2Model::with_world(spec, Box::new(Bench::default()))
    }

    /// A board running `spec` wired to `world`.
    pub fn with_world(spec: FirmwareSpec, world: Box<dyn World>) -> Hm2Model {
        let image = spec.image();
        let mut map = vec![Target::Nothing; WINDOW_WORDS];
        let idrom_end =
            (crate::image::IDROM_ADDR + crate::image::PD_OFFSET) as usize / 4 + spec.pins.len();
        for t in map
            .iter_mut()
            .take(idrom_end.min(WINDOW_WORDS))
            .skip(regs::COOKIE_ADDR as usize / 4)
        {
            *t = Target::Static;
        }
        for m in &spec.modules {
            if m.gtag == gtag::SSERIAL {
                // Command and data per port, then CS and three interface
                // registers per channel (4 bytes apart).
                for port in 0..m.instances {
                    let base = m.base as usize + port as usize * m.instance_stride() as usize;
                    for reg in 0..6u8 {
                        let chans = if reg < 2 {
                            1
                        } else {
                            crate::sserial::MAX_CHANNELS
                        };
                        for chan in 0..chans {
                            let addr = base + reg as usize * 0x100 + 4 * chan;
                            if let Some(slot) = map.get_mut(addr / 4) {
                                *slot = Target::Sserial(reg, port, chan as u8);
                            }
                        }
                    }
                }
                continue;
            }
            for reg in 0..m.num_registers {
                let per_instance = m.multiple_registers & (1 << reg) != 0;
                let count = if per_instance { m.instances } else { 1 };
                for inst in 0..count {
                    let addr = m.base as usize
                        + reg as usize * 0x100
                        + inst as usize * m.instance_stride() as usize;
                    let t = match m.gtag {
                        gtag::IOPORT => Target::IoPort(reg, inst),
                        gtag::WATCHDOG => Target::Watchdog(reg),
                        gtag::ENCODER => Target::Encoder(reg, inst),
                        gtag::STEPGEN => Target::Stepgen(reg, inst),
                        gtag::PWMGEN => Target::Pwm(reg, inst),
                        gtag::LED => Target::Led,
                        gtag::PKTUART_TX => Target::PktUart(false, reg, inst),
                        gtag::PKTUART_RX => Target::PktUart(true, reg, inst),
                        _ => continue,
                    };
                    if let Some(slot) = map.get_mut(addr / 4) {
                        *slot = t;
                    }
                }
            }
        }
        let n_enc = instances(&spec, gtag::ENCODER);
        let n_sg = instances(&spec, gtag::STEPGEN);
        let n_pwm = instances(&spec, gtag::PWMGEN);
        let n_pins = spec.pins.len();
        let n_ports = instances(&spec, gtag::SSERIAL);
        let mut sserial_tx = vec![[None; crate::sserial::MAX_CHANNELS]; n_ports];
        let mut channels = vec![0usize; n_ports];
        for (io, p) in spec.pins.iter().enumerate() {
            if p.sec_tag != gtag::SSERIAL || p.sec_unit as usize >= n_ports {
                continue;
            }
            if let Some(role) = crate::sserial::PinRole::of(p.sec_pin) {
                let c = role.channel() as usize;
                if c < crate::sserial::MAX_CHANNELS {
                    let port = p.sec_unit as usize;
                    channels[port] = channels[port].max(c + 1);
                    if let crate::sserial::PinRole::Tx(_) = role {
                        sserial_tx[port][c] = Some(io);
                    }
                }
            }
        }
        let mut sserial = SimSserial::new(&channels);
        for r in &spec.remotes {
            sserial.attach(r);
        }
        let pktuarts = match (spec.module(gtag::PKTUART_TX), spec.module(gtag::PKTUART_RX)) {
            (Some(t), Some(r)) => SimPktUarts {
                ports: (0..t.instances.min(r.instances))
                    .map(|_| SimPktUart::new(spec.clock_low, t.version, r.version))
                    .collect(),
            },
            _ => SimPktUarts::default(),
        };
        Hm2Model {
            sserial,
            pktuarts,
            sserial_tx,
            image,
            map,
            clock_low: spec.clock_low as u64,
            clock_high: spec.clock_high,
            ioport: SimIoPort::new(instances(&spec, gtag::IOPORT), spec.port_width),
            watchdog: spec.module(gtag::WATCHDOG).map(|_| SimWatchdog::default()),
            encoders: SimEncoders::new(n_enc),
            stepgens: SimStepgens::new(n_sg),
            pwms: SimPwms::new(n_pwm),
            led: 0,
            world,
            enc_pins: function_pins(&spec.pins, gtag::ENCODER, n_enc, false),
            sg_pins: function_pins(&spec.pins, gtag::STEPGEN, n_sg, true),
            sg_in_pins: function_pins(&spec.pins, gtag::STEPGEN, n_sg, false),
            pwm_pins: function_pins(&spec.pins, gtag::PWMGEN, n_pwm, true),
            enc_in: vec![EncoderIn::default(); n_enc],
            external: vec![None; n_pins],
            driven: vec![None; n_pins],
            pwm_out: vec![PwmOut::default(); n_pwm],
            step_out: vec![StepOut::default(); n_sg],
            emitted: vec![0; n_sg],
            rem_ns: 0,
            time_ns: 0,
            levels: vec![0; instances(&spec, gtag::IOPORT)],
            stale: true,
            spec,
        }
    }

    /// The firmware this board runs.
    pub fn spec(&self) -> &FirmwareSpec {
        &self.spec
    }

    /// Simulated time so far, ns.
    pub fn now_ns(&self) -> u64 {
        self.time_ns
    }

    /// Window size in bytes.
    pub fn len(&self) -> usize {
        regs::WINDOW_BYTES
    }

    /// Never empty: the window is 64 KiB.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// What module `tag` instance `unit` drives on its output pin of
    /// function `f`, before the IOPort decides whether it reaches the pin.
    fn module_out(&self, io: usize) -> bool {
        let Some(p) = self.spec.pins.get(io) else {
            return false;
        };
        let unit = p.sec_unit as usize;
        match (p.sec_tag, p.function()) {
            (gtag::STEPGEN, f) => self.stepgens.gens.get(unit).is_some_and(|g| {
                let swap = g.mode & regs::stepgen::MODE_SWAP != 0;
                // The step line idles low; the direction line shows the
                // last direction.
                (f == 2) != swap && g.forward
            }),
            (gtag::PWMGEN, 1) => self.pwms.output(unit, self.clock_high).duty != 0.0,
            (gtag::PWMGEN, 2) => self.pwms.values.get(unit).is_some_and(|v| v >> 31 != 0),
            (gtag::PWMGEN, 3) => self.pwms.enable & (1 << unit) == 0,
            _ => false,
        }
    }

    /// The level on pin `io`: what the board drives, else what the
    /// outside drives, else high (pull-up).
    pub fn pin_level(&self, io: usize) -> bool {
        self.ioport
            .driven(io, self.module_out(io))
            .or(self.external.get(io).copied().flatten())
            .unwrap_or(true)
    }

    /// What the board drives on pin `io` (`None`: not driving).
    pub fn pin_driven(&self, io: usize) -> Option<bool> {
        self.ioport.driven(io, self.module_out(io))
    }

    fn port_levels(&self, port: usize) -> u32 {
        let w = self.spec.port_width as usize;
        (0..w).fold(0, |acc, bit| {
            if self.pin_level(port * w + bit) {
                acc | 1 << bit
            } else {
                acc
            }
        })
    }

    /// A register read at byte `offset`.
    pub fn read32(&mut self, offset: usize) -> u32 {
        let Some(&t) = self.map.get(offset / 4) else {
            return 0;
        };
        match t {
            Target::Nothing => 0,
            Target::Static => self.image[offset / 4],
            Target::IoPort(reg, port) => {
                if self.stale {
                    for p in 0..self.levels.len() {
                        self.levels[p] = self.port_levels(p);
                    }
                    self.stale = false;
                }
                let levels = self.levels.get(port as usize).copied().unwrap_or(0);
                self.ioport.read(reg as usize, port as usize, levels)
            }
            Target::Watchdog(reg) => self.watchdog.as_ref().map_or(0, |w| w.read(reg as usize)),
            Target::Encoder(reg, i) => self.encoders.read(reg as usize, i as usize),
            Target::Stepgen(reg, i) => self.stepgens.read(reg as usize, i as usize),
            Target::Pwm(reg, i) => self.pwms.read(reg as usize, i as usize),
            Target::Led => self.led,
            Target::Sserial(reg, port, chan) => self.sserial.read(reg, port, chan),
            Target::PktUart(is_rx, reg, i) => self
                .pktuarts
                .ports
                .get_mut(i as usize)
                .map_or(0, |p| p.read(is_rx, reg as usize)),
        }
    }

    /// The channels of Smart Serial `port` whose TX pin the board drives.
    fn sserial_reachable(&self, port: usize) -> u8 {
        self.sserial_tx.get(port).map_or(0, |tx| {
            tx.iter().enumerate().fold(0, |m, (c, io)| match io {
                Some(io) if self.ioport.module_drives(*io) => m | 1 << c,
                _ => m,
            })
        })
    }

    /// A register write at byte `offset`.
    pub fn write32(&mut self, offset: usize, v: u32) {
        let Some(&t) = self.map.get(offset / 4) else {
            return;
        };
        self.stale = true;
        match t {
            Target::Nothing | Target::Static => {}
            Target::IoPort(reg, port) => self.ioport.write(reg as usize, port as usize, v),
            Target::Watchdog(reg) => {
                if let Some(w) = &mut self.watchdog {
                    w.write(reg as usize, v)
                }
            }
            Target::Encoder(reg, i) => self.encoders.write(reg as usize, i as usize, v),
            Target::Stepgen(reg, i) => self.stepgens.write(reg as usize, i as usize, v),
            Target::Pwm(reg, i) => self.pwms.write(reg as usize, i as usize, v),
            Target::Led => self.led = v,
            Target::Sserial(reg, port, chan) => {
                let reachable = self.sserial_reachable(port as usize);
                self.sserial.write(reg, port, chan, v, reachable)
            }
            Target::PktUart(is_rx, reg, i) => {
                if let Some(p) = self.pktuarts.ports.get_mut(i as usize) {
                    p.write(is_rx, reg as usize, v)
                }
            }
        }
    }

    /// Lets `dt_ns` of simulated time pass.
    pub fn advance(&mut self, dt_ns: u64) {
        let total = dt_ns as u128 * self.clock_low as u128 + self.rem_ns;
        let ticks = (total / 1_000_000_000) as u64;
        self.rem_ns = total % 1_000_000_000;
        if let Some(w) = &mut self.watchdog {
            if w.advance(ticks) {
                self.ioport.release_all();
            }
        }
        self.stepgens.advance(ticks);
        self.sserial.advance(dt_ns);
        self.pktuarts.advance(dt_ns);
        for (i, g) in self.stepgens.gens.iter().enumerate() {
            let made = g.emitted - self.emitted[i];
            self.emitted[i] = g.emitted;
            let connected = self.sg_pins[i]
                .get(1)
                .is_some_and(|io| self.ioport.module_drives(io));
            self.step_out[i] = StepOut {
                steps: if connected { made } else { 0 },
            };
        }
        for i in 0..self.pwm_out.len() {
            let mut o = self.pwms.output(i, self.clock_high);
            let pins = self.pwm_pins[i];
            let reaches = |f: u8| pins.get(f).is_none_or(|io| self.ioport.module_drives(io));
            if !reaches(1) || !reaches(3) {
                o.enabled = false;
                o.duty = 0.0;
            }
            self.pwm_out[i] = o;
        }
        for io in 0..self.driven.len() {
            self.driven[io] = self.pin_driven(io);
        }
        let out = Outputs {
            pwm: &self.pwm_out,
            steps: &self.step_out,
            pins: &self.driven,
        };
        let mut sense = Inputs {
            encoders: &mut self.enc_in,
            pins: &mut self.external,
        };
        self.world.advance(dt_ns, &out, &mut sense);
        self.encoders.tick(ticks);
        for i in 0..self.enc_in.len() {
            let e = self.enc_in[i];
            let fp = self.enc_pins[i];
            // The encoder's own lines show on its pins.
            for (f, level) in [(1, e.a), (2, e.b), (3, e.z)] {
                if let Some(io) = fp.get(f) {
                    self.external[io] = Some(level);
                }
            }
            let probe = fp.get(5).is_some_and(|io| self.pin_level(io));
            let mask = fp.get(4).is_none_or(|io| self.pin_level(io));
            self.encoders.sense(i, &e, probe, mask, self.clock_low);
        }
        for i in 0..self.sg_in_pins.len() {
            let fp = self.sg_in_pins[i];
            let index = fp.get(1).is_some_and(|io| self.pin_level(io));
            let probe = fp.get(2).is_some_and(|io| self.pin_level(io));
            self.stepgens.sense(i, index, probe);
        }
        self.time_ns += dt_ns;
        self.stale = true;
    }

    /// PktUART `i`, to plug something into its line.
    pub fn pktuart(&mut self, i: usize) -> Option<&mut SimPktUart> {
        self.pktuarts.ports.get_mut(i)
    }

    /// The world at the connectors, if it is a `W`.
    pub fn world<W: World>(&mut self) -> Option<&mut W> {
        self.stale = true;
        self.world.as_any().downcast_mut::<W>()
    }

    /// The IOPort registers.
    pub fn ioport(&self) -> &SimIoPort {
        &self.ioport
    }

    /// The watchdog, if the firmware has one.
    pub fn watchdog(&self) -> Option<&SimWatchdog> {
        self.watchdog.as_ref()
    }

    /// Encoder instance `i`.
    pub fn encoder(&self, i: usize) -> Option<&Counter> {
        self.encoders.counters.get(i)
    }

    /// The encoder module's registers.
    pub fn encoders(&self) -> &SimEncoders {
        &self.encoders
    }

    /// Step generator `i`.
    pub fn stepgen(&self, i: usize) -> Option<&Gen> {
        self.stepgens.gens.get(i)
    }

    /// The step generator module's registers.
    pub fn stepgens(&self) -> &SimStepgens {
        &self.stepgens
    }

    /// What PWM generator `i` puts on its connector this step.
    pub fn pwm_output(&self, i: usize) -> PwmOut {
        self.pwm_out.get(i).copied().unwrap_or_default()
    }

    /// The PWM module's registers.
    pub fn pwms(&self) -> &SimPwms {
        &self.pwms
    }

    /// The Smart Serial module and the cards on its channels.
    pub fn sserial(&mut self) -> &mut SimSserial {
        &mut self.sserial
    }

    /// The LED register.
    pub fn leds(&self) -> u32 {
        self.led
    }
}

impl hal_driver::sim::BoardModel for Hm2Model {
    fn advance(&mut self, dt_ns: u64) {
        Hm2Model::advance(self, dt_ns)
    }

    fn describe(&self) -> String {
        format!("simulated {} ({})", self.spec.board, self.spec.fpga_part)
    }
}

impl hal_driver::sim::MemModel for Hm2Model {
    fn len(&self) -> usize {
        regs::WINDOW_BYTES
    }

    fn read32(&mut self, offset: usize) -> u32 {
        Hm2Model::read32(self, offset)
    }

    fn write32(&mut self, offset: usize, value: u32) {
        Hm2Model::write32(self, offset, value)
    }
}
