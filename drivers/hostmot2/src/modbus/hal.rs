//! `loadrt hm2_modbus ports=... mbccbs=...`: one instance per PktUART
//! (`hm2_modbus.N`, up to eight), each running its `.mbccb` file. Load
//! after the board driver: the PktUART is found by its HAL name among the
//! boards loaded in this HAL. Per instance: the read-only parameters
//! `baudrate`, `drivedelay`, `icdelay`, `parity`, `rxdelay`, `stopbits`,
//! `txdelay`; the pins `fault`, `fault-command`, `last-error-code`,
//! `reset`, `suspend`; per command `command.MM.{disable, disabled,
//! error-code, errors, reset}`; the file's data pins (with `.offset`,
//! `.scale`, `.scaled`); and the function `hm2_modbus.N.process`, which
//! goes after the board's `read` and before its `write`.
//!
//! The function reads its input pins, takes at most one step of the
//! Modbus exchange on what the board's `read` brought (staging what its
//! `write` sends; the period is skipped if a board function holds the
//! board), and sets its output pins. It never reaches the board itself.
//! Load time sets the PktUART up directly and attaches it to the board's
//! bursts; unloading detaches it.

use std::io::Read;
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{HalError, HalHost};
use hal_core::{HostParam, HostPin, In, Out, PinFactory, Ro};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};

use super::engine::Engine;
use super::line::Versions;
use super::mbccb::{self, HalType};
use super::pins::DataPin;
use super::values::Value;
use crate::error::{Hm2Error, MbccbProblem, ModbusParamProblem};
use crate::pktuart::PktUartPort;
use crate::registry::{self, SserialAccess};

const NAME: &str = "hm2_modbus";
/// Instances at most.
pub const MAX_PORTS: usize = 8;

/// hm2_modbus's module parameters (one table, read by both hosts).
#[macro_export]
macro_rules! hm2_modbus_params {
    ($($then:tt)*) => { $($then)*! {
        ports: StrArray(8) = "PktUART HAL names, e.g. hm2_7i96s.0.pktuart.0",
        mbccbs: StrArray(8) = "compiled command files (mesambccc output), one per port",
        debug: Int = "message level 0..5 (-1: leave as is)",
    } };
}

/// The `hm2_modbus` module.
#[derive(Debug)]
pub struct HalModbus;

/// The `hm2_modbus` module.
pub static HM2_MODBUS_MODULE: ModuleDef = module::module_def::<HalModbus>();

/// One instance, opened: its PktUART's link on its board, and engine.
pub struct Opened {
    link: Attached,
    engine: Engine,
}

/// A PktUART attached to its board's bursts; detached when dropped (at
/// unload, or when a later port of the same load fails).
struct Attached {
    board: Arc<dyn SserialAccess>,
    id: usize,
}

impl Attached {
    /// Runs `job` on the link unless a board function holds the board.
    #[inline]
    fn job(&self, job: &mut dyn FnMut(&mut crate::pktuart::PktUartLink)) -> bool {
        self.board.link_job(self.id, job)
    }
}

impl Drop for Attached {
    fn drop(&mut self) {
        self.board.detach_pktuart(self.id);
    }
}

fn fail(e: Hm2Error) -> HalError {
    HalError::module_failed(NAME, e)
}

