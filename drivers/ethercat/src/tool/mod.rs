//! `ethercat-tool`: bring up an EtherCAT segment the way IgH's
//! `ethercat` command does: `slaves`, `master`, `states`, `sii-read`,
//! `pdos`, `upload`, `download` ([`args`]), on an interface or on a
//! simulated segment in process (`--sim FILE`). The tool scans the
//! segment itself ([`bus`]) and prints what IgH prints where IgH's
//! layout is known to users (`slaves`, `pdos`); [`values`] types SDO
//! data.

pub mod args;
pub mod bus;
pub mod values;

use std::io;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use args::{Cli, Cmd};
use bus::{with_bus, Bus, Listed};
use values::ValueType;

use crate::error::{Error, Result};
use crate::link::{InProcess, Link, RawSocket};
use crate::regs::{al, al_code};
use crate::sim::file;
use crate::wire::sii::{self, Sii};

/// What a command produced.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Output {
    /// Lines of text.
    Lines(Vec<String>),
    /// Raw bytes (`sii-read` without `-v`).
    Bytes(Vec<u8>),
}

/// Frames a link sent and received (for `master`).
#[derive(Debug, Default)]
struct Counts {
    sent: AtomicU64,
    received: AtomicU64,
}

/// A link that counts its frames.
struct Counting {
    inner: Box<dyn Link>,
    counts: Arc<Counts>,
}

impl Link for Counting {
    fn send(&mut self, frame: &[u8]) -> io::Result<()> {
        self.counts.sent.fetch_add(1, Ordering::Relaxed);
        self.inner.send(frame)
    }
    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<Option<usize>> {
        let r = self.inner.recv(buf, timeout);
        if let Ok(Some(_)) = r {
            self.counts.received.fetch_add(1, Ordering::Relaxed);
        }
        r
    }
    fn is_up(&self) -> bool {
        self.inner.is_up()
    }
    fn describe(&self) -> String {
        self.inner.describe()
    }
}

/// The link `cli` names: the simulated segment of `--sim`, or a raw
/// socket on `--iface`.
pub fn open_link(cli: &Cli) -> Result<Box<dyn Link>> {
    match &cli.sim {
        Some(path) => {
            let seg = file::read(path)?.build()?;
            Ok(Box::new(InProcess::new(Arc::new(Mutex::new(seg)))))
        }
        None => RawSocket::open(&cli.iface)
            .map(|s| Box::new(s) as Box<dyn Link>)
            .map_err(|e| Error::Interface {
                iface: cli.iface.clone(),
                reason: "cannot open a raw socket".into(),
                source: Some(e),
            }),
    }
}

/// Runs one command line.
pub fn run(cli: &Cli) -> Result<Output> {
    let counts = Arc::new(Counts::default());
    let link = Box::new(Counting {
        inner: open_link(cli)?,
        counts: counts.clone(),
    });
    with_bus(link, |bus| match &cli.command {
        Cmd::Slaves { verbose } => slaves(bus, *verbose).map(Output::Lines),
        Cmd::Master => master(bus, &counts).map(Output::Lines),
        Cmd::States { position, state } => states(bus, *position, state).map(Output::Lines),
        Cmd::SiiRead { position, verbose } => {
            let bytes = bus.sii_bytes(*position)?;
            if *verbose {
                let s = Sii::decode(&bytes, Some(&format!("slave {position}")))?;
                Ok(Output::Lines(describe_sii(&s)))
            } else {
                Ok(Output::Bytes(bytes))
            }
        }
        Cmd::Pdos { position } => pdos(bus, *position).map(Output::Lines),
        Cmd::Upload {
            position,
            ty,
            index,
            sub,
        } => {
            let data = bus.upload(*position, *index, *sub, false)?;
            let t = match ty {
                Some(t) => ValueType::parse(t)?,
                None => ValueType::guess(&data),
            };
            Ok(Output::Lines(vec![t.format(&data)?]))
        }
        Cmd::Download {
            position,
            ty,
            index,
            sub,
            value,
        } => {
            let data = ValueType::parse(ty)?.encode(value)?;
            bus.download(*position, *index, *sub, false, &data)?;
            Ok(Output::Lines(Vec::new()))
        }
    })
}

