//! The `loadrt canservo ...` parameters, read into a [`Config`] with the
//! shared layer's [`Params`] helpers, so every error names the module,
//! the parameter and the item.

use std::path::Path;
use std::time::Duration;

use hal_core::module::{ModuleArgs, ParamDecl};
use hal_driver::params::{Backend, BackendTokens, Params};
use hal_driver::DriverError;

use crate::drivefile::DriveFile;
use crate::engine::EngineConfig;
use crate::error::Error;
use crate::startup::{Mode, NodePlan, StartupConfig};

/// The module name.
pub const NAME: &str = "canservo";
/// Most drives on one bus.
pub const MAX_DRIVES: usize = 16;
/// Backends: a SocketCAN interface, or the in-process simulated bus.
pub const BACKENDS: BackendTokens = BackendTokens::new(&["socketcan"], &[]);

/// canservo's module parameters: the one table both hosts read (our
/// host through [`PARAMS`], LinuxCNC through `canservo.so`'s symbols).
#[macro_export]
macro_rules! canservo_params {
    ($($then:tt)*) => { $($then)*! {
        iface: Str =
            "CAN interface (default can0)",
        backend: Str =
            "socketcan (default) | sim: simulated drives on an in-process bus",
        nodes: IntArray($crate::MAX_DRIVES) =
            "node ids of the drives, 1..127: drive N is canservo.N",
        scale: StrArray($crate::MAX_DRIVES) =
            "counts per user unit, per drive (default 1; the position-scale param)",
        mode: StrArray($crate::MAX_DRIVES) =
            "csp (default) | pv | csv, per drive",
        drive_file: StrArray($crate::MAX_DRIVES) =
            "per drive: file of SDO writes made at start-up (INDEX:SUB TYPE VALUE)",
        sync: Int =
            "1 (default): the write function sends SYNC; 0: another device produces it",
        period_ns: Int =
            "servo period the drives interpolate over (0x60C2), default 1000000; the thread must match",
        heartbeat_ms: Int =
            "drives' heartbeat period (0x1017), default 100; 0 = off",
        heartbeat_timeout_ms: Int =
            "a drive silent this long faults, default 3 x heartbeat_ms",
        master_node: Int =
            "node id of the master's own heartbeat, default 127; 0 = none",
        master_heartbeat_ms: Int =
            "master heartbeat period, default 100; drives fault after 3 x this without it",
        tpdo_misses: Int =
            "consecutive periods without a drive's TPDOs before it faults, default 3",
        quick_stop_ms: Int =
            "a faulted drive gets quick stop this long before disable voltage, default 1000",
        sdo_timeout_ms: Int =
            "wait for each SDO answer at start-up, default 500",
        boot_timeout_ms: Int =
            "wait for boot-up messages after NMT reset, default 2000",
        diag_ms: Int =
            "helper reads each drive's error register this often by SDO, default 1000; 0 = off",
        sim_home: IntArray($crate::MAX_DRIVES) =
            "backend=sim: home switch closed from this motor position (counts) up, default 5000",
    } };
}

/// The parameter table.
pub const PARAMS: &[ParamDecl] = canservo_params!(hal_driver::param_table);

/// Everything `loadrt` was told.
#[derive(Debug, Clone)]
pub struct Config {
    /// The backend.
    pub backend: Backend,
    /// The interface (socketcan).
    pub iface: String,
    /// The drives, in pin order.
    pub plans: Vec<NodePlan>,
    /// Initial position scales.
    pub scales: Vec<f64>,
    /// Start-up settings.
    pub startup: StartupConfig,
    /// Engine settings.
    pub engine: EngineConfig,
    /// Helper's error-register polling period (None = off).
    pub diag: Option<Duration>,
    /// Simulated drives' home switch positions.
    pub sim_home: Vec<i64>,
}

