//! The `cfg` module parameter: which ports, in which mode, through which
//! backend.
//!
//! LinuxCNC's syntax (hardware.md 2.3), kept exactly:
//!
//! * Tokens are separated by whitespace or `_`.
//! * A port is `<addr> [<type>]`. `<addr>` is hexadecimal with an optional
//!   `0x`/`0X` prefix (`378` is 0x378, `10` is 0x10 = 16). Values below 16
//!   are Linux parport numbers (0 = the first port Linux found), others
//!   are I/O addresses.
//! * `<type>` is recognised by its first letter, any case: `i` = in,
//!   `o` = out (the default), `e` = epp, `x` = control lines as inputs.
//!   A token after an address that starts with none of these letters is
//!   the next port's address.
//! * At most 8 ports.
//!
//! This driver's extension: a backend token after the address, before or
//! after the type, spelled in full (any case): `ppdev`, `raw`, `sim`,
//! `simloop`. None of them is a type letter or a hex number, so every
//! LinuxCNC cfg string keeps its meaning; without one, the backend is
//! chosen automatically (see [`crate::select`]).
//!
//! Unlike LinuxCNC, which turns an unparsable address into 0xFFFF and
//! silently ignores ports past the eighth, bad strings are refused with a
//! message naming the token.

use hal_driver::params::{parse_hex, BackendTokens, NumberError};

/// The most ports one `loadrt` handles.
pub const MAX_PORTS: usize = 8;

/// LinuxCNC's default `cfg` value.
pub const DEFAULT_CFG: &str = "0x0278";

/// How the port's pins are used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Data pins 2..9 are outputs (12 outputs, 5 inputs).
    Out,
    /// Data pins 2..9 are inputs (4 outputs, 13 inputs).
    In,
    /// As `Out`, and the ECR is set to EPP mode.
    Epp,
    /// Data pins are outputs and the open-collector control lines are
    /// inputs (8 outputs, 9 inputs).
    X,
}

impl Mode {
    /// Whether the data pins are outputs.
    pub fn data_out(self) -> bool {
        self != Mode::In
    }

    /// Whether the control pins are inputs.
    pub fn control_in(self) -> bool {
        self == Mode::X
    }

    /// The name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Out => "out",
            Mode::In => "in",
            Mode::Epp => "epp",
            Mode::X => "x",
        }
    }
}

/// Which port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PortAddr {
    /// A Linux parport number (`/dev/parportN`), 0..15.
    Number(u8),
    /// An I/O base address, 16..0xffff.
    Address(u16),
}

impl std::fmt::Display for PortAddr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PortAddr::Number(n) => write!(f, "parport{n}"),
            PortAddr::Address(a) => write!(f, "{a:#x}"),
        }
    }
}

/// How the driver reaches the port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// `/dev/parportN` ioctls.
    Ppdev,
    /// `ioperm` + `inb`/`outb`.
    Raw,
    /// The simulator.
    Sim,
    /// The simulator with the loopback plug ([`crate::sim::Plug::loopback`]).
    SimLoop,
}

impl Backend {
    /// The cfg token.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Ppdev => "ppdev",
            Backend::Raw => "raw",
            Backend::Sim => "sim",
            Backend::SimLoop => "simloop",
        }
    }

    fn from_token(t: &str) -> Option<Backend> {
        Some(match TOKENS.parse(t)? {
            hal_driver::params::Backend::Real("ppdev") => Backend::Ppdev,
            hal_driver::params::Backend::Real(_) => Backend::Raw,
            hal_driver::params::Backend::Sim("simloop") => Backend::SimLoop,
            hal_driver::params::Backend::Sim(_) => Backend::Sim,
        })
    }
}

/// The backend tokens, parsed by the driver layer's one rule for all
/// drivers (whole words, any case; simulator tokens start with `sim`).
pub const TOKENS: BackendTokens = BackendTokens::new(&["ppdev", "raw"], &["sim", "simloop"]);

/// One configured port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortSpec {
    /// Which port.
    pub addr: PortAddr,
    /// How its pins are used.
    pub mode: Mode,
    /// The backend, if the cfg string named one.
    pub backend: Option<Backend>,
}

