//! What `loadrt lcec` makes of a `<master>` of the configuration before
//! anything is exported: the master's plan (each slave's expected
//! identity and SDO writes) and, for `backend=sim`, a simulated segment
//! of exactly the configured slaves.

use std::path::Path;
use std::sync::{Arc, Mutex};

use crate::error::{Error, Result};
use crate::lcec::conf;
use crate::master::{DcPlan, MasterConfig, SdoWrite, SlavePlan};
use crate::sim::{self, catalog, Segment};

/// The master's plan for `m` (`sim`: on a simulated segment).
pub(crate) fn plan(m: &conf::Master, sim: bool) -> MasterConfig {
    MasterConfig {
        frame_timeout: sim.then_some(std::time::Duration::from_millis(100)),
        period_ns: m.app_time_period.max(1000),
        slaves: m
            .slaves
            .iter()
            .map(|s| SlavePlan {
                position: s.index,
                name: s.name.clone(),
                identity: identity(s),
                sdos: s
                    .sdos
                    .iter()
                    .map(|w| SdoWrite {
                        index: w.index,
                        sub: w.sub,
                        data: w.data.clone(),
                    })
                    .chain(pdo_writes(s))
                    .collect(),
                dc: s.dc.map(|d| DcPlan {
                    assign_activate: d.assign_activate,
                    sync0_cycle_ns: d.sync0_cycle.ns(m.app_time_period),
                    sync0_shift_ns: d.sync0_shift,
                    sync1_cycle_ns: d.sync1_cycle.ns(m.app_time_period),
                }),
                emergencies: s.kind == "basic_cia402",
            })
            .collect(),
        ref_clock_sync_cycles: m.ref_clock_sync_cycles,
        sync_to_ref_clock: m.sync_to_ref_clock,
        ..MasterConfig::default()
    }
}

/// The SDO writes that give a slave the PDO layout of its
/// `<syncManager>`s (`configPdos="true"`), after its `<sdoConfig>`s as
/// IgH's master orders them: per sync manager its assignment (0x1C10 +
/// index) emptied, each PDO's mapping written (sub-index 0 cleared, the
/// entries as index << 16 | sub-index << 8 | bits, gaps with index 0,
/// then the count), then the PDOs assigned and their count.
pub(crate) fn pdo_writes(s: &conf::Slave) -> Vec<SdoWrite> {
    let w = |index: u16, sub: u8, data: Vec<u8>| SdoWrite {
        index,
        sub: Some(sub),
        data,
    };
    let mut out = Vec::new();
    if !s.config_pdos {
        return out;
    }
    for sm in &s.sync_managers {
        let assign = 0x1C10 + u16::from(sm.index);
        out.push(w(assign, 0, vec![0]));
        for pdo in &sm.pdos {
            out.push(w(pdo.index, 0, vec![0]));
            for (k, e) in pdo.entries.iter().enumerate() {
                let map = u32::from(e.index) << 16 | u32::from(e.sub) << 8 | u32::from(e.bit_len);
                out.push(w(pdo.index, k as u8 + 1, map.to_le_bytes().to_vec()));
            }
            out.push(w(pdo.index, 0, vec![pdo.entries.len() as u8]));
        }
        for (k, pdo) in sm.pdos.iter().enumerate() {
            out.push(w(assign, k as u8 + 1, pdo.index.to_le_bytes().to_vec()));
        }
        out.push(w(assign, 0, vec![sm.pdos.len() as u8]));
    }
    out
}

/// The vendor id and product code a slave must have: a generic slave's
/// or CiA 402 drive's `vid`/`pid`, a catalogue type's own.
fn identity(s: &conf::Slave) -> Option<(u32, u32)> {
    match (s.vid, s.pid) {
        (Some(v), Some(p)) => Some((v, p)),
        _ => sim::device_by_name(&s.kind, 0).map(|d| {
            let id = d.sii().identity;
            (id.vendor, id.product)
        }),
    }
}

/// A simulated segment of `m`'s slaves in position order (serial
/// numbers from 1); an error names a slave the simulator cannot model
/// or a gap in the positions.
pub(crate) fn sim_segment(m: &conf::Master, file: &Path) -> Result<Arc<Mutex<Segment>>> {
    let mut slaves: Vec<&conf::Slave> = m.slaves.iter().collect();
    slaves.sort_by_key(|s| s.index);
    let mut devices = Vec::with_capacity(slaves.len());
    for (n, s) in slaves.iter().enumerate() {
        let err = |reason: String| Error::Config {
            file: file.to_path_buf(),
            line: s.line,
            element: "slave".into(),
            reason,
        };
        if usize::from(s.index) != n {
            return Err(err(format!(
                "slave '{}' at position {}, but backend=sim needs a slave at every position and none is at {n}",
                s.name, s.index
            )));
        }
        let serial = n as u32 + 1;
        let d = match (s.vid, s.pid) {
            (Some(vid), Some(pid)) if s.kind == "generic" => {
                let (outs, ins) = generic_entries(s);
                catalog::generic(vid, pid, serial, &outs, &ins)
            }
            _ => sim::device_by_name(&s.kind, serial).ok_or_else(|| {
                err(format!(
                    "slave '{}': backend=sim has no {} device",
                    s.name, s.kind
                ))
            })?,
        };
        devices.push(d);
    }
    Ok(Arc::new(Mutex::new(Segment::new(devices))))
}

/// A generic slave's output and input entries (gaps left out).
fn generic_entries(s: &conf::Slave) -> (Vec<catalog::GenericEntry>, Vec<catalog::GenericEntry>) {
    let (mut outs, mut ins) = (Vec::new(), Vec::new());
    for sm in &s.sync_managers {
        let list = if sm.output { &mut outs } else { &mut ins };
        for e in sm.pdos.iter().flat_map(|p| &p.entries) {
            if e.index != 0 {
                list.push((e.index, e.sub, e.bit_len));
            }
        }
    }
    (outs, ins)
}
