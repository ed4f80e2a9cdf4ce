//! One load of a module into LinuxCNC: its components (`hal_init`), pins
//! and parameters (`hal_pin_*_newf`, `hal_param_*_newf` on cells of the
//! pool), functions (`hal_export_funct` of a trampoline per closure
//! type), safe state and kept objects; `hal_ready` when the export
//! succeeded, and the teardown that undoes all of it.

use std::any::Any;
use std::cell::RefCell;
use std::ffi::{c_int, c_void, CString};
use std::ptr::NonNull;
use std::sync::Arc;

use hal_core::{
    Direction, FunctCtx, HalError, HalType, HostParam, HostPin, ParamAccess, PinDir, PinFactory,
    PinValue, Result,
};

use super::api::{Api, PerType};
use super::cells;
use super::funct::{self, ModuleCtl, OwnedFunct};
use super::handles::{LcncParam, LcncPin, LinuxCnc};
use super::print;
use crate::error::DriverError;
use crate::fault::SafeState;
use crate::log::LogSink;
use crate::module::{DriverHost, Session};

impl crate::module::sealed::Sealed for LinuxCnc {}

impl DriverHost for LinuxCnc {
    type Component = LcncComponent;
    type Session<'h> = LcncSession;
}

/// LinuxCNC's direction code of a pin (`hal_pin_dir_t`).
fn pin_dir(d: PinDir) -> c_int {
    match d {
        PinDir::In => 16,
        PinDir::Out => 32,
        PinDir::Io => 48,
    }
}

/// LinuxCNC's access code of a parameter (`hal_param_dir_t`).
fn param_dir(d: hal_core::ParamDir) -> c_int {
    match d {
        hal_core::ParamDir::Ro => 64,
        hal_core::ParamDir::Rw => 192,
    }
}

/// The function of `table` for values of type `t`.
fn for_type<F: Copy>(table: &PerType<F>, t: HalType) -> Option<F> {
    match t {
        HalType::Bit => Some(table.bit),
        HalType::Float => Some(table.float),
        HalType::S32 => Some(table.s32),
        HalType::U32 => Some(table.u32),
        HalType::S64 => table.s64,
        HalType::U64 => table.u64,
        // Our modules make no port pins in LinuxCNC.
        HalType::Port => None,
    }
}

/// A component of the module in LinuxCNC: its id, and the cells its pins
/// and parameters use.
pub struct LcncComponent {
    module: &'static str,
    name: String,
    id: c_int,
    api: &'static Api,
    cells: RefCell<Vec<NonNull<c_void>>>,
    /// The aliases given to its parameters, taken back before it is
    /// removed (see [`LcncComponent::unalias`]).
    aliases: RefCell<Vec<CString>>,
}

impl LcncComponent {
    /// A failed LinuxCNC call about `what`, as this module's load error.
    fn refused(&self, call: String, what: &str, rc: c_int) -> HalError {
        HalError::module_failed(
            self.module,
            DriverError::Refused {
                call,
                what: what.to_string(),
                source: std::io::Error::from_raw_os_error(rc.saturating_neg()),
            },
        )
    }

    /// The name as a C string (a NUL inside is refused).
    fn c_name(&self, kind: &'static str, name: &str) -> Result<CString> {
        CString::new(name).map_err(|_| HalError::BadName {
            kind,
            name: name.to_string(),
            reason: "contains a NUL byte",
        })
    }

    /// A zeroed cell of the pool, recorded as this component's.
    fn cell(&self, name: &str) -> Result<NonNull<c_void>> {
        let cell = cells::take(self.api)
            .ok_or_else(|| self.refused("hal_malloc".into(), name, -libc::ENOMEM))?;
        self.cells.borrow_mut().push(cell);
        Ok(cell)
    }

    /// The newf function for `kind` values of type `t`; 64-bit types on
    /// a LinuxCNC without them are refused.
    fn newf<F: Copy>(&self, table: &PerType<F>, t: HalType, kind: &str, name: &str) -> Result<F> {
        for_type(table, t).ok_or_else(|| {
            HalError::module_failed(
                self.module,
                DriverError::Unsupported {
                    what: format!("{t} {kind} '{name}'"),
                    reason: "this LinuxCNC has no 64-bit pins or parameters (2.10 has)".into(),
                },
            )
        })
    }
}

impl LcncComponent {
    /// Gives every aliased parameter its own name back. LinuxCNC 2.9's
    /// HAL recycles a removed parameter's record without clearing its
    /// link to the alias record it freed: a parameter made later on that
    /// record and aliased again shares a freed alias record, and the
    /// next removal loops its free list for ever (halcmd hangs). Taking
    /// the alias back first frees the record and clears the link.
    fn unalias(&self) {
        for alias in self.aliases.borrow_mut().drain(..).rev() {
            // SAFETY: hal_param_alias of a parameter this component
            // aliased, with a NUL-terminated name and a null alias
            // (restore the original name).
            unsafe { (self.api.param_alias)(alias.as_ptr(), std::ptr::null()) };
        }
    }
}

