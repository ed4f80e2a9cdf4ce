//! `<initlist>` and `<commands>`.

use roxmltree::Node;

use super::{
    attr, hal_type, modbus_type, parity_format, valid_name, Comms, Ctx, DEFAULT_COMMS, MAX_DELAY,
    MAX_INTERVAL, MAX_PIN_NAME,
};
use crate::error::Result;
use crate::modbus::mbccb::{flags, pinf, Command, HalType, Init, ModbusType, PinSpec};
use crate::modbus::values::{encode, Send};

const RATE_ATTRS: [&str; 7] = [
    "baudrate",
    "drivedelay",
    "icdelay",
    "parity",
    "rxdelay",
    "stopbits",
    "txdelay",
];

fn is_write(f: u8) -> bool {
    matches!(f, 5 | 6 | 15 | 16)
}

fn is_bits(f: u8) -> bool {
    matches!(f, 1 | 2 | 5 | 15)
}

fn max_count(f: u8) -> usize {
    match f {
        1 | 2 | 15 => 2000,
        5 | 6 => 1,
        _ => 125,
    }
}

fn comms_init(c: &Comms) -> Init {
    let p = parity_format(c.parity);
    let mut f = 0;
    if p & super::format::PARITY_EN != 0 {
        f |= flags::PARITY_EN;
    }
    if p & super::format::PARITY_ODD != 0 {
        f |= flags::PARITY_ODD;
    }
    if c.stop_bits == 2 {
        f |= flags::STOP_BITS2;
    }
    Init::Comms {
        baud: c.baud,
        flags: f,
        rxdelay: c.rxdelay,
        txdelay: c.txdelay,
        drvdelay: c.drvdelay,
        icdelay: c.icdelay.into(),
    }
}

