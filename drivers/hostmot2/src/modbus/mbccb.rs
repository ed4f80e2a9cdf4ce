//! The binary command file LinuxCNC's `mesambccc` writes (`.mbccb`): a
//! 64-byte header, 32-byte init records, 32-byte command records and a
//! data segment of length-prefixed fragments (init packets, type tables,
//! NUL-terminated pin names). All numbers are big-endian. Every field is
//! checked here, and a refusal names the byte offset of the field.

use crate::error::{Hm2Error, MbccbProblem, PinNameProblem, Result};
use crate::modbus::rtu;

/// Signature and version.
pub const SIGNATURE: &[u8; 8] = b"MesaMB01";
/// Header bytes.
pub const HEADER_LEN: usize = 64;
/// Init and command record bytes.
pub const RECORD_LEN: usize = 32;
/// The largest file accepted.
pub const MAX_FILE: usize = 128 * 1024;
/// The longest delay or timeout, microseconds.
pub const MAX_DELAY_US: u32 = 60_000_000;
/// The longest pin name fragment (with its NUL).
pub const MAX_PIN_NAME: usize = 24;

/// Header format bits.
pub mod format {
    /// Parity on.
    pub const PARITY_EN: u16 = 1 << 0;
    /// Odd parity (with `PARITY_EN`).
    pub const PARITY_ODD: u16 = 1 << 1;
    /// Two stop bits.
    pub const STOP_BITS2: u16 = 1 << 2;
    /// Full duplex (receiver not masked while sending).
    pub const DUPLEX: u16 = 1 << 3;
    /// Start suspended.
    pub const SUSPEND: u16 = 1 << 4;
}

/// Command flags.
pub mod flags {
    /// A timeout is not an error.
    pub const TIMESOUT: u16 = 0x0001;
    /// A broadcast gets an answer, which is ignored.
    pub const BCANSWER: u16 = 0x0002;
    /// No answer is expected.
    pub const NOANSWER: u16 = 0x0004;
    /// Writes are sent even when no pin changed.
    pub const RESEND: u16 = 0x0008;
    /// The first round of writes only takes the pins' values in.
    pub const WFLUSH: u16 = 0x0010;
    /// The command starts disabled.
    pub const DISABLED: u16 = 0x0020;
    /// Init-only: parity on for a communication change.
    pub const PARITY_EN: u16 = 0x0100;
    /// Init-only: odd parity.
    pub const PARITY_ODD: u16 = 0x0200;
    /// Init-only: two stop bits.
    pub const STOP_BITS2: u16 = 0x0400;
    /// Flags an init record may have.
    pub const INIT_MASK: u16 = 0x0707;
    /// Flags a command may have (others are dropped with a warning).
    pub const CMD_MASK: u16 = 0x003F;
}

/// Pin flags in a type record.
pub mod pinf {
    /// Scale/offset pins.
    pub const SCALE: u8 = 0x01;
    /// Clamp conversions.
    pub const CLAMP: u8 = 0x02;
    /// Both.
    pub const MASK: u8 = 0x03;
}

/// HAL types as the file numbers them (LinuxCNC's `hal_type_t`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HalType {
    /// bit
    Bit,
    /// float
    Float,
    /// s32
    S32,
    /// u32
    U32,
    /// s64
    S64,
    /// u64
    U64,
}

impl HalType {
    fn from_code(c: u8) -> Option<HalType> {
        Some(match c {
            1 => HalType::Bit,
            2 => HalType::Float,
            3 => HalType::S32,
            4 => HalType::U32,
            6 => HalType::S64,
            7 => HalType::U64,
            _ => return None,
        })
    }
}

/// A Modbus type byte: kind in the high nibble (0 unsigned, 1 signed, 2
/// float), byte order in the low nibble.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModbusType(pub u8);

/// Registers taken by each byte-order code.
const MTYPE_REGS: [u8; 16] = [1, 1, 2, 2, 2, 2, 4, 4, 4, 4, 4, 4, 4, 4, 1, 1];

