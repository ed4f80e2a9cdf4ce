//! Choosing and opening the backend of each configured port.
//!
//! Linux lists the ports it found in `/proc/sys/dev/parport/parportN/`
//! (`base-addr` holds two decimal numbers: base and base_hi) and offers
//! them as `/dev/parportN`. Without a backend token in the cfg string:
//!
//! * a port number N uses ppdev on `/dev/parportN` if it exists, else raw
//!   I/O at the base address /proc lists for it;
//! * an address uses ppdev if a Linux port has that base and its device
//!   node exists, else raw I/O at that address;
//! * `x` and `epp` always use raw I/O (ppdev cannot read live control
//!   lines or write the ECR); the port is still claimed through ppdev when
//!   Linux knows it, so nothing else uses it meanwhile.
//!
//! An explicit backend that cannot work for the port or its mode is an
//! error naming the port and the reason. [`choose_all`] chooses every
//! port of one `loadrt` before any is opened, reading Linux's list once,
//! and refuses two entries that are one port (`0` and `0x378` when
//! parport0 is at 0x378): the second `PPCLAIM` of a port would block
//! forever. [`open`] then claims each port once.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::cfg::{Backend, Mode, PortAddr, PortSpec};
use crate::clock::Clock;
use crate::port::ppdev::{PpIoctl, PpdevPort, MODE_TRISTATE};
use crate::port::raw::RawPort;
use crate::port::{PortError, PortIo};
use crate::regs;
use crate::sim::{SimConfig, SimPort};

/// Where the kernel's parport information lives (tests point this at a
/// directory of their own).
#[derive(Debug, Clone)]
pub struct SysPaths {
    /// The device directory (`/dev`).
    pub dev: PathBuf,
    /// The parport sysctl directory (`/proc/sys/dev/parport`).
    pub proc_parport: PathBuf,
}

impl SysPaths {
    /// The real system's paths.
    pub fn system() -> SysPaths {
        SysPaths {
            dev: PathBuf::from("/dev"),
            proc_parport: PathBuf::from("/proc/sys/dev/parport"),
        }
    }

    fn dev_node(&self, n: u8) -> PathBuf {
        self.dev.join(format!("parport{n}"))
    }
}

/// A port Linux registered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinuxPort {
    /// Its number (`/dev/parportN`).
    pub num: u8,
    /// Its base I/O address.
    pub base: u16,
    /// Its ECP register address, if it has one.
    pub base_hi: Option<u16>,
}

/// The ports Linux registered (numbers 0..15).
pub fn linux_ports(paths: &SysPaths) -> Vec<LinuxPort> {
    (0..16u8)
        .filter_map(|num| {
            let f = paths
                .proc_parport
                .join(format!("parport{num}"))
                .join("base-addr");
            let text = std::fs::read_to_string(f).ok()?;
            let mut it = text.split_whitespace().map(|w| w.parse::<u32>().ok());
            let base = u16::try_from(it.next()??).ok()?;
            let base_hi = it
                .next()
                .flatten()
                .and_then(|h| u16::try_from(h).ok())
                .filter(|&h| h != 0);
            Some(LinuxPort { num, base, base_hi })
        })
        .collect()
}

/// The simulated base address of a port number: the three legacy ISA
/// addresses, then a made-up range.
pub fn sim_base(n: u8) -> u16 {
    match n {
        0 => 0x378,
        1 => 0x278,
        2 => 0x3BC,
        n => 0x1000 + 0x10 * n as u16,
    }
}

/// The backend chosen for a port, with what it needs to open.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Choice {
    /// `/dev/parportN` through ppdev.
    Ppdev {
        /// The device node.
        dev: PathBuf,
        /// The base address, when /proc lists the port.
        base: Option<u16>,
        /// The ECP register address, when /proc lists one.
        base_hi: Option<u16>,
    },
    /// `inb`/`outb` after `ioperm`.
    Raw {
        /// The base address.
        base: u16,
        /// The ECP register address, when Linux knows the port and it has
        /// one (never guessed: base+0x400 may be another device's).
        base_hi: Option<u16>,
        /// The ppdev node to claim the port through, when Linux knows it,
        /// so nothing else uses the port meanwhile.
        claim_via: Option<PathBuf>,
    },
    /// The simulator.
    Sim {
        /// The simulated base address.
        base: u16,
        /// The simulated ECP register address.
        base_hi: Option<u16>,
        /// Whether the loopback plug is in the connector.
        loopback: bool,
    },
}