fn ms(p: &Params<'_>, name: &str, default: i64, max: i64) -> Result<u64, DriverError> {
    Ok(p.int_in(name, default, 0..=max)? as u64)
}

/// Reads the parameters; drive files are read and parsed here too.
pub fn parse(args: &ModuleArgs) -> Result<Config, DriverError> {
    let p = Params::new(NAME, args);
    let token = p.str_or("backend", "socketcan");
    let backend = BACKENDS.parse(token).ok_or_else(|| {
        p.error(
            "backend",
            format!("'{token}' is not one of {}", BACKENDS.list()),
        )
    })?;
    let iface = p.str_or("iface", "can0").to_string();
    let nodes: Vec<i64> = args.int_array("nodes").to_vec();
    if nodes.is_empty() {
        return Err(p.error("nodes", "no drives given (nodes=1,2,3)"));
    }
    let count = nodes.len();
    for (i, &n) in nodes.iter().enumerate() {
        if !(1..=127).contains(&n) {
            return Err(p.item_error("nodes", i, &n.to_string(), "a node id is 1..127"));
        }
        if nodes[..i].contains(&n) {
            return Err(p.item_error("nodes", i, &n.to_string(), "given twice"));
        }
    }
    let scales = p.strs_per(
        "scale",
        count,
        |_, s| match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v != 0.0 => Ok(v),
            _ => Err(Error::NotAScale),
        },
        |_| 1.0,
    )?;
    let modes = p.strs_per(
        "mode",
        count,
        |_, s| {
            Mode::parse(s)
                .filter(|m| *m != Mode::Pp)
                .ok_or(Error::NotAMode)
        },
        |_| Mode::Csp,
    )?;
    let files = p.strs_per(
        "drive_file",
        count,
        |_, s| DriveFile::load(Path::new(s)).map(Some),
        |_| None,
    )?;
    let sync = p.int_in("sync", 1, 0..=1)? == 1;
    let period_ns = p.int_in("period_ns", 1_000_000, 50_000..=100_000_000)? as u64;
    let heartbeat_ms = ms(&p, "heartbeat_ms", 100, 65_535)?;
    let hb_timeout_ms = ms(
        &p,
        "heartbeat_timeout_ms",
        (3 * heartbeat_ms) as i64,
        600_000,
    )?;
    let master_node = p.int_in("master_node", 127, 0..=127)? as u8;
    if master_node != 0 && nodes.contains(&i64::from(master_node)) {
        return Err(p.error(
            "master_node",
            format!("{master_node} is also a drive's node id"),
        ));
    }
    let master_ms = ms(&p, "master_heartbeat_ms", 100, 21_845)?;
    let tpdo_misses = p.int_in("tpdo_misses", 3, 1..=1000)? as u32;
    let quick_stop_ms = ms(&p, "quick_stop_ms", 1000, 60_000)?;
    let sdo_timeout = ms(&p, "sdo_timeout_ms", 500, 60_000)?.max(1);
    let boot_timeout = ms(&p, "boot_timeout_ms", 2000, 60_000)?.max(1);
    let diag_ms = ms(&p, "diag_ms", 1000, 3_600_000)?;
    let sim_home = p.ints_per(
        "sim_home",
        count,
        5000,
        i64::from(i32::MIN)..=i64::from(i32::MAX),
    )?;
    let master_heartbeat = (master_node != 0 && master_ms > 0).then_some(master_node);
    let plans = nodes
        .iter()
        .zip(modes)
        .zip(files)
        .map(|((&n, mode), file)| NodePlan {
            node: n as u8,
            mode,
            file,
        })
        .collect();
    Ok(Config {
        backend,
        iface,
        plans,
        scales,
        startup: StartupConfig {
            sdo_timeout: Duration::from_millis(sdo_timeout),
            boot_timeout: Duration::from_millis(boot_timeout),
            heartbeat_ms: heartbeat_ms as u16,
            master_heartbeat: master_heartbeat.map(|n| (n, (3 * master_ms) as u16)),
            period_ns,
        },
        engine: EngineConfig {
            sync_producer: sync,
            tpdo_misses,
            heartbeat_timeout_ns: if heartbeat_ms == 0 {
                0
            } else {
                hb_timeout_ms * 1_000_000
            },
            master_heartbeat: master_heartbeat.map(|n| (n, master_ms * 1_000_000)),
            quick_stop_ns: quick_stop_ms * 1_000_000,
            period_ns,
            rx_budget: crate::engine::DEFAULT_RX_BUDGET,
        },
        diag: (diag_ms > 0).then(|| Duration::from_millis(diag_ms)),
        sim_home,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_args(a: &[&str]) -> hal_core::Result<Config> {
        let args = ModuleArgs::parse(NAME, PARAMS, a)?;
        parse(&args).map_err(|e| e.into_hal(NAME))
    }

    #[test]
    fn defaults() {
        let c = parse_args(&["nodes=1,2,3"]).unwrap();
        assert_eq!(c.iface, "can0");
        assert!(!c.backend.is_sim());
        assert_eq!(c.plans.len(), 3);
        assert_eq!(c.plans[2].node, 3);
        assert_eq!(c.plans[0].mode, Mode::Csp);
        assert_eq!(c.scales, vec![1.0; 3]);
        assert_eq!(c.engine.heartbeat_timeout_ns, 300_000_000);
        assert_eq!(c.startup.master_heartbeat, Some((127, 300)));
        assert_eq!(c.engine.master_heartbeat, Some((127, 100_000_000)));
        assert_eq!(c.sim_home, vec![5000; 3]);
    }

    #[test]
    fn per_drive_values() {
        let c = parse_args(&[
            "backend=sim",
            "nodes=4,9",
            "scale=1000,-2.5",
            "mode=pv,csv",
            "heartbeat_ms=0",
            "master_node=0",
        ])
        .unwrap();
        assert!(c.backend.is_sim());
        assert_eq!(c.scales, vec![1000.0, -2.5]);
        assert_eq!((c.plans[0].mode, c.plans[1].mode), (Mode::Pv, Mode::Csv));
        assert_eq!(c.engine.heartbeat_timeout_ns, 0);
        assert_eq!(c.engine.master_heartbeat, None);
    }

    #[test]
    fn errors_name_the_parameter_and_item() {
        let cases = [
            (vec!["nodes=1", "backend=usb"], "canservo: parameter 'backend': 'usb' is not one of socketcan|sim"),
            (vec!["iface=can0"], "canservo: parameter 'nodes': no drives given"),
            (vec!["nodes=1,128"], "canservo: parameter 'nodes': item 1 \"128\": a node id is 1..127"),
            (vec!["nodes=3,3"], "canservo: parameter 'nodes': item 1 \"3\": given twice"),
            (vec!["nodes=1,2", "scale=1,0"], "canservo: parameter 'scale': item 1 \"0\": not a non-zero number"),
            (vec!["nodes=1", "mode=pp"], "canservo: parameter 'mode': item 0 \"pp\": not csp, pv or csv"),
            (vec!["nodes=1", "mode=csp,csp"], "canservo: parameter 'mode': 2 items given, but there are only 1"),
            (vec!["nodes=1", "sync=2"], "canservo: parameter 'sync': 2 is out of range (0..=1)"),
            (vec!["nodes=1", "master_node=1"], "canservo: parameter 'master_node': 1 is also a drive's node id"),
            (
                vec!["nodes=1", "drive_file=/nonexistent/x.sdo"],
                "canservo: parameter 'drive_file': item 0 \"/nonexistent/x.sdo\": drive file /nonexistent/x.sdo: ",
            ),
        ];
        for (a, want) in cases {
            let e = parse_args(&a).unwrap_err().to_string();
            assert!(e.starts_with(want), "{a:?}: {e}");
        }
    }
}