impl ModbusType {
    /// Byte-order code (0 AB .. 13 HGFEDCBA, 14 A, 15 B).
    pub fn order(self) -> u8 {
        self.0 & 0x0F
    }
    /// 0 unsigned, 1 signed, 2 float.
    pub fn kind(self) -> u8 {
        self.0 >> 4
    }
    /// Registers it takes.
    pub fn regs(self) -> u8 {
        MTYPE_REGS[self.order() as usize]
    }
    /// Whether the file may hold it (no 8-bit floats, kinds 0..=2).
    pub fn valid(self) -> bool {
        self.kind() <= 2 && !(self.kind() == 2 && self.order() >= 14)
    }
}

/// One pin of a command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PinSpec {
    /// Name after the instance prefix.
    pub name: String,
    /// HAL type (bit for the coil functions).
    pub htype: HalType,
    /// Modbus type (registers functions only).
    pub mtype: ModbusType,
    /// [`pinf`] bits.
    pub flags: u8,
    /// Register offset in the command's block.
    pub regofs: u8,
}

/// An init record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Init {
    /// Wait this long.
    Delay {
        /// Microseconds.
        us: u32,
    },
    /// Change the line settings.
    Comms {
        /// Baud rate.
        baud: u32,
        /// [`flags`] parity and stop bits.
        flags: u16,
        /// Receive inter-frame delay (0 = auto).
        rxdelay: u16,
        /// Transmit inter-frame delay (0 = auto).
        txdelay: u16,
        /// Driver delay (0 = auto).
        drvdelay: u16,
        /// Inter-character limit (0 = auto).
        icdelay: u32,
    },
    /// Send a prepared request (address, function, data; CRC added).
    Packet {
        /// Device address.
        mbid: u8,
        /// Function.
        func: u8,
        /// [`flags`].
        flags: u16,
        /// Reply timeout, microseconds.
        timeout_us: u32,
        /// The request.
        pdu: Vec<u8>,
    },
}

/// A command of the loop.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Command {
    /// Device address (0 broadcast).
    pub mbid: u8,
    /// Function (0 for a delay).
    pub func: u8,
    /// [`flags`].
    pub flags: u16,
    /// First coil/register address.
    pub addr: u16,
    /// Registers (register functions).
    pub regcnt: u16,
    /// Repeat interval, microseconds (`u32::MAX`: once).
    pub interval_us: u32,
    /// Reply timeout, or the delay of a delay command, microseconds.
    pub timeout_us: u32,
    /// The pins.
    pub pins: Vec<PinSpec>,
}

/// A whole file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mbccb {
    /// Baud rate.
    pub baudrate: u32,
    /// [`format`] bits.
    pub format: u16,
    /// Transmit inter-frame delay, bit times (0 = auto).
    pub txdelay: u16,
    /// Receive inter-frame delay, bit times (0 = auto).
    pub rxdelay: u16,
    /// Driver delay (0 = auto).
    pub drvdelay: u16,
    /// Inter-character limit, bit times (0 = auto).
    pub icdelay: u16,
    /// Init records.
    pub inits: Vec<Init>,
    /// Loop commands.
    pub commands: Vec<Command>,
    /// Things accepted but worth saying (extra flags dropped).
    pub warnings: Vec<String>,
}

fn err(offset: usize, what: MbccbProblem) -> Hm2Error {
    Hm2Error::Mbccb { offset, what }
}

fn field(offset: usize, field: String, value: u64, expected: &'static str) -> Hm2Error {
    err(
        offset,
        MbccbProblem::Field {
            field,
            value,
            expected,
        },
    )
}

fn be16(b: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([b[at], b[at + 1]])
}

fn be32(b: &[u8], at: usize) -> u32 {
    u32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// The data segment: where it starts in the file, and its bytes.
struct Data<'a> {
    base: usize,
    bytes: &'a [u8],
}

