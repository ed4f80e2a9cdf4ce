//! The `loadrt` parameters and opening the board they describe: the
//! backend, the base address (searched or given), the model (detected
//! or forced), the channel count and the digital port directions.

use std::sync::Arc;

use hal_core::module::ModuleArgs;
use hal_driver::bus::{IopermPorts, PortBus};
use hal_driver::params::{Backend, BackendTokens, Params};
use hal_driver::sim::{Clock, MonotonicClock, SimBoard, SimClock};
use hal_driver::DriverError;

use crate::detect::{self, Model};
use crate::dio::{self, Dio};
use crate::driver::Stg;
use crate::error::StgError;
use crate::regs;
use crate::sim::StgModel;

/// The backend tokens of `backend=`.
pub const BACKENDS: BackendTokens = BackendTokens::new(&["ioperm", "devport"], &[]);
/// Where a simulated board sits when `base` is not given.
pub const SIM_DEFAULT_BASE: u16 = 0x300;

/// The parsed parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// How the ports are reached.
    pub backend: Backend,
    /// The base address, or `None` to search.
    pub base: Option<u16>,
    /// The model, or `None` to detect it.
    pub model: Option<Model>,
    /// Channels exported (1..8).
    pub num_chan: usize,
    /// The digital ports' directions.
    pub dio: Dio,
}

/// Reads `backend`, `base`, `model`, `num_chan` and `dio`.
pub fn parse(args: &ModuleArgs) -> Result<Config, DriverError> {
    let p = Params::new(crate::hal::NAME, args);
    let token = p.str_or("backend", "ioperm");
    let backend = BACKENDS.parse(token).ok_or_else(|| {
        p.error(
            "backend",
            format!("'{token}' is not one of {}", BACKENDS.list()),
        )
    })?;
    let base = p.int_or("base", 0);
    let base = match base {
        0 => None,
        b if (0..=0xFFFF).contains(&b) && regs::CANDIDATE_BASES.contains(&(b as u16)) => {
            Some(b as u16)
        }
        b => {
            let shown = if b < 0 {
                b.to_string()
            } else {
                format!("{b:#x}")
            };
            return Err(p.error(
                "base",
                format!(
                    "{shown} is not a Servo-To-Go base address (0x200, 0x220, ... 0x3e0; 0 \
                     searches them)"
                ),
            ));
        }
    };
    let model = match p.int_in("model", 0, 0..=2)? {
        0 => None,
        n => Model::from_number(n),
    };
    let num_chan = p.int_in("num_chan", regs::CHANNELS as i64, 1..=regs::CHANNELS as i64)? as usize;
    let dio =
        Dio::parse(p.str_or("dio", dio::DEFAULT)).map_err(|e| p.error("dio", e.to_string()))?;
    Ok(Config {
        backend,
        base,
        model,
        num_chan,
        dio,
    })
}

/// The board, opened and initialised.
pub struct Opened {
    /// Its registers.
    pub drv: Stg,
    /// The simulated board, when it is one.
    pub sim: Option<Arc<SimBoard<StgModel>>>,
    /// What the search or the forced model had to say (a signature that
    /// disagrees with `model=`).
    pub warning: Option<String>,
}

/// Opens the board `cfg` describes: a simulated one, or the ports
/// through `ioperm`; finds its base and model; initialises it.
pub fn open(cfg: &Config) -> Result<Opened, StgError> {
    let (bus, sim, settle): (Arc<dyn PortBus>, _, Arc<dyn Clock>) = match cfg.backend {
        Backend::Sim(_) => {
            let model = cfg.model.unwrap_or(Model::Two);
            let base = cfg.base.unwrap_or(SIM_DEFAULT_BASE);
            let sim = Arc::new(SimBoard::new(StgModel::new(model, base)));
            // The multiplexer settles on a clock of its own that moves
            // 1 us per reading, so the wait ends at once.
            (sim.clone(), Some(sim), Arc::new(SimClock::new(0, 1_000)))
        }
        Backend::Real("devport") => {
            return Err(StgError::Backend(
                "backend=devport cannot drive a Servo-To-Go: /dev/port moves one byte per \
                 access, and the board's DACs and ADCs take 16-bit accesses (a DAC written a \
                 byte at a time outputs a wrong voltage in between); use backend=ioperm \
                 (CAP_SYS_RAWIO). hal_stg::probe works over /dev/port."
                    .into(),
            ))
        }
        Backend::Real(_) => {
            let ranges = match cfg.base {
                Some(b) => detect::port_ranges(b)?.to_vec(),
                None => detect::candidate_ranges(),
            };
            (
                Arc::new(IopermPorts::open(&ranges)?),
                None,
                Arc::new(MonotonicClock),
            )
        }
    };
    let (base, model, warning) = locate(&*bus, cfg)?;
    // A search opened every candidate window; keep only the board's.
    let bus: Arc<dyn PortBus> = match (cfg.backend, cfg.base) {
        (Backend::Real(_), None) => Arc::new(IopermPorts::open(&detect::port_ranges(base)?)?),
        _ => bus,
    };
    let drv = Stg::new(bus, base, model, cfg.dio, settle);
    drv.init();
    Ok(Opened { drv, sim, warning })
}

