//! The CAN servo bring-up tool's logic (`canservo-tool`): find the nodes
//! on a bus, read and write their objects by SDO with types, show a
//! drive's statusword decoded, step it through the CiA 402 power states,
//! send NMT commands, and watch the traffic with decoded fields. It runs
//! on a SocketCAN interface or on simulated drives in the process.

use std::time::{Duration, Instant};

use crate::bus::{CanBus, Filters, SimBus, SocketCanBus, WallClock};
use crate::decode::{nmt_state, Decoder};
use crate::drivefile::{parse_object, parse_type, TYPES};
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::power::{describe_statusword, AfterQuickStop, AnyPower, PowerState};
use crate::regs::{cob, describe_object, mode, nmt, obj};
use crate::sdo::SdoClient;

/// A bus to work on, with one endpoint that sees everything.
pub struct Tool {
    bus: Box<dyn CanBus>,
    timeout: Duration,
    _time: Option<WallClock>,
}

/// A power-state step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Shutdown (2, 6, 8).
    Shutdown,
    /// Switch on (3).
    SwitchOn,
    /// Enable operation (4, 16).
    EnableOperation,
    /// Disable operation (5).
    DisableOperation,
    /// Disable voltage (7, 9, 10, 12).
    DisableVoltage,
    /// Quick stop (11).
    QuickStop,
    /// Fault reset (15).
    FaultReset,
    /// All the way to Operation enabled.
    Up,
    /// All the way down to Switch on disabled.
    Down,
}

impl Step {
    /// The step named `s`.
    pub fn parse(s: &str) -> Option<Step> {
        Some(match s {
            "shutdown" => Step::Shutdown,
            "switch-on" => Step::SwitchOn,
            "enable-operation" | "enable" => Step::EnableOperation,
            "disable-operation" => Step::DisableOperation,
            "disable-voltage" | "disable" => Step::DisableVoltage,
            "quick-stop" => Step::QuickStop,
            "fault-reset" => Step::FaultReset,
            "up" => Step::Up,
            "down" => Step::Down,
            _ => return None,
        })
    }
}

impl Step {
    /// The step's name, as [`Step::parse`] takes it.
    pub fn name(self) -> &'static str {
        match self {
            Step::Shutdown => "shutdown",
            Step::SwitchOn => "switch-on",
            Step::EnableOperation => "enable-operation",
            Step::DisableOperation => "disable-operation",
            Step::DisableVoltage => "disable-voltage",
            Step::QuickStop => "quick-stop",
            Step::FaultReset => "fault-reset",
            Step::Up => "up",
            Step::Down => "down",
        }
    }
}

/// What `watch` does.
#[derive(Debug, Clone, Default)]
pub struct WatchOptions {
    /// Drives whose PDOs to decode.
    pub nodes: Vec<u8>,
    /// Read their PDO mappings first (else canservo's layout is assumed).
    pub read_mapping: bool,
    /// Send NMT start to them first.
    pub start: bool,
    /// Produce SYNC at this period while watching.
    pub sync: Option<Duration>,
    /// Stop after this many frames.
    pub count: Option<usize>,
    /// Stop after this long.
    pub duration: Option<Duration>,
}

/// The types [`Tool::read`] takes: the SDO types and `str`.
pub const READ_TYPES: &str = "u8, u16, u32, i8, i16, i32, str";

/// The names [`Step::parse`] takes.
pub const STEPS: &str =
    "shutdown, switch-on, enable-operation, disable-operation, disable-voltage, quick-stop, fault-reset, up, down";

impl Tool {
    /// Opens `iface`.
    pub fn socket(iface: &str, timeout: Duration) -> Result<Tool> {
        let bus = SocketCanBus::open(iface, &Filters::everything())?;
        Ok(Tool {
            bus: Box::new(bus),
            timeout,
            _time: None,
        })
    }

    /// Simulated drives at `nodes`, on a bus whose time follows the wall
    /// clock while the tool runs.
    pub fn sim(nodes: &[u8], timeout: Duration) -> Tool {
        let bus = SimBus::with_drives(nodes);
        let time = WallClock::run(bus.clone(), Duration::from_micros(500));
        let ep = bus.open(Filters::everything());
        Tool {
            bus: Box::new(ep),
            timeout,
            _time: Some(time),
        }
    }