fn names(bus: &mut Bus<'_>, rows: &[Listed]) -> Vec<String> {
    rows.iter()
        .map(|r| match bus.sii(r.position) {
            Ok(s) if !s.name.is_empty() => s.name,
            Ok(s) => s.order,
            Err(e) => format!("(SII unreadable: {e})"),
        })
        .collect()
}

/// IgH's `ethercat slaves`: `0  0:0  PREOP  +  EK1100 EtherCAT-Koppler`,
/// the columns padded to their widest entry.
pub fn format_slaves(rows: &[Listed], names: &[String]) -> Vec<String> {
    let pos: Vec<String> = rows.iter().map(|r| r.position.to_string()).collect();
    let at: Vec<String> = rows
        .iter()
        .enumerate()
        .map(|(i, _)| {
            // Relative position after the last alias, as IgH counts it.
            let base = rows[..=i].iter().rposition(|x| x.alias != 0).unwrap_or(0);
            let alias = rows.get(base).map_or(0, |x| x.alias);
            format!("{alias}:{}", i - base)
        })
        .collect();
    let state: Vec<&str> = rows.iter().map(|r| al::name(r.al_status)).collect();
    let w = |v: &[&str]| v.iter().map(|s| s.len()).max().unwrap_or(0);
    let (wp, wa, ws) = (
        w(&pos.iter().map(String::as_str).collect::<Vec<_>>()),
        w(&at.iter().map(String::as_str).collect::<Vec<_>>()),
        w(&state),
    );
    rows.iter()
        .enumerate()
        .map(|(i, r)| {
            let flag = if r.al_status & al::ERROR != 0 {
                'E'
            } else {
                '+'
            };
            format!(
                "{:>wp$}  {:<wa$}  {:<ws$}  {flag}  {}",
                pos[i],
                at[i],
                state[i],
                names.get(i).map_or("", String::as_str)
            )
        })
        .collect()
}

fn slaves(bus: &mut Bus<'_>, verbose: bool) -> Result<Vec<String>> {
    let rows = bus.list()?;
    let names = names(bus, &rows);
    if !verbose {
        return Ok(format_slaves(&rows, &names));
    }
    let mut out = Vec::new();
    for (r, name) in rows.iter().zip(&names) {
        let (_, code) = bus.al_status(r.position)?;
        out.extend([
            format!("=== Master 0, Slave {} ===", r.position),
            format!("Device: {name}"),
            format!("State: {}", al::name(r.al_status)),
            format!(
                "Flag: {}",
                if r.al_status & al::ERROR != 0 {
                    'E'
                } else {
                    '+'
                }
            ),
            format!("Station address: {:#06x}, alias {}", r.station, r.alias),
            "Identity:".into(),
            format!("  Vendor Id:       {:#010x}", r.identity.0),
            format!("  Product code:    {:#010x}", r.identity.1),
            format!("  Revision number: {:#010x}", r.identity.2),
            format!("  Serial number:   {:#010x}", r.identity.3),
            format!("AL status code: {code:#06x} ({})", al_code::meaning(code)),
            String::new(),
        ]);
    }
    Ok(out)
}

fn master(bus: &mut Bus<'_>, counts: &Counts) -> Result<Vec<String>> {
    let rows = bus.list()?;
    let mut states = 0u8;
    for r in &rows {
        states |= r.al_status & al::STATE_MASK;
    }
    let state_names: Vec<&str> = [al::INIT, al::PREOP, al::SAFEOP, al::OP]
        .into_iter()
        .filter(|s| states & s != 0)
        .map(al::name)
        .collect();
    let sent = counts.sent.load(Ordering::Relaxed);
    let received = counts.received.load(Ordering::Relaxed);
    Ok(vec![
        "Master0".into(),
        "  Phase: Idle (ethercat-tool's own master; the segment at PRE-OP)".into(),
        format!("  Slaves: {}", rows.len()),
        format!("  AL states: {}", state_names.join(", ")),
        "  Ethernet devices:".into(),
        format!("    Main: {}", bus.iface()),
        format!("      Tx frames:   {sent}"),
        format!("      Rx frames:   {received}"),
        format!("      Lost frames: {}", sent.saturating_sub(received)),
    ])
}

