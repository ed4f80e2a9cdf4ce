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
//! error naming the port and the reason.

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
pub struct Choice {
    /// Which backend.
    pub backend: Backend,
    /// The ppdev node (for ppdev, or to claim a raw port).
    pub dev: Option<PathBuf>,
    /// The base address, when known.
    pub base: Option<u16>,
    /// The ECP register address, when known.
    pub base_hi: Option<u16>,
}

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

/// Chooses the backend of `spec` (no device is opened).
pub fn choose(spec: &PortSpec, paths: &SysPaths) -> Result<Choice, PortError> {
    let linux = linux_ports(paths);
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
    let unknown_number = |n: u8| {
        PortError::NotFound(format!(
            "Linux has no parport{n}: {} does not exist and {} lists no such port \
             (load the parport_pc and ppdev kernel modules, or give the I/O address)",
            paths.dev_node(n).display(),
            paths.proc_parport.display()
        ))
    };
    match backend {
        Backend::Sim | Backend::SimLoop => {
            let base = match spec.addr {
                PortAddr::Number(n) => sim_base(n),
                PortAddr::Address(a) => a,
            };
            Ok(Choice {
                backend,
                dev: None,
                base: Some(base),
                base_hi: base.checked_add(regs::HI_OFFSET),
            })
        }
        Backend::Ppdev => {
            if let Some(why) = need_raw(spec.mode) {
                return Err(PortError::Unsupported(format!(
                    "{why}; use the raw backend (needs CAP_SYS_RAWIO)"
                )));
            }
            let dev = match spec.addr {
                PortAddr::Number(n) => paths.dev_node(n),
                PortAddr::Address(a) => match known {
                    Some(p) => paths.dev_node(p.num),
                    None => {
                        return Err(PortError::NotFound(format!(
                            "no Linux parport has base address {a:#x} ({} lists none), \
                             so ppdev cannot reach it; use the raw backend",
                            paths.proc_parport.display()
                        )))
                    }
                },
            };
            if !dev.exists() {
                return Err(PortError::NoDevice {
                    path: dev.display().to_string(),
                });
            }
            Ok(Choice {
                backend,
                dev: Some(dev),
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
                (PortAddr::Number(n), None) => return Err(unknown_number(n)),
            };
            Ok(Choice {
                backend,
                dev: node,
                base: Some(base),
                base_hi,
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
    /// The backend in use.
    pub backend: Backend,
}

impl std::fmt::Debug for Opened {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Opened")
            .field("io", &self.io.describe())
            .field("backend", &self.backend)
            .finish()
    }
}

/// Checks, after the claim, that a ppdev port can serve `mode`: `in`
/// needs a bidirectional port (`PARPORT_MODE_TRISTATE`); `x` and `epp`
/// need raw I/O.
pub fn check_ppdev_mode<I: PpIoctl>(p: &PpdevPort<I>, mode: Mode) -> Result<(), PortError> {
    if let Some(why) = need_raw(mode) {
        return Err(PortError::Unsupported(format!(
            "{why}; use the raw backend (needs CAP_SYS_RAWIO)"
        )));
    }
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
    let opened = match choice.backend {
        Backend::Sim | Backend::SimLoop => {
            let base = choice.base.unwrap_or(0x378);
            let mut cfg = SimConfig::new(base);
            cfg.base_hi = choice.base_hi;
            if choice.backend == Backend::SimLoop {
                cfg = cfg.with_loopback();
            }
            let sim = Arc::new(SimPort::new(cfg, clock));
            Opened {
                io: sim.clone(),
                sim: Some(sim),
                backend: choice.backend,
            }
        }
        Backend::Ppdev => {
            let dev = choice.dev.as_deref().unwrap_or(Path::new("/dev/parport0"));
            let p = PpdevPort::open(&dev.display().to_string(), choice.base)?;
            p.claim()?;
            check_ppdev_mode(&p, mode)?;
            Opened {
                io: Arc::new(p),
                sim: None,
                backend: Backend::Ppdev,
            }
        }
        Backend::Raw => {
            let base = choice.base.ok_or_else(|| {
                PortError::NotFound("raw port I/O needs the port's address".into())
            })?;
            let claim_via = match &choice.dev {
                Some(d) => Some(PpdevPort::open(&d.display().to_string(), Some(base))?),
                None => None,
            };
            let p = RawPort::open(base, choice.base_hi, claim_via)?;
            Opened {
                io: Arc::new(p),
                sim: None,
                backend: Backend::Raw,
            }
        }
    };
    opened.io.claim()?;
    Ok(opened)
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
        assert_eq!(c.backend, Backend::Ppdev);
        assert_eq!(c.dev, Some(p.dev.join("parport0")));
        assert_eq!((c.base, c.base_hi), (Some(0x378), Some(0x778)));
        assert_eq!(pick("0x378", &p).unwrap().backend, Backend::Ppdev);
        let c = pick("1", &p).unwrap();
        assert_eq!(
            (c.backend, c.base, c.dev),
            (Backend::Raw, Some(0x278), None)
        );
        // An address Linux does not know: no ECR is guessed (base+0x400
        // may be another device's on a PCI card).
        let c = pick("0xc000", &p).unwrap();
        assert_eq!(
            (c.backend, c.base, c.base_hi),
            (Backend::Raw, Some(0xc000), None)
        );
        // x and epp need raw I/O; the Linux port is still claimed by ppdev.
        let c = pick("0 x", &p).unwrap();
        assert_eq!(c.backend, Backend::Raw);
        assert_eq!(c.dev, Some(p.dev.join("parport0")));
        assert_eq!(pick("0x378 epp", &p).unwrap().backend, Backend::Raw);
        let e = pick("3", &p).unwrap_err().to_string();
        assert!(e.contains("Linux has no parport3"), "{e}");
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
        assert_eq!((c.base, c.base_hi), (Some(0x278), Some(0x678)));
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
