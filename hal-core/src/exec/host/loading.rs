//! Loading: `loadrt` and `unloadrt` of modules, the realtime components they
//! build ([`RtComponentBuilder`]) and their unload.

use crate::error::{HalError, Result};
use crate::exec::funct::{FunctCode, FunctCtx};
use crate::module::{ModuleArgs, ModuleDef};
use crate::objects::{Component, ComponentKind};

use super::{lock, Hook, Host, HostState, LoadedComp};

impl Host {
    /// Starts building a realtime component in this host.
    pub fn new_rt_component(&self, name: &str) -> Result<RtComponentBuilder<'_>> {
        let comp = self.inst.new_component(name, ComponentKind::Realtime)?;
        Ok(RtComponentBuilder {
            host: self,
            comp: Some(comp),
            functs: Vec::new(),
            safe_state: None,
        })
    }

    /// Unloads a realtime component: takes its functions out of every
    /// thread (waiting for each thread to pass a boundary), calls its
    /// safe-state hook, then frees it.
    pub fn unload(&self, comp: &str) -> Result<()> {
        let mut st = lock(&self.state);
        let ci = st
            .comps
            .iter()
            .position(|c| c.comp.name() == comp)
            .ok_or_else(|| HalError::NotFound {
                kind: "component",
                name: comp.to_string(),
            })?;
        self.unload_at(&mut st, ci)
    }

    pub(super) fn unload_at(&self, st: &mut HostState, ci: usize) -> Result<()> {
        let ids = st.comps[ci].functs.clone();
        for id in &ids {
            for ti in 0..st.threads.len() {
                while st.threads[ti].holds(*id) {
                    self.remove_from_thread(st, ti, *id)?;
                }
            }
        }
        let mut lc = st.comps.remove(ci);
        if let Some(hook) = lc.safe_state.as_mut() {
            hook();
        }
        for id in &ids {
            st.release_funct(*id);
        }
        drop(lc);
        Ok(())
    }

    /// Loads a module (halcmd `loadrt`): parses `args` against its table
    /// and runs its `load`. On any error, every component and thread the
    /// load created is removed again.
    pub fn loadrt<S: AsRef<str>>(&self, def: &'static ModuleDef, args: &[S]) -> Result<()> {
        self.inst.check_unlocked(crate::lock_bits::LOAD, "loadrt")?;
        if lock(&self.state).modules.contains(&def.name) {
            return Err(HalError::ModuleLoaded {
                name: def.name.to_string(),
            });
        }
        let parsed = ModuleArgs::parse(def.name, def.params, args)?;
        let (comps_before, threads_before) = {
            let st = lock(&self.state);
            (st.comps.len(), st.threads.len())
        };
        let result = (def.load)(self, &parsed).and_then(|()| {
            // What `save` prints after `loadrt `: the name, a space, the
            // arguments (LinuxCNC keeps the space when there are none).
            let saved = format!("{} {}", def.name, parsed.raw());
            let mut st = lock(&self.state);
            for c in &mut st.comps[comps_before..] {
                c.module = Some(def.name);
                c.comp.set_loadrt_args(&saved)?;
            }
            st.modules.push(def.name);
            Ok(())
        });
        if result.is_err() {
            let mut st = lock(&self.state);
            while st.comps.len() > comps_before {
                let last = st.comps.len() - 1;
                let _ = self.unload_at(&mut st, last);
            }
            let extra: Vec<String> = st.threads[threads_before.min(st.threads.len())..]
                .iter()
                .map(|t| t.ctl.name.clone())
                .collect();
            drop(st);
            for t in extra.iter().rev() {
                let _ = self.delete_thread(t);
            }
        }
        result
    }

    /// Unloads a module (halcmd `unloadrt`), or every module for `all`,
    /// newest first.
    pub fn unloadrt(&self, name: &str) -> Result<()> {
        let mut st = lock(&self.state);
        let targets: Vec<&'static str> = if name == "all" {
            st.modules.iter().rev().copied().collect()
        } else {
            match st.modules.iter().find(|m| **m == name) {
                Some(m) => vec![*m],
                None => {
                    return Err(HalError::NotFound {
                        kind: "module",
                        name: name.to_string(),
                    })
                }
            }
        };
        for m in targets {
            while let Some(ci) = st.comps.iter().rposition(|c| c.module == Some(m)) {
                self.unload_at(&mut st, ci)?;
            }
            st.modules.retain(|x| *x != m);
        }
        Ok(())
    }

    /// Names of the loaded modules, in load order.
    pub fn loaded_modules(&self) -> Vec<&'static str> {
        lock(&self.state).modules.clone()
    }

    /// Names of the loaded realtime components, in load order.
    pub fn loaded_components(&self) -> Vec<String> {
        lock(&self.state)
            .comps
            .iter()
            .map(|c| c.comp.name().to_string())
            .collect()
    }
}