impl Choice {
    /// Which backend.
    pub fn backend(&self) -> Backend {
        match self {
            Choice::Ppdev { .. } => Backend::Ppdev,
            Choice::Raw { .. } => Backend::Raw,
            Choice::Sim {
                loopback: false, ..
            } => Backend::Sim,
            Choice::Sim { loopback: true, .. } => Backend::SimLoop,
        }
    }

    /// The ppdev node the port is opened or claimed through, if any.
    pub fn dev(&self) -> Option<&Path> {
        match self {
            Choice::Ppdev { dev, .. } => Some(dev),
            Choice::Raw { claim_via, .. } => claim_via.as_deref(),
            Choice::Sim { .. } => None,
        }
    }

    /// The base address, when known.
    pub fn base(&self) -> Option<u16> {
        match *self {
            Choice::Ppdev { base, .. } => base,
            Choice::Raw { base, .. } | Choice::Sim { base, .. } => Some(base),
        }
    }

    /// What `self` and `other` share if they are the same port: the
    /// device node or the base address.
    fn shared_with(&self, other: &Choice) -> Option<String> {
        if let (Some(a), Some(b)) = (self.dev(), other.dev()) {
            if a == b {
                return Some(format!("both use {}", a.display()));
            }
        }
        match (self.base(), other.base()) {
            (Some(a), Some(b)) if a == b => Some(format!("both are at base {a:#x}")),
            _ => None,
        }
    }
}

/// Why a mode needs raw I/O, if it does.
fn need_raw(mode: Mode) -> Option<&'static str> {
    match mode {
        Mode::X => Some(
            "x mode reads the control lines, but ppdev's PPRCONTROL returns the kernel's cached \
             copy of the last written value, not the live levels",
        ),
        Mode::Epp => Some("epp mode writes the ECR, which ppdev cannot reach"),
        _ => None,
    }
}

/// Chooses the backend of `spec` (no device is opened). Reads Linux's
/// port list; to choose several ports, [`choose_all`] reads it once.
pub fn choose(spec: &PortSpec, paths: &SysPaths) -> Result<Choice, PortError> {
    choose_among(spec, &linux_ports(paths), paths)
}

/// Chooses the backend of every port of one `loadrt`, reading Linux's
/// port list once, and refuses two entries that are the same port (the
/// same device node or base address, e.g. `0` and `0x378` when parport0
/// is at 0x378). Nothing is opened: claiming one port twice would block
/// in `PPCLAIM` forever. An error comes with the index of the entry it
/// concerns.
pub fn choose_all(specs: &[PortSpec], paths: &SysPaths) -> Result<Vec<Choice>, (usize, PortError)> {
    let linux = linux_ports(paths);
    let mut choices: Vec<Choice> = Vec::with_capacity(specs.len());
    for (i, spec) in specs.iter().enumerate() {
        let c = choose_among(spec, &linux, paths).map_err(|e| (i, e))?;
        for (j, earlier) in choices.iter().enumerate() {
            if let Some(shared) = c.shared_with(earlier) {
                return Err((
                    i,
                    PortError::SamePort {
                        other: j,
                        other_spec: specs[j].to_string(),
                        shared,
                    },
                ));
            }
        }
        choices.push(c);
    }
    Ok(choices)
}

