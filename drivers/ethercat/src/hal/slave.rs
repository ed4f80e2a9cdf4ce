//! One slave's pins on its part of the process image: each pin with an
//! entry is bound to the entry's bits in the slave's layout; what a type
//! computes beyond the bits (inverted inputs and outputs, analog scaling,
//! counters) is here too; CiA 402 drives have [`super::drive`].

use hal_core::{HalHost, PinFactory, Result};
use hal_driver::LogSink;

use super::any_pin::AnyPin;
use super::drive::DriveRt;
use super::encoder::{Encoder, EncoderPins};
use super::field::{self, Field};
use super::stepper::{Stepper, StepperPins};
use crate::error::Error;
use crate::lcec::pins::{self, Coding, Kind, PinSpec, PinType};
use crate::master::{Failure, Layout, ReadStatus};
use crate::regs::al;

/// Bits within an 8-bit status or control entry, for the catalogue pins
/// that are one bit of it: (type, pin suffix, bit).
const BYTE_BITS: &[(&str, &str, u8)] = &[
    ("EL3102", "underrange", 0),
    ("EL3102", "overrange", 1),
    ("EL3102", "error", 6),
    ("EL5101", "enc-latch-c-valid", 0),
    ("EL5101", "enc-latch-ext-valid", 1),
    ("EL5101", "enc-underflow", 3),
    ("EL5101", "enc-overflow", 4),
    ("EL5101", "enc-inext", 5),
    ("EL5101", "enc-index-c-enable", 0),
    ("EL5101", "enc-index-ext-pos-enable", 1),
    ("EL5101", "enc-set-raw-count", 2),
    ("EL5101", "enc-index-ext-neg-enable", 3),
];

/// What a bound pin does each cycle.
enum Role {
    /// Takes its value from the inputs.
    Input {
        at: Field,
        coding: Coding,
        invert: bool,
    },
    /// Puts its value into the outputs; `invert` names the parameter
    /// that inverts a bit.
    Output {
        at: Field,
        coding: Coding,
        invert: Option<usize>,
    },
    /// Puts another pin's value into this pin's entry: the EL4102's
    /// `aout-N-value` entry gets `aout-N-raw`, which the type computes.
    OutputFrom { at: Field, source: usize },
    /// Computed by the slave type's code (or a parameter).
    Computed,
}

/// An input pin's entry, next to the others of its slave.
struct InputSlot {
    at: Field,
    coding: Coding,
    invert: bool,
    /// Its index in the slave's pins.
    pin: usize,
    /// The bits it last took.
    last: Option<u64>,
}

/// A pin putting its value into the outputs, with what it last put.
struct OutputSlot {
    /// Its index in the slave's pins.
    pin: usize,
    /// The value it last encoded (its f64 bits) and the field's bits
    /// that made: while both hold, encoding again would write the same.
    last: Option<(u64, u64)>,
}

impl OutputSlot {
    /// Puts `v` into the field `at` of `img`, unless the field already
    /// holds what `v` encodes to. The field is read back rather than
    /// trusted, so whatever else wrote the image since (safe outputs, a
    /// drive's words, an overlapping entry) is written over as before.
    #[inline]
    fn put(&mut self, img: &mut [u8], at: Field, coding: &Coding, v: f64) {
        let key = v.to_bits();
        if self
            .last
            .is_some_and(|(k, raw)| k == key && at.read(img) == raw)
        {
            return;
        }
        at.write(img, field::encode(coding, v, at.bits));
        self.last = Some((key, at.read(img)));
    }
}

struct Bound<H: HalHost> {
    pin: AnyPin<H>,
    role: Role,
    /// The pin's name after the slave's (found at export).
    name: Box<str>,
}

/// A slave's state pins, in [`pins::slave_state_pins`] order.
struct StatePins<H: HalHost>(Vec<AnyPin<H>>);

