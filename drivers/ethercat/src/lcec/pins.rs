//! The pins and parameters `lcec` exports, as data: names, HAL types,
//! directions, initial values and the process-data entry each one is
//! read from or written to. Phase 2 (the `loadrt lcec` module) turns each
//! [`PinSpec`] into a HAL pin or parameter named [`full_name`]; the names
//! are linuxcnc-ethercat's, so an lcec user's HAL file finds them:
//!
//! * the global pins `lcec.<pin>` and each master's `lcec.<m>.<pin>`
//!   ([`master_pins`]): `slaves-responding`, `state-init`, `state-preop`,
//!   `state-safeop`, `state-op`, `link-up`, `all-op`; each master adds the
//!   working counter (`wkc`, `wkc-state`, `wkc-min`, `wkc-change-count`,
//!   `wkc-reset`), the DC drift (`dc-sync-diff`, `dc-sync-converged`,
//!   parameters `dc-sync-max`, `dc-sync-monitor`) and the time pair
//!   (`app-time-lo`/`-hi`: the cycle's DC application time,
//!   `mono-time-lo`/`-hi`: its CLOCK_MONOTONIC time) and, for
//!   `syncToRefClock`, the PLL (`pll-err`, `pll-out`,
//!   `pll-reset-count`, parameters `pll-step`, `pll-max-err`);
//! * every slave's state ([`slave_state_pins`]): `slave-online`,
//!   `slave-oper`, `slave-state-init`, `-preop`, `-safeop`, `-op`;
//! * what its type adds ([`slave_pins`]): `din-N`/`din-N-not` (EL1xxx),
//!   `dout-N` with parameter `dout-N-invert` (EL2xxx), `ain-N-*`
//!   (EL31x2), `aout-N-*` (EL41x2), `enc-*` (EL5101), `enc-*` and `srv-*`
//!   (EL7041), `srv-*` (CiA 402 drives), and for a `generic` slave one
//!   pin per `halPin` of its PDO entries and complex entries;
//! * the functions [`FUNCTIONS`] and each master's [`master_functions`].

use std::path::Path;

use crate::error::{Error, Result};
use crate::lcec::conf::{self, HalType};

/// The module name and the first part of every name.
pub const MODULE: &str = "lcec";

/// The functions of the whole module: read and write every master.
pub const FUNCTIONS: [&str; 2] = ["lcec.read-all", "lcec.write-all"];

/// A HAL type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PinType {
    /// `bit`.
    Bit,
    /// `s32`.
    S32,
    /// `u32`.
    U32,
    /// `float`.
    Float,
}

/// A pin's direction as HAL sees it, or a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A pin the driver reads (HAL_IN).
    In,
    /// A pin the driver writes (HAL_OUT).
    Out,
    /// A pin both write (HAL_IO): a handshake or a value the driver
    /// corrects (a scale of 0 becomes 1).
    Io,
    /// A read-write parameter (HAL_RW).
    Param,
}

/// A value of one of the [`PinType`]s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PinValue {
    /// A bit.
    Bit(bool),
    /// A signed 32-bit value.
    S32(i32),
    /// An unsigned 32-bit value.
    U32(u32),
    /// A float.
    Float(f64),
}

/// A process-data entry: what a pin reads or writes on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entry {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Bits of the entry.
    pub bits: u8,
    /// For a complex entry's field: its first bit within the entry.
    pub bit_offset: u8,
    /// Its bits (the entry's bits for a whole entry).
    pub field_bits: u8,
}

impl Entry {
    const fn whole(index: u16, sub: u8, bits: u8) -> Entry {
        Entry {
            index,
            sub,
            bits,
            bit_offset: 0,
            field_bits: bits,
        }
    }
}

/// How a generic pin's value is coded on the wire (`halType`, `scale`,
/// `offset` of the XML).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coding {
    /// The XML's type.
    pub hal_type: HalType,
    /// Value = raw × scale + offset (float types).
    pub scale: f64,
    /// See `scale`.
    pub offset: f64,
}