impl DriverModule for HalModbus {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "Modbus RTU over Mesa PktUARTs (load after the board driver)";
    const PARAMS: &'static [ParamDecl] = hm2_modbus_params!(hal_driver::param_table);
    type Opened = Vec<Opened>;

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Vec<Opened>> {
        let ports = args.str_array("ports");
        let files = args.str_array("mbccbs");
        if ports.is_empty() {
            return Err(fail(Hm2Error::ModbusParams(ModbusParamProblem::NoPorts)));
        }
        if ports.len() > MAX_PORTS {
            return Err(fail(Hm2Error::ModbusParams(ModbusParamProblem::TooMany(
                ports.len(),
            ))));
        }
        let log = env.log();
        let mut out = Vec::with_capacity(ports.len());
        for (i, port) in ports.iter().enumerate() {
            let file = files
                .get(i)
                .filter(|f| !f.is_empty())
                .ok_or_else(|| fail(Hm2Error::ModbusParams(ModbusParamProblem::MissingFile(i))))?;
            let o = open_one(env.instance(), port, file).map_err(fail)?;
            for w in &o.engine.file().warnings {
                log.warn(format_args!("{NAME}.{i}: warning: {w}"));
            }
            let l = o.engine.line;
            let parity = ['N', 'O', 'E'][l.parity.min(2) as usize];
            log.info(format_args!(
                "{NAME}.{i}: PktUART serial port '{port}' configured to 8{parity}{}@{}",
                l.stop_bits, l.baud
            ));
            out.push(o);
        }
        Ok(out)
    }

    fn export<H: DriverHost>(
        opened: Vec<Opened>,
        ex: &mut Exporter<'_, H>,
    ) -> hal_core::Result<()> {
        let comp = ex.component(NAME)?;
        for (i, o) in opened.into_iter().enumerate() {
            let prefix = format!("{NAME}.{i}");
            let hal = HalPins::<H>::export(ex.pins(comp), &prefix, &o.engine)?;
            let Opened { link, mut engine } = o;
            ex.funct(comp, &format!("{prefix}.process"), true, move |ctx| {
                hal.get(&mut engine);
                let period = ctx.period();
                link.job(&mut |l| engine.process(l, period));
                hal.set(&engine);
            })?;
        }
        Ok(())
    }
}

/// Finds `port` on this HAL's boards, reads and checks `file`, and sets
/// the PktUART up.
fn open_one(instance: &str, port_name: &str, file: &str) -> Result<Opened, Hm2Error> {
    let (board, inst) = registry::boards_of(instance)
        .into_iter()
        .find_map(|(_, b)| {
            let i = b.pktuart().by_name(port_name).cloned()?;
            Some((b, i))
        })
        .ok_or_else(|| Hm2Error::NoSuchPktUart {
            port: port_name.to_string(),
        })?;
    let bytes = read_file(file)?;
    let parsed = mbccb::parse(&bytes)?;
    let versions = Versions {
        rx: inst.rx_version,
        tx: inst.tx_version,
    };
    let engine = Engine::new(parsed, versions);
    let port = PktUartPort::new(inst);
    let (rx, tx) = engine.configs();
    let mut res = Ok(());
    board.transport_job(true, &mut |t| res = port.configure(t, &rx, &tx, true));
    res.map_err(|source| Hm2Error::Transport {
        op: format!("PktUART setup of {port_name}"),
        source,
    })?;
    let id = board.attach_pktuart(port.instance())?;
    Ok(Opened {
        link: Attached { board, id },
        engine,
    })
}