fn states(bus: &mut Bus<'_>, position: Option<u16>, state: &str) -> Result<Vec<String>> {
    let s = al::parse(state).ok_or_else(|| {
        Error::malformed(
            format!("state '{state}'"),
            "not one of INIT, PREOP, BOOT, SAFEOP, OP",
        )
    })?;
    let targets: Vec<u16> = match position {
        Some(p) => vec![p],
        None => (0..bus.len())
            .map(|p| u16::try_from(p).unwrap_or(u16::MAX))
            .collect(),
    };
    for p in targets {
        bus.request_state(p, s, Duration::from_secs(5))?;
    }
    Ok(Vec::new())
}

/// IgH's `ethercat pdos` layout for one slave's SII.
pub fn format_pdos(s: &Sii) -> Vec<String> {
    let mut out = Vec::new();
    for (i, sm) in s.sync_managers.iter().enumerate() {
        out.push(format!(
            "SM{i}: PhysAddr {:#06x}, DefaultSize {:4}, ControlRegister {:#04x}, Enable {}",
            sm.start,
            sm.length,
            sm.control,
            sm.enable & 1
        ));
        let pdos = s
            .rx_pdos
            .iter()
            .map(|p| ("RxPDO", p))
            .chain(s.tx_pdos.iter().map(|p| ("TxPDO", p)))
            .filter(|(_, p)| usize::from(p.sm) == i);
        for (kind, p) in pdos {
            out.push(format!("  {kind} {:#06x} \"{}\"", p.index, p.name));
            for e in &p.entries {
                out.push(format!(
                    "    PDO entry {:#06x}:{:02x}, {:2} bit, \"{}\"",
                    e.index, e.sub, e.bits, e.name
                ));
            }
        }
    }
    out
}

fn pdos(bus: &mut Bus<'_>, position: Option<u16>) -> Result<Vec<String>> {
    let all = position.is_none();
    let targets: Vec<u16> = match position {
        Some(p) => vec![p],
        None => (0..bus.len())
            .map(|p| u16::try_from(p).unwrap_or(u16::MAX))
            .collect(),
    };
    let mut out = Vec::new();
    for p in targets {
        let s = bus.sii(p)?;
        if all {
            out.push(format!("=== Master 0, Slave {p} ==="));
        }
        out.extend(format_pdos(&s));
    }
    Ok(out)
}

/// A decoded SII, field by field.
pub fn describe_sii(s: &Sii) -> Vec<String> {
    let mut out = vec![
        format!("Name: {}", s.name),
        format!("Order: {}", s.order),
        format!("Group: {}", s.group),
        format!("Vendor Id:       {:#010x}", s.identity.vendor),
        format!("Product code:    {:#010x}", s.identity.product),
        format!("Revision number: {:#010x}", s.identity.revision),
        format!("Serial number:   {:#010x}", s.identity.serial),
        format!("Alias: {}", s.alias),
    ];
    match &s.mailbox {
        Some(m) => out.push(format!(
            "Mailbox: out {:#06x}/{} in {:#06x}/{}, protocols {:#06x}{}",
            m.rx_offset,
            m.rx_size,
            m.tx_offset,
            m.tx_size,
            m.protocols,
            if m.protocols & sii::protocol::COE != 0 {
                " (CoE)"
            } else {
                ""
            }
        )),
        None => out.push("Mailbox: none".into()),
    }
    out.push(format!("CoE details: {:#04x}", s.coe_details));
    out.push(format!(
        "Distributed clocks: {}",
        if s.dc { "yes" } else { "no" }
    ));
    out.extend(format_pdos(s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slaves_are_listed_as_igh_lists_them() {
        let row = |position, alias, al_status| Listed {
            position,
            station: 0x1001 + position,
            alias,
            al_status,
            identity: (2, 0, 0, 0),
        };
        let rows: Vec<Listed> = (0..11)
            .map(|p| {
                row(
                    p,
                    0,
                    if p == 3 {
                        al::SAFEOP | al::ERROR
                    } else {
                        al::PREOP
                    },
                )
            })
            .collect();
        let names: Vec<String> = (0..11).map(|p| format!("T{p}")).collect();
        let out = format_slaves(&rows, &names);
        assert_eq!(out[0], " 0  0:0   PREOP   +  T0");
        assert_eq!(out[3], " 3  0:3   SAFEOP  E  T3");
        assert_eq!(out[10], "10  0:10  PREOP   +  T10");
    }
}