/// One pin or parameter of a slave, a master or the module.
#[derive(Debug, Clone, PartialEq)]
pub struct PinSpec {
    /// The part after `lcec.<master>.<slave>.` (or `lcec.[<master>.]`).
    pub name: String,
    /// HAL type.
    pub ty: PinType,
    /// Direction, or a parameter.
    pub kind: Kind,
    /// The value it starts with.
    pub initial: PinValue,
    /// The entry it comes from or goes to, where it maps to one
    /// directly; None for values the driver computes (scales, positions
    /// from counts, states).
    pub entry: Option<Entry>,
    /// For a generic slave's pin: how the entry codes the value.
    pub coding: Option<Coding>,
}

impl PinSpec {
    fn new(name: impl Into<String>, ty: PinType, kind: Kind) -> PinSpec {
        let initial = match ty {
            PinType::Bit => PinValue::Bit(false),
            PinType::S32 => PinValue::S32(0),
            PinType::U32 => PinValue::U32(0),
            PinType::Float => PinValue::Float(0.0),
        };
        PinSpec {
            name: name.into(),
            ty,
            kind,
            initial,
            entry: None,
            coding: None,
        }
    }

    fn at(mut self, e: Entry) -> PinSpec {
        self.entry = Some(e);
        self
    }

    fn starting(mut self, v: f64) -> PinSpec {
        self.initial = PinValue::Float(v);
        self
    }
}

/// `lcec.<master>.<slave>.<pin>`, or with `slave` None `lcec.<master>.<pin>`,
/// or with both None the global `lcec.<pin>`.
pub fn full_name(master: Option<&str>, slave: Option<&str>, pin: &str) -> String {
    let mut s = String::from(MODULE);
    for part in [master, slave].into_iter().flatten() {
        s.push('.');
        s.push_str(part);
    }
    s.push('.');
    s.push_str(pin);
    s
}

/// A master's functions: `lcec.<m>.read`, `lcec.<m>.write`.
pub fn master_functions(master: &str) -> [String; 2] {
    [
        full_name(Some(master), None, "read"),
        full_name(Some(master), None, "write"),
    ]
}

/// The pins of the module (`global`: `lcec.<pin>`) or of one master
/// (`lcec.<m>.<pin>`, which adds the working counter and DC drift).
pub fn master_pins(global: bool) -> Vec<PinSpec> {
    use PinType::*;
    let mut v = vec![PinSpec::new("slaves-responding", U32, Kind::Out)];
    for s in ["init", "preop", "safeop", "op"] {
        v.push(PinSpec::new(format!("state-{s}"), Bit, Kind::Out));
    }
    v.push(PinSpec::new("link-up", Bit, Kind::Out));
    v.push(PinSpec::new("all-op", Bit, Kind::Out));
    if !global {
        v.extend([
            PinSpec::new("wkc", U32, Kind::Out),
            PinSpec::new("wkc-state", S32, Kind::Out),
            PinSpec::new("wkc-min", U32, Kind::Out),
            PinSpec::new("wkc-change-count", U32, Kind::Out),
            PinSpec::new("wkc-reset", Bit, Kind::Io),
            PinSpec::new("dc-sync-diff", U32, Kind::Out),
            PinSpec::new("dc-sync-converged", Bit, Kind::Out),
            PinSpec::new("dc-sync-max", U32, Kind::Param),
            PinSpec {
                initial: PinValue::Bit(true),
                ..PinSpec::new("dc-sync-monitor", Bit, Kind::Param)
            },
            PinSpec::new("app-time-lo", U32, Kind::Out),
            PinSpec::new("app-time-hi", U32, Kind::Out),
            PinSpec::new("mono-time-lo", U32, Kind::Out),
            PinSpec::new("mono-time-hi", U32, Kind::Out),
            PinSpec::new("pll-err", S32, Kind::Out),
            PinSpec::new("pll-out", S32, Kind::Out),
            PinSpec::new("pll-reset-count", U32, Kind::Out),
            PinSpec::new("pll-step", U32, Kind::Param),
            PinSpec::new("pll-max-err", U32, Kind::Param),
        ]);
    }
    v
}