impl std::fmt::Display for PortSpec {
    /// `<addr>, <mode> mode`, as messages name a port.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}, {} mode", self.addr, self.mode.name())
    }
}

/// Why a cfg string was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CfgError {
    /// No port at all.
    #[error("no ports configured (expected e.g. cfg=\"0x378 out\" or cfg=\"0 in\")")]
    Empty,
    /// A token where an address belongs is not one.
    #[error("bad port address '{token}': {reason}")]
    BadAddress {
        /// The token as written.
        token: String,
        /// Why it is not an address.
        reason: String,
    },
    /// More than [`MAX_PORTS`] ports.
    #[error("{count} ports configured, at most {MAX_PORTS} are supported")]
    TooManyPorts {
        /// How many ports the string names.
        count: usize,
    },
    /// The same port twice, written the same way (`0` and `0x378` for
    /// one port are only found when the backends are chosen).
    #[error("port {addr} is configured twice")]
    Duplicate {
        /// The port named twice.
        addr: PortAddr,
    },
}

fn is_sep(c: char) -> bool {
    // C's isspace() set, plus '_' (insmod truncated strings at spaces).
    matches!(c, ' ' | '\t' | '\n' | '\x0b' | '\x0c' | '\r' | '_')
}

fn mode_of(t: &str) -> Option<Mode> {
    match t.as_bytes().first()?.to_ascii_lowercase() {
        b'i' => Some(Mode::In),
        b'o' => Some(Mode::Out),
        b'e' => Some(Mode::Epp),
        b'x' => Some(Mode::X),
        _ => None,
    }
}

/// Parses an address token: hex, optional `0x` prefix (the driver
/// layer's [`parse_hex`]).
pub fn parse_addr(t: &str) -> Result<PortAddr, CfgError> {
    let v = parse_hex(t, 0xFFFF).map_err(|e| {
        let reason = match e {
            NumberError::BadHexDigit(_) if mode_of(t).is_some() => {
                format!("{e} (a port takes one type; is a port address missing before it?)")
            }
            e => e.to_string(),
        };
        CfgError::BadAddress {
            token: t.to_string(),
            reason,
        }
    })?;
    Ok(if v < 16 {
        PortAddr::Number(v as u8)
    } else {
        PortAddr::Address(v as u16)
    })
}

/// Splits a cfg string into its tokens.
pub fn tokens(cfg: &str) -> Vec<&str> {
    cfg.split(is_sep).filter(|t| !t.is_empty()).collect()
}

