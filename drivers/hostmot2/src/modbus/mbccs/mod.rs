//! `mesambccc`'s compiler: LinuxCNC's XML command source (`.mbccs`) into
//! an [`Mbccb`]. The root `<mesamodbus>` holds the line settings, then
//! `<devices>` (first), `<initlist>` and `<commands>`. Numbers take
//! decimal, `0x`, `0o` and `0b` forms, booleans `true`/`false`/`1`/`0`
//! (and `t`/`f`), names of functions, types and parities any case. Pin
//! names become `<device>.<name>`, or `<device>.<name>-NN` for pins
//! made from a command's `count`. An automatic timeout is the request
//! and reply time at 2.5 characters per byte, doubled, plus 16 ms.
//! Every refusal names its line and column; warnings do too.

mod lists;

use roxmltree::{Document, Node};

use super::mbccb::{flags, format, pinf, HalType, Mbccb, ModbusType};
use super::rtu;

use crate::error::{Hm2Error, Result};

/// Longest delay, microseconds.
const MAX_DELAY: u64 = 60_000_000;
/// Longest interval, microseconds.
const MAX_INTERVAL: u64 = 3_600_000_000;
/// Longest pin name.
const MAX_PIN_NAME: usize = 24;

/// The line settings of `<mesamodbus>` or an init override.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Comms {
    baud: u32,
    parity: u8,
    stop_bits: u8,
    rxdelay: u16,
    txdelay: u16,
    drvdelay: u16,
    icdelay: u16,
}

const DEFAULT_COMMS: Comms = Comms {
    baud: 9600,
    parity: 2,
    stop_bits: 1,
    rxdelay: 0,
    txdelay: 0,
    drvdelay: 0,
    icdelay: 0,
};

struct Ctx<'a> {
    doc: &'a Document<'a>,
    warnings: Vec<String>,
    devices: Vec<(String, u8)>,
    comms: Comms,
    timeout: u32,
    interval: u32,
    writeflush: bool,
    pin_names: Vec<String>,
}

/// The result: the file, and the warnings (each with its line).
pub type Compiled = (Mbccb, Vec<String>);

/// Compiles `text`.
pub fn compile(text: &str) -> Result<Compiled> {
    let doc = Document::parse(text).map_err(|e| {
        let p = e.pos();
        Hm2Error::Mbccs {
            line: p.row,
            column: p.col,
            what: e.to_string(),
        }
    })?;
    let root = doc.root_element();
    let mut cx = Ctx {
        doc: &doc,
        warnings: Vec::new(),
        devices: vec![("broadcast".into(), 0)],
        comms: DEFAULT_COMMS,
        timeout: 0,
        interval: 0,
        writeflush: true,
        pin_names: Vec::new(),
    };
    if root.tag_name().name() != "mesamodbus" {
        return Err(cx.err(root, "expected the <mesamodbus> root tag".into()));
    }
    cx.check_attrs(
        root,
        &[
            "baudrate",
            "drivedelay",
            "duplex",
            "icdelay",
            "interval",
            "parity",
            "rxdelay",
            "stopbits",
            "suspend",
            "timeout",
            "txdelay",
            "writeflush",
        ],
    );
    let fmt = cx.header(root)?;
    let (mut inits, mut commands, mut seen_devices) = (None, None, false);
    for node in root.children().filter(Node::is_element) {
        match node.tag_name().name() {
            "devices" if !seen_devices => {
                cx.devices(node)?;
                seen_devices = true;
            }
            _ if !seen_devices => {
                return Err(cx.err(node, "the <devices> tag must come first".into()))
            }
            "initlist" if inits.is_none() => inits = Some(cx.inits(node)?),
            "commands" if commands.is_none() => commands = Some(cx.commands(node)?),
            t @ ("devices" | "initlist" | "commands") => {
                return Err(cx.err(node, format!("a second <{t}> tag")))
            }
            t => return Err(cx.err(node, format!("unknown tag <{t}>"))),
        }
    }
    let commands = commands.unwrap_or_default();
    if commands.is_empty() {
        return Err(cx.err(root, "no <commands> to run".into()));
    }
    let c = cx.comms;
    let file = Mbccb {
        baudrate: c.baud,
        format: fmt,
        txdelay: c.txdelay,
        rxdelay: c.rxdelay,
        drvdelay: c.drvdelay,
        icdelay: c.icdelay,
        inits: inits.unwrap_or_default(),
        commands,
        warnings: Vec::new(),
    };
    Ok((file, cx.warnings))
}

