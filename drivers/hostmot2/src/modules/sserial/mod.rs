//! Smart Serial (GTag 0xC1; hostmot2-more.md 2): remote cards (7I76,
//! 7I77, ...) on the ports of the FPGA, found at load ([`discovery`]),
//! their process data turned into HAL objects ([`fields`]) and moved
//! every cycle.
//!
//! # HAL objects
//!
//! Each card's objects are under `<board>.<card>.<port>.<channel>.`
//! (`hm2_7i76e.0.7i76.0.0.input-05`; with hostmot2's
//! `use_serial_numbers=1`, `hm2_<card>.<unit>.` with the unit number's
//! low 16 bits in hex): its process data as [`fields`] says, and its
//! globals as params of their lower-cased names (`nvbaudrate`,
//! `nvwatchdogtimeout`, `swrevision`, read from the card at load; read
//! only when the card only reports them). Per port,
//! `<board>.sserial.port-<i>.`: `run` (bit IN, TRUE), `port_state`,
//! `port_state2`, `port_state3`, `fault-count` (u32 OUT), params
//! `fault-inc` (10), `fault-dec` (1), `fault-lim` (200); and
//! `<board>.<i>.debug` (s32 OUT), as LinuxCNC names them. One addition:
//! `<board>.sserial.port-<i>.fault` (bit OUT), TRUE while the port is
//! stopped by faults.
//!
//! # Each cycle
//!
//! `write` sends the process data and a DoIt (`0x1000 | channels`); the
//! firmware moves the data on the serial links; the next `read` finds
//! the answers (so inputs are one period old). A port runs a small state
//! machine: 0 idle → (`run`) start in normal mode → 2 starting → 3
//! running; `run` FALSE → 4 stopping → 5 → 0; 10 stopped by faults.
//!
//! # Faults
//!
//! A cycle whose DoIt is still pending, or in which a channel's transfer
//! failed, adds `fault-inc` to `fault-count`; every cycle takes
//! `fault-dec` away. Past `fault-lim` the port stops (`port_state` 10,
//! `fault` TRUE), says which link errors the channels had, and sends
//! nothing until `run` goes FALSE (then TRUE restarts it). A card that
//! gets no process data turns its own outputs off after its watchdog
//! time (`nvwatchdogtimeout`). A channel whose transfer failed keeps its
//! inputs. A card that reports a fault of its own (watchdog, over
//! temperature, ...) has it said once.
//!
//! The port's state machine is LinuxCNC's; `port_state2` holds the last
//! data register (the channels whose transfer failed), `port_state3`
//! the last command register readback, `debug` the consecutive cycles
//! whose DoIt was not done.

pub mod discovery;
pub mod fields;

use hal_core::{
    HalHost, HostParam, HostPin, In, Ours, Out, PinFactory, Result as HalResult, Ro, Rw,
};

use crate::log::Level;
use crate::md::ModuleDescriptor;
use crate::modules::{Export, Notify};
use crate::sserial::records::{data_type as dt, DataRecord};
use crate::sserial::{cmd, reg, status};
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};
use discovery::{PortFound, RemoteFound, SserialFirmware};
use fields::Field;