/// Parses a cfg string.
pub fn parse(cfg: &str) -> Result<Vec<PortSpec>, CfgError> {
    let toks = tokens(cfg);
    let mut ports: Vec<PortSpec> = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        let addr = parse_addr(toks[i])?;
        i += 1;
        let mut mode = None;
        let mut backend = None;
        // A type and a backend may follow, in either order.
        while i < toks.len() {
            let t = toks[i];
            if let Some(b) = Backend::from_token(t).filter(|_| backend.is_none()) {
                backend = Some(b);
            } else if let Some(m) = mode_of(t).filter(|_| mode.is_none()) {
                mode = Some(m);
            } else {
                break;
            }
            i += 1;
        }
        if ports.iter().any(|p| p.addr == addr) {
            return Err(CfgError::Duplicate { addr });
        }
        ports.push(PortSpec {
            addr,
            mode: mode.unwrap_or(Mode::Out),
            backend,
        });
    }
    if ports.is_empty() {
        return Err(CfgError::Empty);
    }
    if ports.len() > MAX_PORTS {
        return Err(CfgError::TooManyPorts { count: ports.len() });
    }
    Ok(ports)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(addr: PortAddr, mode: Mode, backend: Option<Backend>) -> PortSpec {
        PortSpec {
            addr,
            mode,
            backend,
        }
    }

    #[test]
    fn linuxcnc_forms() {
        use PortAddr::*;
        assert_eq!(
            parse("0x378 out 0x278 in").unwrap(),
            vec![
                spec(Address(0x378), Mode::Out, None),
                spec(Address(0x278), Mode::In, None)
            ]
        );
        assert_eq!(
            parse("0 out 1 in").unwrap(),
            vec![
                spec(Number(0), Mode::Out, None),
                spec(Number(1), Mode::In, None)
            ]
        );
        assert_eq!(
            parse("0x278 0x378 in 0x20A0 out").unwrap(),
            vec![
                spec(Address(0x278), Mode::Out, None),
                spec(Address(0x378), Mode::In, None),
                spec(Address(0x20A0), Mode::Out, None)
            ]
        );
        assert_eq!(parse("378").unwrap()[0].addr, Address(0x378));
        assert_eq!(
            parse("10").unwrap()[0].addr,
            Address(0x10),
            "hex: 16 is an address"
        );
        assert_eq!(parse("f").unwrap()[0].addr, Number(15));
        assert_eq!(parse("0X00f").unwrap()[0].addr, Number(15));
        assert_eq!(parse("0xc000 E").unwrap()[0].mode, Mode::Epp);
        assert_eq!(parse("0xc000 Xtra").unwrap()[0].mode, Mode::X);
        assert_eq!(parse("0xc000 ignored-after-i").unwrap()[0].mode, Mode::In);
        assert_eq!(parse("0x378 Output").unwrap()[0].mode, Mode::Out);
        assert_eq!(parse(DEFAULT_CFG).unwrap()[0].addr, Address(0x278));
        // '_' and any whitespace separate tokens.
        assert_eq!(
            parse("\t0x378_in__0x278\nx\r\x0b\x0c").unwrap(),
            vec![
                spec(Address(0x378), Mode::In, None),
                spec(Address(0x278), Mode::X, None)
            ]
        );
        // A token that is not a type is the next address, even "ab".
        assert_eq!(
            parse("0x378 ab").unwrap(),
            vec![
                spec(Address(0x378), Mode::Out, None),
                spec(Address(0xab), Mode::Out, None)
            ]
        );
        // Only the token after an address is a type: "e0" first is 0xe0.
        assert_eq!(
            parse("e0 e0").unwrap()[0],
            spec(Address(0xe0), Mode::Epp, None)
        );
        // Eight ports is the limit, not an error.
        assert_eq!(parse("0 1 2 3 4 5 6 7").unwrap().len(), 8);
    }

    #[test]
    fn backend_tokens() {
        use PortAddr::*;
        assert_eq!(
            parse("0 sim").unwrap(),
            vec![spec(Number(0), Mode::Out, Some(Backend::Sim))]
        );
        assert_eq!(
            parse("0x378 in SimLoop 0x278 raw x 1 ppdev").unwrap(),
            vec![
                spec(Address(0x378), Mode::In, Some(Backend::SimLoop)),
                spec(Address(0x278), Mode::X, Some(Backend::Raw)),
                spec(Number(1), Mode::Out, Some(Backend::Ppdev)),
            ]
        );
        assert_eq!(
            parse("0 sim in").unwrap(),
            vec![spec(Number(0), Mode::In, Some(Backend::Sim))]
        );
    }

    #[test]
    fn bad_strings_are_refused_naming_the_token() {
        for (cfg, want) in [
            ("", "no ports configured"),
            ("  _ \t", "no ports configured"),
            ("zz", "bad port address 'zz': 'z' is not a hex digit"),
            ("0x37g", "bad port address '0x37g': 'g'"),
            ("0x", "bad port address '0x': no hex digits"),
            ("0x10000", "larger than 0xffff"),
            ("123456789abcdef", "larger than 0xffff"),
            ("0x378 in out", "bad port address 'out'"),
            ("0x378 in out", "a port takes one type"),
            ("0 sim sim", "bad port address 'sim'"),
            ("-1", "'-' is not a hex digit"),
            ("0 1 2 3 4 5 6 7 8", "9 ports configured, at most 8"),
            ("0x378 0378", "port 0x378 is configured twice"),
            ("0 out 0 in", "port parport0 is configured twice"),
        ] {
            let e = parse(cfg).expect_err(cfg).to_string();
            assert!(e.contains(want), "{cfg:?}: {e}");
        }
    }
}