    fn sdo(&self, node: u8) -> SdoClient<'_> {
        SdoClient::new(&*self.bus, node, self.timeout)
    }

    /// Sends `f`, retrying for a while if the transmit queue is full.
    fn send(&self, f: &Frame) -> Result<()> {
        let end = Instant::now() + self.timeout;
        while !self.bus.send(f) {
            if Instant::now() >= end {
                return Err(Error::SendFailed {
                    what: format!("frame {f}"),
                    bus: self.bus.describe(),
                });
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        Ok(())
    }

    /// Finds the nodes: optionally resets every node's communication
    /// first (and lists the boot-ups), then asks every node id for its
    /// device type at once and reads the identity of those that answer.
    pub fn scan(&self, reset: bool) -> Result<Vec<String>> {
        let mut lines = Vec::new();
        while self.bus.recv_timeout(Duration::ZERO).is_some() {}
        if reset {
            self.send(&Frame::new(cob::NMT, &[nmt::RESET_COMMUNICATION, 0]))?;
            let mut booted = Vec::new();
            let end = Instant::now() + self.timeout;
            while let Some(f) = self
                .bus
                .recv_timeout(end.saturating_duration_since(Instant::now()))
            {
                if let Some(id) = f.cob_id() {
                    let node = (id - cob::HEARTBEAT).to_string();
                    if (0x701..=0x77F).contains(&id)
                        && f.payload() == [nmt::STATE_BOOTUP]
                        && !booted.contains(&node)
                    {
                        booted.push(node);
                    }
                }
            }
            lines.push(format!(
                "boot-up from: {}",
                if booted.is_empty() {
                    "none".into()
                } else {
                    booted.join(", ")
                }
            ));
        }
        for node in 1..=127u16 {
            self.send(&Frame::new(
                cob::SDO_RX + node,
                &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0],
            ))?;
        }
        let mut found = Vec::new();
        let end = Instant::now() + self.timeout;
        while let Some(f) = self
            .bus
            .recv_timeout(end.saturating_duration_since(Instant::now()))
        {
            if let Some((cob::SDO_TX, node)) = f.cob_id().and_then(cob::split) {
                if f.data[1..3] == [0x00, 0x10] && !found.contains(&node) {
                    found.push(node);
                }
            }
        }
        found.sort_unstable();
        if found.is_empty() {
            lines.push(format!("no node answered on {}", self.bus.describe()));
        }
        for node in found {
            let sdo = self.sdo(node);
            let device_type = sdo.read_u32(obj::DEVICE_TYPE, 0)?;
            let profile = if device_type & 0xFFFF == obj::PROFILE_402 {
                " (CiA 402 drive)"
            } else {
                ""
            };
            let id = |sub| {
                sdo.read_u32(obj::IDENTITY, sub)
                    .map_or("-".to_string(), |v| format!("{v:#010x}"))
            };
            let name = sdo
                .read_string(obj::DEVICE_NAME, 0)
                .map(|n| format!(", \"{n}\""))
                .unwrap_or_default();
            lines.push(format!(
                "node {node}: device type {device_type:#010x}{profile}, vendor {} product {} revision {} serial {}{name}",
                id(1),
                id(2),
                id(3),
                id(4)
            ));
        }
        Ok(lines)
    }

    /// Reads `object` (`INDEX:SUB`) of `node` as `ty` (a [`SdoType`] name
    /// or `str`; None: the raw bytes and, up to 4 bytes, as unsigned).
    pub fn read(&self, node: u8, object: &str, ty: Option<&str>) -> Result<String> {
        let (index, sub) = parse_object(object)?;
        let name = describe_object(index, sub);
        let sdo = self.sdo(node);
        match ty {
            Some("str") => Ok(format!("{name} = \"{}\"", sdo.read_string(index, sub)?)),
            Some(t) => {
                let ty = parse_type(t, READ_TYPES)?;
                let bytes = sdo.upload(index, sub)?;
                let v = ty.decode(&bytes).ok_or_else(|| Error::TooShort {
                    object: name.clone(),
                    len: bytes.len(),
                    ty,
                })?;
                Ok(format!("{name} = {v} ({v:#x})"))
            }
            None => {
                let bytes = sdo.upload(index, sub)?;
                let hex: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
                let mut s = format!("{name} = [{}]", hex.join(" "));
                if (1..=4).contains(&bytes.len()) {
                    let mut b = [0u8; 4];
                    b[..bytes.len()].copy_from_slice(&bytes);
                    s.push_str(&format!(" = {}", u32::from_le_bytes(b)));
                }
                Ok(s)
            }
        }
    }

    /// Writes `value` as `ty` to `object` of `node`.
    pub fn write(&self, node: u8, object: &str, ty: &str, value: &str) -> Result<String> {
        let (index, sub) = parse_object(object)?;
        let ty = parse_type(ty, TYPES)?;
        let v = ty.parse_value(value)?;
        self.sdo(node).download(index, sub, &ty.bytes(v))?;
        Ok(format!("{} = {v}", describe_object(index, sub)))
    }

    /// A drive's state in words.
    pub fn status(&self, node: u8) -> Result<Vec<String>> {
        let sdo = self.sdo(node);
        let statusword = sdo.read_u16(obj::STATUSWORD, 0)?;
        let shown = sdo.read_i8(obj::MODES_DISPLAY, 0)?;
        let error = sdo.read_u16(obj::ERROR_CODE, 0)?;
        let register = sdo.read_u8(obj::ERROR_REGISTER, 0)?;
        let mut lines = vec![
            format!("statusword {}", describe_statusword(statusword)),
            format!("mode {shown} ({})", mode::name(shown)),
            format!("error code {}", crate::codes::ErrorCode(error)),
            format!("error register {register:#04x}"),
        ];
        for (index, what) in [
            (obj::POSITION_ACTUAL, "position actual"),
            (obj::VELOCITY_ACTUAL, "velocity actual"),
        ] {
            if let Ok(v) = sdo.read_i32(index, 0) {
                lines.push(format!("{what} {v}"));
            }
        }
        let end = Instant::now() + Duration::from_millis(300).min(self.timeout);
        while let Some(f) = self
            .bus
            .recv_timeout(end.saturating_duration_since(Instant::now()))
        {
            if f.cob_id() == Some(cob::HEARTBEAT + u16::from(node)) && f.len == 1 {
                lines.push(format!("NMT {}", nmt_state(f.data[0])));
                break;
            }
        }
        Ok(lines)
    }

    /// Copies the actual position into the target (and zeroes the target
    /// velocity), so enabling moves nothing (§6.11 step 6).
    fn hold_position(&self, node: u8) -> Result<()> {
        let sdo = self.sdo(node);
        let actual = sdo.read_i32(obj::POSITION_ACTUAL, 0)?;
        for r in [
            sdo.write_i32(obj::TARGET_POSITION, 0, actual),
            sdo.write_i32(obj::TARGET_VELOCITY, 0, 0),
        ] {
            match r {
                Err(Error::SdoAbort { code, .. }) if code == crate::codes::AbortCode::NO_OBJECT => {
                }
                r => r?,
            }
        }
        Ok(())
    }

    /// Takes `step` from the state the drive is in; the states passed.
    pub fn power(&self, node: u8, step: Step) -> Result<Vec<String>> {
        let sdo = self.sdo(node);
        let mut passed = Vec::new();
        let mut seen = |s: PowerState| passed.push(s.name().to_string());
        let now = AnyPower::read(&sdo, self.timeout)?;
        let from = match &now {
            AnyPower::SwitchOnDisabled(_) => PowerState::SwitchOnDisabled,
            AnyPower::ReadyToSwitchOn(_) => PowerState::ReadyToSwitchOn,
            AnyPower::SwitchedOn(_) => PowerState::SwitchedOn,
            AnyPower::OperationEnabled(_) => PowerState::OperationEnabled,
            AnyPower::QuickStopActive(_) => PowerState::QuickStopActive,
            AnyPower::Fault(_) => PowerState::Fault,
            AnyPower::NotReady(sw) => {
                return Err(Error::NotCommandable {
                    node,
                    statusword: describe_statusword(*sw),
                })
            }
        };
        seen(from);
        let refused = || Error::NoTransition {
            node,
            state: from.name(),
            step: step.name(),
        };
        match (now, step) {
            (AnyPower::SwitchOnDisabled(p), Step::Shutdown) => seen(p.shutdown()?.state()),
            (AnyPower::SwitchedOn(p), Step::Shutdown) => seen(p.shutdown()?.state()),
            (AnyPower::OperationEnabled(p), Step::Shutdown) => seen(p.shutdown()?.state()),
            (AnyPower::ReadyToSwitchOn(p), Step::SwitchOn) => seen(p.switch_on()?.state()),
            (AnyPower::SwitchedOn(p), Step::EnableOperation) => {
                self.hold_position(node)?;
                seen(p.enable_operation()?.state())
            }
            (AnyPower::QuickStopActive(p), Step::EnableOperation) => {
                seen(p.enable_operation()?.state())
            }
            (AnyPower::OperationEnabled(p), Step::DisableOperation) => {
                seen(p.disable_operation()?.state())
            }
            (AnyPower::ReadyToSwitchOn(p), Step::DisableVoltage) => {
                seen(p.disable_voltage()?.state())
            }
            (AnyPower::SwitchedOn(p), Step::DisableVoltage) => seen(p.disable_voltage()?.state()),
            (AnyPower::OperationEnabled(p), Step::DisableVoltage) => {
                seen(p.disable_voltage()?.state())
            }
            (AnyPower::QuickStopActive(p), Step::DisableVoltage) => {
                seen(p.disable_voltage()?.state())
            }
            (AnyPower::OperationEnabled(p), Step::QuickStop) => match p.quick_stop()? {
                AfterQuickStop::Active(q) => seen(q.state()),
                AfterQuickStop::Disabled(d) => {
                    seen(PowerState::QuickStopActive);
                    seen(d.state())
                }
            },
            (AnyPower::Fault(p), Step::FaultReset) => seen(p.fault_reset()?.state()),
            (AnyPower::Fault(_), Step::Up) => return Err(Error::InFault { node }),
            (now, Step::Up) => {
                let p = match now {
                    AnyPower::QuickStopActive(p) => {
                        let p = p.disable_voltage()?;
                        seen(p.state());
                        p.shutdown()?
                    }
                    AnyPower::SwitchOnDisabled(p) => p.shutdown()?,
                    AnyPower::ReadyToSwitchOn(p) => p,
                    AnyPower::SwitchedOn(p) => {
                        self.hold_position(node)?;
                        seen(p.enable_operation()?.state());
                        return Ok(passed);
                    }
                    _ => return Ok(passed),
                };
                seen(p.state());
                let p = p.switch_on()?;
                seen(p.state());
                self.hold_position(node)?;
                seen(p.enable_operation()?.state());
            }
            (now, Step::Down) => match now {
                AnyPower::OperationEnabled(p) => {
                    let p = p.disable_operation()?;
                    seen(p.state());
                    let p = p.shutdown()?;
                    seen(p.state());
                    seen(p.disable_voltage()?.state());
                }
                AnyPower::SwitchedOn(p) => {
                    let p = p.shutdown()?;
                    seen(p.state());
                    seen(p.disable_voltage()?.state());
                }
                AnyPower::ReadyToSwitchOn(p) => seen(p.disable_voltage()?.state()),
                AnyPower::QuickStopActive(p) => seen(p.disable_voltage()?.state()),
                _ => {}
            },
            _ => return Err(refused()),
        }
        Ok(passed)
    }

    /// Sends NMT `command` (start, stop, pre-operational, reset,
    /// reset-communication) to `node` (0 = all).
    pub fn nmt(&self, node: u8, command: &str) -> Result<String> {
        let cs = match command {
            "start" => nmt::START,
            "stop" => nmt::STOP,
            "pre-operational" | "preop" => nmt::ENTER_PRE_OPERATIONAL,
            "reset" => nmt::RESET_NODE,
            "reset-communication" => nmt::RESET_COMMUNICATION,
            c => {
                return Err(Error::NotAnNmtCommand {
                    command: c.to_string(),
                })
            }
        };
        let f = Frame::new(cob::NMT, &[cs, node]);
        self.send(&f)?;
        Ok(Decoder::new().describe(&f))
    }

    /// Prints the traffic, decoded, through `out`, as `opts` says.
    pub fn watch(&self, opts: &WatchOptions, mut out: impl FnMut(String)) -> Result<()> {
        let WatchOptions {
            nodes,
            read_mapping,
            start,
            sync,
            count,
            duration,
        } = opts.clone();
        let nodes = &nodes[..];
        let decoder = if read_mapping {
            Decoder::read_from(&*self.bus, nodes, self.timeout)
        } else {
            Decoder::canservo(nodes, true)
        };
        if start {
            for &n in nodes {
                self.send(&Frame::new(cob::NMT, &[nmt::START, n]))?;
            }
        }
        let begin = Instant::now();
        let mut next_sync = begin;
        let mut seen = 0usize;
        loop {
            if count.is_some_and(|c| seen >= c) || duration.is_some_and(|d| begin.elapsed() >= d) {
                return Ok(());
            }
            if let Some(p) = sync {
                if Instant::now() >= next_sync {
                    self.send(&Frame::new(cob::SYNC, &[]))?;
                    next_sync += p;
                }
            }
            let wait = sync.map_or(Duration::from_millis(50), |p| {
                p.min(Duration::from_millis(50))
            });
            if let Some(f) = self.bus.recv_timeout(wait) {
                seen += 1;
                out(format!(
                    "{:>10.6}  {:<30}  {}",
                    begin.elapsed().as_secs_f64(),
                    f.to_string(),
                    decoder.describe(&f)
                ));
            }
        }
    }
}
