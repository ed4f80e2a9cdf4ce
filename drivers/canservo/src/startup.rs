//! Bringing drives up, in hardware.md §6.11's order, with the steps as
//! types: a [`Network`] is `Network<Booted>` after NMT reset
//! communication and the boot-up messages, `Network<Identified>` after
//! the identity checks, `Network<Configured>` after heartbeats, PDO
//! mapping, mode and drive file, and `Network<Operational>` after NMT
//! start. Each step is a method of the state before it and consumes it,
//! and the cyclic engine takes only an operational network, so a step
//! left out or taken out of order does not compile:
//!
//! ```compile_fail
//! # use hal_canservo::startup::{Network, Booted};
//! # fn f(net: Network<'_, Booted>) {
//! let _ = net.start(); // configure (and identify) first
//! # }
//! ```
//!
//! Every failure names the node and what it did not answer or refused.
//!
//! The process image the driver maps (the same for every drive):
//!
//! | PDO | COB-ID | type | contents |
//! |---|---|---|---|
//! | RPDO1 | 0x200 + id | 1 | controlword 0x6040, target (0x607A in CSP, 0x60FF in PV/CSV), modes of operation 0x6060 (7 bytes) |
//! | TPDO1 | 0x180 + id | 1 | statusword 0x6041, position actual 0x6064, modes of operation display 0x6061 (7 bytes) |
//! | TPDO2 | 0x280 + id | 1 | velocity actual 0x606C, error code 0x603F (6 bytes) |
//!
//! RPDO2..4 and TPDO3..4 are switched off. The mode byte in RPDO1 lets
//! the realtime side switch to homing mode and back without SDO.

use std::marker::PhantomData;
use std::time::{Duration, Instant};

use crate::bus::CanBus;
use crate::codes::AbortCode;
use crate::drivefile::DriveFile;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::regs::{cob, mode, nmt, obj};
use crate::sdo::SdoClient;

/// The control mode a drive runs in (the shared CiA 402 layer's; canservo
/// runs CSP, PV and CSV).
pub use hal_cia402::Mode;

/// What is known of one drive.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct DeviceIdentity {
    /// 0x1000.
    pub device_type: u32,
    /// 0x1018:1.
    pub vendor: u32,
    /// 0x1018:2 (0 if absent).
    pub product: u32,
    /// 0x1018:3 (0 if absent).
    pub revision: u32,
    /// 0x1018:4 (0 if absent).
    pub serial: u32,
}

impl std::fmt::Display for DeviceIdentity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "vendor {:#010x} product {:#010x} revision {:#010x} serial {:#010x}",
            self.vendor, self.product, self.revision, self.serial
        )
    }
}

/// One drive to bring up.
#[derive(Debug, Clone)]
pub struct NodePlan {
    /// Node id, 1..=127.
    pub node: u8,
    /// Its mode.
    pub mode: Mode,
    /// Its drive file, if any.
    pub file: Option<DriveFile>,
}

/// One drive as far as it has come.
#[derive(Debug, Clone)]
pub struct NodeInfo {
    /// What was asked for.
    pub plan: NodePlan,
    /// What it reported (after identification).
    pub identity: DeviceIdentity,
}

/// Settings of the whole start-up.
#[derive(Debug, Clone)]
pub struct StartupConfig {
    /// Wait for each SDO answer.
    pub sdo_timeout: Duration,
    /// Wait for the boot-up messages.
    pub boot_timeout: Duration,
    /// The drives' heartbeat period (0x1017, ms; 0 = off).
    pub heartbeat_ms: u16,
    /// The master's own heartbeat: its node id and the time after which
    /// each drive counts it lost (written to 0x1016 sub 1); None = the
    /// drives do not watch the master.
    pub master_heartbeat: Option<(u8, u16)>,
    /// The servo period, written to 0x60C2.
    pub period_ns: u64,
}

impl Default for StartupConfig {
    fn default() -> StartupConfig {
        StartupConfig {
            sdo_timeout: Duration::from_millis(500),
            boot_timeout: Duration::from_millis(1000),
            heartbeat_ms: 100,
            master_heartbeat: Some((127, 300)),
            period_ns: 1_000_000,
        }
    }
}