/// [`choose`] with Linux's port list already read.
fn choose_among(
    spec: &PortSpec,
    linux: &[LinuxPort],
    paths: &SysPaths,
) -> Result<Choice, PortError> {
    let known = match spec.addr {
        PortAddr::Number(n) => linux.iter().find(|p| p.num == n).copied(),
        PortAddr::Address(a) => linux.iter().find(|p| p.base == a).copied(),
    };
    let node = match spec.addr {
        PortAddr::Number(n) => Some(paths.dev_node(n)),
        PortAddr::Address(_) => known.map(|p| paths.dev_node(p.num)),
    }
    .filter(|p| p.exists());
    let backend = match spec.backend {
        Some(b) => b,
        None if need_raw(spec.mode).is_some() => Backend::Raw,
        None if node.is_some() => Backend::Ppdev,
        None => Backend::Raw,
    };
    match backend {
        Backend::Sim | Backend::SimLoop => {
            let base = match spec.addr {
                PortAddr::Number(n) => sim_base(n),
                PortAddr::Address(a) => a,
            };
            Ok(Choice::Sim {
                base,
                base_hi: base.checked_add(regs::HI_OFFSET),
                loopback: backend == Backend::SimLoop,
            })
        }
        Backend::Ppdev => {
            if let Some(why) = need_raw(spec.mode) {
                return Err(PortError::Unsupported(format!(
                    "{why}; use the raw backend (needs CAP_SYS_RAWIO)"
                )));
            }
            let dev = match (spec.addr, known) {
                (PortAddr::Number(n), _) => paths.dev_node(n),
                (PortAddr::Address(_), Some(p)) => paths.dev_node(p.num),
                (PortAddr::Address(a), None) => {
                    return Err(PortError::NotFound(format!(
                        "no Linux parport has base address {a:#x} ({} lists none), \
                         so ppdev cannot reach it; use the raw backend",
                        paths.proc_parport.display()
                    )))
                }
            };
            if node.is_none() {
                return Err(PortError::NoDevice {
                    path: dev.display().to_string(),
                });
            }
            Ok(Choice::Ppdev {
                dev,
                base: known.map(|p| p.base),
                base_hi: known.and_then(|p| p.base_hi),
            })
        }
        Backend::Raw => {
            let (base, base_hi) = match (spec.addr, known) {
                (_, Some(p)) => (p.base, p.base_hi),
                // Not a port Linux knows: its ECR address is unknown, and
                // base+0x400 may belong to another device on a PCI card.
                (PortAddr::Address(a), None) => (a, None),
                (PortAddr::Number(n), None) => {
                    return Err(PortError::NotFound(format!(
                        "Linux has no parport{n}: {} does not exist and {} lists no such port \
                         (load the parport_pc and ppdev kernel modules, or give the I/O address)",
                        paths.dev_node(n).display(),
                        paths.proc_parport.display()
                    )))
                }
            };
            Ok(Choice::Raw {
                base,
                base_hi,
                claim_via: node,
            })
        }
    }
}

/// An opened, claimed port.
pub struct Opened {
    /// The register access.
    pub io: Arc<dyn PortIo>,
    /// The simulator, for the sim backends.
    pub sim: Option<Arc<SimPort>>,
}

impl std::fmt::Debug for Opened {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Opened")
            .field("io", &self.io.describe())
            .finish()
    }
}

/// Checks, after the claim, that a ppdev port can serve `mode`: `in`
/// needs a bidirectional port (`PARPORT_MODE_TRISTATE`), which only the
/// claimed port reports. (`x` and `epp` never get this far: [`choose`]
/// refuses them on ppdev.)
pub fn check_ppdev_mode<I: PpIoctl>(p: &PpdevPort<I>, mode: Mode) -> Result<(), PortError> {
    if mode == Mode::In && p.modes() & MODE_TRISTATE == 0 {
        return Err(PortError::Unsupported(format!(
            "in mode needs a bidirectional port, and {} reports no PARPORT_MODE_TRISTATE \
             (set the port to PS/2, EPP or ECP mode in the BIOS)",
            p.path()
        )));
    }
    Ok(())
}