impl Ctx<'_> {
    fn children<'a, 'i>(&self, n: Node<'a, 'i>, tag: &str) -> Result<Vec<Node<'a, 'i>>> {
        let mut v = Vec::new();
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "description" => {}
                t if t == tag => v.push(c),
                t => return Err(self.err(c, format!("expected <{tag}>, not <{t}>"))),
            }
        }
        Ok(v)
    }

    pub(super) fn inits(&mut self, node: Node) -> Result<Vec<Init>> {
        let mut out = Vec::new();
        let mut cur = self.comms;
        for cmd in self.children(node, "command")? {
            if attr(cmd, "delay").is_some() {
                self.check_attrs(cmd, &["delay"]);
                out.push(Init::Delay {
                    us: self.int(cmd, "delay", 0, MAX_DELAY)? as u32,
                });
                continue;
            }
            if cmd.attributes().any(|a| RATE_ATTRS.contains(&a.name())) {
                self.check_attrs(cmd, &RATE_ATTRS);
                cur = self.comms_of(cmd, DEFAULT_COMMS)?;
                out.push(comms_init(&cur));
                continue;
            }
            self.check_attrs(
                cmd,
                &[
                    "address",
                    "bcanswer",
                    "count",
                    "delay",
                    "device",
                    "function",
                    "noanswer",
                    "timeout",
                    "timeoutbits",
                    "timesout",
                ],
            );
            out.push(self.init_packet(cmd, &cur)?);
        }
        if cur != self.comms {
            self.warn(
                node,
                "communication overrides do not return to the defaults: a return to them is added"
                    .into(),
            );
            out.push(comms_init(&self.comms));
        }
        Ok(out)
    }

    fn init_packet(&mut self, cmd: Node, cur: &Comms) -> Result<Init> {
        let (dev, mbid) = self.device(cmd)?;
        let fl = self.cmd_flags(cmd, &dev, 0)?;
        let mut timeout = self.timeout(cmd)?;
        let func = self.function(cmd)?;
        let addr = self.int(cmd, "address", 0, 65535)? as u16;
        let mut data: Vec<u8> = Vec::new();
        let mut bits = 0usize;
        for d in self.children(cmd, "data")? {
            if !is_write(func) {
                return Err(self.err(d, "only write functions take <data>".into()));
            }
            self.check_attrs(d, &["modbustype", "value"]);
            bits += self.init_value(d, func, &mut data)?;
        }
        let count = match func {
            15 => bits,
            5 | 6 | 16 => data.len() / 2,
            2 if attr(cmd, "count").is_none() => 1,
            _ => self.int(cmd, "count", 1, 2000)? as usize,
        };
        if count < 1 || count > max_count(func) || addr as usize + count > 65536 {
            return Err(self.err(
                cmd,
                format!(
                    "count {count} out of range [1..{}] for function {func} at address {addr}",
                    max_count(func)
                ),
            ));
        }
        if timeout == 0 {
            timeout = self.auto_timeout(func, count, cur);
        }
        let mut pdu = vec![mbid, func];
        pdu.extend_from_slice(&addr.to_be_bytes());
        match func {
            5 | 6 => pdu.extend_from_slice(&data),
            15 => {
                pdu.extend_from_slice(&(count as u16).to_be_bytes());
                pdu.push(count.div_ceil(8) as u8);
                let mut packed = vec![0u8; count.div_ceil(8)];
                for (i, b) in data.iter().enumerate() {
                    packed[i / 8] |= (b & 1) << (i % 8);
                }
                pdu.extend_from_slice(&packed);
            }
            16 => {
                pdu.extend_from_slice(&(count as u16).to_be_bytes());
                pdu.push(data.len() as u8);
                pdu.extend_from_slice(&data);
            }
            _ => pdu.extend_from_slice(&(count as u16).to_be_bytes()),
        }
        if pdu.len() > 254 {
            return Err(self.err(
                cmd,
                format!(
                    "the request is {} bytes, more than Modbus allows",
                    pdu.len()
                ),
            ));
        }
        Ok(Init::Packet {
            mbid,
            func,
            flags: fl,
            timeout_us: timeout,
            pdu,
        })
    }

    /// One `<data>` value appended to `out`; returns 1 for a W_COILS bit.
    fn init_value(&mut self, d: Node, func: u8, out: &mut Vec<u8>) -> Result<usize> {
        let t = match attr(d, "modbustype") {
            None => ModbusType(0),
            Some(n) => {
                modbus_type(n).ok_or_else(|| self.err(d, format!("unknown modbustype '{n}'")))?
            }
        };
        let v = attr(d, "value").ok_or_else(|| self.err(d, "attribute 'value' missing".into()))?;
        if func == 15 {
            if attr(d, "modbustype").is_some() {
                return Err(self.err(d, "W_COILS data takes no modbustype".into()));
            }
            let b = self.int(d, "value", 0, 1)? as u8;
            out.push(b);
            return Ok(1);
        }
        if func == 6 && t.regs() != 1 || func == 5 && t != ModbusType(0) {
            return Err(self.err(
                d,
                "single writes take a 16-bit modbustype (W_COIL: U_AB)".into(),
            ));
        }
        let mut buf = [0u8; 8];
        let n = 2 * t.regs() as usize;
        if t.kind() == 2 {
            let f: f64 = v
                .trim()
                .parse()
                .map_err(|_| self.err(d, format!("'{v}' is not a number")))?;
            let lim = match n {
                2 => 65504.0,
                4 => 3.4e38,
                _ => 1.7e308,
            };
            if f.is_nan() || f.abs() > lim {
                return Err(self.err(d, format!("value {v} out of range for {n}-byte float")));
            }
            encode(t, Send::F(f), true, &mut buf[..n]);
        } else {
            let bits = 8 * n as u32;
            let (lo, hi): (i128, i128) = if t.kind() == 1 {
                (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
            } else {
                (0, (1i128 << bits) - 1)
            };
            let x =
                super::number(v).ok_or_else(|| self.err(d, format!("'{v}' is not an integer")))?;
            if x < lo || x > hi {
                return Err(self.err(d, format!("value {x} out of range [{lo},{hi}]")));
            }
            if func == 5 && x != 0 && x != 0xFF00 {
                self.warn(d, format!("W_COIL value {x} is normally 0 or 0xff00"));
            }
            let s = if t.kind() == 1 {
                Send::S(x as i64)
            } else {
                Send::U(x as u64)
            };
            encode(t, s, false, &mut buf[..n]);
        }
        out.extend_from_slice(&buf[..n]);
        Ok(0)
    }

    pub(super) fn commands(&mut self, node: Node) -> Result<Vec<Command>> {
        let mut out = Vec::new();
        for cmd in self.children(node, "command")? {
            if attr(cmd, "delay").is_some() {
                self.check_attrs(cmd, &["delay"]);
                let us = self.int(cmd, "delay", 0, MAX_DELAY)? as u32;
                out.push(Command {
                    mbid: 0,
                    func: 0,
                    flags: 0,
                    addr: 0,
                    regcnt: 0,
                    interval_us: 0,
                    timeout_us: us,
                    pins: Vec::new(),
                });
                continue;
            }
            self.check_attrs(
                cmd,
                &[
                    "address",
                    "bcanswer",
                    "clamp",
                    "count",
                    "delay",
                    "device",
                    "function",
                    "haltype",
                    "interval",
                    "modbustype",
                    "name",
                    "noanswer",
                    "resend",
                    "scale",
                    "timeout",
                    "timeoutbits",
                    "timesout",
                    "writeflush",
                ],
            );
            out.push(self.command(cmd)?);
        }
        Ok(out)
    }

    fn command(&mut self, cmd: Node) -> Result<Command> {
        let (dev, mbid) = self.device(cmd)?;
        let timeout = self.timeout(cmd)?;
        let interval = match attr(cmd, "interval") {
            None => self.interval,
            Some(v) if v.eq_ignore_ascii_case("once") => u32::MAX,
            Some(_) => self.int(cmd, "interval", 0, MAX_INTERVAL)? as u32,
        };
        let addr = self.int(cmd, "address", 0, 65535)? as u16;
        let func = self.function(cmd)?;
        if dev == "broadcast" && !is_write(func) {
            return Err(self.err(cmd, format!("function {func} cannot be broadcast")));
        }
        let count = if matches!(func, 5 | 6) {
            1
        } else if attr(cmd, "count").is_some() {
            self.int(cmd, "count", 1, 2000)? as usize
        } else {
            0
        };
        let (def_m, def_h) = self.command_types(cmd, func)?;
        let (cflags, pflags) = self.command_flags(cmd, &dev, func, interval, def_h)?;
        let name = attr(cmd, "name");
        if let Some(n) = name {
            if !valid_name(n) || n.len() > MAX_PIN_NAME - 3 {
                let max = MAX_PIN_NAME - 3;
                let why =
                    format!("name '{n}': lower case letters, digits, '.' and '-', at most {max}");
                return Err(self.err(cmd, why));
            }
        }
        let defs = (def_m, def_h, pflags);
        let (mut pins, regofs) = self.pins(cmd, func, &dev, name, defs)?;
        let count = if count == 0 { pins.len() } else { count };
        if count == 0 || pins.len() > count {
            let why = format!("{} <pin> tags for a count of {count}", pins.len());
            return Err(self.err(cmd, why));
        }
        let regofs = self.fill_pins(cmd, (func, &dev, name, count), defs, &mut pins, regofs)?;
        let max = max_count(func);
        if regofs > max || count > max || addr as usize + regofs > 65536 {
            let why = format!(
                "{count} pins in {regofs} registers out of range [1..{max}] at address {addr}"
            );
            return Err(self.err(cmd, why));
        }
        if is_bits(func) {
            // Coils have no type table: their place is their index.
            pins.iter_mut().for_each(|p| p.regofs = 0);
        }
        let timeout_us = match timeout {
            0 => self.auto_timeout(func, regofs, &self.comms),
            t => t,
        };
        let regcnt = regofs as u16;
        Ok(Command {
            mbid,
            func,
            flags: cflags,
            addr,
            regcnt,
            interval_us: interval,
            timeout_us,
            pins,
        })
    }

    /// The command's default Modbus and HAL types (bit for coils).
    fn command_types(&self, cmd: Node, func: u8) -> Result<(Option<ModbusType>, Option<HalType>)> {
        if is_bits(func) {
            return Ok((Some(ModbusType(0)), Some(HalType::Bit)));
        }
        let m = match attr(cmd, "modbustype") {
            None => None,
            Some(n) => Some(
                modbus_type(n).ok_or_else(|| self.err(cmd, format!("unknown modbustype '{n}'")))?,
            ),
        };
        let h = match attr(cmd, "haltype") {
            None => None,
            Some(n) => {
                Some(hal_type(n).ok_or_else(|| self.err(cmd, format!("unknown haltype '{n}'")))?)
            }
        };
        if func == 6 && m.is_some_and(|m| m.regs() != 1) {
            return Err(self.err(cmd, "W_REGISTER needs a 16-bit modbustype".into()));
        }
        Ok((m, h))
    }

    /// The command's flags and its pins' default flags: writeflush from
    /// `<mesamodbus>` (writes only), scale for floats, clamp for
    /// registers, each overridable.
    fn command_flags(
        &mut self,
        cmd: Node,
        dev: &str,
        func: u8,
        interval: u32,
        def_h: Option<HalType>,
    ) -> Result<(u16, u8)> {
        let base_c = if self.writeflush { flags::WFLUSH } else { 0 };
        let mut cflags = self.cmd_flags(cmd, dev, base_c)?;
        let mut base_p = if def_h == Some(HalType::Float) {
            pinf::SCALE
        } else {
            0
        };
        if !is_bits(func) {
            base_p |= pinf::CLAMP;
        }
        let mut pflags = self.pin_flags(cmd, base_p)?;
        if matches!(def_h, Some(HalType::U32 | HalType::U64 | HalType::Bit)) {
            pflags &= !pinf::SCALE;
        }
        if cflags & flags::RESEND != 0 && interval == u32::MAX {
            return Err(self.err(
                cmd,
                "interval 'once' and 'resend' exclude each other".into(),
            ));
        }
        if !is_write(func) {
            cflags &= !flags::WFLUSH;
        }
        Ok((cflags, pflags))
    }

    /// Pins `<name>-NN` up to `count` after the `<pin>` tags' ones;
    /// returns the register offset after them.
    fn fill_pins(
        &mut self,
        cmd: Node,
        (func, dev, name, count): (u8, &str, Option<&str>, usize),
        (def_m, def_h, pflags): (Option<ModbusType>, Option<HalType>, u8),
        pins: &mut Vec<PinSpec>,
        mut regofs: usize,
    ) -> Result<usize> {
        while pins.len() < count {
            let (Some(m), Some(h), Some(n)) = (def_m, def_h, name) else {
                let why = "pins made from 'count' need 'name', 'modbustype' and 'haltype'";
                return Err(self.err(cmd, why.into()));
            };
            let full = format!("{dev}.{n}-{:02}", pins.len());
            self.claim(cmd, &full)?;
            let flags = if is_bits(func) { 0 } else { pflags };
            pins.push(PinSpec {
                name: full,
                htype: h,
                mtype: m,
                flags,
                regofs: regofs as u8,
            });
            regofs += m.regs() as usize;
        }
        Ok(regofs)
    }

    /// A `<pin>` of a register function: its types (the command's
    /// unless given), flags, and where it sits.
    fn reg_pin(
        &mut self,
        p: Node,
        func: u8,
        name: String,
        regofs: usize,
        (def_m, def_h, pflags): (Option<ModbusType>, Option<HalType>, u8),
    ) -> Result<PinSpec> {
        let m = match attr(p, "modbustype") {
            Some(n) => {
                modbus_type(n).ok_or_else(|| self.err(p, format!("unknown modbustype '{n}'")))?
            }
            None => def_m
                .ok_or_else(|| self.err(p, "no 'modbustype' on the command or the pin".into()))?,
        };
        let h = match attr(p, "haltype") {
            Some(n) => hal_type(n).ok_or_else(|| self.err(p, format!("unknown haltype '{n}'")))?,
            None => {
                def_h.ok_or_else(|| self.err(p, "no 'haltype' on the command or the pin".into()))?
            }
        };
        if h == HalType::Bit && m.kind() != 0 {
            let why = "HAL_BIT with a register function needs an unsigned modbustype";
            return Err(self.err(p, why.into()));
        }
        if func == 6 && m.regs() != 1 {
            return Err(self.err(p, "W_REGISTER needs a 16-bit modbustype".into()));
        }
        let mut flags = self.pin_flags(p, pflags)?;
        if matches!(h, HalType::U32 | HalType::U64 | HalType::Bit) {
            flags &= !pinf::SCALE;
        }
        if (m.regs() >= 2 && regofs % 2 != 0) || (m.regs() >= 4 && regofs % 4 != 0) {
            self.warn(
                p,
                "multi-register type not aligned to its natural boundary".into(),
            );
        }
        Ok(PinSpec {
            name,
            htype: h,
            mtype: m,
            flags,
            regofs: regofs as u8,
        })
    }

    fn claim(&mut self, n: Node, full: &str) -> Result<()> {
        if full.len() + 1 > MAX_PIN_NAME {
            return Err(self.err(
                n,
                format!(
                    "pin name '{full}' is longer than hm2_modbus takes ({} characters)",
                    MAX_PIN_NAME - 1
                ),
            ));
        }
        if self.pin_names.iter().any(|p| p == full) {
            return Err(self.err(n, format!("pin name '{full}' already in use")));
        }
        self.pin_names.push(full.to_string());
        Ok(())
    }

    /// The `<pin>` tags: pins and the register offset after them.
    fn pins(
        &mut self,
        cmd: Node,
        func: u8,
        dev: &str,
        cmdname: Option<&str>,
        defs: (Option<ModbusType>, Option<HalType>, u8),
    ) -> Result<(Vec<PinSpec>, usize)> {
        let (def_m, def_h, pflags) = defs;
        let mut pins = Vec::new();
        let mut regofs = 0usize;
        for p in self.children(cmd, "pin")? {
            if attr(p, "skip").is_some() {
                if !matches!(func, 3 | 4 | 16) {
                    return Err(self.err(p, format!("'skip' is not allowed with function {func}")));
                }
                self.check_attrs(p, &["skip"]);
                // hm2_modbus takes a command's first pin at its first
                // register, so a leading skip is a later address.
                if pins.is_empty() {
                    return Err(self.err(
                        p,
                        "'skip' before the first pin: start the command's address after the skipped registers instead".into(),
                    ));
                }
                let s = self.int(p, "skip", 1, 24)? as usize;
                if s > 11 {
                    self.warn(
                        p,
                        "skip larger than 11 registers: splitting the command may be better".into(),
                    );
                }
                regofs += s;
                continue;
            }
            self.check_attrs(p, &["clamp", "name", "haltype", "modbustype", "scale"]);
            let pinname = match (attr(p, "name"), cmdname) {
                (Some(n), _) if valid_name(n) => n.to_string(),
                (Some(n), _) => {
                    return Err(self.err(
                        p,
                        format!("pin name '{n}': lower case letters, digits, '.' and '-'"),
                    ))
                }
                (None, Some(c)) => format!("{c}-{:02}", pins.len()),
                (None, None) => return Err(self.err(p, "attribute 'name' missing".into())),
            };
            let full = format!("{dev}.{pinname}");
            self.claim(p, &full)?;
            if is_bits(func) {
                pins.push(PinSpec {
                    name: full,
                    htype: HalType::Bit,
                    mtype: ModbusType(0),
                    flags: 0,
                    regofs: regofs as u8,
                });
                regofs += 1;
                continue;
            }
            let spec = self.reg_pin(p, func, full, regofs, (def_m, def_h, pflags))?;
            regofs += spec.mtype.regs() as usize;
            pins.push(spec);
        }
        Ok((pins, regofs))
    }
}