/// 0x60C2's (value, index) for a period: the coarsest unit from 1 ms
/// down to 1 µs that gives a whole value up to 255, else the nearest
/// µs-based value.
pub fn interpolation_period(period_ns: u64) -> (u8, i8) {
    for index in [-3i8, -4, -5, -6] {
        let unit = 10u64.pow((9 + i32::from(index)) as u32);
        if period_ns % unit == 0 && period_ns / unit <= 255 && period_ns / unit > 0 {
            return ((period_ns / unit) as u8, index);
        }
    }
    for index in [-6i8, -5, -4, -3] {
        let unit = 10u64.pow((9 + i32::from(index)) as u32);
        let v = (period_ns + unit / 2) / unit;
        if (1..=255).contains(&v) {
            return (v as u8, index);
        }
    }
    (255, -3)
}

/// After NMT reset communication: every node has sent its boot-up.
#[derive(Debug)]
pub struct Booted;
/// Every node is a CiA 402 drive supporting its mode.
#[derive(Debug)]
pub struct Identified;
/// Heartbeats, PDOs, mode and drive files are set.
#[derive(Debug)]
pub struct Configured;
/// NMT start sent: PDOs flow.
#[derive(Debug)]
pub struct Operational;

/// The drives of one bus during start-up, in state `S`.
pub struct Network<'b, S> {
    bus: &'b dyn CanBus,
    cfg: StartupConfig,
    nodes: Vec<NodeInfo>,
    _state: PhantomData<S>,
}

impl<S> std::fmt::Debug for Network<'_, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Network")
            .field("bus", &self.bus.describe())
            .field("nodes", &self.nodes)
            .finish()
    }
}

impl<'b, S> Network<'b, S> {
    fn next<T>(self) -> Network<'b, T> {
        Network {
            bus: self.bus,
            cfg: self.cfg,
            nodes: self.nodes,
            _state: PhantomData,
        }
    }

    /// The drives.
    pub fn nodes(&self) -> &[NodeInfo] {
        &self.nodes
    }

    fn sdo(&self, node: u8) -> SdoClient<'b> {
        SdoClient::new(self.bus, node, self.cfg.sdo_timeout)
    }

    fn nmt(&self, command: u8, node: u8, what: &str) -> Result<()> {
        if self.bus.send(&Frame::new(cob::NMT, &[command, node])) {
            Ok(())
        } else {
            Err(Error::SendFailed {
                what: format!("NMT {what} to node {node}"),
                bus: self.bus.describe(),
            })
        }
    }
}

/// Whether an abort means the object is simply not there (optional
/// objects are then skipped).
fn missing(e: &Error) -> bool {
    matches!(e, Error::SdoAbort { code, .. } if *code == AbortCode::NO_OBJECT || *code == AbortCode::NO_SUBINDEX)
}

