//! Host 1, ours: a driver loaded by `loadrt` into a [`Host`].
//!
//! Each component is an [`RtComponentBuilder`]; its safe states and kept
//! objects become its safe-state hook (which the host calls after a
//! fault, at unload and at exit, and drops at unload). The builders are
//! marked ready in the order made once `export` succeeded; dropped
//! unready (an error), they remove what they made.

use std::any::Any;
use std::sync::Arc;

use hal_core::module::ModuleArgs;
use hal_core::{Component, FunctCtx, Host, Ours, Result, RtComponentBuilder};

use super::export::{sealed, DriverHost, Exporter, Session};
use super::{DriverModule, LoadEnv};
use crate::fault::SafeState;
use crate::log::LogSink;

impl sealed::Sealed for Ours {}

impl DriverHost for Ours {
    type Component = Component;
    type Session<'h> = OursSession<'h>;
}

/// `loadrt` of driver `D` in our host: parses nothing itself (the host
/// parsed `args` against `D::PARAMS`), opens, then exports
/// ([`load_opened`]).
pub fn load<D: DriverModule>(host: &Host, args: &ModuleArgs) -> Result<()> {
    let opened = D::open(args, &env(host))?;
    load_opened::<D>(host, opened)
}

/// What a driver's `open` knows of `host`.
pub fn env(host: &Host) -> LoadEnv {
    LoadEnv::new(host.instance().name(), host.rt_log().into())
}

/// Exports what `D::open` (or a test's own opening, on a fake sysfs or
/// its own ports) opened into `host`, and marks it ready.
pub fn load_opened<D: DriverModule>(host: &Host, opened: D::Opened) -> Result<()> {
    let mut ex = Exporter::<Ours>::new(OursSession {
        host,
        comps: Vec::new(),
        sims: Vec::new(),
    });
    D::export(opened, &mut ex)?;
    ex.into_session().finish()
}

/// One load into our host (see the module docs).
pub struct OursSession<'h> {
    host: &'h Host,
    comps: Vec<OursComponent<'h>>,
    sims: Vec<(String, Arc<dyn Any + Send + Sync>)>,
}

/// A component being built, with what its safe-state hook will hold.
struct OursComponent<'h> {
    builder: RtComponentBuilder<'h>,
    safe: Vec<Box<dyn SafeState>>,
    kept: Vec<Box<dyn Any + Send>>,
}

impl OursSession<'_> {
    /// Installs the hooks, marks every component ready in order, then
    /// publishes the simulated boards.
    fn finish(self) -> Result<()> {
        for c in self.comps {
            let mut b = c.builder;
            if !c.safe.is_empty() || !c.kept.is_empty() {
                let (safe, kept) = (c.safe, c.kept);
                b.on_safe_state(move || {
                    for s in &safe {
                        s.go_safe();
                    }
                    // Held until unload, when the hook is dropped.
                    let _ = &kept;
                });
            }
            b.ready()?;
        }
        let instance = self.host.instance().name().to_string();
        for (key, board) in &self.sims {
            crate::sim::publish_any(&instance, key, board);
        }
        Ok(())
    }
}

impl<'h> Session<Ours> for OursSession<'h> {
    fn component(&mut self, name: &str) -> Result<usize> {
        self.comps.push(OursComponent {
            builder: self.host.new_rt_component(name)?,
            safe: Vec::new(),
            kept: Vec::new(),
        });
        Ok(self.comps.len() - 1)
    }

    fn get(&self, index: usize) -> &Component {
        self.comps[index].builder.component()
    }

    fn funct<F: FnMut(&FunctCtx) + Send + 'static>(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        f: F,
    ) -> Result<()> {
        self.comps[index].builder.funct(name, uses_fp, f)
    }

    fn funct_reentrant<F: Fn(&FunctCtx) + Send + Sync + 'static>(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        f: F,
    ) -> Result<()> {
        self.comps[index].builder.funct_reentrant(name, uses_fp, f)
    }

    fn safe_state(&mut self, index: usize, state: Box<dyn SafeState>) {
        self.comps[index].safe.push(state);
    }

    fn keep(&mut self, index: usize, obj: Box<dyn Any + Send>) {
        self.comps[index].kept.push(obj);
    }

    fn log(&self) -> LogSink {
        self.host.rt_log().into()
    }

    fn flush_log(&self) {
        self.host.flush_rt_log();
    }

    fn publish_sim(&mut self, key: String, board: Arc<dyn Any + Send + Sync>) {
        self.sims.push((key, board));
    }
}
