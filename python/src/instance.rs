//! The HAL instance the module works on, and how HAL errors reach Python.

use std::sync::Mutex;

use hal_core::{instance_from_env, HalError, Instance};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

mod exception {
    // The class is `hal.error`, lower case, as in LinuxCNC.
    #![allow(non_camel_case_types)]
    pyo3::create_exception!(
        hal,
        error,
        pyo3::exceptions::PyException,
        "A HAL operation failed."
    );
}
pub(crate) use exception::error;

/// The instance module functions use (the one `HAL_INSTANCE` names), kept
/// attached between calls and attached again once its host has gone.
static SHARED: Mutex<Option<Instance>> = Mutex::new(None);

/// The instance named by `HAL_INSTANCE` (or `default`).
pub(crate) fn shared() -> Result<Instance, HalError> {
    let mut cached = SHARED.lock().unwrap_or_else(|e| e.into_inner());
    let name = instance_from_env();
    if let Some(inst) = cached.as_ref() {
        if inst.name() == name && inst.host_alive() {
            return Ok(inst.clone());
        }
    }
    let inst = Instance::attach(&name)?;
    *cached = Some(inst.clone());
    Ok(inst)
}

/// The shared instance, or the RuntimeError LinuxCNC raises when no HAL
/// is there to work on.
pub(crate) fn shared_or_runtime_error() -> PyResult<Instance> {
    shared().map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// A HAL failure as `hal.error`.
pub(crate) fn hal_error(e: HalError) -> PyErr {
    error::new_err(e.to_string())
}