impl<'b> Network<'b, Booted> {
    /// NMT reset communication to each planned node, then waits for every
    /// boot-up message.
    pub fn boot(
        bus: &'b dyn CanBus,
        plans: Vec<NodePlan>,
        cfg: StartupConfig,
    ) -> Result<Network<'b, Booted>> {
        let net = Network::<Booted> {
            bus,
            cfg,
            nodes: plans
                .into_iter()
                .map(|plan| NodeInfo {
                    plan,
                    identity: DeviceIdentity::default(),
                })
                .collect(),
            _state: PhantomData,
        };
        while bus.try_recv().is_some() {}
        for n in &net.nodes {
            net.nmt(nmt::RESET_COMMUNICATION, n.plan.node, "reset communication")?;
        }
        let mut waiting: Vec<u8> = net.nodes.iter().map(|n| n.plan.node).collect();
        let end = Instant::now() + net.cfg.boot_timeout;
        while !waiting.is_empty() {
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(Error::NoBootUp {
                    nodes: waiting,
                    timeout_ms: net.cfg.boot_timeout.as_millis() as u64,
                });
            }
            let Some(f) = bus.recv_timeout(left) else {
                continue;
            };
            if let Some(id) = f.cob_id() {
                if (0x701..=0x77F).contains(&id) && f.len == 1 && f.data[0] == nmt::STATE_BOOTUP {
                    let node = (id - cob::HEARTBEAT) as u8;
                    waiting.retain(|&n| n != node);
                }
            }
        }
        Ok(net)
    }

    /// Reads 0x1000 and 0x1018 of every node and checks 0x6502 for its
    /// mode.
    pub fn identify(mut self) -> Result<Network<'b, Identified>> {
        for i in 0..self.nodes.len() {
            let node = self.nodes[i].plan.node;
            let sdo = self.sdo(node);
            let device_type = sdo.read_u32(obj::DEVICE_TYPE, 0)?;
            if device_type & 0xFFFF != obj::PROFILE_402 {
                return Err(Error::NotCia402 { node, device_type });
            }
            let optional = |sub: u8| match sdo.read_u32(obj::IDENTITY, sub) {
                Err(e) if missing(&e) => Ok(0),
                r => r,
            };
            let identity = DeviceIdentity {
                device_type,
                vendor: sdo.read_u32(obj::IDENTITY, 1)?,
                product: optional(2)?,
                revision: optional(3)?,
                serial: optional(4)?,
            };
            let m = self.nodes[i].plan.mode;
            match sdo.read_u32(obj::SUPPORTED_MODES, 0) {
                Ok(supported) => {
                    let bit = mode::supported_bit(m.number()).unwrap_or(0);
                    if supported & bit == 0 {
                        return Err(Error::ModeUnsupported {
                            node,
                            mode: m.number(),
                            name: mode::name(m.number()),
                            supported,
                        });
                    }
                }
                Err(e) if missing(&e) => {}
                Err(e) => return Err(e),
            }
            self.nodes[i].identity = identity;
        }
        Ok(self.next())
    }
}

impl<'b> Network<'b, Identified> {
    /// Heartbeat producer and consumer, PDO mapping, interpolation
    /// period, mode of operation, then the drive file, on every node.
    pub fn configure(self) -> Result<Network<'b, Configured>> {
        for n in &self.nodes {
            configure_node(self.bus, &self.cfg, &n.plan)?;
        }
        Ok(self.next())
    }
}

