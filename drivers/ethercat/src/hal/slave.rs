//! One slave's pins on its part of the process image: each pin with an
//! entry is bound to the entry's bits in the slave's layout; what a type
//! computes beyond the bits (inverted inputs and outputs, analog scaling,
//! counters) is here too; CiA 402 drives have [`super::drive`].

use hal_core::{HalHost, PinFactory, Result};
use hal_driver::LogSink;

use super::any_pin::AnyPin;
use super::drive::DriveRt;
use super::field::{self, Field};
use crate::error::Error;
use crate::lcec::pins::{self, Coding, Kind, PinSpec, PinType};
use crate::master::{Layout, ReadStatus};
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

struct Bound<H: HalHost> {
    spec: PinSpec,
    pin: AnyPin<H>,
    role: Role,
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
    kind: String,
    state: StatePins<H>,
    pins: Vec<Bound<H>>,
    drive: Option<Box<DriveRt>>,
    /// EL5101/EL7041: the counter extended past 16 bits.
    count: Counter,
}

#[derive(Default)]
struct Counter {
    last_raw: Option<i16>,
    count: i64,
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
                spec: spec.clone(),
                pin,
                role,
            });
        }
        let drive = if slave.kind == "basic_cia402" {
            Some(Box::new(DriveRt::new(
                format!("{} (slave {})", name("srv"), slave.index),
                slave,
                layout,
                file,
            )?))
        } else {
            None
        };
        Ok(SlaveRt {
            index,
            label: pins::full_name(Some(master), None, &slave.name),
            was_healthy: true,
            kind: slave.kind.clone(),
            state,
            pins: bound,
            drive,
            count: Counter::default(),
        })
    }

    /// A cycle's reception: state pins, then every input.
    pub(crate) fn read(
        &mut self,
        inputs: &[u8],
        al_state: u8,
        healthy: bool,
        status: &ReadStatus,
        log: Option<&LogSink>,
    ) {
        if healthy != self.was_healthy {
            self.was_healthy = healthy;
            if let Some(log) = log {
                self.log_health(log, al_state, healthy, status);
            }
        }
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
        for b in &self.pins {
            if let Role::Input { at, coding, invert } = &b.role {
                let mut v = field::decode(coding, at.read(inputs), at.bits);
                if *invert {
                    v = f64::from(u8::from(v == 0.0));
                }
                b.pin.set(v);
            }
        }
        match self.kind.as_str() {
            "EL3102" => self.analog_in(),
            "EL5101" | "EL7041" => self.counter(),
            _ => {}
        }
        if let Some(d) = &mut self.drive {
            d.read(inputs, healthy, &Named(&self.pins), log);
        }
    }

    /// A cycle's transmission into the slave's outputs.
    pub(crate) fn write(&mut self, outputs: &mut [u8], now_ns: u64) {
        if self.kind == "EL4102" {
            self.analog_out();
        }
        for b in &self.pins {
            match &b.role {
                Role::Output { at, coding, invert } => {
                    let mut v = b.pin.get();
                    if invert.is_some_and(|i| self.pins[i].pin.is_set()) {
                        v = f64::from(u8::from(v == 0.0));
                    }
                    at.write(outputs, field::encode(coding, v, at.bits));
                }
                Role::OutputFrom { at, source } => {
                    let v = self.pins[*source].pin.get();
                    at.write(
                        outputs,
                        field::encode(&field::plain(PinType::S32), v, at.bits),
                    );
                }
                _ => {}
            }
        }
        if let Some(d) = &mut self.drive {
            d.write(outputs, now_ns, &Named(&self.pins));
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

    fn pin(&self, name: &str) -> Option<&AnyPin<H>> {
        self.pins
            .iter()
            .find(|b| b.spec.name == name)
            .map(|b| &b.pin)
    }

    /// EL3102: `val` = `bias` + `scale` × raw / 32767.
    fn analog_in(&self) {
        for i in 0..2 {
            let p = |s: &str| self.pin(&format!("ain-{i}-{s}"));
            if let (Some(raw), Some(val), Some(scale), Some(bias)) =
                (p("raw"), p("val"), p("scale"), p("bias"))
            {
                val.set(bias.get() + scale.get() * raw.get() / 32767.0);
            }
        }
    }

    /// EL4102: the duty cycle `value` × `scale` + `offset`, limited to
    /// `min-dc`..`max-dc`, 0 while not enabled; `raw` = duty × 32767.
    fn analog_out(&self) {
        for i in 0..2 {
            let p = |s: &str| self.pin(&format!("aout-{i}-{s}"));
            let (Some(value), Some(scale), Some(offset), Some(lo), Some(hi)) = (
                p("value"),
                p("scale"),
                p("offset"),
                p("min-dc"),
                p("max-dc"),
            ) else {
                continue;
            };
            let enabled = p("enable").is_some_and(AnyPin::is_set);
            let dc = if enabled {
                (value.get() * scale.get() + offset.get()).clamp(lo.get(), hi.get().max(lo.get()))
            } else {
                0.0
            };
            let raw = (dc * 32767.0).round();
            for (s, v) in [
                ("curr-dc", dc),
                ("raw", raw),
                ("pos", f64::from(u8::from(dc > 0.0))),
                ("neg", f64::from(u8::from(dc < 0.0))),
            ] {
                if let Some(pin) = p(s) {
                    pin.set(v);
                }
            }
        }
    }

    /// EL5101, EL7041: the 16-bit counter extended, and the position.
    fn counter(&mut self) {
        let Some(raw) = self.pin("enc-raw-count").map(|p| p.get() as i64 as i16) else {
            return;
        };
        let reset = self.pin("enc-reset").is_some_and(AnyPin::is_set);
        let c = &mut self.count;
        match c.last_raw {
            Some(last) if !reset => c.count += i64::from(raw.wrapping_sub(last)),
            _ => c.count = 0,
        }
        c.last_raw = Some(raw);
        let count = c.count;
        let scale = self.pin("enc-pos-scale").map_or(1.0, |s| s.get());
        let scale = if scale.abs() < 1e-20 { 1.0 } else { scale };
        if let Some(p) = self.pin("enc-count") {
            p.set(count as f64);
        }
        if let Some(p) = self.pin("enc-pos") {
            p.set(count as f64 / scale);
        }
    }
}

/// A slave's bound pins, found by name.
pub(crate) struct Named<'a, H: HalHost>(&'a [Bound<H>]);

impl<H: HalHost> Named<'_, H> {
    /// The pin `name` (the part after the slave's name).
    pub(crate) fn get(&self, name: &str) -> Option<&AnyPin<H>> {
        self.0.iter().find(|b| b.spec.name == name).map(|b| &b.pin)
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