/// Every slave's state pins.
pub fn slave_state_pins() -> Vec<PinSpec> {
    let mut v = vec![
        PinSpec::new("slave-online", PinType::Bit, Kind::Out),
        PinSpec::new("slave-oper", PinType::Bit, Kind::Out),
    ];
    for s in ["init", "preop", "safeop", "op"] {
        v.push(PinSpec::new(
            format!("slave-state-{s}"),
            PinType::Bit,
            Kind::Out,
        ));
    }
    v
}

/// The slave types lcec knows that this crate supports, with what they
/// add to the state pins.
pub const SLAVE_TYPES: &[&str] = &[
    "EK1100",
    "EL1008",
    "EL1018",
    "EL2008",
    "EL2088",
    "EL3102",
    "EL4102",
    "EL5101",
    "EL7041",
    "basic_cia402",
    "generic",
];

/// The pins a slave's type adds to [`slave_state_pins`]; an error names
/// the configuration `file` and the slave's line for an unknown type or
/// a generic slave whose pins clash.
pub fn slave_pins(slave: &conf::Slave, file: &Path) -> Result<Vec<PinSpec>> {
    let pins = match slave.kind.as_str() {
        "EK1100" => Vec::new(),
        "EL1008" | "EL1018" => digital_inputs(8),
        "EL2008" | "EL2088" => digital_outputs(8),
        "EL3102" => analog_inputs(2),
        "EL4102" => analog_outputs(2),
        "EL5101" => encoder_el5101(),
        "EL7041" => stepper_el7041(),
        "basic_cia402" => cia402_drive(),
        "generic" => generic(slave)?,
        other => {
            return Err(unsupported(slave, other, file));
        }
    };
    let mut names: Vec<&str> = pins.iter().map(|p| p.name.as_str()).collect();
    names.sort_unstable();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        return Err(Error::Config {
            file: file.to_path_buf(),
            line: slave.line,
            element: "slave".into(),
            reason: format!("slave '{}': two pins named '{}'", slave.name, w[0]),
        });
    }
    Ok(pins)
}

fn unsupported(slave: &conf::Slave, kind: &str, file: &Path) -> Error {
    Error::Config {
        file: file.to_path_buf(),
        line: slave.line,
        element: "slave".into(),
        reason: format!(
            "type=\"{kind}\" of slave '{}' is not supported; supported: {}",
            slave.name,
            SLAVE_TYPES.join(", ")
        ),
    }
}

fn digital_inputs(n: u16) -> Vec<PinSpec> {
    (0..n)
        .flat_map(|i| {
            let e = Entry::whole(0x6000 + (i << 4), 1, 1);
            [
                PinSpec::new(format!("din-{i}"), PinType::Bit, Kind::Out).at(e),
                PinSpec::new(format!("din-{i}-not"), PinType::Bit, Kind::Out).at(e),
            ]
        })
        .collect()
}

fn digital_outputs(n: u16) -> Vec<PinSpec> {
    (0..n)
        .flat_map(|i| {
            let e = Entry::whole(0x7000 + (i << 4), 1, 1);
            [
                PinSpec::new(format!("dout-{i}"), PinType::Bit, Kind::In).at(e),
                PinSpec::new(format!("dout-{i}-invert"), PinType::Bit, Kind::Param),
            ]
        })
        .collect()
}

fn analog_inputs(n: u16) -> Vec<PinSpec> {
    use PinType::*;
    (0..n)
        .flat_map(|i| {
            let status = Entry::whole(0x3101 + i, 1, 8);
            let value = Entry::whole(0x3101 + i, 2, 16);
            let p = |s: &str, t, k| PinSpec::new(format!("ain-{i}-{s}"), t, k);
            [
                p("error", Bit, Kind::Out).at(status),
                p("overrange", Bit, Kind::Out).at(status),
                p("underrange", Bit, Kind::Out).at(status),
                p("raw", S32, Kind::Out).at(value),
                p("val", Float, Kind::Out).at(value),
                p("scale", Float, Kind::Io).starting(1.0),
                p("bias", Float, Kind::Io),
            ]
        })
        .collect()
}

