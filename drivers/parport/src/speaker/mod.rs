//! `hal_speaker`: LinuxCNC's PC-speaker driver. Eight bit inputs
//! `speaker.0.pin-NN-out` (NN 00 to 07); the function `speaker.0.write`
//! clicks the speaker when their combined value changed since its last
//! run: it sets the speaker data bit of system control port B (0x61) in
//! that run and clears it in the next. The gate of the interval timer's
//! channel 2 (bit 0 of the same port) is kept off, as LinuxCNC keeps it:
//! the speaker is driven by the data bit alone, and the timer is left as
//! it is. The other bits of port B are written back as read.
//!
//! Port I/O goes through the driver layer's port buses: `ioperm` (raw
//! `inb`/`outb`, needs `CAP_SYS_RAWIO`) or `devport` (`/dev/port`), or
//! the simulated speaker of [`sim`]. `backend` is this suite's addition
//! (LinuxCNC's module takes no parameters): `auto`, the default, takes
//! `ioperm` when the port can be had and otherwise the simulator, with a
//! warning saying why (nothing but a speaker depends on it); a named
//! backend that cannot be had is a load error.

pub mod sim;

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Pin, Result};
use hal_driver::bus::{DevPortPorts, IopermPorts, PortBus, PortRange};
use hal_driver::params::BackendTokens;
use hal_driver::sim::SimBoard;

use sim::{SpeakerModel, PORT_B};

/// The module's name.
pub const NAME: &str = "hal_speaker";

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "backend",
    kind: ParamKind::Str,
    help:
        "auto|ioperm|devport|sim: auto (the default) takes ioperm if permitted, else the simulator",
}];

/// The `hal_speaker` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: PARAMS,
    help: "PC speaker driver: clicks when its eight bit inputs change",
    load,
};

/// The key under which a simulated speaker is published
/// ([`hal_driver::sim::find`] with the instance's name).
pub const SIM_KEY: &str = "hal_speaker.0";

/// How the speaker is reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// ioperm when it can be had, else the simulator.
    Auto,
    /// Raw port I/O.
    Ioperm,
    /// `/dev/port`.
    DevPort,
    /// The simulated speaker.
    Sim,
}

/// The `backend=` tokens, read the way every driver reads them.
const BACKENDS: BackendTokens = BackendTokens::new(&["auto", "ioperm", "devport"], &[]);

/// `backend=`, checked.
pub fn backend(args: &ModuleArgs) -> Result<Backend> {
    let token = args.str("backend").unwrap_or("auto");
    let bad = || HalError::ModuleParam {
        module: NAME.into(),
        param: "backend".into(),
        reason: format!("'{token}' is not one of {}", BACKENDS.list()),
    };
    Ok(match BACKENDS.parse(token).ok_or_else(bad)?.token() {
        "auto" => Backend::Auto,
        "ioperm" => Backend::Ioperm,
        "devport" => Backend::DevPort,
        _ => Backend::Sim,
    })
}

fn port_range() -> Result<[PortRange; 1]> {
    PortRange::new(PORT_B, 1)
        .map(|r| [r])
        .map_err(|e| HalError::ModuleParam {
            module: NAME.into(),
            param: "backend".into(),
            reason: e.to_string(),
        })
}

fn no_port(backend: &str, e: impl std::fmt::Display) -> HalError {
    HalError::ModuleParam {
        module: NAME.into(),
        param: "backend".into(),
        reason: format!("{backend}: port {PORT_B:#x} cannot be reached: {e}"),
    }
}

/// A new simulated speaker, published for tests and tools under
/// [`SIM_KEY`] in `host`'s instance.
fn simulated(host: &Host) -> Arc<dyn PortBus> {
    let board = Arc::new(SimBoard::new(SpeakerModel::new()));
    hal_driver::sim::publish(host.instance().name(), SIM_KEY, &board);
    board
}

/// Opens the bus `backend` names.
pub fn open(host: &Host, backend: Backend) -> Result<Arc<dyn PortBus>> {
    Ok(match backend {
        Backend::Sim => simulated(host),
        Backend::Ioperm => {
            Arc::new(IopermPorts::open(&port_range()?).map_err(|e| no_port("ioperm", e))?)
        }
        Backend::DevPort => {
            Arc::new(DevPortPorts::open(&port_range()?).map_err(|e| no_port("devport", e))?)
        }
        Backend::Auto => match IopermPorts::open(&port_range()?) {
            Ok(p) => Arc::new(p),
            Err(e) => {
                host.rt_log().warn(format_args!(
                    "{NAME}: port {PORT_B:#x} cannot be reached ({e}): the speaker is simulated; \
                     give backend=ioperm to make this an error"
                ));
                simulated(host)
            }
        },
    })
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let bus = open(host, backend(args)?)?;
    load_on(host, bus)
}

/// Exports the speaker on `bus` (what `loadrt` does after opening it).
pub fn load_on(host: &Host, bus: Arc<dyn PortBus>) -> Result<()> {
    let mut b = host.new_rt_component(NAME)?;
    let pins = (0..8)
        .map(|i| {
            b.component()
                .pin::<bool, In>(&format!("speaker.0.pin-{i:02}-out"))
        })
        .collect::<Result<Vec<Pin<bool, In>>>>()?;
    let mut speaker = Speaker { last: 0 };
    let safe_bus = bus.clone();
    b.funct("speaker.0.write", false, move |_| {
        speaker.write(&*bus, &pins)
    })?;
    // Silence: the data bit off, the timer's gate off.
    b.on_safe_state(move || {
        let rest = safe_bus.inb(PORT_B) & 0xfc;
        safe_bus.outb(PORT_B, rest);
    });
    b.ready()
}

/// The function's state: the inputs at its last run.
struct Speaker {
    last: u8,
}

impl Speaker {
    /// One run: packs the inputs, and sets the speaker bit if they
    /// changed since the last run (clears it otherwise).
    fn write(&mut self, bus: &dyn PortBus, pins: &[Pin<bool, In>]) {
        let v = pins
            .iter()
            .enumerate()
            .fold(0u8, |acc, (i, p)| acc | (u8::from(p.get()) << i));
        let rest = bus.inb(PORT_B) & 0xfc;
        bus.outb(PORT_B, if v != self.last { rest | 2 } else { rest });
        self.last = v;
    }
}

#[cfg(test)]
mod tests;