impl PinFactory<LinuxCnc> for LcncComponent {
    fn pin_init<T: PinValue, D: Direction>(&self, name: &str, init: T) -> Result<LcncPin<T, D>> {
        let newf = self.newf(&self.api.pin_newf, T::HAL_TYPE, "pin", name)?;
        let c_name = self.c_name("pin", name)?;
        let cell = self.cell(name)?;
        // SAFETY: LinuxCNC's hal_pin_<type>_newf with a pointer cell in
        // HAL shared memory, this component's id, and "%s" with a
        // NUL-terminated name.
        let rc = unsafe {
            newf(
                pin_dir(D::DIR),
                cell.as_ptr().cast(),
                self.id,
                c"%s".as_ptr(),
                c_name.as_ptr(),
            )
        };
        if rc != 0 {
            return Err(self.refused(format!("hal_pin_{}_newf", T::HAL_TYPE), name, rc));
        }
        // SAFETY: LinuxCNC made the cell point at the pin's value, of the
        // pin's type, and keeps it pointing at one while the pin exists.
        let pin = unsafe { LcncPin::new(cell) };
        pin.overwrite(init);
        Ok(pin)
    }

    fn param<T: PinValue, A: ParamAccess>(&self, name: &str, init: T) -> Result<LcncParam<T, A>> {
        let newf = self.newf(&self.api.param_newf, T::HAL_TYPE, "parameter", name)?;
        let c_name = self.c_name("parameter", name)?;
        let cell = self.cell(name)?;
        // SAFETY: the cell is 8 aligned bytes of HAL shared memory, this
        // component's until it is removed.
        let param = unsafe { LcncParam::new(cell) };
        param.set(init);
        // SAFETY: LinuxCNC's hal_param_<type>_newf with the value's cell
        // in HAL shared memory, this component's id, "%s" and the name.
        let rc = unsafe {
            newf(
                param_dir(A::DIR),
                cell.as_ptr(),
                self.id,
                c"%s".as_ptr(),
                c_name.as_ptr(),
            )
        };
        if rc != 0 {
            return Err(self.refused(format!("hal_param_{}_newf", T::HAL_TYPE), name, rc));
        }
        Ok(param)
    }

    fn alias_param(&self, param: &str, alias: &str) -> Result<()> {
        let c_param = self.c_name("parameter", param)?;
        let c_alias = self.c_name("alias", alias)?;
        // SAFETY: LinuxCNC's hal_param_alias with two NUL-terminated
        // names; it copies what it keeps.
        let rc = unsafe { (self.api.param_alias)(c_param.as_ptr(), c_alias.as_ptr()) };
        if rc != 0 {
            return Err(self.refused("hal_param_alias".into(), alias, rc));
        }
        self.aliases.borrow_mut().push(c_alias);
        Ok(())
    }
}

/// One load into LinuxCNC. Dropped before [`finish`](Self::finish) (a
/// failed load) or at unload, it tears everything down
/// ([`teardown`](Self::teardown)).
pub struct LcncSession {
    module: &'static str,
    api: &'static Api,
    comps: Vec<LcncComponent>,
    functs: Vec<OwnedFunct>,
    safe: Vec<Box<dyn SafeState>>,
    kept: Vec<Box<dyn Any + Send>>,
    ctl: Arc<ModuleCtl>,
    ready: bool,
}

// SAFETY: the components' cells are addresses in shared memory and the
// functions' closures are `Send` (both `funct` methods require it); the
// session moves between the threads rtapi_app loads and unloads from,
// never used by two at once (it lives behind a mutex).
unsafe impl Send for LcncSession {}

impl LcncSession {
    /// A load of `module` with LinuxCNC's functions `api`.
    pub(crate) fn new(module: &'static str, api: &'static Api) -> LcncSession {
        LcncSession {
            module,
            api,
            comps: Vec::new(),
            functs: Vec::new(),
            safe: Vec::new(),
            kept: Vec::new(),
            ctl: Arc::new(ModuleCtl::new(module)),
            ready: false,
        }
    }

    /// Marks every component ready (`hal_ready`), in order, and arms the
    /// safe state for a panic in a function. On an error the session is
    /// dropped, which removes everything.
    pub(crate) fn finish(mut self) -> Result<LcncSession> {
        for c in &self.comps {
            // SAFETY: hal_ready of a component this load made.
            let rc = unsafe { (self.api.hal_ready)(c.id) };
            if rc != 0 {
                return Err(c.refused("hal_ready".into(), &c.name, rc));
            }
        }
        self.ctl.arm(std::mem::take(&mut self.safe));
        self.ready = true;
        Ok(self)
    }