/// The board's base and model: searched or probed, the model detected
/// or forced. A forced model still needs something to answer.
fn locate(bus: &dyn PortBus, cfg: &Config) -> Result<(u16, Model, Option<String>), StgError> {
    let (base, detected) = match cfg.base {
        None => {
            let (b, m) = detect::autodetect(bus)?;
            (b, Some(m))
        }
        Some(b) => {
            let s = detect::read_signature(bus, b);
            if s.empty {
                return Err(StgError::NothingAnswers { base: b });
            }
            match (Model::from_signature(s.value), cfg.model) {
                (Some(m), _) => (b, Some(m)),
                (None, Some(_)) => (b, None),
                (None, None) => {
                    return Err(StgError::NotAnStg {
                        base: b,
                        signature: s.value,
                    })
                }
            }
        }
    };
    Ok(match (cfg.model, detected) {
        (Some(forced), Some(found)) if forced != found => (
            base,
            forced,
            Some(format!(
                "{}: the board at {base:#x} says it is a {found}; model={} makes it a {forced}",
                crate::hal::NAME,
                if forced.is_two() { 2 } else { 1 }
            )),
        ),
        (Some(forced), None) => (
            base,
            forced,
            Some(format!(
                "{}: the board at {base:#x} gives no Servo-To-Go signature; model={} makes it a {forced}",
                crate::hal::NAME,
                if forced.is_two() { 2 } else { 1 }
            )),
        ),
        (_, Some(found)) => (base, found, None),
        (None, None) => unreachable!("a search or an unforced probe found a model"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(args: &[&str]) -> hal_core::Result<Config> {
        let a = ModuleArgs::parse(crate::hal::NAME, crate::hal::PARAMS, args)?;
        parse(&a).map_err(|e| e.into_hal(crate::hal::NAME))
    }

    #[test]
    fn linuxcnc_parameters() {
        let c = cfg(&["base=0x300", "num_chan=4", "dio=\"IOIO\""]).unwrap();
        assert_eq!(c.base, Some(0x300));
        assert_eq!(c.model, None);
        assert_eq!(c.num_chan, 4);
        assert_eq!(c.dio.to_string(), "IOIO");
        assert_eq!(c.backend, Backend::Real("ioperm"));
        let c = cfg(&[]).unwrap();
        assert_eq!((c.base, c.model, c.num_chan), (None, None, 8));
        assert_eq!(c.dio.to_string(), "IIOO");
        let c = cfg(&["model=1", "backend=sim"]).unwrap();
        assert_eq!(
            (c.model, c.backend),
            (Some(Model::One), Backend::Sim("sim"))
        );
    }

    #[test]
    fn bad_parameters_name_the_parameter() {
        for (args, want) in [
            (&["base=0x310"][..], "hal_stg: parameter 'base': 0x310 is not a Servo-To-Go base address (0x200, 0x220, ... 0x3e0; 0 searches them)"),
            (&["base=-1"], "hal_stg: parameter 'base': -1 is not a Servo-To-Go base address (0x200, 0x220, ... 0x3e0; 0 searches them)"),
            (&["model=3"], "hal_stg: parameter 'model': 3 is out of range (0..=2)"),
            (&["num_chan=0"], "hal_stg: parameter 'num_chan': 0 is out of range (1..=8)"),
            (&["num_chan=9"], "hal_stg: parameter 'num_chan': 9 is out of range (1..=8)"),
            (&["dio=IOX"], "hal_stg: parameter 'dio': \"IOX\" is not 4 letters, one per port A, B, C, D (e.g. \"IIOO\")"),
            (&["dio=IOXO"], "hal_stg: parameter 'dio': port C: 'X' is neither I (input) nor O (output)"),
            (&["backend=ppdev"], "hal_stg: parameter 'backend': 'ppdev' is not one of ioperm|devport|sim"),
        ] {
            assert_eq!(cfg(args).unwrap_err().to_string(), want, "{args:?}");
        }
    }

    #[test]
    fn sim_boards_are_found_or_probed_and_models_forced() {
        let open_with = |args: &[&str]| {
            let c = cfg(args).unwrap();
            open(&c).map(|o| (o.drv.base(), o.drv.model(), o.warning))
        };
        assert_eq!(
            open_with(&["backend=sim"]).unwrap(),
            (0x300, Model::Two, None)
        );
        assert_eq!(
            open_with(&["backend=sim", "model=1", "base=0x220"]).unwrap(),
            (0x220, Model::One, None)
        );
        assert_eq!(
            open_with(&["backend=sim", "model=1"]).unwrap().1,
            Model::One
        );
        let e = open_with(&["backend=devport"]).err().unwrap().to_string();
        assert!(
            e.starts_with("backend=devport cannot drive a Servo-To-Go"),
            "{e}"
        );
    }

    #[test]
    fn forcing_a_model_warns_when_the_board_disagrees() {
        let bus = SimBoard::new(StgModel::new(Model::Two, 0x240));
        let c = |m| Config {
            backend: Backend::Real("ioperm"),
            base: Some(0x240),
            model: m,
            num_chan: 8,
            dio: Dio::parse("IIOO").unwrap(),
        };
        let (b, m, w) = locate(&bus, &c(Some(Model::One))).unwrap();
        assert_eq!((b, m), (0x240, Model::One));
        assert_eq!(
            w.unwrap(),
            "hal_stg: the board at 0x240 says it is a Model II; model=1 makes it a Model I"
        );
        let e = locate(
            &bus,
            &Config {
                base: Some(0x260),
                ..c(Some(Model::Two))
            },
        )
        .unwrap_err();
        assert!(matches!(e, StgError::NothingAnswers { base: 0x260 }), "{e}");
        let (b, m, w) = locate(
            &bus,
            &Config {
                base: None,
                ..c(None)
            },
        )
        .unwrap();
        assert_eq!((b, m, w), (0x240, Model::Two, None));
    }
}