/// A global's param.
enum GlobalParam<H: HalHost = Ours> {
    U32(H::Param<u32, Rw>),
    S32(H::Param<i32, Rw>),
    Float(H::Param<f64, Rw>),
    /// Reported by the card only: never written back.
    U32Ro(#[allow(dead_code)] H::Param<u32, Ro>),
    S32Ro(#[allow(dead_code)] H::Param<i32, Ro>),
    FloatRo(#[allow(dead_code)] H::Param<f64, Ro>),
}

/// A global of a card, as a param; a change is written to the card when
/// its port is idle (`run` FALSE), in its EEPROM for non-volatile ones.
struct Global<H: HalHost = Ours> {
    param: GlobalParam<H>,
    bits: u8,
    addr: u16,
    nonvolatile: bool,
    /// The raw value the card holds.
    written: u64,
}

impl<H: HalHost> Global<H> {
    fn export<F: PinFactory<H>>(
        c: &F,
        name: &str,
        r: &DataRecord,
        raw: u64,
    ) -> HalResult<Global<H>> {
        let ro = !r.is_out();
        let signed = matches!(r.data_type, dt::SIGNED | dt::NV_SIGNED);
        let float = matches!(r.data_type, dt::FLOAT | dt::NV_FLOAT);
        let param = if float {
            let v = if r.bits == 64 {
                f64::from_bits(raw)
            } else {
                f32::from_bits(raw as u32) as f64
            };
            if ro {
                GlobalParam::FloatRo(c.param(name, v)?)
            } else {
                GlobalParam::Float(c.param(name, v)?)
            }
        } else if signed {
            let v = crate::sserial::data::sign_extend(raw, r.bits.clamp(1, 64)) as i32;
            if ro {
                GlobalParam::S32Ro(c.param(name, v)?)
            } else {
                GlobalParam::S32(c.param(name, v)?)
            }
        } else if ro {
            GlobalParam::U32Ro(c.param(name, raw as u32)?)
        } else {
            GlobalParam::U32(c.param(name, raw as u32)?)
        };
        Ok(Global {
            param,
            bits: r.bits,
            addr: r.addr,
            nonvolatile: dt::is_nonvolatile(r.data_type),
            written: raw,
        })
    }

    /// The raw value the param asks for, if the user may change it.
    fn wanted(&self) -> Option<u64> {
        let mask = if self.bits >= 64 {
            u64::MAX
        } else {
            (1u64 << self.bits.max(1)) - 1
        };
        let raw = match &self.param {
            GlobalParam::U32(p) => p.get() as u64,
            GlobalParam::S32(p) => p.get() as i64 as u64,
            GlobalParam::Float(p) => {
                if self.bits == 64 {
                    p.get().to_bits()
                } else {
                    (p.get() as f32).to_bits() as u64
                }
            }
            _ => return None,
        };
        Some(raw & mask)
    }
}

/// One register transfer of a parameter write: the channel's CS, its
/// interface 0 (and 1), then the command.
#[derive(Debug, Clone, Copy)]
struct Step {
    cs: Option<u32>,
    iface: Option<u64>,
    command: u32,
}

/// A parameter being written to a card.
#[derive(Debug, Clone, Copy)]
struct ParamWrite {
    remote: usize,
    global: usize,
    value: u64,
    step: usize,
    sent: bool,
}

/// A card on a channel.
struct Remote<H: HalHost = Ours> {
    channel: u8,
    mode: u8,
    label: String,
    cs_read: Slot,
    in_read: Option<Slot>,
    cs_write: Slot,
    out_write: Option<Slot>,
    fields: Vec<Field<H>>,
    globals: Vec<Global<H>>,
    /// Status bits of the card already said.
    reported: u32,
    words: [u32; reg::INTERFACES],
}

/// The port states (LinuxCNC's numbers).
mod state {
    pub const IDLE: u32 = 0;
    pub const STARTING: u32 = 2;
    pub const RUNNING: u32 = 3;
    pub const STOPPING: u32 = 4;
    pub const STOP_WAIT: u32 = 5;
    /// Writing changed globals to the cards.
    pub const PARAMS: u32 = 6;
    pub const FAULTED: u32 = 10;
}

/// How long a start may take before it counts as a fault.
const START_TIMEOUT_NS: i64 = 2_100_000_000;

/// One port.
struct Port<H: HalHost = Ours> {
    index: u8,
    md: ModuleDescriptor,
    tag: u8,
    command_read: Slot,
    data_read: Slot,
    command_write: Slot,
    remotes: Vec<Remote<H>>,
    run: H::Pin<bool, In>,
    port_state: H::Pin<u32, Out>,
    port_state2: H::Pin<u32, Out>,
    port_state3: H::Pin<u32, Out>,
    fault_count: H::Pin<u32, Out>,
    fault: H::Pin<bool, Out>,
    debug: H::Pin<i32, Out>,
    fault_inc: H::Param<u32, Rw>,
    fault_dec: H::Param<u32, Rw>,
    fault_lim: H::Param<u32, Rw>,
    st: u32,
    waited_ns: i64,
    misses: i32,
    faults: u32,
    pending: Option<ParamWrite>,
}

/// The Smart Serial module.
pub struct Sserial<H: HalHost = Ours> {
    ports: Vec<Port<H>>,
}

/// The prefix of a card's objects.
pub(crate) fn remote_prefix(
    board: &str,
    r: &RemoteFound,
    port: u8,
    serial_numbers: bool,
) -> String {
    if serial_numbers {
        format!("hm2_{}.{:04x}", r.name(), r.unit & 0xFFFF)
    } else {
        format!("{board}.{}.{port}.{}", r.name(), r.channel)
    }
}

impl<H: HalHost> Sserial<H> {
    /// Exports every port's and card's objects and registers the TRAM
    /// regions: per card the CS and data registers each way, then per
    /// port the command and data reads and the command write (after the
    /// cards', so the DoIt goes out with its data).
    pub fn export<F: PinFactory<H>>(
        x: &mut Export<'_, F>,
        f: &SserialFirmware,
        serial_numbers: bool,
    ) -> HalResult<Sserial<H>> {
        let mut ports = Vec::new();
        for p in &f.ports {
            if p.remotes.is_empty() || p.setup {
                continue;
            }
            ports.push(Self::export_port(x, &f.md, p, serial_numbers)?);
        }
        Ok(Sserial { ports })
    }

    fn export_port(
        x: &mut Export<'_, impl PinFactory<H>>,
        md: &ModuleDescriptor,
        p: &PortFound,
        serial_numbers: bool,
    ) -> HalResult<Port<H>> {
        let i = p.index;
        let mut remotes = Vec::new();
        for r in &p.remotes {
            let prefix = remote_prefix(x.prefix, r, i, serial_numbers);
            let chan = r.channel as u32;
            let at = |reg_index: usize| md.inst_reg(reg_index, i as usize) + 4 * chan;
            let (in_bits, out_bits) = r.widths();
            // The interface registers are 4 bytes apart per channel but a
            // register stride apart from each other: one region each, in
            // a row of the TRAM buffer.
            let interfaces = |bits: usize, add: &mut dyn FnMut(u32) -> Slot| {
                (0..bits.div_ceil(32))
                    .map(|k| add(at(reg::INTERFACE0 + k)))
                    .reduce(|a, b| Slot {
                        start: a.start,
                        words: a.words + b.words,
                    })
            };
            let cs_read = x.tram.add_read(at(reg::CS), 1);
            let in_read = interfaces(in_bits, &mut |a| x.tram.add_read(a, 1));
            let cs_write = x.tram.add_write(at(reg::CS), 1);
            let out_write = interfaces(out_bits, &mut |a| x.tram.add_write(a, 1));
            let (mut at_in, mut at_out) = (0, 0);
            let mut fields = Vec::new();
            for rec in &r.process {
                let i_at = rec.is_in().then_some(at_in);
                let o_at = rec.is_out().then_some(at_out);
                if rec.is_in() {
                    at_in += rec.bits as usize;
                }
                if rec.is_out() {
                    at_out += rec.bits as usize;
                }
                let base = format!("{prefix}.{}", r.hal_name(rec));
                fields.push(Field::export(x.comp, &base, rec, i_at, o_at)?);
            }
            let mut globals = Vec::new();
            for (g, v) in &r.globals {
                let name = format!("{prefix}.{}", r.hal_name(g));
                globals.push(Global::export(x.comp, &name, g, *v)?);
            }
            remotes.push(Remote {
                channel: r.channel,
                mode: r.mode,
                label: format!("{} on port {i} channel {}", r.name(), r.channel),
                cs_read,
                in_read,
                cs_write,
                out_write,
                fields,
                globals,
                reported: 0,
                words: [0; reg::INTERFACES],
            });
        }
        let base = format!("{}.sserial.port-{i}", x.prefix);
        let n = |s: &str| format!("{base}.{s}");
        Ok(Port {
            index: i,
            md: *md,
            tag: p.mask(),
            command_read: x.tram.add_read(md.inst_reg(reg::COMMAND, i as usize), 1),
            data_read: x.tram.add_read(md.inst_reg(reg::DATA, i as usize), 1),
            command_write: x.tram.add_write(md.inst_reg(reg::COMMAND, i as usize), 1),
            remotes,
            run: x.comp.pin_init(&n("run"), true)?,
            port_state: x.comp.pin(&n("port_state"))?,
            port_state2: x.comp.pin(&n("port_state2"))?,
            port_state3: x.comp.pin(&n("port_state3"))?,
            fault_count: x.comp.pin(&n("fault-count"))?,
            fault: x.comp.pin(&n("fault"))?,
            debug: x.comp.pin(&format!("{}.{i}.debug", x.prefix))?,
            fault_inc: x.comp.param(&n("fault-inc"), 10u32)?,
            fault_dec: x.comp.param(&n("fault-dec"), 1u32)?,
            fault_lim: x.comp.param(&n("fault-lim"), 200u32)?,
            st: state::IDLE,
            waited_ns: 0,
            misses: 0,
            faults: 0,
            pending: None,
        })
    }

    /// Takes the answers of the last DoIt.
    pub fn process_read(&mut self, buf: &[u32], say: &Notify) {
        for p in &mut self.ports {
            p.process_read(buf, say);
        }
    }

    /// Puts the process data and each port's command into TRAM.
    pub fn prepare_write(&mut self, buf: &mut [u32], period_ns: i64, say: &Notify) {
        for p in &mut self.ports {
            p.prepare_write(buf, period_ns, say);
        }
    }

    /// Queues the register writes of parameter changes (after TRAM, so
    /// they go out after the command slot's "nothing").
    pub fn write_config(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        for p in &mut self.ports {
            p.write_config(t)?;
        }
        Ok(())
    }

    /// Stops every port (safe state): the cards get no more data and
    /// their watchdogs turn their outputs off.
    pub fn go_safe(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        for p in &mut self.ports {
            t.write(p.md.inst_reg(reg::COMMAND, p.index as usize), &[cmd::STOP])?;
            p.st = state::IDLE;
            p.port_state.set(state::IDLE);
        }
        Ok(())
    }

    /// Puts every port back to idle after `setsserial` used the module
    /// directly (it stops the channels): the ports whose `run` is TRUE
    /// start again at the next `write`.
    pub fn restart_after_setup(&mut self) {
        for p in &mut self.ports {
            p.pending = None;
            p.misses = 0;
            p.faults = 0;
            p.set_state(state::IDLE);
        }
    }

    /// Whether any port is stopped by faults.
    pub fn faulted(&self) -> bool {
        self.ports.iter().any(|p| p.st == state::FAULTED)
    }
}

impl<H: HalHost> Port<H> {
    fn set_state(&mut self, s: u32) {
        self.st = s;
        self.waited_ns = 0;
        self.port_state.set(s);
    }

    fn process_read(&mut self, buf: &[u32], say: &Notify) {
        let command = self.command_read.of(buf)[0];
        let data = self.data_read.of(buf)[0];
        self.port_state2.set(data);
        self.port_state3.set(command);
        match self.st {
            state::STARTING if command == 0 => self.set_state(state::RUNNING),
            state::STOP_WAIT if command == 0 => self.set_state(state::IDLE),
            state::PARAMS if command == 0 => self.param_step_done(data, say),
            state::RUNNING => self.running_read(buf, command, data, say),
            _ => {}
        }
    }

    fn running_read(&mut self, buf: &[u32], command: u32, data: u32, say: &Notify) {
        let inc = self.fault_inc.get();
        let failed = (data & self.tag as u32) as u8;
        if command != 0 {
            self.misses += 1;
            self.faults = self.faults.saturating_add(inc);
            if self.misses == 4 {
                say.say(
                    Level::Err,
                    format_args!(
                        "Smart Serial port {}: DoIt not cleared from previous servo thread. Servo thread rate probably too fast",
                        self.index
                    ),
                );
            }
        } else {
            self.misses = 0;
            if failed != 0 {
                self.faults = self.faults.saturating_add(inc);
            }
            for r in &mut self.remotes {
                if failed & (1 << r.channel) != 0 {
                    continue;
                }
                let cs = r.cs_read.of(buf)[0];
                if cs & status::REMOTE_FAULT != 0 {
                    let new = cs & status::REMOTE_MASK & !status::REMOTE_FAULT & !r.reported;
                    if new != 0 {
                        r.reported |= new;
                        say.say(
                            Level::Err,
                            format_args!(
                                "Smart Serial Error: port {} channel {}: {}",
                                self.index,
                                r.channel,
                                StatusWords(new)
                            ),
                        );
                    }
                }
                if let Some(s) = r.in_read {
                    r.words.fill(0);
                    r.words[..s.words].copy_from_slice(s.of(buf));
                    for f in &mut r.fields {
                        f.receive(&r.words);
                    }
                }
            }
        }
        self.debug.set(self.misses);
        self.faults = self.faults.saturating_sub(self.fault_dec.get());
        self.fault_count.set(self.faults);
        if self.faults > self.fault_lim.get() {
            for r in &self.remotes {
                if failed & (1 << r.channel) != 0 {
                    let cs = r.cs_read.of(buf)[0] & status::LOCAL_MASK;
                    say.say(
                        Level::Err,
                        format_args!(
                            "Smart Serial port {} channel {}: {}: {}",
                            self.index,
                            r.channel,
                            r.label,
                            StatusWords(cs)
                        ),
                    );
                }
            }
            say.say(
                Level::Err,
                format_args!("***Smart Serial Port {} will be stopped***", self.index),
            );
            self.fault.set(true);
            self.set_state(state::FAULTED);
        }
    }

    fn prepare_write(&mut self, buf: &mut [u32], period_ns: i64, say: &Notify) {
        let run = self.run.get();
        let mut command = cmd::NOTHING;
        if self.st == state::IDLE && self.pending.is_none() && self.find_changed_global() {
            self.set_state(state::PARAMS);
        }
        match self.st {
            state::IDLE if run => {
                for r in &self.remotes {
                    r.cs_write.of_mut(buf)[0] = (r.mode as u32) << 24;
                }
                command = cmd::START_NORMAL | self.tag as u32;
                self.faults = 0;
                self.misses = 0;
                self.fault.set(false);
                self.fault_count.set(0);
                self.set_state(state::STARTING);
            }
            state::STARTING => {
                self.waited_ns += period_ns.max(0);
                if self.waited_ns > START_TIMEOUT_NS {
                    say.say(
                        Level::Err,
                        format_args!("Smart Serial port {}: the start was never acknowledged; the port is stopped", self.index),
                    );
                    self.fault.set(true);
                    self.set_state(state::FAULTED);
                }
            }
            state::RUNNING => {
                if !run {
                    command = cmd::STOP;
                    self.set_state(state::STOPPING);
                } else {
                    for r in &mut self.remotes {
                        r.cs_write.of_mut(buf)[0] = (r.mode as u32) << 24;
                        if let Some(s) = r.out_write {
                            r.words.fill(0);
                            for f in &r.fields {
                                f.send(&mut r.words);
                            }
                            s.of_mut(buf).copy_from_slice(&r.words[..s.words]);
                        }
                    }
                    command = cmd::DOIT | self.tag as u32;
                }
            }
            state::STOPPING => self.set_state(state::STOP_WAIT),
            state::FAULTED if !run => {
                command = cmd::STOP;
                self.set_state(state::STOPPING);
            }
            _ => {}
        }
        self.command_write.of_mut(buf)[0] = command;
    }
}

impl<H: HalHost> Port<H> {
    /// Looks for a global whose param changed; starts writing it.
    fn find_changed_global(&mut self) -> bool {
        for (ri, r) in self.remotes.iter().enumerate() {
            for (gi, g) in r.globals.iter().enumerate() {
                if let Some(v) = g.wanted().filter(|&v| v != g.written) {
                    self.pending = Some(ParamWrite {
                        remote: ri,
                        global: gi,
                        value: v,
                        step: 0,
                        sent: false,
                    });
                    return true;
                }
            }
        }
        false
    }

    /// The transfer `w.step` of a parameter write: stop, setup start, NV
    /// on, the write, NV off, stop.
    fn param_step(&self, w: &ParamWrite) -> Option<Step> {
        use crate::sserial::lbp;
        let r = &self.remotes[w.remote];
        let g = &r.globals[w.global];
        let bit = 1u32 << r.channel;
        let size = match g.bits {
            0..=8 => 0u32,
            9..=16 => 1,
            17..=32 => 2,
            _ => 3,
        };
        let nv = |on: u64| Step {
            cs: Some((lbp::NONVOLATILE as u32) << 24),
            iface: Some(on),
            command: cmd::DOIT | bit,
        };
        let steps = [
            Some(Step {
                cs: None,
                iface: None,
                command: cmd::STOP,
            }),
            Some(Step {
                cs: Some((r.mode as u32) << 24),
                iface: None,
                command: cmd::START_SETUP | bit,
            }),
            g.nonvolatile.then(|| nv(1)),
            Some(Step {
                cs: Some(((lbp::WRITE as u32) + size) << 24 | g.addr as u32),
                iface: Some(w.value),
                command: cmd::DOIT | bit,
            }),
            g.nonvolatile.then(|| nv(0)),
            Some(Step {
                cs: None,
                iface: None,
                command: cmd::STOP,
            }),
        ];
        steps.into_iter().flatten().nth(w.step)
    }

    fn write_config(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let Some(mut w) = self.pending.filter(|w| !w.sent && self.st == state::PARAMS) else {
            return Ok(());
        };
        let Some(step) = self.param_step(&w) else {
            return Ok(());
        };
        let c = self.remotes[w.remote].channel as u32;
        let i = self.index as usize;
        if let Some(cs) = step.cs {
            t.queue_write(self.md.inst_reg(reg::CS, i) + 4 * c, &[cs])?;
        }
        if let Some(v) = step.iface {
            t.queue_write(self.md.inst_reg(reg::INTERFACE0, i) + 4 * c, &[v as u32])?;
            t.queue_write(
                self.md.inst_reg(reg::INTERFACE0 + 1, i) + 4 * c,
                &[(v >> 32) as u32],
            )?;
        }
        t.queue_write(self.md.inst_reg(reg::COMMAND, i), &[step.command])?;
        w.sent = true;
        self.pending = Some(w);
        Ok(())
    }

    /// The last step's command is done.
    fn param_step_done(&mut self, data: u32, say: &Notify) {
        let Some(mut w) = self.pending.filter(|w| w.sent) else {
            return;
        };
        let step = self.param_step(&w);
        let channel = self.remotes[w.remote].channel;
        let transfer = step.is_some_and(|s| s.command & (cmd::DOIT | cmd::START_SETUP) != 0);
        if transfer && data & (1 << channel) != 0 {
            say.say(
                Level::Err,
                format_args!(
                    "Smart Serial port {} channel {}: writing a parameter to {} failed",
                    self.index, channel, self.remotes[w.remote].label
                ),
            );
            // Take the card's value as it stands and try no more.
            let g = &mut self.remotes[w.remote].globals[w.global];
            g.written = w.value;
            self.pending = None;
            self.set_state(state::IDLE);
            return;
        }
        w.step += 1;
        w.sent = false;
        if self.param_step(&w).is_none() {
            self.remotes[w.remote].globals[w.global].written = w.value;
            self.pending = None;
            self.set_state(state::IDLE);
        } else {
            self.pending = Some(w);
        }
    }
}

/// Status bits in words, without allocating.
struct StatusWords(u32);

impl std::fmt::Display for StatusWords {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut first = true;
        for b in 0..32 {
            if self.0 & (1 << b) != 0 {
                if let Some(w) = status::describe(b) {
                    if !first {
                        f.write_str(", ")?;
                    }
                    f.write_str(w)?;
                    first = false;
                }
            }
        }
        if first {
            f.write_str("no error bit")?;
        }
        Ok(())
    }
}