/// The file's bytes, refusing one over the size limit without reading it
/// all, and anything but a regular file (a FIFO would block the load).
fn read_file(path: &str) -> Result<Vec<u8>, Hm2Error> {
    let io = |e: std::io::Error| Hm2Error::MbccbRead {
        path: path.to_string(),
        reason: e.to_string(),
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(Hm2Error::MbccbRead {
            path: path.to_string(),
            reason: "not a regular file".into(),
        });
    }
    let f = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    f.take(mbccb::MAX_FILE as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() > mbccb::MAX_FILE {
        return Err(Hm2Error::Mbccb {
            offset: mbccb::MAX_FILE,
            what: MbccbProblem::SizeMismatch {
                len: bytes.len(),
                expected: mbccb::MAX_FILE,
            },
        });
    }
    Ok(bytes)
}

/// A data pin's HAL handle, by type and direction.
enum DataHandle<H: HalHost> {
    BitIn(H::Pin<bool, In>),
    BitOut(H::Pin<bool, Out>),
    FloatIn(H::Pin<f64, In>),
    FloatOut(H::Pin<f64, Out>),
    S32In(H::Pin<i32, In>),
    S32Out(H::Pin<i32, Out>),
    U32In(H::Pin<u32, In>),
    U32Out(H::Pin<u32, Out>),
    S64In(H::Pin<i64, In>),
    S64Out(H::Pin<i64, Out>),
    U64In(H::Pin<u64, In>),
    U64Out(H::Pin<u64, Out>),
}

/// An input pin of any of the offset types.
enum OffsetHandle<H: HalHost> {
    Float(H::Pin<f64, In>),
    S32(H::Pin<i32, In>),
    S64(H::Pin<i64, In>),
    U64(H::Pin<u64, In>),
}

struct DataHal<H: HalHost> {
    pin: DataHandle<H>,
    offset: Option<OffsetHandle<H>>,
    scale: Option<H::Pin<f64, In>>,
    scaled: Option<H::Pin<f64, Out>>,
}

struct CommandHal<H: HalHost> {
    disable: H::Pin<bool, In>,
    disabled: H::Pin<bool, Out>,
    error_code: H::Pin<u32, Out>,
    errors: H::Pin<u32, Out>,
    reset: H::Pin<bool, In>,
}

struct HalPins<H: HalHost> {
    suspend: H::Pin<bool, In>,
    reset: H::Pin<bool, In>,
    fault: H::Pin<bool, Out>,
    fault_command: H::Pin<u32, Out>,
    last_error_code: H::Pin<u32, Out>,
    params: [H::Param<u32, Ro>; 7],
    commands: Vec<CommandHal<H>>,
    data: Vec<DataHal<H>>,
}

fn data_pin<H: HalHost>(
    c: &impl PinFactory<H>,
    name: &str,
    p: &DataPin,
) -> hal_core::Result<DataHal<H>> {
    use DataHandle as D;
    let pin = match (p.spec.htype, p.output) {
        (HalType::Bit, false) => D::BitIn(c.pin(name)?),
        (HalType::Bit, true) => D::BitOut(c.pin(name)?),
        (HalType::Float, false) => D::FloatIn(c.pin(name)?),
        (HalType::Float, true) => D::FloatOut(c.pin(name)?),
        (HalType::S32, false) => D::S32In(c.pin(name)?),
        (HalType::S32, true) => D::S32Out(c.pin(name)?),
        (HalType::U32, false) => D::U32In(c.pin(name)?),
        (HalType::U32, true) => D::U32Out(c.pin(name)?),
        (HalType::S64, false) => D::S64In(c.pin(name)?),
        (HalType::S64, true) => D::S64Out(c.pin(name)?),
        (HalType::U64, false) => D::U64In(c.pin(name)?),
        (HalType::U64, true) => D::U64Out(c.pin(name)?),
    };
    let scale = match p.scale {
        Some(s) => Some(c.pin_init(&format!("{name}.scale"), s)?),
        None => None,
    };
    let scaled = match p.scaled {
        Some(_) => Some(c.pin(&format!("{name}.scaled"))?),
        None => None,
    };
    let on = format!("{name}.offset");
    let offset = match p.offset {
        None => None,
        Some(Value::Float(_)) => Some(OffsetHandle::Float(c.pin(&on)?)),
        Some(Value::S32(_)) => Some(OffsetHandle::S32(c.pin(&on)?)),
        Some(Value::S64(_)) => Some(OffsetHandle::S64(c.pin(&on)?)),
        Some(_) => Some(OffsetHandle::U64(c.pin(&on)?)),
    };
    Ok(DataHal {
        pin,
        offset,
        scale,
        scaled,
    })
}

impl<H: HalHost> HalPins<H> {
    fn export(c: &impl PinFactory<H>, prefix: &str, e: &Engine) -> hal_core::Result<HalPins<H>> {
        let l = e.line;
        let param = |n: &str, v: u32| c.param::<u32, Ro>(&format!("{prefix}.{n}"), v);
        let params = [
            param("baudrate", l.baud)?,
            param("drivedelay", l.drvdelay)?,
            param("icdelay", l.icdelay)?,
            param("parity", l.parity)?,
            param("rxdelay", l.rxdelay)?,
            param("stopbits", l.stop_bits)?,
            param("txdelay", l.txdelay)?,
        ];
        let pin_name = |n: &str| format!("{prefix}.{n}");
        let mut commands = Vec::with_capacity(e.commands.len());
        for (m, p) in e.commands.iter().enumerate() {
            let n = |s: &str| format!("{prefix}.command.{m:02}.{s}");
            commands.push(CommandHal {
                disable: c.pin(&n("disable"))?,
                disabled: c.pin_init(&n("disabled"), p.disabled)?,
                error_code: c.pin_init(&n("error-code"), p.error_code)?,
                errors: c.pin(&n("errors"))?,
                reset: c.pin(&n("reset"))?,
            });
        }
        let data = e
            .pins
            .iter()
            .map(|p| data_pin(c, &pin_name(&p.spec.name), p))
            .collect::<hal_core::Result<Vec<_>>>()?;
        Ok(HalPins {
            suspend: c.pin_init(&pin_name("suspend"), e.global.suspend)?,
            reset: c.pin(&pin_name("reset"))?,
            fault: c.pin(&pin_name("fault"))?,
            fault_command: c.pin(&pin_name("fault-command"))?,
            last_error_code: c.pin(&pin_name("last-error-code"))?,
            params,
            commands,
            data,
        })
    }

    /// Input pins into the engine.
    fn get(&self, e: &mut Engine) {
        e.global.suspend = self.suspend.get();
        e.global.reset = self.reset.get();
        for (h, p) in self.commands.iter().zip(&mut e.commands) {
            p.disable = h.disable.get();
            p.reset = h.reset.get();
        }
        for (h, p) in self.data.iter().zip(&mut e.pins) {
            use DataHandle as D;
            match &h.pin {
                D::BitIn(x) => p.value = Value::Bit(x.get()),
                D::FloatIn(x) => p.value = Value::Float(x.get()),
                D::S32In(x) => p.value = Value::S32(x.get()),
                D::U32In(x) => p.value = Value::U32(x.get()),
                D::S64In(x) => p.value = Value::S64(x.get()),
                D::U64In(x) => p.value = Value::U64(x.get()),
                _ => {}
            }
            if let Some(s) = &h.scale {
                p.scale = Some(s.get());
            }
            p.offset = h.offset.as_ref().map(|o| match o {
                OffsetHandle::Float(x) => Value::Float(x.get()),
                OffsetHandle::S32(x) => Value::S32(x.get()),
                OffsetHandle::S64(x) => Value::S64(x.get()),
                OffsetHandle::U64(x) => Value::U64(x.get()),
            });
        }
    }

    /// The engine onto the output pins and parameters.
    fn set(&self, e: &Engine) {
        self.fault.set(e.global.fault);
        self.fault_command.set(e.global.fault_command);
        self.last_error_code.set(e.global.last_error_code);
        let l = e.line;
        let vals = [
            l.baud,
            l.drvdelay,
            l.icdelay,
            l.parity,
            l.rxdelay,
            l.stop_bits,
            l.txdelay,
        ];
        for (p, v) in self.params.iter().zip(vals) {
            p.set(v);
        }
        for (h, p) in self.commands.iter().zip(&e.commands) {
            h.disabled.set(p.disabled);
            h.error_code.set(p.error_code);
            h.errors.set(p.errors);
        }
        for (h, p) in self.data.iter().zip(&e.pins) {
            use DataHandle as D;
            match (&h.pin, p.value) {
                (D::BitOut(x), Value::Bit(v)) => x.set(v),
                (D::FloatOut(x), Value::Float(v)) => x.set(v),
                (D::S32Out(x), Value::S32(v)) => x.set(v),
                (D::U32Out(x), Value::U32(v)) => x.set(v),
                (D::S64Out(x), Value::S64(v)) => x.set(v),
                (D::U64Out(x), Value::U64(v)) => x.set(v),
                _ => {}
            }
            if let (Some(x), Some(v)) = (&h.scaled, p.scaled) {
                x.set(v);
            }
        }
    }
}