impl<'a> Data<'a> {
    /// The fragment at `ptr` (its bytes without the length byte), or an
    /// error at `at` (the pointer field's offset).
    fn fragment(&self, ptr: u32, at: usize, what: String) -> Result<&'a [u8]> {
        let p = ptr as usize;
        let len = *self.bytes.get(p).ok_or_else(|| {
            field(
                at,
                what.clone(),
                ptr.into(),
                "must point inside the data segment",
            )
        })? as usize;
        self.bytes.get(p + 1..p + 1 + len).ok_or_else(|| {
            field(
                self.base + p,
                what,
                len as u64,
                "fragment length runs past the data segment",
            )
        })
    }
}

/// Parses and checks a whole `.mbccb` file.
pub fn parse(file: &[u8]) -> Result<Mbccb> {
    if file.len() > MAX_FILE {
        return Err(err(
            MAX_FILE,
            MbccbProblem::SizeMismatch {
                len: file.len(),
                expected: MAX_FILE,
            },
        ));
    }
    if file.len() < HEADER_LEN {
        return Err(err(
            file.len(),
            MbccbProblem::Truncated {
                need: HEADER_LEN,
                len: file.len(),
            },
        ));
    }
    if &file[..8] != SIGNATURE {
        let found = file[..8]
            .iter()
            .map(|&c| if c.is_ascii_graphic() { c as char } else { '?' })
            .collect();
        return Err(err(0, MbccbProblem::Signature { found }));
    }
    let h = header(file)?;
    let (initlen, cmdslen) = sections(file)?;
    let init_at = HEADER_LEN;
    let cmds_at = init_at + initlen as usize;
    let data_at = cmds_at + cmdslen as usize;
    let data = Data {
        base: data_at,
        bytes: &file[data_at..],
    };
    check_fragments(&data)?;
    let inits = (0..initlen as usize / RECORD_LEN)
        .map(|i| init(file, init_at + i * RECORD_LEN, i, &data))
        .collect::<Result<Vec<_>>>()?;
    let mut warnings = Vec::new();
    let commands = (0..cmdslen as usize / RECORD_LEN)
        .map(|i| command(file, cmds_at + i * RECORD_LEN, i, &data, &mut warnings))
        .collect::<Result<Vec<_>>>()?;
    Ok(Mbccb {
        inits,
        commands,
        warnings,
        ..h
    })
}