/// One slave of a master, bound.
pub(crate) struct SlaveRt<H: HalHost> {
    /// Its position in the master's [`crate::master::Cyclic`].
    pub(crate) index: usize,
    /// `lcec.<master>.<slave>`, for the log.
    label: String,
    /// Healthy at the last `read` (a change is logged once).
    was_healthy: bool,
    /// What the slave's type computes each cycle, its pins found once.
    code: TypeCode,
    state: StatePins<H>,
    pins: Vec<Bound<H>>,
    /// The pins taking their value from the inputs, each with the bits
    /// it last took (a pin whose bits did not change is not touched),
    /// and the pins putting theirs into the outputs: the cycle walks
    /// these, not every pin.
    inputs: Vec<InputSlot>,
    /// The bytes the slots read as they were when the slots last took
    /// them (while `seen_valid`): an image that did not change since is
    /// not walked again, which most terminals' images do not.
    seen: Box<[u8]>,
    seen_valid: bool,
    outputs: Vec<OutputSlot>,
    /// The AL state byte and health the state pins last showed.
    shown_state: Option<(u8, bool)>,
    drive: Option<Box<DriveRt>>,
    /// EL5101/EL7041: the counter extended past 16 bits, the latches.
    encoder: Encoder,
    /// EL7041: the motor's enable edge and automatic reset.
    stepper: Stepper,
    /// The other device found at its position that the master refused
    /// to bring back (vendor, product), as last logged.
    refused_shown: Option<(u32, u32)>,
    /// Why bringing it back failed, as last logged.
    failure_shown: Option<Failure>,
}

/// What a slave type computes beyond its entries' bits, with the pins it
/// uses found by name at export: the cycle indexes them and compares no
/// names.
enum TypeCode {
    /// Nothing beyond the bits.
    Plain,
    /// EL3102: the scaled value of each channel.
    AnalogIn([AnalogInPins; 2]),
    /// EL4102: the duty cycle of each channel.
    AnalogOut([AnalogOutPins; 2]),
    /// EL5101: the encoder.
    Encoder(EncoderPins),
    /// EL7041: the encoder and the motor in velocity mode.
    Stepper(Box<(EncoderPins, StepperPins)>),
}

/// An EL3102 channel's pins (`ain-N-*`), as indices into the slave's pins.
struct AnalogInPins {
    raw: Option<usize>,
    val: Option<usize>,
    scale: Option<usize>,
    bias: Option<usize>,
}

/// An EL4102 channel's pins (`aout-N-*`).
struct AnalogOutPins {
    value: Option<usize>,
    scale: Option<usize>,
    offset: Option<usize>,
    min_dc: Option<usize>,
    max_dc: Option<usize>,
    enable: Option<usize>,
    curr_dc: Option<usize>,
    raw: Option<usize>,
    pos: Option<usize>,
    neg: Option<usize>,
}

impl TypeCode {
    /// The code of slave type `kind`, its pins found in `pins`, its
    /// entries in `layout`.
    fn new<H: HalHost>(kind: &str, pins: &Named<'_, H>, layout: &Layout) -> TypeCode {
        let ch = |kind: &str, n: usize, what: &str| pins.index(&format!("{kind}-{n}-{what}"));
        match kind {
            "EL3102" => TypeCode::AnalogIn([0, 1].map(|n| AnalogInPins {
                raw: ch("ain", n, "raw"),
                val: ch("ain", n, "val"),
                scale: ch("ain", n, "scale"),
                bias: ch("ain", n, "bias"),
            })),
            "EL4102" => TypeCode::AnalogOut([0, 1].map(|n| AnalogOutPins {
                value: ch("aout", n, "value"),
                scale: ch("aout", n, "scale"),
                offset: ch("aout", n, "offset"),
                min_dc: ch("aout", n, "min-dc"),
                max_dc: ch("aout", n, "max-dc"),
                enable: ch("aout", n, "enable"),
                curr_dc: ch("aout", n, "curr-dc"),
                raw: ch("aout", n, "raw"),
                pos: ch("aout", n, "pos"),
                neg: ch("aout", n, "neg"),
            })),
            "EL5101" => TypeCode::Encoder(EncoderPins::new(kind, pins, layout)),
            "EL7041" => TypeCode::Stepper(Box::new((
                EncoderPins::new(kind, pins, layout),
                StepperPins::new(pins, layout),
            ))),
            _ => TypeCode::Plain,
        }
    }
}

