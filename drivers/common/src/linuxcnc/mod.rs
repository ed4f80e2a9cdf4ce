//! Host 2: LinuxCNC 2.9/2.10 in uspace mode (feature `linuxcnc`).
//!
//! A driver declared as a [`DriverModule`] also builds as `<module>.so`,
//! which LinuxCNC's `rtapi_app` loads with `loadrt <module> ...`: a
//! `cdylib` crate whose lib.rs is one [`linuxcnc_module!`](crate::linuxcnc_module)
//! line. The macro exports LinuxCNC's parameter symbols
//! (`rtapi_info_address_<p>`, `rtapi_info_type_<p>`, `rtapi_info_size_<p>`,
//! [`args`](self) says how they are read) from the driver's parameter
//! table, and `rtapi_app_main`/`rtapi_app_exit`, which run [`app_main`]
//! and [`app_exit`]:
//!
//! * load: LinuxCNC's functions are looked up in the process
//!   (`hal_init`, `hal_malloc`, `hal_pin_*_newf`, `hal_param_*_newf`,
//!   `hal_export_funct`, `hal_ready`, `hal_exit`, `rtapi_print_msg`); the
//!   parameters are parsed by our host's parser; the driver's `open` and
//!   `export` run unchanged against LinuxCNC's HAL ([`LinuxCnc`] is the
//!   host type, its pins [`LcncPin`]); every component is made ready. Any
//!   error is said through `rtapi_print_msg` with the text our host gives,
//!   everything made so far is removed (`hal_exit`), and a negative errno
//!   is returned. A panic is caught: `rtapi_app` never unwinds.
//! * unload: the module's functions stop and the unload waits until none
//!   runs; the safe state runs; the components are removed; the
//!   closures, kept objects and backends are dropped; the shared-memory
//!   cells go back to the module's pool for the next load.
//!
//! The realtime functions are the driver's own code, monomorphised for
//! [`LinuxCnc`]: a pin access is a load of the pin's pointer cell and one
//! of the value. Each call passes a trampoline that counts it in and out
//! of the module and catches a panic (after which the module goes safe
//! and its functions do nothing until unloaded).
//!
//! What differs from our host, by LinuxCNC's design:
//!
//! * names: LinuxCNC's HAL limits names to 47 bytes; a longer name is
//!   refused by LinuxCNC when the pin is made, and the load fails.
//! * 64-bit pins and parameters exist from LinuxCNC 2.10 on; on 2.9 a
//!   driver that makes one fails to load, naming the pin.
//! * a simulated board cannot be reached from outside `rtapi_app`: it
//!   runs, but nothing publishes it.
//! * parameters LinuxCNC's own parser refuses (an unknown key, too many
//!   items) are refused by `rtapi_app` with its own message before the
//!   module runs; see [`args`](self) for what that leaves behind.

mod api;
mod args;
mod cells;
mod funct;
mod handles;
mod print;
mod session;

pub use args::{ArgStore, SymPtr};
pub use handles::{LcncParam, LcncPin, LinuxCnc};
pub use session::{LcncComponent, LcncSession};

use std::ffi::c_int;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use hal_core::module::ModuleArgs;
use hal_core::{HalError, MsgLevel};

use crate::error::DriverError;
use crate::log::LogSink;
use crate::module::{DriverModule, Exporter, LoadEnv};

/// The module's one load (rtapi_app loads a module once at a time).
static LOADED: Mutex<Option<LcncSession>> = Mutex::new(None);

fn loaded() -> std::sync::MutexGuard<'static, Option<LcncSession>> {
    LOADED.lock().unwrap_or_else(|e| e.into_inner())
}

/// `rtapi_app_main` of driver `D` with the `key=value` words rtapi_app
/// stored: 0, or a negative errno after saying why.
pub fn app_main<D: DriverModule>(args: Vec<String>) -> c_int {
    match catch_unwind(AssertUnwindSafe(|| load::<D>(&args))) {
        Ok(Ok(session)) => {
            *loaded() = Some(session);
            0
        }
        Ok(Err(e)) => {
            print::say(MsgLevel::Err, format_args!("{e}"));
            -errno_of(&e)
        }
        Err(_) => {
            print::say(
                MsgLevel::Err,
                format_args!(
                    "{}: the driver panicked while loading; nothing stays loaded",
                    D::NAME
                ),
            );
            -libc::EFAULT
        }
    }
}

/// `rtapi_app_exit` of driver `D`: unloads what [`app_main`] loaded.
pub fn app_exit<D: DriverModule>() {
    let session = loaded().take();
    if catch_unwind(AssertUnwindSafe(move || drop(session))).is_err() {
        print::say(
            MsgLevel::Err,
            format_args!("{}: the driver panicked while unloading", D::NAME),
        );
    }
}

/// Parses, opens and exports `D` into LinuxCNC.
fn load<D: DriverModule>(args: &[String]) -> Result<LcncSession, HalError> {
    let api = api::api().map_err(|e| e.into_hal(D::NAME))?;
    if loaded().is_some() {
        return Err(HalError::ModuleLoaded {
            name: D::NAME.to_string(),
        });
    }
    let parsed = ModuleArgs::parse(D::NAME, D::PARAMS, args)?;
    let env = LoadEnv::new("linuxcnc", LogSink::foreign(print::say));
    let opened = D::open(&parsed, &env)?;
    let mut ex = Exporter::<LinuxCnc>::new(LcncSession::new(D::NAME, api));
    D::export(opened, &mut ex)?;
    ex.into_session().finish()
}

/// The errno a failed load returns to rtapi_app, which prints it after
/// our message.
fn errno_of(e: &HalError) -> c_int {
    match e {
        HalError::ModuleParam { .. } | HalError::BadName { .. } => libc::EINVAL,
        HalError::ModuleLoaded { .. } => libc::EEXIST,
        HalError::ModuleFailed { source, .. } => match source.downcast_ref::<DriverError>() {
            Some(DriverError::Permission { .. }) => libc::EACCES,
            Some(DriverError::Lockdown { .. } | DriverError::PortIo { .. }) => libc::EPERM,
            Some(DriverError::Refused { source, .. }) => {
                source.raw_os_error().unwrap_or(libc::EINVAL)
            }
            Some(DriverError::Unsupported { .. }) => libc::ENOSYS,
            _ => libc::ENODEV,
        },
        _ => libc::ENODEV,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_map_to_errnos_rtapi_app_prints() {
        let p = HalError::ModuleParam {
            module: "m".into(),
            param: "cfg".into(),
            reason: "bad".into(),
        };
        assert_eq!(errno_of(&p), libc::EINVAL);
        let r = HalError::module_failed(
            "m",
            DriverError::Refused {
                call: "hal_pin_bit_newf".into(),
                what: "m.x".into(),
                source: std::io::Error::from_raw_os_error(libc::ENOMEM),
            },
        );
        assert_eq!(errno_of(&r), libc::ENOMEM);
        assert_eq!(
            r.to_string(),
            "m: LinuxCNC's hal_pin_bit_newf refused 'm.x': Cannot allocate memory (os error 12)"
        );
    }
}