/// Opens and claims the port `choice` describes, checking that the
/// backend can serve `mode`. `clock` stamps a simulator's log.
pub fn open(choice: &Choice, mode: Mode, clock: Arc<dyn Clock>) -> Result<Opened, PortError> {
    match choice {
        &Choice::Sim {
            base,
            base_hi,
            loopback,
        } => {
            let mut cfg = SimConfig::new(base);
            cfg.base_hi = base_hi;
            if loopback {
                cfg = cfg.with_loopback();
            }
            let sim = Arc::new(SimPort::new(cfg, clock));
            sim.claim()?;
            Ok(Opened {
                io: sim.clone(),
                sim: Some(sim),
            })
        }
        Choice::Ppdev { dev, base, .. } => {
            let p = PpdevPort::open(&dev.display().to_string(), *base)?;
            p.claim()?;
            check_ppdev_mode(&p, mode)?;
            Ok(Opened {
                io: Arc::new(p),
                sim: None,
            })
        }
        Choice::Raw {
            base,
            base_hi,
            claim_via,
        } => {
            let claim_via = match claim_via {
                Some(d) => Some(PpdevPort::open(&d.display().to_string(), Some(*base))?),
                None => None,
            };
            let p = RawPort::open(*base, *base_hi, claim_via)?;
            p.claim()?;
            Ok(Opened {
                io: Arc::new(p),
                sim: None,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cfg::parse;

    struct Tree(PathBuf);

    impl Drop for Tree {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// A fake /dev + /proc with Linux ports `(num, base, base_hi, has_node)`.
    fn tree(tag: &str, ports: &[(u8, u16, u16, bool)]) -> (Tree, SysPaths) {
        let root = std::env::temp_dir().join(format!("pp-sel-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let paths = SysPaths {
            dev: root.join("dev"),
            proc_parport: root.join("proc"),
        };
        std::fs::create_dir_all(&paths.dev).unwrap();
        for &(n, base, hi, node) in ports {
            let d = paths.proc_parport.join(format!("parport{n}"));
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(d.join("base-addr"), format!("{base}\t{hi}\n")).unwrap();
            if node {
                std::fs::write(paths.dev.join(format!("parport{n}")), b"").unwrap();
            }
        }
        (Tree(root), paths)
    }

    fn pick(cfg: &str, paths: &SysPaths) -> Result<Choice, PortError> {
        choose(&parse(cfg).unwrap()[0], paths)
    }

    #[test]
    fn reads_proc_base_addresses() {
        let (_t, p) = tree("proc", &[(0, 0x378, 0x778, true), (2, 0xc000, 0, false)]);
        assert_eq!(
            linux_ports(&p),
            vec![
                LinuxPort {
                    num: 0,
                    base: 0x378,
                    base_hi: Some(0x778)
                },
                LinuxPort {
                    num: 2,
                    base: 0xc000,
                    base_hi: None
                }
            ]
        );
    }

    #[test]
    fn default_backend_prefers_ppdev_then_raw() {
        let (_t, p) = tree("auto", &[(0, 0x378, 0x778, true), (1, 0x278, 0, false)]);
        let c = pick("0", &p).unwrap();
        assert_eq!(c.backend(), Backend::Ppdev);
        assert_eq!(
            c,
            Choice::Ppdev {
                dev: p.dev.join("parport0"),
                base: Some(0x378),
                base_hi: Some(0x778)
            }
        );
        assert_eq!(pick("0x378", &p).unwrap().backend(), Backend::Ppdev);
        let c = pick("1", &p).unwrap();
        assert_eq!(
            c,
            Choice::Raw {
                base: 0x278,
                base_hi: None,
                claim_via: None
            }
        );
        // An address Linux does not know: no ECR is guessed (base+0x400
        // may be another device's on a PCI card).
        let c = pick("0xc000", &p).unwrap();
        assert_eq!(
            c,
            Choice::Raw {
                base: 0xc000,
                base_hi: None,
                claim_via: None
            }
        );
        // x and epp need raw I/O; the Linux port is still claimed by ppdev.
        let c = pick("0 x", &p).unwrap();
        assert_eq!(c.backend(), Backend::Raw);
        assert_eq!(c.dev(), Some(p.dev.join("parport0").as_path()));
        assert_eq!(pick("0x378 epp", &p).unwrap().backend(), Backend::Raw);
        let e = pick("3", &p).unwrap_err().to_string();
        assert!(e.contains("Linux has no parport3"), "{e}");
    }

    #[test]
    fn one_port_named_twice_is_refused_before_anything_is_opened() {
        // parport0 is at 0x378: "0" and "0x378" are the same port, which
        // the cfg parser cannot see. Opening both would block in the
        // second PPCLAIM forever, so the chooser must refuse them.
        let (_t, p) = tree("twice", &[(0, 0x378, 0x778, true), (1, 0x278, 0, true)]);
        let all = |cfg: &str| choose_all(&parse(cfg).unwrap(), &p);
        for (cfg, shared) in [
            ("0 0x378", "parport0"),
            ("0 x 0x378", "parport0"),
            ("0x378 epp 0", "parport0"),
            ("1 0 sim 0x278 raw", "parport1"),
            ("0 sim 0x378 sim", "base 0x378"),
            ("2 simloop 0x3bc sim", "base 0x3bc"),
        ] {
            let (i, e) = all(cfg).expect_err(cfg);
            let e = e.to_string();
            assert!(i > 0, "{cfg}: the later entry is the one refused");
            assert!(e.contains("same port as port"), "{cfg}: {e}");
            assert!(e.contains(shared), "{cfg}: {e}");
        }
        let (i, e) = all("0 x 0x378").unwrap_err();
        assert_eq!(i, 1);
        assert_eq!(
            e.to_string(),
            format!(
                "it is the same port as port 0 (parport0, x mode): both use {}",
                p.dev.join("parport0").display()
            )
        );
        // Different ports are fine, on every backend.
        let c = all("0 1 sim 0x3bc raw").unwrap();
        assert_eq!(
            c.iter().map(Choice::backend).collect::<Vec<_>>(),
            vec![Backend::Ppdev, Backend::Sim, Backend::Raw]
        );
    }

    #[test]
    fn impossible_combinations_are_refused_with_reasons() {
        let (_t, p) = tree("bad", &[(0, 0x378, 0x778, true), (1, 0x278, 0, false)]);
        let e = pick("0 x ppdev", &p).unwrap_err().to_string();
        assert!(e.contains("x mode") && e.contains("cached"), "{e}");
        let e = pick("0 epp ppdev", &p).unwrap_err().to_string();
        assert!(e.contains("ECR"), "{e}");
        let e = pick("1 ppdev", &p).unwrap_err().to_string();
        assert!(e.contains("parport1 does not exist"), "{e}");
        let e = pick("0x3bc ppdev", &p).unwrap_err().to_string();
        assert!(e.contains("no Linux parport has base address 0x3bc"), "{e}");
        let e = pick("5 raw", &p).unwrap_err().to_string();
        assert!(e.contains("Linux has no parport5"), "{e}");
    }

    #[test]
    fn sim_backends_need_nothing_from_the_system() {
        let (_t, p) = tree("sim", &[]);
        let c = pick("1 simloop", &p).unwrap();
        assert_eq!(
            c,
            Choice::Sim {
                base: 0x278,
                base_hi: Some(0x678),
                loopback: true
            }
        );
        let o = open(&c, Mode::Out, Arc::new(crate::clock::MonotonicClock)).unwrap();
        assert!(o.sim.as_ref().unwrap().plug().is_some());
        assert!(o.sim.as_ref().unwrap().is_claimed());
        assert_eq!(sim_base(5), 0x1050);
    }

    #[test]
    fn opening_a_node_that_is_not_a_parport_fails_at_claim() {
        let (_t, p) = tree("claim", &[(0, 0x378, 0x778, true)]);
        let c = pick("0", &p).unwrap();
        let e = open(&c, Mode::Out, Arc::new(crate::clock::MonotonicClock)).unwrap_err();
        assert!(e.to_string().contains("PPCLAIM on"), "{e}");
    }
}
