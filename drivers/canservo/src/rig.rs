//! [`Rig`]: simulated drives on an in-process bus, brought up by the
//! real start-up and run by the real engine on simulated time, one servo
//! period per [`Rig::cycle`]. Tests, the benchmark and the bring-up
//! tool's simulation use it; nothing in it is test-only behaviour.

use std::sync::Arc;

use hal_core::{MsgLevel, RtLog};

use crate::bus::{CanBus, Filters, SimBus};
use crate::engine::{DriveInputs, DriveShared, DriveStatus, Engine, EngineConfig};
use crate::error::Result;
use crate::frame::Frame;
use crate::sim::SimDrive;
use crate::startup::{Mode, Network, NodePlan, StartupConfig};

/// Drives, bus and engine, on simulated time.
pub struct Rig {
    /// The bus with the drives.
    pub bus: Arc<SimBus>,
    /// The engine, on its realtime endpoint.
    pub engine: Engine,
    /// Each drive's inputs, as its HAL pins would give them.
    pub inputs: Vec<DriveInputs>,
    /// Simulated time of the last cycle.
    pub now_ns: u64,
    /// The servo period.
    pub period_ns: u64,
    /// The engine's log.
    pub log: RtLog,
    /// What the drives share with a helper (none runs here).
    pub shared: Vec<Arc<DriveShared>>,
}

impl std::fmt::Debug for Rig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Rig")
            .field("engine", &self.engine)
            .field("now_ns", &self.now_ns)
            .finish()
    }
}

impl Rig {
    /// Default simulated drives at `nodes`, all in `mode`, 1 ms period.
    pub fn new(nodes: &[u8], mode: Mode) -> Result<Rig> {
        let plans = nodes
            .iter()
            .map(|&node| NodePlan {
                node,
                mode,
                file: None,
            })
            .collect();
        Rig::with(
            SimBus::with_drives(nodes),
            plans,
            StartupConfig::default(),
            EngineConfig::default(),
        )
    }

    /// `plans` brought up on `bus` (drives already on it) with `startup`,
    /// then run by an engine with `engine` settings; the period is
    /// `startup.period_ns`.
    pub fn with(
        bus: Arc<SimBus>,
        plans: Vec<NodePlan>,
        startup: StartupConfig,
        engine: EngineConfig,
    ) -> Result<Rig> {
        let nodes: Vec<u8> = plans.iter().map(|p| p.node).collect();
        let period_ns = startup.period_ns;
        let setup = bus.open(Filters::setup(&nodes));
        let rt: Arc<dyn CanBus> = Arc::new(bus.open(Filters::realtime(&nodes)));
        let up = Network::boot(&setup, plans, startup)?
            .identify()?
            .configure()?
            .start()?
            .into_nodes();
        while rt.try_recv().is_some() {}
        let shared: Vec<Arc<DriveShared>> = up
            .iter()
            .map(|_| Arc::new(DriveShared::default()))
            .collect();
        let log = RtLog::new(256);
        log.set_level(MsgLevel::Info);
        let engine = Engine::new(
            rt,
            up,
            shared.clone(),
            engine,
            Some(log.clone().into()),
            false,
        );
        let inputs = vec![DriveInputs::default(); nodes.len()];
        Ok(Rig {
            now_ns: bus.now_ns(),
            bus,
            engine,
            inputs,
            period_ns,
            log,
            shared,
        })
    }

    /// One servo period: time moves on, `read`, then `write`.
    pub fn cycle(&mut self) {
        self.bus.clock().advance(self.period_ns);
        self.now_ns = self.bus.now_ns();
        self.engine.read(self.now_ns, &self.inputs);
        for (inp, st) in self.inputs.iter_mut().zip(self.engine.status()) {
            if st.home_clear {
                inp.home = false;
            }
        }
        self.engine
            .write(self.now_ns, self.period_ns as i64, &self.inputs);
    }

    /// `n` periods.
    pub fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    /// Cycles until `done` holds (checked after each), at most `max`
    /// times; the number of cycles it took.
    pub fn run_until(&mut self, max: usize, mut done: impl FnMut(&Rig) -> bool) -> Option<usize> {
        for n in 1..=max {
            self.cycle();
            if done(self) {
                return Some(n);
            }
        }
        None
    }

    /// Drive `i`'s feedback.
    pub fn status(&self, i: usize) -> DriveStatus {
        self.engine.status()[i]
    }

    /// Runs `f` on the simulated drive at `node`.
    pub fn drive<R>(&self, node: u8, f: impl FnOnce(&mut SimDrive, &mut Vec<Frame>) -> R) -> R {
        self.bus
            .with_drive(node, f)
            .expect("no such simulated drive")
    }

    /// The log lines so far (and empties the log).
    pub fn log_lines(&self) -> Vec<String> {
        let mut v = Vec::new();
        self.log.drain(|_, t| v.push(t.to_string()));
        v
    }
}