fn analog_outputs(n: u16) -> Vec<PinSpec> {
    use PinType::*;
    (0..n)
        .flat_map(|i| {
            let value = Entry::whole(0x3001 + i, 1, 16);
            let p = |s: &str, t, k| PinSpec::new(format!("aout-{i}-{s}"), t, k);
            [
                p("scale", Float, Kind::Io).starting(1.0),
                p("offset", Float, Kind::Io),
                p("min-dc", Float, Kind::Io).starting(-1.0),
                p("max-dc", Float, Kind::Io).starting(1.0),
                p("curr-dc", Float, Kind::Out),
                p("enable", Bit, Kind::In),
                p("absmode", Bit, Kind::In),
                p("value", Float, Kind::In).at(value),
                p("raw", S32, Kind::Out),
                p("pos", Bit, Kind::Out),
                p("neg", Bit, Kind::Out),
            ]
        })
        .collect()
}

/// Pins from a table of (name, type, kind, entry).
fn table(rows: &[(&str, PinType, Kind, Option<Entry>)]) -> Vec<PinSpec> {
    rows.iter()
        .map(|&(n, t, k, e)| {
            let p = PinSpec::new(n, t, k);
            let p = if n.ends_with("scale") {
                p.starting(1.0)
            } else {
                p
            };
            match e {
                Some(e) => p.at(e),
                None => p,
            }
        })
        .collect()
}

const fn e(index: u16, sub: u8, bits: u8) -> Option<Entry> {
    Some(Entry::whole(index, sub, bits))
}

fn encoder_el5101() -> Vec<PinSpec> {
    use Kind::*;
    use PinType::*;
    table(&[
        ("enc-index-c-enable", Bit, Io, e(0x7000, 1, 8)),
        ("enc-index-ext-pos-enable", Bit, Io, e(0x7000, 1, 8)),
        ("enc-index-ext-neg-enable", Bit, Io, e(0x7000, 1, 8)),
        ("enc-reset", Bit, In, None),
        ("enc-inext", Bit, Out, e(0x6000, 1, 8)),
        ("enc-overflow", Bit, Out, e(0x6000, 1, 8)),
        ("enc-underflow", Bit, Out, e(0x6000, 1, 8)),
        ("enc-latch-c-valid", Bit, Out, e(0x6000, 1, 8)),
        ("enc-latch-ext-valid", Bit, Out, e(0x6000, 1, 8)),
        ("enc-set-raw-count", Bit, Io, e(0x7000, 1, 8)),
        ("enc-set-raw-count-val", S32, In, e(0x7000, 2, 16)),
        ("enc-raw-count", S32, Out, e(0x6000, 2, 16)),
        ("enc-count", S32, Out, None),
        ("enc-raw-latch", S32, Out, None),
        ("enc-raw-freq", U32, Out, e(0x6000, 4, 32)),
        ("enc-raw-period", U32, Out, e(0x6000, 5, 16)),
        ("enc-raw-window", U32, Out, e(0x6000, 6, 16)),
        ("enc-pos", Float, Out, None),
        ("enc-period", Float, Out, None),
        ("enc-frequency", Float, Out, None),
        ("enc-pos-scale", Float, Io, None),
        ("enc-frequency-scale", Float, Io, None),
    ])
    .into_iter()
    .map(|p| match p.name.as_str() {
        // lcec's default, kept for its users' configurations.
        "enc-frequency-scale" => p.starting(0.05),
        _ => p,
    })
    .collect()
}