    /// Stops the functions, puts the outputs in their safe state (a
    /// loaded module), removes the components from LinuxCNC, frees the
    /// closures and returns the cells. A function still running after
    /// the wait keeps its closure (leaked rather than freed under it).
    fn teardown(&mut self) {
        let quiet = self.ctl.stop_and_wait();
        if self.ready {
            self.ctl.go_safe();
        }
        for c in self.comps.iter().rev() {
            c.unalias();
            // SAFETY: hal_exit of a component this load made, once.
            unsafe { (self.api.hal_exit)(c.id) };
        }
        // A thread may have fetched a function just before hal_exit took
        // it out of its list: give such a call time to start and see the
        // stop, then wait for it.
        std::thread::sleep(funct::GRACE);
        let quiet = quiet && self.ctl.stop_and_wait();
        let functs = std::mem::take(&mut self.functs);
        if quiet {
            drop(functs);
        } else {
            print::say(
                hal_core::MsgLevel::Err,
                format_args!(
                    "{}: a function did not return within {:?} of unload; its state is left allocated",
                    self.module,
                    funct::QUIESCE_LIMIT
                ),
            );
            std::mem::forget(functs);
        }
        self.kept.clear();
        for c in self.comps.drain(..) {
            cells::give_back(c.cells.into_inner());
        }
    }
}

impl Drop for LcncSession {
    fn drop(&mut self) {
        self.teardown();
    }
}

impl Session<LinuxCnc> for LcncSession {
    fn component(&mut self, name: &str) -> Result<usize> {
        let c_name = CString::new(name).map_err(|_| HalError::BadName {
            kind: "component",
            name: name.to_string(),
            reason: "contains a NUL byte",
        })?;
        // SAFETY: hal_init with a NUL-terminated name.
        let id = unsafe { (self.api.hal_init)(c_name.as_ptr()) };
        if id < 0 {
            return Err(HalError::module_failed(
                self.module,
                DriverError::Refused {
                    call: "hal_init".into(),
                    what: name.to_string(),
                    source: std::io::Error::from_raw_os_error(id.saturating_neg()),
                },
            ));
        }
        self.comps.push(LcncComponent {
            module: self.module,
            name: name.to_string(),
            id,
            api: self.api,
            cells: RefCell::new(Vec::new()),
            aliases: RefCell::new(Vec::new()),
        });
        Ok(self.comps.len() - 1)
    }

    fn get(&self, index: usize) -> &LcncComponent {
        &self.comps[index]
    }

    fn funct<F: FnMut(&FunctCtx) + Send + 'static>(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        f: F,
    ) -> Result<()> {
        let owned = OwnedFunct::exclusive(self.ctl.clone(), name, f);
        self.export(index, name, uses_fp, false, owned)
    }

    fn funct_reentrant<F: Fn(&FunctCtx) + Send + Sync + 'static>(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        f: F,
    ) -> Result<()> {
        let owned = OwnedFunct::shared(self.ctl.clone(), name, f);
        self.export(index, name, uses_fp, true, owned)
    }

    fn safe_state(&mut self, _index: usize, state: Box<dyn SafeState>) {
        self.safe.push(state);
    }

    fn keep(&mut self, _index: usize, obj: Box<dyn Any + Send>) {
        self.kept.push(obj);
    }

    fn log(&self) -> LogSink {
        LogSink::foreign(print::say)
    }

    fn flush_log(&self) {
        // rtapi_print_msg prints at once.
    }

    fn publish_sim(&mut self, _key: String, _board: Arc<dyn Any + Send + Sync>) {
        // LinuxCNC has no registry of simulated boards; the driver keeps
        // its board.
    }
}

impl LcncSession {
    /// Exports `owned` as function `name` of component `index`, called
    /// through `call`; the closure is freed with the session.
    fn export(
        &mut self,
        index: usize,
        name: &str,
        uses_fp: bool,
        reentrant: bool,
        owned: OwnedFunct,
    ) -> Result<()> {
        let comp = &self.comps[index];
        let c_name = comp.c_name("function", name)?;
        let (call, arg) = (owned.call(), owned.arg());
        self.functs.push(owned);
        // SAFETY: hal_export_funct with a NUL-terminated name, the
        // trampoline of the closure's type and the closure's slot, which
        // lives until the session's teardown has taken the function out
        // of every thread.
        let rc = unsafe {
            (self.api.export_funct)(
                c_name.as_ptr(),
                call,
                arg,
                uses_fp as c_int,
                reentrant as c_int,
                comp.id,
            )
        };
        if rc != 0 {
            return Err(comp.refused("hal_export_funct".into(), name, rc));
        }
        Ok(())
    }
}