/// The header's line settings.
fn header(file: &[u8]) -> Result<Mbccb> {
    let format = be16(file, 12);
    if format & format::PARITY_ODD != 0 && format & format::PARITY_EN == 0 {
        return Err(field(
            12,
            "format".into(),
            format.into(),
            "odd parity set while parity is off",
        ));
    }
    let limits: [(usize, &str, u16, &'static str); 4] = [
        (14, "txdelay", 1020, "must be 0..=1020"),
        (16, "rxdelay", 1020, "must be 0..=1020"),
        (18, "drivedelay", 31, "must be 0..=31"),
        (20, "icdelay", 255, "must be 0..=255"),
    ];
    for (at, name, max, expected) in limits {
        let v = be16(file, at);
        if v > max {
            return Err(field(at, name.into(), v.into(), expected));
        }
    }
    let baudrate = be32(file, 8);
    if !(300..=10_000_000).contains(&baudrate) {
        return Err(field(
            8,
            "baudrate".into(),
            baudrate.into(),
            "must be 300..=10000000",
        ));
    }
    Ok(Mbccb {
        baudrate,
        format,
        txdelay: be16(file, 14),
        rxdelay: be16(file, 16),
        drvdelay: be16(file, 18),
        icdelay: be16(file, 20),
        inits: Vec::new(),
        commands: Vec::new(),
        warnings: Vec::new(),
    })
}

/// The data segment must be whole fragments end to end.
fn check_fragments(data: &Data) -> Result<()> {
    let mut p = 0usize;
    while p < data.bytes.len() {
        p += data.bytes[p] as usize + 1;
    }
    if p != data.bytes.len() {
        return Err(err(
            data.base + data.bytes.len(),
            MbccbProblem::SizeMismatch {
                len: data.bytes.len(),
                expected: p,
            },
        ));
    }
    Ok(())
}

fn init(file: &[u8], at: usize, i: usize, data: &Data) -> Result<Init> {
    let r = &file[at..at + RECORD_LEN];
    let (mbid, func, fl) = (r[0], r[1], be16(r, 2));
    if fl & !flags::INIT_MASK != 0 {
        return Err(field(
            at + 2,
            format!("init {i} flags"),
            fl.into(),
            "only 0x0707 may be set",
        ));
    }
    let timeout = be32(r, 24);
    if func == 0 {
        return init_meta(r, at, i);
    }
    if !rtu::supported(func) {
        return Err(field(
            at + 1,
            format!("init {i} function"),
            func.into(),
            "must be 1-6, 15 or 16",
        ));
    }
    if timeout > MAX_DELAY_US {
        return Err(field(
            at + 24,
            format!("init {i} timeout"),
            timeout.into(),
            "must be at most 60000000 us",
        ));
    }
    let ptr = be32(r, 28);
    if ptr == 0 {
        return Err(field(
            at + 28,
            format!("init {i} data pointer"),
            0,
            "must point at the request",
        ));
    }
    let pdu = data.fragment(ptr, at + 28, format!("init {i} request"))?;
    if !(6..=rtu::MAX_FRAME - 2).contains(&pdu.len()) {
        return Err(field(
            data.base + ptr as usize,
            format!("init {i} request length"),
            pdu.len() as u64,
            "must be 6..=254 bytes",
        ));
    }
    Ok(Init::Packet {
        mbid,
        func,
        flags: fl,
        timeout_us: timeout,
        pdu: pdu.to_vec(),
    })
}

fn command(
    file: &[u8],
    at: usize,
    c: usize,
    data: &Data,
    warnings: &mut Vec<String>,
) -> Result<Command> {
    let r = &file[at..at + RECORD_LEN];
    let mut cmd = Command {
        mbid: r[0],
        func: r[1],
        flags: be16(r, 2),
        addr: be16(r, 4),
        regcnt: be16(r, 8),
        interval_us: be32(r, 20),
        timeout_us: be32(r, 24),
        pins: Vec::new(),
    };
    let pincnt = be16(r, 6);
    if cmd.flags & !flags::CMD_MASK != 0 {
        warnings.push(format!(
            "command {c} has extra flags set (flags=0x{:04x}, allowed=0x{:04x}), ignored",
            cmd.flags,
            flags::CMD_MASK
        ));
        cmd.flags &= flags::CMD_MASK;
    }
    if cmd.timeout_us > MAX_DELAY_US {
        return Err(field(
            at + 24,
            format!("command {c} timeout"),
            cmd.timeout_us.into(),
            "must be at most 60000000 us",
        ));
    }
    let htypes: Vec<(HalType, ModbusType, u8, u8)> = match cmd.func {
        0 => {
            if cmd.mbid != 0 || pincnt != 0 || cmd.addr != 0 {
                return Err(field(
                    at,
                    format!("command {c} (delay) device/pins/address"),
                    1,
                    "must all be 0 in a delay",
                ));
            }
            return Ok(cmd);
        }
        rtu::R_COILS | rtu::R_INPUTS | rtu::W_COILS | rtu::W_COIL => {
            let max = if cmd.func == rtu::W_COIL { 1 } else { 2000 };
            if pincnt < 1 || pincnt > max {
                return Err(field(
                    at + 6,
                    format!("command {c} pin count"),
                    pincnt.into(),
                    "must be 1..=2000 (1 for W_COIL)",
                ));
            }
            vec![(HalType::Bit, ModbusType(0), 0, 0); pincnt as usize]
        }
        rtu::R_REGISTERS | rtu::R_INPUTREGS | rtu::W_REGISTERS | rtu::W_REGISTER => {
            types(r, at, c, pincnt, data)?
        }
        f => {
            return Err(field(
                at + 1,
                format!("command {c} function"),
                f.into(),
                "must be 0 (delay), 1-6, 15 or 16",
            ))
        }
    };
    cmd.pins = pins_of(be32(r, 28), at + 28, c, htypes, data)?;
    Ok(cmd)
}

/// The type table of a register command, checked against its counts.
fn types(
    r: &[u8],
    at: usize,
    c: usize,
    pincnt: u16,
    data: &Data,
) -> Result<Vec<(HalType, ModbusType, u8, u8)>> {
    let ptr = be32(r, 16);
    let regcnt = be16(r, 8);
    let single = r[1] == rtu::W_REGISTER;
    if single && (pincnt != 1 || regcnt != 1) {
        return Err(field(
            at + 6,
            format!("command {c} (W_REGISTER) pin/register count"),
            pincnt.into(),
            "must both be 1",
        ));
    }
    if !(1..=125).contains(&pincnt) {
        return Err(field(
            at + 6,
            format!("command {c} pin count"),
            pincnt.into(),
            "must be 1..=125",
        ));
    }
    if !(1..=125).contains(&regcnt) {
        return Err(field(
            at + 8,
            format!("command {c} register count"),
            regcnt.into(),
            "must be 1..=125",
        ));
    }
    if ptr == 0 || (ptr + 1) % 4 != 0 {
        return Err(field(
            at + 16,
            format!("command {c} type pointer"),
            ptr.into(),
            "must be non-zero with its records 4-byte aligned",
        ));
    }
    let t = data.fragment(ptr, at + 16, format!("command {c} types"))?;
    if t.len() != 4 * pincnt as usize {
        return Err(field(
            data.base + ptr as usize,
            format!("command {c} type table length"),
            t.len() as u64,
            "must be 4 bytes per pin",
        ));
    }
    let mut next = 0u16;
    let mut out = Vec::with_capacity(pincnt as usize);
    for (pin, rec) in t.chunks(4).enumerate() {
        let at = TypeAt {
            off: data.base + ptr as usize + 1 + 4 * pin,
            c,
            pin,
        };
        let t = type_record(&at, rec, single, regcnt, next)?;
        next = u16::from(t.3) + u16::from(t.1.regs());
        out.push(t);
    }
    Ok(out)
}

/// A pin name fragment: 2..=24 bytes, NUL-terminated, `[a-z0-9.-]`.
fn pin_name(frag: &[u8]) -> std::result::Result<String, PinNameProblem> {
    if frag.len() < 2 {
        return Err(PinNameProblem::Empty);
    }
    if frag.len() > MAX_PIN_NAME {
        return Err(PinNameProblem::TooLong {
            len: frag.len(),
            max: MAX_PIN_NAME,
        });
    }
    let (text, nul) = frag.split_at(frag.len() - 1);
    if nul[0] != 0 {
        return Err(PinNameProblem::Unterminated);
    }
    if let Some(&b) = text
        .iter()
        .find(|&&b| !(b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'.' || b == b'-'))
    {
        return Err(PinNameProblem::BadByte(b));
    }
    Ok(String::from_utf8_lossy(text).into_owned())
}

/// Where a type record is: its offset, command and pin.
struct TypeAt {
    off: usize,
    c: usize,
    pin: usize,
}

/// One 4-byte type record (Modbus type, HAL type, flags, register
/// offset), checked against the command (`next`: the first register the
/// pin may start at).
fn type_record(
    at: &TypeAt,
    rec: &[u8],
    single: bool,
    regcnt: u16,
    next: u16,
) -> Result<(HalType, ModbusType, u8, u8)> {
    let (off, c, pin) = (at.off, at.c, at.pin);
    let what = |f: &str| format!("command {c} pin {pin} {f}");
    let mtype = ModbusType(rec[0]);
    if !mtype.valid() {
        return Err(field(
            off,
            what("modbustype"),
            rec[0].into(),
            "is not a known type",
        ));
    }
    if single && mtype.regs() != 1 {
        let e = "must be one register for W_REGISTER";
        return Err(field(off, what("modbustype"), rec[0].into(), e));
    }
    let htype = HalType::from_code(rec[1]).ok_or_else(|| {
        let e = "must be bit, float, s32, u32, s64 or u64";
        field(off + 1, what("haltype"), rec[1].into(), e)
    })?;
    if rec[2] & !pinf::MASK != 0 {
        return Err(field(
            off + 2,
            what("flags"),
            rec[2].into(),
            "only 0x03 may be set",
        ));
    }
    let regofs = u16::from(rec[3]);
    if (pin == 0 && regofs != 0) || regofs < next || regofs + u16::from(mtype.regs()) > regcnt {
        let e = "must follow the previous pin and fit the register count";
        return Err(field(off + 3, what("register offset"), regofs.into(), e));
    }
    Ok((htype, mtype, rec[2], rec[3]))
}

/// The pins of command `c`: their names from the fragments at `ptr` (the
/// pointer field at `ptr_at`), with their types.
fn pins_of(
    ptr: u32,
    ptr_at: usize,
    c: usize,
    types: Vec<(HalType, ModbusType, u8, u8)>,
    data: &Data,
) -> Result<Vec<PinSpec>> {
    let mut p = ptr as usize;
    let mut pins = Vec::with_capacity(types.len());
    for (pin, (htype, mtype, flags, regofs)) in types.into_iter().enumerate() {
        let frag = data.fragment(p as u32, ptr_at, format!("command {c} pin {pin} name"))?;
        let name = pin_name(frag).map_err(|why| {
            let what = MbccbProblem::PinName {
                command: c,
                pin,
                why,
            };
            err(data.base + p, what)
        })?;
        pins.push(PinSpec {
            name,
            htype,
            mtype,
            flags,
            regofs,
        });
        p += frag.len() + 1;
    }
    Ok(pins)
}

/// A meta init record (function 0): a delay or a line change.
fn init_meta(r: &[u8], at: usize, i: usize) -> Result<Init> {
    let (mbid, fl, value) = (r[0], be16(r, 2), be32(r, 24));
    if mbid != 0 {
        let e = "must be 0 in a meta command";
        return Err(field(at, format!("init {i} device"), mbid.into(), e));
    }
    match be16(r, 4) {
        0 if value <= MAX_DELAY_US => Ok(Init::Delay { us: value }),
        0 => {
            let e = "must be at most 60000000 us";
            Err(field(at + 24, format!("init {i} delay"), value.into(), e))
        }
        1 if (300..=10_000_000).contains(&value) => Ok(Init::Comms {
            baud: value,
            flags: fl,
            rxdelay: be16(r, 6).min(1020),
            txdelay: be16(r, 8).min(1020),
            drvdelay: be16(r, 10).min(31),
            icdelay: be32(r, 12).min(255),
        }),
        1 => {
            let e = "must be 300..=10000000";
            Err(field(
                at + 24,
                format!("init {i} baudrate"),
                value.into(),
                e,
            ))
        }
        m => {
            let e = "must be 0 (delay) or 1 (comms change)";
            Err(field(at + 4, format!("init {i} meta command"), m.into(), e))
        }
    }
}

/// The section lengths (init, commands) after checking them against each
/// other and the file's size.
fn sections(file: &[u8]) -> Result<(u32, u32)> {
    let (initlen, cmdslen, datalen) = (be32(file, 52), be32(file, 56), be32(file, 60));
    for (at, len, name) in [(52, initlen, "initlen"), (56, cmdslen, "cmdslen")] {
        if len as usize % RECORD_LEN != 0 {
            return Err(field(
                at,
                name.into(),
                len.into(),
                "must be a multiple of 32",
            ));
        }
    }
    if cmdslen == 0 {
        return Err(field(
            56,
            "cmdslen".into(),
            0,
            "must hold at least one command",
        ));
    }
    if datalen == 0 {
        return Err(field(
            60,
            "datalen".into(),
            0,
            "must hold at least the pin names",
        ));
    }
    let expected = HEADER_LEN as u64 + u64::from(initlen) + u64::from(cmdslen) + u64::from(datalen);
    if expected != file.len() as u64 {
        return Err(err(
            file.len().min(expected as usize),
            MbccbProblem::SizeMismatch {
                len: file.len(),
                expected: expected as usize,
            },
        ));
    }
    Ok((initlen, cmdslen))
}
