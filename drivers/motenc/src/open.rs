//! Choosing and opening the boards a `loadrt` asks for: every MOTENC on
//! the PCI bus, or simulated ones; and giving each its HAL board ID.

use std::sync::Arc;

use hal_core::module::ModuleArgs;
use hal_driver::bus::RegWindow;
use hal_driver::params::{Backend, BackendTokens, Params};
use hal_driver::pci::{self, EnableGuard, PciMatch, Sysfs};
use hal_driver::sim::SimBoard;
use hal_driver::DriverError;

use crate::board::{identify, BoardKind, Identity, Motenc};
use crate::error::MotencError;
use crate::regs;
use crate::sim::MotencModel;

/// The backend tokens of `backend=`.
pub const BACKENDS: BackendTokens = BackendTokens::new(&["pci"], &[]);
/// At most this many boards (the ID jumpers have two bits).
pub const MAX_BOARDS: usize = 4;

/// Where the boards come from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// Every MOTENC on the PCI bus.
    Pci,
    /// Simulated boards: kind and ID jumpers of each.
    Sim(Vec<(BoardKind, u8)>),
}

/// Parses a `sim_boards` item: `100` or `lite` (any case).
pub fn parse_board_kind(text: &str) -> Result<BoardKind, MotencError> {
    match text.to_ascii_lowercase().as_str() {
        "100" | "motenc-100" => Ok(BoardKind::Motenc100),
        "lite" | "motenc-lite" => Ok(BoardKind::MotencLite),
        _ => Err(MotencError::NotABoardKind),
    }
}

/// Reads `backend`, `sim_boards` and `sim_ids`.
pub fn parse_source(args: &ModuleArgs) -> Result<Source, DriverError> {
    let p = Params::new(crate::hal::NAME, args);
    let token = p.str_or("backend", "pci");
    let backend = BACKENDS.parse(token).ok_or_else(|| {
        p.error(
            "backend",
            format!("'{token}' is not one of {}", BACKENDS.list()),
        )
    })?;
    let kinds_given = args.str_array("sim_boards").len();
    let ids_given = args.int_array("sim_ids");
    if let Backend::Real(_) = backend {
        for (name, given) in [("sim_boards", kinds_given), ("sim_ids", ids_given.len())] {
            if given > 0 {
                return Err(p.error(name, "only with backend=sim"));
            }
        }
        return Ok(Source::Pci);
    }
    let n = kinds_given.max(ids_given.len()).max(1);
    let kinds = p.strs_per(
        "sim_boards",
        n,
        |_, t| parse_board_kind(t),
        |_| BoardKind::Motenc100,
    )?;
    let mut boards = Vec::with_capacity(n);
    for (i, kind) in kinds.into_iter().enumerate() {
        let id = match ids_given.get(i) {
            Some(&v) if (0..=3).contains(&v) => v as u8,
            Some(&v) => {
                return Err(p.item_error("sim_ids", i, &v.to_string(), "out of range (0..=3)"))
            }
            None => i as u8,
        };
        boards.push((kind, id));
    }
    Ok(Source::Sim(boards))
}

/// One board, open and identified.
pub struct Opened {
    /// The board's registers.
    pub drv: Motenc,
    /// Where it is, for messages: `PCI 0000:03:00.0` or `simulated`.
    pub location: String,
    /// Keeps a PCI board enabled while the driver lives.
    pub guard: Option<EnableGuard>,
    /// The simulated board, when it is one.
    pub sim: Option<Arc<SimBoard<MotencModel>>>,
}

/// Opens every board of `table` under `sysfs`: enables it, maps BAR 2
/// and identifies it. Any failure names the board.
pub fn open_pci(sysfs: &Sysfs, table: &[PciMatch]) -> Result<Vec<Opened>, MotencError> {
    let devices = pci::find(sysfs, table)?;
    if devices.len() > MAX_BOARDS {
        return Err(MotencError::TooManyBoards {
            found: devices.len(),
        });
    }
    let mut boards = Vec::with_capacity(devices.len());
    for dev in devices {
        let guard = dev.enable()?;
        let bus: Arc<dyn RegWindow> = Arc::new(dev.map_bar_window(regs::BAR, regs::WINDOW_LEN)?);
        let location = format!("PCI {}", dev.address);
        let id = identify(&*bus).map_err(|e| rename(e, &location))?;
        boards.push(Opened {
            drv: Motenc::new(bus, id),
            location,
            guard: Some(guard),
            sim: None,
        });
    }
    Ok(boards)
}

/// Names the board by its bus address in an identification error.
fn rename(e: MotencError, location: &str) -> MotencError {
    match e {
        MotencError::NoAnswer { .. } => MotencError::NoAnswer {
            board: location.to_string(),
        },
        MotencError::UnknownVersion { found, .. } => MotencError::UnknownVersion {
            board: location.to_string(),
            found,
        },
        other => other,
    }
}