impl<H: HalHost> SlaveRt<H> {
    /// Exports slave `slave`'s pins as `lcec.<master>.<slave>.<pin>` and
    /// binds those with entries to `layout`. A generic slave's `halPin`
    /// whose entry the slave does not map is an error; a catalogue pin
    /// without its entry stays at its initial value.
    pub(crate) fn export(
        c: &impl PinFactory<H>,
        master: &str,
        slave: &crate::lcec::conf::Slave,
        index: usize,
        layout: &Layout,
        file: &std::path::Path,
    ) -> Result<Self> {
        let specs = pins::slave_pins(slave, file).map_err(load_error)?;
        let name = |p: &str| pins::full_name(Some(master), Some(&slave.name), p);
        let state = pins::slave_state_pins();
        let state = StatePins(
            state
                .iter()
                .map(|p| AnyPin::export(c, &name(&p.name), p))
                .collect::<Result<_>>()?,
        );
        let mut bound = Vec::with_capacity(specs.len());
        for spec in &specs {
            let pin = AnyPin::export(c, &name(&spec.name), spec)?;
            let role = role(slave, spec, &specs, layout, file)?;
            bound.push(Bound {
                pin,
                role,
                name: spec.name.as_str().into(),
            });
        }
        let named = Named(&bound);
        let code = TypeCode::new(&slave.kind, &named, layout);
        let drive = if slave.kind == "basic_cia402" {
            Some(Box::new(DriveRt::new(
                format!("{} (slave {})", name("srv"), slave.index),
                slave,
                layout,
                file,
                &named,
            )?))
        } else {
            None
        };
        let with = |f: fn(&Role) -> bool| {
            (0..bound.len())
                .filter(|&i| f(&bound[i].role))
                .collect::<Vec<_>>()
        };
        let inputs = bound
            .iter()
            .enumerate()
            .filter_map(|(pin, b)| match b.role {
                Role::Input { at, coding, invert } => Some(InputSlot {
                    at,
                    coding,
                    invert,
                    pin,
                    last: None,
                }),
                _ => None,
            })
            .collect::<Vec<_>>();
        // The bytes the slots read: a slave's whole image for most types.
        let extent = inputs
            .iter()
            .map(|s| (s.at.bit + usize::from(s.at.bits)).div_ceil(8))
            .max()
            .unwrap_or(0);
        let outputs = with(|r| matches!(r, Role::Output { .. } | Role::OutputFrom { .. }))
            .into_iter()
            .map(|pin| OutputSlot { pin, last: None })
            .collect();
        Ok(SlaveRt {
            index,
            inputs,
            seen: vec![0; extent].into_boxed_slice(),
            seen_valid: false,
            outputs,
            shown_state: None,
            label: pins::full_name(Some(master), None, &slave.name),
            was_healthy: true,
            code,
            state,
            pins: bound,
            drive,
            encoder: Encoder::default(),
            stepper: Stepper::default(),
            refused_shown: None,
            failure_shown: None,
        })
    }

    /// A cycle's reception: state pins, then every input; `emcy`: the
    /// error code of an emergency the slave sent since the last.
    pub(crate) fn read(
        &mut self,
        inputs: &[u8],
        (al_state, healthy): (u8, bool),
        emcy: Option<u16>,
        status: &ReadStatus,
        log: Option<&LogSink>,
    ) {
        if healthy != self.was_healthy {
            self.was_healthy = healthy;
            if let Some(log) = log {
                self.log_health(log, al_state, healthy, status);
            }
        }
        if self.shown_state != Some((al_state, healthy)) {
            self.shown_state = Some((al_state, healthy));
            let st = al_state & al::STATE_MASK;
            let online = al_state != 0;
            for (pin, on) in self.state.0.iter().zip([
                online,
                healthy,
                st == al::INIT,
                st == al::PREOP,
                st == al::SAFEOP,
                st == al::OP,
            ]) {
                pin.set(f64::from(u8::from(on)));
            }
        }
        let span = inputs.get(..self.seen.len());
        if !(self.seen_valid && span == Some(&self.seen[..])) {
            self.take_slots(inputs);
            match span {
                Some(bytes) => {
                    self.seen.copy_from_slice(bytes);
                    self.seen_valid = true;
                }
                None => self.seen_valid = false,
            }
        }
        let named = Named(&self.pins);
        match &self.code {
            TypeCode::AnalogIn(channels) => analog_in(&self.pins, channels),
            TypeCode::Encoder(at) => self.encoder.read(inputs, healthy, at, &named),
            TypeCode::Stepper(at) => {
                self.encoder.read(inputs, healthy, &at.0, &named);
                self.stepper.read(&at.1, &named);
            }
            TypeCode::Plain | TypeCode::AnalogOut(_) => {}
        }
        if let Some(d) = &mut self.drive {
            d.read(inputs, healthy, emcy, &Named(&self.pins), log);
        }
    }