/// The writes of [`Network::configure`] for one node.
fn configure_node(bus: &dyn CanBus, cfg: &StartupConfig, plan: &NodePlan) -> Result<()> {
    let node = plan.node;
    let id = u32::from(node);
    let sdo = SdoClient::new(bus, node, cfg.sdo_timeout);
    sdo.write_u16(obj::PRODUCER_HEARTBEAT, 0, cfg.heartbeat_ms)?;
    if let Some((master, ms)) = cfg.master_heartbeat {
        sdo.write_u32(
            obj::CONSUMER_HEARTBEAT,
            1,
            u32::from(master) << 16 | u32::from(ms),
        )?;
    }
    let target = obj::map_entry(plan.mode.target_object(), 0, 32);
    let pdo = |comm: u16, map: u16, cob_base: u32, entries: &[u32]| -> Result<()> {
        let cob_id = cob_base + id;
        sdo.write_u32(comm, 1, obj::COB_INVALID | cob_id)?;
        if entries.is_empty() {
            return Ok(());
        }
        sdo.write_u8(map, 0, 0)?;
        for (s, e) in entries.iter().enumerate() {
            sdo.write_u32(map, s as u8 + 1, *e)?;
        }
        sdo.write_u8(map, 0, entries.len() as u8)?;
        sdo.write_u8(comm, 2, 1)?;
        sdo.write_u32(comm, 1, cob_id)
    };
    pdo(
        obj::RPDO_COMM,
        obj::RPDO_MAP,
        0x200,
        &[
            obj::map_entry(obj::CONTROLWORD, 0, 16),
            target,
            obj::map_entry(obj::MODES_OF_OPERATION, 0, 8),
        ],
    )?;
    for p in 1..4u16 {
        pdo(
            obj::RPDO_COMM + p,
            obj::RPDO_MAP + p,
            0x200 + 0x100 * u32::from(p),
            &[],
        )?;
    }
    pdo(
        obj::TPDO_COMM,
        obj::TPDO_MAP,
        0x180,
        &[
            obj::map_entry(obj::STATUSWORD, 0, 16),
            obj::map_entry(obj::POSITION_ACTUAL, 0, 32),
            obj::map_entry(obj::MODES_DISPLAY, 0, 8),
        ],
    )?;
    pdo(
        obj::TPDO_COMM + 1,
        obj::TPDO_MAP + 1,
        0x280,
        &[
            obj::map_entry(obj::VELOCITY_ACTUAL, 0, 32),
            obj::map_entry(obj::ERROR_CODE, 0, 16),
        ],
    )?;
    for p in 2..4u16 {
        pdo(
            obj::TPDO_COMM + p,
            obj::TPDO_MAP + p,
            0x180 + 0x100 * u32::from(p),
            &[],
        )?;
    }
    let (value, index) = interpolation_period(cfg.period_ns);
    match sdo
        .write_u8(obj::INTERPOLATION_PERIOD, 1, value)
        .and_then(|()| sdo.write_i8(obj::INTERPOLATION_PERIOD, 2, index))
    {
        Err(e) if missing(&e) && plan.mode == Mode::Pv => {}
        r => r?,
    }
    let wanted = plan.mode.number();
    sdo.write_i8(obj::MODES_OF_OPERATION, 0, wanted)?;
    let end = Instant::now() + cfg.sdo_timeout;
    loop {
        let shown = sdo.read_i8(obj::MODES_DISPLAY, 0)?;
        if shown == wanted {
            break;
        }
        if Instant::now() >= end {
            return Err(Error::ModeNotTaken {
                node,
                wanted,
                shown,
            });
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    if let Some(file) = &plan.file {
        file.apply(&sdo)?;
    }
    Ok(())
}

impl<'b> Network<'b, Configured> {
    /// NMT start to every node.
    pub fn start(self) -> Result<Network<'b, Operational>> {
        for n in &self.nodes {
            self.nmt(nmt::START, n.plan.node, "start")?;
        }
        Ok(self.next())
    }

    /// Lets go of the bus, to start the drives later on the same bus
    /// ([`Detached::attach`]): the driver configures its drives before it
    /// exports anything, and starts them once its pins exist.
    pub fn detach(self) -> Detached {
        Detached {
            cfg: self.cfg,
            nodes: self.nodes,
        }
    }
}

/// A configured network between [`Network::detach`] and
/// [`Detached::attach`].
#[derive(Debug)]
pub struct Detached {
    cfg: StartupConfig,
    nodes: Vec<NodeInfo>,
}

impl Detached {
    /// The drives.
    pub fn nodes(&self) -> &[NodeInfo] {
        &self.nodes
    }

    /// The configured network again, on `bus`: the bus it was configured
    /// on.
    pub fn attach(self, bus: &dyn CanBus) -> Network<'_, Configured> {
        Network {
            bus,
            cfg: self.cfg,
            nodes: self.nodes,
            _state: PhantomData,
        }
    }
}

impl<'b> Network<'b, Operational> {
    /// The operational drives, for the cyclic engine.
    pub fn into_nodes(self) -> Vec<NodeInfo> {
        self.nodes
    }
}

/// Brings one node up again from scratch (after a bus-off or a reboot
/// of the drive): the same steps as at load, for that node only.
pub fn restart_node(bus: &dyn CanBus, cfg: &StartupConfig, plan: &NodePlan) -> Result<NodeInfo> {
    let net = Network::boot(bus, vec![plan.clone()], cfg.clone())?;
    let mut nodes = net.identify()?.configure()?.start()?.into_nodes();
    Ok(nodes.remove(0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_periods() {
        assert_eq!(interpolation_period(1_000_000), (1, -3));
        assert_eq!(interpolation_period(4_000_000), (4, -3));
        assert_eq!(interpolation_period(2_500_000), (25, -4));
        assert_eq!(interpolation_period(250_000), (25, -5));
        assert_eq!(interpolation_period(125_000), (125, -6));
        assert_eq!(interpolation_period(333_333), (33, -5));
    }
}