impl Ctx<'_> {
    /// `<mesamodbus>`'s settings: the line, suspend, duplex, the default
    /// writeflush, interval and timeout; returns the header's format bits.
    fn header(&mut self, root: Node) -> Result<u16> {
        self.comms = self.comms_of(root, DEFAULT_COMMS)?;
        let mut fmt = parity_format(self.comms.parity)
            | if self.comms.stop_bits == 2 {
                format::STOP_BITS2
            } else {
                0
            };
        match attr(root, "duplex").map(str::to_ascii_lowercase).as_deref() {
            None | Some("half") => {}
            Some("full") => fmt |= format::DUPLEX,
            Some(_) => {
                return Err(self.err(root, "attribute 'duplex' must be 'full' or 'half'".into()))
            }
        }
        if self.boolean(root, "suspend")?.unwrap_or(false) {
            fmt |= format::SUSPEND;
        }
        self.writeflush = self.boolean(root, "writeflush")?.unwrap_or(true);
        self.interval = match attr(root, "interval") {
            None => 0,
            Some(_) => self.int(root, "interval", 0, MAX_INTERVAL)? as u32,
        };
        self.timeout = match attr(root, "timeout") {
            None => 0,
            Some(v) if v.eq_ignore_ascii_case("auto") => 0,
            Some(_) => self.int(root, "timeout", 10_000, 10_000_000)? as u32,
        };
        Ok(fmt)
    }
}

fn attr<'a>(n: Node<'a, '_>, name: &str) -> Option<&'a str> {
    n.attribute(name)
}

fn parity_format(p: u8) -> u16 {
    match p {
        0 => 0,
        1 => format::PARITY_EN | format::PARITY_ODD,
        _ => format::PARITY_EN,
    }
}

/// A number in decimal, 0x, 0o or 0b form.
fn number(s: &str) -> Option<i128> {
    let t = s.trim();
    let (neg, t) = t.strip_prefix('-').map_or((false, t), |r| (true, r));
    let t = t.strip_prefix('+').unwrap_or(t);
    let lower = t.to_ascii_lowercase();
    let v = if let Some(h) = lower.strip_prefix("0x") {
        i128::from_str_radix(h, 16).ok()?
    } else if let Some(o) = lower.strip_prefix("0o") {
        i128::from_str_radix(o, 8).ok()?
    } else if let Some(b) = lower.strip_prefix("0b") {
        i128::from_str_radix(b, 2).ok()?
    } else {
        lower.parse::<i128>().ok()?
    };
    Some(if neg { -v } else { v })
}

/// A Modbus type by name (`U_AB`, `F_ABCD`, ...).
fn modbus_type(name: &str) -> Option<ModbusType> {
    const ORDERS: [&str; 14] = [
        "AB", "BA", "ABCD", "BADC", "CDAB", "DCBA", "ABCDEFGH", "BADCFEHG", "CDABGHEF", "DCBAHGFE",
        "EFGHABCD", "FEHGBADC", "GHEFCDAB", "HGFEDCBA",
    ];
    let up = name.to_ascii_uppercase();
    let (kind, order) = up.split_once('_')?;
    let k = match kind {
        "U" => 0,
        "S" => 1,
        "F" => 2,
        _ => return None,
    };
    let o = ORDERS.iter().position(|x| *x == order)? as u8;
    Some(ModbusType(k << 4 | o))
}

fn hal_type(name: &str) -> Option<HalType> {
    let up = name.to_ascii_uppercase();
    Some(match up.strip_prefix("HAL_").unwrap_or(&up) {
        "BIT" => HalType::Bit,
        "FLOAT" => HalType::Float,
        "S32" => HalType::S32,
        "U32" => HalType::U32,
        "S64" => HalType::S64,
        "U64" => HalType::U64,
        _ => return None,
    })
}