    /// The input pins whose bits changed since they last took them.
    fn take_slots(&mut self, inputs: &[u8]) {
        for slot in &mut self.inputs {
            let raw = slot.at.read(inputs);
            if slot.last == Some(raw) {
                continue;
            }
            slot.last = Some(raw);
            let mut v = field::decode(&slot.coding, raw, slot.at.bits);
            if slot.invert {
                v = f64::from(u8::from(v == 0.0));
            }
            if let Some(b) = self.pins.get(slot.pin) {
                b.pin.set(v);
            }
        }
    }

    /// A cycle's transmission into the slave's outputs; an unhealthy
    /// slave gets its safe outputs ([`SlaveRt::hold_safe`]) instead.
    pub(crate) fn write(&mut self, outputs: &mut [u8], now_ns: u64, healthy: bool) {
        if !healthy {
            self.hold_safe(outputs, now_ns);
            return;
        }
        if let TypeCode::AnalogOut(channels) = &self.code {
            analog_out(&self.pins, channels);
        }
        for slot in &mut self.outputs {
            let b = &self.pins[slot.pin];
            let (at, coding, v) = match &b.role {
                Role::Output { at, coding, invert } => {
                    let mut v = b.pin.get();
                    if invert.is_some_and(|i| self.pins[i].pin.is_set()) {
                        v = f64::from(u8::from(v == 0.0));
                    }
                    (*at, *coding, v)
                }
                Role::OutputFrom { at, source } => (
                    *at,
                    field::plain(PinType::S32),
                    self.pins[*source].pin.get(),
                ),
                _ => continue,
            };
            slot.put(outputs, at, &coding, v);
        }
        if let TypeCode::Stepper(at) = &self.code {
            self.stepper.write(outputs, &at.1, &Named(&self.pins));
        }
        if let Some(d) = &mut self.drive {
            d.write(outputs, now_ns, &Named(&self.pins));
        }
    }

    /// The safe outputs of a slave that is not exchanging data, per
    /// meaning, and the output pins that report them: digital and
    /// generic entries 0 (lcec has no per-entry safe value), the
    /// EL4102's channels 0 V (`curr-dc`, `raw`, `pos`, `neg` 0), the
    /// EL7041 disabled (`srv-curr-dc`, `srv-raw-cmd` 0), a drive's
    /// controlword as the CiA 402 layer plans it with its latch tripped
    /// (`srv-cia-controlword`). These are what the next frame carries,
    /// the first after the link returns included.
    fn hold_safe(&mut self, outputs: &mut [u8], now_ns: u64) {
        outputs.fill(0);
        let named = Named(&self.pins);
        match &self.code {
            TypeCode::AnalogOut(channels) => {
                for c in channels {
                    for i in [c.curr_dc, c.raw, c.pos, c.neg] {
                        if let Some(pin) = named.at(i) {
                            pin.set(0.0);
                        }
                    }
                }
            }
            TypeCode::Stepper(at) => self.stepper.safe(&at.1, &named),
            TypeCode::Plain | TypeCode::AnalogIn(_) | TypeCode::Encoder(_) => {}
        }
        if let Some(d) = &mut self.drive {
            d.write_lost(outputs, now_ns, &named);
        }
    }