/// Builds a realtime component inside the host. Dropped without
/// [`ready`](Self::ready), it removes everything it created.
pub struct RtComponentBuilder<'h> {
    host: &'h Host,
    comp: Option<Component>,
    functs: Vec<usize>,
    safe_state: Option<Hook>,
}

impl RtComponentBuilder<'_> {
    /// The component, to create pins, params and regions on.
    pub fn component(&self) -> &Component {
        self.comp.as_ref().expect("component present until ready")
    }

    /// Exports a non-reentrant function: it may be added to one thread.
    ///
    /// Functions of one component may run in different threads, which
    /// preempt each other. State they share must therefore be `Sync`
    /// (atomics, pins): plain shared state does not compile.
    ///
    /// ```compile_fail
    /// # use hal_core::*;
    /// # fn build(host: &Host) -> Result<()> {
    /// let mut b = host.new_rt_component("sg")?;
    /// let freq = std::sync::Arc::new(std::cell::Cell::new(0.0));
    /// let f2 = freq.clone();
    /// b.funct("sg.update-freq", true, move |_| f2.set(1.0))?; // Cell is not Sync
    /// b.funct("sg.make-pulses", true, move |_| { let _ = freq.get(); })?;
    /// # Ok(()) }
    /// ```
    ///
    /// ```no_run
    /// # use hal_core::*;
    /// # use std::sync::{Arc, atomic::{AtomicU64, Ordering::Relaxed}};
    /// # fn build(host: &Host) -> Result<()> {
    /// let mut b = host.new_rt_component("sg")?;
    /// let freq = Arc::new(AtomicU64::new(0));
    /// let f2 = freq.clone();
    /// b.funct("sg.update-freq", true, move |_| f2.store(1.0f64.to_bits(), Relaxed))?;
    /// b.funct("sg.make-pulses", true, move |_| { let _ = f64::from_bits(freq.load(Relaxed)); })?;
    /// b.ready()
    /// # }
    /// ```
    pub fn funct(
        &mut self,
        name: &str,
        uses_fp: bool,
        f: impl FnMut(&FunctCtx) + Send + 'static,
    ) -> Result<()> {
        let code = FunctCode::exclusive(f);
        let id = self
            .host
            .export_funct(self.component(), name, uses_fp, code, false)?;
        self.functs.push(id);
        Ok(())
    }

    /// Exports a reentrant function: it may be added to several threads.
    pub fn funct_reentrant(
        &mut self,
        name: &str,
        uses_fp: bool,
        f: impl Fn(&FunctCtx) + Send + Sync + 'static,
    ) -> Result<()> {
        let code = FunctCode::shared(f);
        let id = self
            .host
            .export_funct(self.component(), name, uses_fp, code, true)?;
        self.functs.push(id);
        Ok(())
    }

    /// Sets the hook that puts the component's outputs in a safe state
    /// (outputs off, amplifiers disabled); called after a fault, at unload
    /// and at host exit, in reverse load order.
    pub fn on_safe_state(&mut self, f: impl FnMut() + Send + 'static) {
        self.safe_state = Some(Box::new(f));
    }

    /// Marks the component ready and hands it to the host.
    pub fn ready(mut self) -> Result<()> {
        let comp = self.comp.take().expect("component present until ready");
        if let Err(e) = comp.ready() {
            self.comp = Some(comp);
            return Err(e);
        }
        let mut st = lock(&self.host.state);
        st.comps.push(LoadedComp {
            module: None,
            comp,
            functs: std::mem::take(&mut self.functs),
            safe_state: self.safe_state.take(),
        });
        Ok(())
    }
}

impl Drop for RtComponentBuilder<'_> {
    fn drop(&mut self) {
        if self.comp.is_some() {
            self.host.drop_functs(&self.functs);
            self.comp = None;
        }
    }
}
