//! What a driver's `export` sees: the [`Exporter`], whatever the host.

use std::any::Any;
use std::sync::Arc;

use hal_core::{FunctCtx, HalHost, PinFactory, Result};

use crate::fault::SafeState;
use crate::log::LogSink;

/// A host drivers load into: ours ([`hal_core::Ours`]) or, with feature
/// `linuxcnc`, LinuxCNC's `rtapi_app`. Implemented in this crate only.
pub trait DriverHost: HalHost + sealed::Sealed {
    /// A component under construction: where pins and parameters are
    /// made ([`Exporter::pins`]).
    type Component: PinFactory<Self>;
    /// One load's state in this host.
    #[doc(hidden)]
    type Session<'h>: Session<Self>;
}

pub(crate) mod sealed {
    /// Only this crate's hosts are driver hosts.
    pub trait Sealed {}
}

/// One load in progress: what a host adapter does for the [`Exporter`].
/// Not for drivers; they call the exporter.
#[doc(hidden)]
pub trait Session<H: DriverHost> {
    /// Creates a component; returns its index.
    fn component(&mut self, name: &str) -> Result<usize>;
    /// The component at `index` (made by `component`).
    fn get(&self, index: usize) -> &H::Component;
    /// Exports a non-reentrant function of component `index`.
    fn funct<F: FnMut(&FunctCtx) + Send + 'static>(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        f: F,
    ) -> Result<()>;
    /// Exports a reentrant function of component `index`.
    fn funct_reentrant<F: Fn(&FunctCtx) + Send + Sync + 'static>(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        f: F,
    ) -> Result<()>;
    /// Adds to component `index`'s safe state.
    fn safe_state(&mut self, index: usize, state: Box<dyn SafeState>);
    /// Keeps `obj` alive until component `index` is unloaded.
    fn keep(&mut self, index: usize, obj: Box<dyn Any + Send>);
    /// The host's realtime-safe message path.
    fn log(&self) -> LogSink;
    /// Prints what waits in the log now (load-time messages in order).
    fn flush_log(&self);
    /// Publishes a simulated board under `key` once the load succeeded.
    fn publish_sim(&mut self, key: String, board: Arc<dyn Any + Send + Sync>);
}

/// A component made by [`Exporter::component`]: pins, parameters and
/// functions are attached to it by this id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompId(usize);

/// What a driver's [`export`](super::DriverModule::export) builds with,
/// in host `H`: components, their pins and parameters (through
/// [`pins`](Self::pins), a [`PinFactory<H>`]), functions, the safe state,
/// objects that must live as long as the module, the message path, and
/// simulated boards to publish.
///
/// Nothing is visible to the host's users until `export` returns `Ok`:
/// then every component is marked ready, in the order made. On an error
/// everything made so far is removed again.
pub struct Exporter<'h, H: DriverHost> {
    session: H::Session<'h>,
}

impl<'h, H: DriverHost> Exporter<'h, H> {
    /// An exporter over a host adapter's session.
    pub(crate) fn new(session: H::Session<'h>) -> Self {
        Exporter { session }
    }

    /// The session, to finish or drop the load.
    pub(crate) fn into_session(self) -> H::Session<'h> {
        self.session
    }

    /// Creates a realtime component named `name` (most drivers one, named
    /// after the module; hostmot2 one per board).
    pub fn component(&mut self, name: &str) -> Result<CompId> {
        self.session.component(name).map(CompId)
    }

    /// Where component `comp`'s pins and parameters are made.
    pub fn pins(&self, comp: CompId) -> &H::Component {
        self.session.get(comp.0)
    }

    /// Exports a function of `comp`; it may be added to one thread, so it
    /// may keep state of its own (`FnMut`). Functions of one component
    /// may run in different threads: what they share must be `Sync`.
    pub fn funct(
        &mut self,
        comp: CompId,
        name: &str,
        uses_fp: bool,
        f: impl FnMut(&FunctCtx) + Send + 'static,
    ) -> Result<()> {
        self.session.funct(comp.0, name, uses_fp, f)
    }

    /// Exports a reentrant function of `comp`: it may be added to several
    /// threads.
    pub fn funct_reentrant(
        &mut self,
        comp: CompId,
        name: &str,
        uses_fp: bool,
        f: impl Fn(&FunctCtx) + Send + Sync + 'static,
    ) -> Result<()> {
        self.session.funct_reentrant(comp.0, name, uses_fp, f)
    }

    /// Makes `state` part of `comp`'s safe state: called after a fault in
    /// any realtime function, at unload and at exit, in reverse load
    /// order (several states of one component in the order given).
    pub fn safe_state(&mut self, comp: CompId, state: impl SafeState) {
        self.session.safe_state(comp.0, Box::new(state));
    }

    /// Keeps `obj` (a helper thread's handle, a PCI enable guard) alive
    /// until `comp` is unloaded; it is dropped after the safe state ran.
    pub fn keep(&mut self, comp: CompId, obj: impl Send + 'static) {
        self.session.keep(comp.0, Box::new(obj));
    }

    /// The host's realtime-safe message path, for fault latches and
    /// load-time warnings.
    pub fn log(&self) -> LogSink {
        self.session.log()
    }

    /// Prints the messages waiting in the log now, so load-time messages
    /// come out before the load's result.
    pub fn flush_log(&self) {
        self.session.flush_log()
    }

    /// Publishes a simulated board under `key` once the load succeeded,
    /// so tests and tools of our host find it with
    /// [`sim::find`](crate::sim::find) (the host's instance name is the
    /// other half of the key). LinuxCNC has no such registry; there the
    /// board is only kept by whoever holds it.
    pub fn publish_sim<T: Any + Send + Sync>(&mut self, key: &str, board: &Arc<T>) {
        self.session.publish_sim(key.to_string(), board.clone());
    }
}