fn stepper_el7041() -> Vec<PinSpec> {
    use Kind::*;
    use PinType::*;
    table(&[
        ("enc-reset", Bit, In, None),
        ("enc-ina", Bit, Out, e(0x6000, 0x09, 1)),
        ("enc-inb", Bit, Out, e(0x6000, 0x0A, 1)),
        ("enc-inc", Bit, Out, e(0x6000, 0x0B, 1)),
        ("enc-inext", Bit, Out, e(0x6000, 0x0D, 1)),
        ("enc-sync-error", Bit, Out, e(0x6000, 0x0E, 1)),
        ("enc-expol-stall", Bit, Out, e(0x6000, 0x08, 1)),
        ("enc-tx-toggle", Bit, Out, e(0x6000, 0x10, 1)),
        ("enc-count-overflow", Bit, Out, e(0x6000, 0x05, 1)),
        ("enc-count-underflow", Bit, Out, e(0x6000, 0x04, 1)),
        ("enc-latch-c-valid", Bit, Out, e(0x6000, 0x01, 1)),
        ("enc-latch-ext-valid", Bit, Out, e(0x6000, 0x02, 1)),
        ("enc-set-raw-count", Bit, Io, e(0x7000, 0x03, 1)),
        ("enc-latch-c-enable", Bit, Io, e(0x7000, 0x01, 1)),
        ("enc-index-ext-pos-enable", Bit, Io, e(0x7000, 0x02, 1)),
        ("enc-index-ext-neg-enable", Bit, Io, e(0x7000, 0x04, 1)),
        ("enc-set-raw-count-val", S32, In, e(0x7000, 0x11, 16)),
        ("enc-raw-count", S32, Out, e(0x6000, 0x11, 16)),
        ("enc-count", S32, Out, None),
        ("enc-raw-latch", S32, Out, None),
        ("enc-pos", Float, Out, None),
        ("enc-pos-scale", Float, Io, None),
        ("srv-scale", Float, Io, None),
        ("srv-offset", Float, Io, None),
        ("srv-min-dc", Float, Io, None),
        ("srv-max-dc", Float, Io, None),
        ("srv-curr-dc", Float, Out, None),
        ("srv-enable", Bit, In, e(0x7010, 0x01, 1)),
        ("srv-absmode", Bit, In, None),
        ("srv-cmd", Float, In, None),
        ("srv-raw-cmd", S32, Out, None),
        ("srv-reset", Bit, In, None),
        ("srv-reduce-torque", Bit, In, e(0x7010, 0x03, 1)),
        ("srv-ready-to-enable", Bit, Out, e(0x6010, 0x01, 1)),
        ("srv-ready", Bit, Out, e(0x6010, 0x02, 1)),
        ("srv-warning", Bit, Out, e(0x6010, 0x03, 1)),
        ("srv-error", Bit, Out, e(0x6010, 0x04, 1)),
        ("srv-move-pos", Bit, Out, e(0x6010, 0x05, 1)),
        ("srv-move-neg", Bit, Out, e(0x6010, 0x06, 1)),
        ("srv-torque-reduced", Bit, Out, e(0x6010, 0x07, 1)),
        ("srv-din1", Bit, Out, e(0x6010, 0x0C, 1)),
        ("srv-din2", Bit, Out, e(0x6010, 0x0D, 1)),
        ("srv-sync-error", Bit, Out, e(0x6010, 0x0E, 1)),
        ("srv-tx-toggle", Bit, Out, e(0x6010, 0x10, 1)),
        ("srv-fault", Bit, Out, None),
        ("srv-fault-reset", Bit, In, None),
    ])
    .into_iter()
    .map(|p| match p.name.as_str() {
        "srv-min-dc" => p.starting(-1.0),
        "srv-max-dc" => p.starting(1.0),
        _ => p,
    })
    .collect()
}

/// A CiA 402 drive over CoE: lcec's `srv-*` names for the objects, and
/// the shared power state machine behind `srv-enable` (hal-cia402, as
/// canservo drives its drives): `srv-fault` latches a drive fault, an
/// EMCY, a lost slave or an AL error, and `srv-fault-reset` clears it.
fn cia402_drive() -> Vec<PinSpec> {
    use Kind::*;
    use PinType::*;
    table(&[
        ("srv-enable", Bit, In, None),
        ("srv-enabled", Bit, Out, None),
        ("srv-fault", Bit, Out, None),
        ("srv-fault-reset", Bit, In, None),
        ("srv-fault-code", U32, Out, None),
        ("srv-error-code", U32, Out, e(0x603F, 0, 16)),
        ("srv-cia-controlword", U32, Out, e(0x6040, 0, 16)),
        ("srv-cia-statusword", U32, Out, e(0x6041, 0, 16)),
        ("srv-opmode", S32, Param, e(0x6060, 0, 8)),
        ("srv-opmode-display", S32, Out, e(0x6061, 0, 8)),
        ("srv-target-position", Float, In, e(0x607A, 0, 32)),
        ("srv-target-velocity", Float, In, e(0x60FF, 0, 32)),
        ("srv-actual-position", Float, Out, e(0x6064, 0, 32)),
        ("srv-actual-velocity", Float, Out, e(0x606C, 0, 32)),
        ("srv-pos-scale", Float, Io, None),
        ("srv-home", Bit, Io, None),
        ("srv-home-complete", Bit, Out, None),
    ])
}