/// Makes the simulated boards of `specs`.
pub fn open_sim(specs: &[(BoardKind, u8)]) -> Result<Vec<Opened>, MotencError> {
    specs
        .iter()
        .map(|&(kind, jumper)| {
            let sim = Arc::new(SimBoard::new(MotencModel::new(kind, jumper)));
            let id = identify(&*sim)?;
            Ok(Opened {
                drv: Motenc::new(sim.clone(), id),
                location: "simulated".into(),
                guard: None,
                sim: Some(sim),
            })
        })
        .collect()
}

/// The HAL board IDs of boards whose jumpers say `jumpers`: its jumper
/// ID where no earlier board took it, else the lowest free ID (as
/// LinuxCNC does); plus a warning for each board moved.
pub fn assign_ids(ids: &[Identity], locations: &[String]) -> (Vec<u8>, Vec<String>) {
    let mut used = [false; MAX_BOARDS];
    let mut out = Vec::with_capacity(ids.len());
    let mut warnings = Vec::new();
    for (i, id) in ids.iter().enumerate() {
        let want = id.jumper_id as usize;
        let got = if !used[want] {
            want
        } else {
            let free = (0..MAX_BOARDS).find(|&k| !used[k]).unwrap_or(want);
            warnings.push(format!(
                "{}: board {i} ({}) has ID jumpers {want}, already used by an earlier board; \
                 it is motenc.{free}",
                crate::hal::NAME,
                locations.get(i).map_or("?", String::as_str),
            ));
            free
        };
        used[got] = true;
        out.push(got as u8);
    }
    (out, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_args(args: &[&str]) -> Result<Source, DriverError> {
        let a = ModuleArgs::parse(crate::hal::NAME, crate::hal::PARAMS, args).unwrap();
        parse_source(&a)
    }

    /// The source `args` choose.
    fn source(args: &[&str]) -> Source {
        parse_args(args).unwrap()
    }

    /// Why `args` are refused.
    fn refusal(args: &[&str]) -> String {
        parse_args(args).unwrap_err().to_string()
    }

    #[test]
    fn backends_and_sim_boards() {
        assert_eq!(source(&[]), Source::Pci);
        assert_eq!(source(&["backend=PCI"]), Source::Pci);
        assert_eq!(
            source(&["backend=sim"]),
            Source::Sim(vec![(BoardKind::Motenc100, 0)])
        );
        assert_eq!(
            source(&["backend=sim", "sim_boards=lite,100,Lite"]),
            Source::Sim(vec![
                (BoardKind::MotencLite, 0),
                (BoardKind::Motenc100, 1),
                (BoardKind::MotencLite, 2)
            ])
        );
        assert_eq!(
            source(&["backend=sim", "sim_ids=3,3"]),
            Source::Sim(vec![(BoardKind::Motenc100, 3), (BoardKind::Motenc100, 3)])
        );
    }

    #[test]
    fn bad_parameters_say_what_and_where() {
        assert_eq!(
            refusal(&["backend=isa"]),
            "hal_motenc: parameter 'backend': 'isa' is not one of pci|sim"
        );
        assert_eq!(
            refusal(&["sim_boards=100"]),
            "hal_motenc: parameter 'sim_boards': only with backend=sim"
        );
        assert_eq!(
            refusal(&["backend=pci", "sim_ids=1"]),
            "hal_motenc: parameter 'sim_ids': only with backend=sim"
        );
        assert_eq!(
            refusal(&["backend=sim", "sim_boards=100,200"]),
            "hal_motenc: parameter 'sim_boards': item 1 \"200\": not a board kind: 100 or lite"
        );
        assert_eq!(
            refusal(&["backend=sim", "sim_ids=0,4"]),
            "hal_motenc: parameter 'sim_ids': item 1 \"4\": out of range (0..=3)"
        );
    }

    #[test]
    fn duplicate_jumpers_get_the_lowest_free_id() {
        let id = |j| Identity {
            kind: BoardKind::Motenc100,
            version: 0,
            jumper_id: j,
        };
        let locs: Vec<String> = (0..4).map(|i| format!("PCI 0000:0{i}:00.0")).collect();
        let (ids, warn) = assign_ids(&[id(2), id(2), id(0), id(2)], &locs);
        assert_eq!(ids, vec![2, 0, 1, 3]);
        assert_eq!(warn.len(), 3);
        assert_eq!(
            warn[0],
            "hal_motenc: board 1 (PCI 0000:01:00.0) has ID jumpers 2, already used by an \
             earlier board; it is motenc.0"
        );
        let (ids, warn) = assign_ids(&[id(3), id(1)], &locs);
        assert_eq!((ids, warn.len()), (vec![3, 1], 0));
    }
}