    /// Says once that the master found another device at this slave's
    /// position (`refused`: its vendor and product) than the one it
    /// brought up (`expected`), and left it unconfigured.
    pub(crate) fn show_refused(
        &mut self,
        refused: Option<(u32, u32)>,
        expected: (u32, u32),
        log: Option<&LogSink>,
    ) {
        if refused == self.refused_shown {
            return;
        }
        self.refused_shown = refused;
        if let (Some(log), Some((vendor, product))) = (log, refused) {
            log.err(format_args!(
                "{}: position {} now holds vendor {vendor:#010x} product {product:#010x}, not the device found at start-up (vendor {:#010x} product {:#010x}): not configured, left in INIT",
                self.label, self.index, expected.0, expected.1
            ));
        }
    }

    /// Says once why the master could not bring the slave back after it
    /// lost its configuration (a different device is said by
    /// [`SlaveRt::show_refused`]).
    pub(crate) fn show_failure(&mut self, failure: Option<Failure>, log: Option<&LogSink>) {
        if failure == self.failure_shown {
            return;
        }
        self.failure_shown = failure;
        match (log, failure) {
            (Some(log), Some(f)) if f != Failure::Refused => log.err(format_args!(
                "{}: not back in OP: {}; the master tries again every 500 ms",
                self.label,
                f.describe()
            )),
            _ => {}
        }
    }

    /// Says once why the slave stopped exchanging data (its outputs go
    /// to their safe values), or that it is back.
    fn log_health(&self, log: &LogSink, al_state: u8, healthy: bool, st: &ReadStatus) {
        let label = &self.label;
        if healthy {
            log.info(format_args!("{label}: back in OP, exchanging data"));
        } else if !st.link_up {
            log.err(format_args!(
                "{label}: link down ({} frames in a row lost); outputs safe",
                crate::master::LOST_LIMIT
            ));
        } else if al_state & al::STATE_MASK != al::OP {
            let flag = if al_state & al::ERROR != 0 {
                " with an AL error"
            } else {
                ""
            };
            log.err(format_args!(
                "{label}: in {}{flag}, not OP; outputs safe",
                al::name(al_state)
            ));
        } else {
            log.err(format_args!(
                "{label}: working counter {} of {}: a slave does not exchange its data; outputs safe",
                st.wkc, st.expected_wkc
            ));
        }
    }

    /// Forgets what its output pins last wrote, so the next cycle
    /// writes them all (see [`AnyPin`]: a host that links an output
    /// pin to a signal that keeps its own value is set right this way).
    pub(crate) fn rewrite_outputs(&mut self) {
        for p in self.state.0.iter().chain(self.pins.iter().map(|b| &b.pin)) {
            p.forget();
        }
        self.shown_state = None;
        self.seen_valid = false;
        for slot in &mut self.inputs {
            slot.last = None;
        }
    }

    /// Whether this slave's drive asked for a fault reset this cycle.
    pub(crate) fn wants_reset(&self) -> bool {
        self.drive.as_ref().is_some_and(|d| d.wants_reset())
    }

    /// The outputs of the safe state: a drive's disable, zeros elsewhere.
    pub(crate) fn safe(&mut self, outputs: &mut [u8]) {
        outputs.fill(0);
        if let Some(d) = &mut self.drive {
            d.safe(outputs);
        }
    }
}

/// The pin at `index` of a slave's pins, if the slave has it.
fn at<H: HalHost>(pins: &[Bound<H>], index: Option<usize>) -> Option<&AnyPin<H>> {
    index.and_then(|i| pins.get(i)).map(|b| &b.pin)
}

/// EL3102: `val` = `bias` + `scale` × raw / 32767.
fn analog_in<H: HalHost>(pins: &[Bound<H>], channels: &[AnalogInPins; 2]) {
    for c in channels {
        let p = |i| at(pins, i);
        if let (Some(raw), Some(val), Some(scale), Some(bias)) =
            (p(c.raw), p(c.val), p(c.scale), p(c.bias))
        {
            val.set(bias.get() + scale.get() * raw.get() / 32767.0);
        }
    }
}