/// A generic slave: a pin per `halPin` of its entries (a complex entry's
/// fields each their own), HAL_IN on output sync managers, HAL_OUT on
/// input ones.
fn generic(slave: &conf::Slave) -> Result<Vec<PinSpec>> {
    let mut pins = Vec::new();
    for sm in &slave.sync_managers {
        let kind = if sm.output { Kind::In } else { Kind::Out };
        for pe in sm.pdos.iter().flat_map(|p| &p.entries) {
            let whole = Entry::whole(pe.index, pe.sub, pe.bit_len);
            if let (Some(name), Some(t)) = (&pe.hal_pin, pe.hal_type) {
                if t != HalType::Complex {
                    pins.push(generic_pin(name, t, kind, whole, pe.scale, pe.offset));
                }
            }
            let mut at = 0u8;
            for ce in &pe.complex {
                if let (Some(name), Some(t)) = (&ce.hal_pin, ce.hal_type) {
                    let field = Entry {
                        bit_offset: at,
                        field_bits: ce.bit_len,
                        ..whole
                    };
                    pins.push(generic_pin(name, t, kind, field, ce.scale, ce.offset));
                }
                at = at.saturating_add(ce.bit_len);
            }
        }
    }
    Ok(pins)
}

fn generic_pin(
    name: &str,
    t: HalType,
    kind: Kind,
    entry: Entry,
    scale: f64,
    offset: f64,
) -> PinSpec {
    let ty = match t {
        HalType::Bit => PinType::Bit,
        HalType::S32 => PinType::S32,
        HalType::U32 => PinType::U32,
        _ => PinType::Float,
    };
    let mut p = PinSpec::new(name, ty, kind).at(entry);
    p.coding = Some(Coding {
        hal_type: t,
        scale,
        offset,
    });
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slave(xml_slave: &str) -> conf::Slave {
        let text = format!(
            "<masters><master idx=\"0\" appTimePeriod=\"1000000\" refClockSyncCycles=\"1\">{xml_slave}</master></masters>"
        );
        let c = conf::parse(&text, Path::new("t.xml")).unwrap();
        c.masters[0].slaves[0].clone()
    }

    fn names(v: &[PinSpec]) -> Vec<&str> {
        v.iter().map(|p| p.name.as_str()).collect()
    }

    #[test]
    fn global_master_and_slave_names() {
        assert_eq!(full_name(None, None, "all-op"), "lcec.all-op");
        assert_eq!(full_name(Some("0"), None, "link-up"), "lcec.0.link-up");
        assert_eq!(
            full_name(Some("0"), Some("D1"), "slave-state-op"),
            "lcec.0.D1.slave-state-op"
        );
        assert_eq!(master_functions("0"), ["lcec.0.read", "lcec.0.write"]);
        let g = master_pins(true);
        assert_eq!(
            names(&g),
            [
                "slaves-responding",
                "state-init",
                "state-preop",
                "state-safeop",
                "state-op",
                "link-up",
                "all-op"
            ]
        );
        assert!(names(&master_pins(false)).contains(&"dc-sync-diff"));
        assert_eq!(
            names(&slave_state_pins()),
            [
                "slave-online",
                "slave-oper",
                "slave-state-init",
                "slave-state-preop",
                "slave-state-safeop",
                "slave-state-op"
            ]
        );
    }

    #[test]
    fn terminals_have_lcec_names_and_types() {
        let d = slave_pins(
            &slave(r#"<slave idx="1" type="EL1008" name="in"/>"#),
            Path::new("t.xml"),
        )
        .unwrap();
        assert_eq!(names(&d)[..4], ["din-0", "din-0-not", "din-1", "din-1-not"]);
        assert_eq!(d[2].entry.unwrap().index, 0x6010);
        let o = slave_pins(
            &slave(r#"<slave idx="1" type="EL2008" name="out"/>"#),
            Path::new("t.xml"),
        )
        .unwrap();
        assert_eq!((o[14].name.as_str(), o[14].kind), ("dout-7", Kind::In));
        assert_eq!(
            (o[15].name.as_str(), o[15].kind),
            ("dout-7-invert", Kind::Param)
        );
        let a = slave_pins(
            &slave(r#"<slave idx="1" type="EL3102" name="a"/>"#),
            Path::new("t.xml"),
        )
        .unwrap();
        assert_eq!(a.len(), 14);
        assert_eq!(a[11].name, "ain-1-val");
        assert_eq!(a[12].initial, PinValue::Float(1.0));
        let q = slave_pins(
            &slave(r#"<slave idx="1" type="EL4102" name="q"/>"#),
            Path::new("t.xml"),
        )
        .unwrap();
        assert!(names(&q).contains(&"aout-1-curr-dc"));
        let s = slave_pins(
            &slave(r#"<slave idx="1" type="EL7041" name="x"/>"#),
            Path::new("t.xml"),
        )
        .unwrap();
        let cmd = s.iter().find(|p| p.name == "srv-cmd").unwrap();
        assert_eq!((cmd.ty, cmd.kind), (PinType::Float, Kind::In));
        let enc = slave_pins(
            &slave(r#"<slave idx="1" type="EL5101" name="e"/>"#),
            Path::new("t.xml"),
        )
        .unwrap();
        assert!(names(&enc).contains(&"enc-raw-freq"));
    }

    #[test]
    fn generic_pins_follow_the_xml() {
        let g = slave(
            r#"<slave idx="2" type="generic" vid="2" pid="3" name="g">
              <syncManager idx="2" dir="out"><pdo idx="1600">
                <pdoEntry idx="7000" subIdx="1" bitLen="16" halPin="cmd" halType="s32"/>
              </pdo></syncManager>
              <syncManager idx="3" dir="in"><pdo idx="1a00">
                <pdoEntry idx="6000" subIdx="1" bitLen="16" halType="complex">
                  <complexEntry bitLen="3"/>
                  <complexEntry bitLen="1" halPin="ready" halType="bit"/>
                  <complexEntry bitLen="12" halPin="level" halType="float" scale="0.5"/>
                </pdoEntry>
              </pdo></syncManager>
            </slave>"#,
        );
        let p = slave_pins(&g, Path::new("t.xml")).unwrap();
        assert_eq!(names(&p), ["cmd", "ready", "level"]);
        assert_eq!((p[0].ty, p[0].kind), (PinType::S32, Kind::In));
        assert_eq!((p[1].ty, p[1].kind), (PinType::Bit, Kind::Out));
        let level = p[2].entry.unwrap();
        assert_eq!((level.bit_offset, level.field_bits), (4, 12));
        assert_eq!(p[2].coding.unwrap().scale, 0.5);
    }

    #[test]
    fn unknown_types_and_clashing_names_are_errors_naming_the_line() {
        let e = slave_pins(
            &slave(r#"<slave idx="1" type="EL9999" name="z"/>"#),
            Path::new("t.xml"),
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("t.xml:1: <slave>: type=\"EL9999\""), "{e}");
        let twice = slave(
            r#"<slave idx="2" type="generic" vid="2" pid="3" name="g"><syncManager idx="3" dir="in"><pdo idx="1a00">
                <pdoEntry idx="6000" subIdx="1" bitLen="1" halPin="a" halType="bit"/>
                <pdoEntry idx="6000" subIdx="2" bitLen="1" halPin="a" halType="bit"/>
              </pdo></syncManager></slave>"#,
        );
        let e = slave_pins(&twice, Path::new("t.xml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("two pins named 'a'"), "{e}");
    }
}