fn function(name: &str) -> Option<u8> {
    const NAMES: [(&str, u8); 8] = [
        ("R_COILS", 1),
        ("R_INPUTS", 2),
        ("R_REGISTERS", 3),
        ("R_INPUTREGS", 4),
        ("W_COIL", 5),
        ("W_REGISTER", 6),
        ("W_COILS", 15),
        ("W_REGISTERS", 16),
    ];
    let up = name.to_ascii_uppercase();
    NAMES
        .iter()
        .find(|(n, _)| *n == up)
        .map(|(_, f)| *f)
        .or_else(|| {
            number(name)
                .and_then(|v| u8::try_from(v).ok())
                .filter(|f| rtu::supported(*f))
        })
}

fn valid_name(s: &str) -> bool {
    !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'.' || b == b'-')
}

impl Ctx<'_> {
    fn pos(&self, n: Node) -> (u32, u32) {
        let p = self.doc.text_pos_at(n.range().start);
        (p.row, p.col)
    }

    fn err(&self, n: Node, what: String) -> Hm2Error {
        let (line, column) = self.pos(n);
        Hm2Error::Mbccs { line, column, what }
    }

    fn warn(&mut self, n: Node, what: String) {
        let (line, col) = self.pos(n);
        self.warnings
            .push(format!("line {line}, column {col}: {what}"));
    }

    fn check_attrs(&mut self, n: Node, allowed: &[&str]) {
        for a in n.attributes() {
            if !allowed.contains(&a.name()) {
                self.warn(n, format!("unrecognized attribute '{}'", a.name()));
            }
        }
    }

    fn int(&self, n: Node, name: &str, min: i128, max: u64) -> Result<i128> {
        let v = attr(n, name).ok_or_else(|| self.err(n, format!("attribute '{name}' missing")))?;
        let x = number(v)
            .ok_or_else(|| self.err(n, format!("attribute '{name}': '{v}' is not an integer")))?;
        if x < min || x > i128::from(max) {
            return Err(self.err(
                n,
                format!("attribute '{name}' is {x}, must be {min}..={max}"),
            ));
        }
        Ok(x)
    }

    fn boolean(&self, n: Node, name: &str) -> Result<Option<bool>> {
        Ok(
            match attr(n, name).map(str::to_ascii_lowercase).as_deref() {
                None => None,
                Some("1" | "true" | "t") => Some(true),
                Some("0" | "false" | "f") => Some(false),
                Some(v) => {
                    return Err(self.err(
                        n,
                        format!("attribute '{name}': expected a boolean, not '{v}'"),
                    ))
                }
            },
        )
    }

    /// `auto` (0) or a number in `1..=max`.
    fn auto(&self, n: Node, name: &str, max: u64) -> Result<u16> {
        match attr(n, name) {
            None => Ok(0),
            Some(v) if v.eq_ignore_ascii_case("auto") => Ok(0),
            Some(_) => Ok(self.int(n, name, 1, max)? as u16),
        }
    }

    fn comms_of(&self, n: Node, base: Comms) -> Result<Comms> {
        let parity = match attr(n, "parity").map(str::to_ascii_uppercase).as_deref() {
            None => base.parity,
            Some("N") => 0,
            Some("O") => 1,
            Some("E") => 2,
            Some(_) => return Err(self.err(n, "attribute 'parity' must be 'E', 'O' or 'N'".into())),
        };
        Ok(Comms {
            baud: if attr(n, "baudrate").is_some() {
                self.int(n, "baudrate", 1200, 1_000_000)? as u32
            } else {
                base.baud
            },
            parity,
            stop_bits: if attr(n, "stopbits").is_some() {
                self.int(n, "stopbits", 1, 2)? as u8
            } else {
                base.stop_bits
            },
            rxdelay: self.auto(n, "rxdelay", 1020)?,
            txdelay: self.auto(n, "txdelay", 1020)?,
            drvdelay: self.auto(n, "drivedelay", 31)?,
            icdelay: self.auto(n, "icdelay", 255)?,
        })
    }

    fn devices(&mut self, node: Node) -> Result<()> {
        for d in node.children().filter(Node::is_element) {
            if d.tag_name().name() != "device" {
                return Err(self.err(d, "expected <device> in <devices>".into()));
            }
            self.check_attrs(d, &["address", "name"]);
            let name =
                attr(d, "name").ok_or_else(|| self.err(d, "attribute 'name' missing".into()))?;
            if !valid_name(name) || name.len() > MAX_PIN_NAME {
                return Err(self.err(d, format!("device name '{name}': lower case letters, digits, '.' and '-', at most {MAX_PIN_NAME}")));
            }
            let address = self.int(d, "address", 1, 255)? as u8;
            if address > 247 {
                self.warn(
                    d,
                    format!("address {address} is a Modbus reserved value (1..247)"),
                );
            }
            if let Some((other, _)) = self
                .devices
                .iter()
                .find(|(n, a)| n == name || *a == address)
            {
                return Err(self.err(
                    d,
                    format!("device '{name}' at {address} clashes with '{other}'"),
                ));
            }
            self.devices.push((name.to_string(), address));
        }
        if self.devices.len() < 2 {
            self.warn(node, "no devices defined other than broadcast".into());
        }
        Ok(())
    }

    fn device(&self, n: Node) -> Result<(String, u8)> {
        let name =
            attr(n, "device").ok_or_else(|| self.err(n, "attribute 'device' missing".into()))?;
        self.devices
            .iter()
            .find(|(d, _)| d == name)
            .cloned()
            .ok_or_else(|| self.err(n, format!("device '{name}' is not in <devices>")))
    }

    fn function(&self, n: Node) -> Result<u8> {
        let f = attr(n, "function")
            .ok_or_else(|| self.err(n, "attribute 'function' missing".into()))?;
        function(f).ok_or_else(|| self.err(n, format!("function '{f}' is not supported")))
    }

    /// The command's timeout: `timeout`, `timeoutbits`, or the default;
    /// 0 for automatic.
    fn timeout(&mut self, n: Node) -> Result<u32> {
        if let Some(v) = attr(n, "timeout") {
            if attr(n, "timeoutbits").is_some() {
                self.warn(
                    n,
                    "attribute 'timeout' has preference over 'timeoutbits'".into(),
                );
            }
            if v.eq_ignore_ascii_case("auto") {
                return Ok(0);
            }
            return Ok(self.int(n, "timeout", 1, MAX_DELAY)? as u32);
        }
        if attr(n, "timeoutbits").is_some() {
            let bits = self.int(n, "timeoutbits", 0, 1_000_000)? as u64;
            return Ok((bits * 1_000_000).div_ceil(u64::from(self.comms.baud)) as u32);
        }
        Ok(self.timeout)
    }

    /// The automatic timeout of an exchange moving `count` coils or
    /// registers.
    fn auto_timeout(&self, func: u8, count: usize, c: &Comms) -> u32 {
        let n = match func {
            1 | 2 => 8 + 5 + count.div_ceil(8),
            15 => 9 + count.div_ceil(8) + 8,
            3 | 4 => 8 + 3 + count * 2,
            5 | 6 => 16,
            _ => 9 + count * 2 + 8,
        };
        let per_char = 10 + u64::from(c.parity != 0) + u64::from(c.stop_bits == 1);
        let bits = (per_char * n as u64) as f64 * 2.5;
        let baud = f64::from(c.baud);
        ((2.0 * bits * 1_000_000.0 + baud - 1.0) / baud) as u32 + 16_000
    }

    fn cmd_flags(&self, n: Node, dev: &str, base: u16) -> Result<u16> {
        let mut f = base;
        for (name, bit) in [
            ("timesout", flags::TIMESOUT),
            ("bcanswer", flags::BCANSWER),
            ("noanswer", flags::NOANSWER),
            ("resend", flags::RESEND),
            ("writeflush", flags::WFLUSH),
        ] {
            match self.boolean(n, name)? {
                Some(true) => f |= bit,
                Some(false) => f &= !bit,
                None => {}
            }
        }
        if dev != "broadcast" && f & flags::BCANSWER != 0 {
            return Err(self.err(n, format!("'bcanswer' on non-broadcast target '{dev}'")));
        }
        Ok(f)
    }

    fn pin_flags(&self, n: Node, base: u8) -> Result<u8> {
        let mut f = base;
        for (name, bit) in [("scale", pinf::SCALE), ("clamp", pinf::CLAMP)] {
            match self.boolean(n, name)? {
                Some(true) => f |= bit,
                Some(false) => f &= !bit,
                None => {}
            }
        }
        Ok(f)
    }
}