/// EL4102: the duty cycle `value` × `scale` + `offset`, limited to
/// `min-dc`..`max-dc`, 0 while not enabled; `raw` = duty × 32767.
fn analog_out<H: HalHost>(pins: &[Bound<H>], channels: &[AnalogOutPins; 2]) {
    for c in channels {
        let p = |i| at(pins, i);
        let (Some(value), Some(scale), Some(offset), Some(lo), Some(hi)) = (
            p(c.value),
            p(c.scale),
            p(c.offset),
            p(c.min_dc),
            p(c.max_dc),
        ) else {
            continue;
        };
        let enabled = p(c.enable).is_some_and(AnyPin::is_set);
        let dc = if enabled {
            (value.get() * scale.get() + offset.get()).clamp(lo.get(), hi.get().max(lo.get()))
        } else {
            0.0
        };
        let raw = (dc * 32767.0).round();
        for (i, v) in [
            (c.curr_dc, dc),
            (c.raw, raw),
            (c.pos, f64::from(u8::from(dc > 0.0))),
            (c.neg, f64::from(u8::from(dc < 0.0))),
        ] {
            if let Some(pin) = p(i) {
                pin.set(v);
            }
        }
    }
}

/// A slave's bound pins: found by name at export ([`Named::index`]), by
/// that index in the cycle ([`Named::at`]).
pub(crate) struct Named<'a, H: HalHost>(&'a [Bound<H>]);

impl<H: HalHost> Named<'_, H> {
    /// The index of pin `name` (the part after the slave's name).
    pub(crate) fn index(&self, name: &str) -> Option<usize> {
        self.0.iter().position(|b| &*b.name == name)
    }

    /// The pin at `index`, found by [`Named::index`].
    pub(crate) fn at(&self, index: Option<usize>) -> Option<&AnyPin<H>> {
        at(self.0, index)
    }
}

fn load_error(e: Error) -> hal_core::HalError {
    hal_core::HalError::module_failed(pins::MODULE, e)
}

/// The role of `spec` on `slave` with `layout`.
fn role(
    slave: &crate::lcec::conf::Slave,
    spec: &PinSpec,
    all: &[PinSpec],
    layout: &Layout,
    file: &std::path::Path,
) -> Result<Role> {
    let Some(e) = spec.entry else {
        return Ok(Role::Computed);
    };
    // Catalogue values the type computes from their entries.
    let raw_of_value = (slave.kind == "EL4102" && spec.name.ends_with("-value"))
        .then(|| {
            let raw = spec.name.replace("-value", "-raw");
            all.iter().position(|p| p.name == raw)
        })
        .flatten();
    let computed =
        spec.coding.is_none() && (spec.ty == PinType::Float || slave.kind == "basic_cia402");
    if computed && raw_of_value.is_none() {
        return Ok(Role::Computed);
    }
    let output = matches!(spec.kind, Kind::In | Kind::Io | Kind::Param);
    let Some(m) = layout.find(e.index, e.sub, output) else {
        if spec.coding.is_some() {
            return Err(load_error(Error::Config {
                file: file.to_path_buf(),
                line: slave.line,
                element: "pdoEntry".into(),
                reason: format!(
                    "slave '{}' does not map entry {:#06x}:{:02x} of pin '{}' in its {}",
                    slave.name,
                    e.index,
                    e.sub,
                    spec.name,
                    if output { "outputs" } else { "inputs" }
                ),
            }));
        }
        return Ok(Role::Computed);
    };
    let suffix = spec.name.rsplit('-').next().unwrap_or("");
    let byte_bit = BYTE_BITS
        .iter()
        .find(|(k, s, _)| {
            *k == slave.kind && (spec.name == *s || (suffix == *s && spec.name.starts_with("ain-")))
        })
        .map(|t| t.2);
    let at = match byte_bit {
        Some(b) => Field {
            bit: m.bit + usize::from(b),
            bits: 1,
        },
        None => Field {
            bit: m.bit + usize::from(e.bit_offset),
            bits: e.field_bits.min(m.bits.max(1)),
        },
    };
    if let Some(source) = raw_of_value {
        return Ok(Role::OutputFrom { at, source });
    }
    let coding = spec.coding.unwrap_or_else(|| field::plain(spec.ty));
    Ok(if output {
        let invert = all
            .iter()
            .position(|p| p.name == format!("{}-invert", spec.name));
        Role::Output { at, coding, invert }
    } else {
        Role::Input {
            at,
            coding,
            invert: spec.name.ends_with("-not"),
        }
    })
}
