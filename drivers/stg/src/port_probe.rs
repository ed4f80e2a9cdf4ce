//! `hal-board probe`: which Servo-To-Go answers at an ISA base address,
//! read from the board test register's signature ([`crate::probe`]),
//! or at every address the board's jumpers can select. Reads only.

use std::sync::Arc;

use hal_driver::bus::{DevPortPorts, IopermPorts, PortBus, PortRange};
use hal_driver::sim::SimBoard;

use crate::detect::Model;
use crate::open::SIM_DEFAULT_BASE;
use crate::regs::{BRDTST, CANDIDATE_BASES};
use crate::sim::StgModel;
use crate::StgError;

/// How the ports are reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Via {
    /// `in`/`out` after `ioperm` (needs CAP_SYS_RAWIO).
    Ioperm,
    /// `/dev/port` (needs CAP_SYS_RAWIO).
    DevPort,
    /// A simulated board of this model at 0x300.
    Sim(Model),
}

/// Parses `--via`: `ioperm`, `devport`, `sim` (a Model II) or `sim1`.
pub fn parse_via(s: &str) -> Result<Via, StgError> {
    match s {
        "ioperm" => Ok(Via::Ioperm),
        "devport" => Ok(Via::DevPort),
        "sim" | "sim2" => Ok(Via::Sim(Model::Two)),
        "sim1" => Ok(Via::Sim(Model::One)),
        _ => Err(StgError::NotAWay {
            text: s.to_string(),
        }),
    }
}

/// Parses a base address: one of the jumper choices 0x200 … 0x3e0.
pub fn parse_base(s: &str) -> Result<u16, StgError> {
    let v = hal_driver::params::parse_number(s, 0xFFFF).map_err(|source| StgError::BadBase {
        text: s.to_string(),
        source,
    })?;
    CANDIDATE_BASES
        .iter()
        .copied()
        .find(|&b| b as u64 == v)
        .ok_or(StgError::NotABase { base: v })
}

/// Probes `base` (or every candidate) through `via`: one line per board
/// found, or why none was.
pub fn probe(base: Option<u16>, via: Via) -> Result<Vec<String>, StgError> {
    let bases: Vec<u16> = base.map_or_else(|| CANDIDATE_BASES.to_vec(), |b| vec![b]);
    // Only the board test register of each base is read.
    let ranges: Vec<PortRange> = bases
        .iter()
        .map(|b| PortRange::new(b + BRDTST, 1))
        .collect::<Result<_, _>>()?;
    let bus: Arc<dyn PortBus> = match via {
        Via::Ioperm => Arc::new(IopermPorts::open(&ranges)?),
        Via::DevPort => Arc::new(DevPortPorts::open(&ranges)?),
        Via::Sim(m) => Arc::new(SimBoard::new(StgModel::new(m, SIM_DEFAULT_BASE))),
    };
    let found = |b: u16, m: Model| {
        format!(
            "{b:#x}: Servo-To-Go {m} (signature {:#04x}): loadrt hal_stg base={b:#x} model={}",
            m.signature(),
            if m.is_two() { 2 } else { 1 }
        )
    };
    match base {
        Some(b) => crate::probe(&*bus, b).map(|m| vec![found(b, m)]),
        None => {
            let lines: Vec<String> = bases
                .iter()
                .filter_map(|&b| crate::probe(&*bus, b).ok().map(|m| found(b, m)))
                .collect();
            if lines.is_empty() {
                Err(StgError::NotFound)
            } else {
                Ok(lines)
            }
        }
    }
}
