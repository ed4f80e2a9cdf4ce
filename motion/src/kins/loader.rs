//! What every kinematics module does at `loadrt`: make its component,
//! export its geometry pins, register its [`Kinematics`] for `motmod` to
//! find, and refuse bad module parameters by name.

use std::sync::Arc;

use hal_core::{Component, HalError, Host, In, Io, Pin, Result, RtComponentBuilder};

use super::{Kinematics, KINEMATICS};

/// The error for a refused module parameter.
pub(crate) fn bad_param(module: &str, param: &str, reason: impl Into<String>) -> HalError {
    HalError::ModuleParam {
        module: module.into(),
        param: param.into(),
        reason: reason.into(),
    }
}

/// A float input pin `name` starting at `init` (a geometry value).
pub(crate) fn float_in(c: &Component, name: &str, init: f64) -> Result<Pin<f64, In>> {
    c.pin_init(name, init)
}

/// A float bidirectional pin `name` starting at `init` (LinuxCNC makes
/// some modules' geometry pins `io`).
pub(crate) fn float_io(c: &Component, name: &str, init: f64) -> Result<Pin<f64, Io>> {
    c.pin_init(name, init)
}

/// Registers `kins` as the kinematics of the host's instance and marks
/// the component ready. The component owns the registration: unloading
/// it (or the host going down) removes the entry, so `motmod` can only
/// ever find a live module.
pub(crate) fn register(
    host: &Host,
    mut b: RtComponentBuilder<'_>,
    module: &str,
    kins: Arc<dyn Kinematics>,
) -> Result<()> {
    let registration = KINEMATICS
        .register(host.instance().name(), module, kins)
        .map_err(|e| HalError::ModuleLoad {
            module: module.into(),
            reason: e.to_string(),
        })?;
    // Kinematics have no outputs to make safe; the hook only keeps the
    // registration alive for as long as the component.
    b.on_safe_state(move || {
        let _keep = &registration;
    });
    b.ready()
}
