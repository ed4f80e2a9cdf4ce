//! The module's functions on the whole instance: signals, links, values
//! by name and listings. They need no component of their own; they work
//! on the instance `HAL_INSTANCE` names and raise RuntimeError if no HAL
//! runs there.

use hal_core::{HalType, Instance, ParamDir, PinDir, Value};
use hal_lang::parse_value;
use pyo3::exceptions::{PyNameError, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use pyo3::IntoPyObjectExt;

use crate::codes;
use crate::convert::{to_python, to_value};
use crate::instance::shared_or_runtime_error as instance;
use crate::instance::{error, hal_error, shared};

fn runtime(msg: impl Into<String>) -> PyErr {
    PyRuntimeError::new_err(msg.into())
}

/// `value` for a pin, param or signal of type `t`: text is read as
/// `halcmd setp` reads it, other objects as a pin assignment converts
/// them. Any failure is the RuntimeError LinuxCNC raises.
fn value_for(what: &str, name: &str, value: &Bound<'_, PyAny>, t: HalType) -> PyResult<Value> {
    let bad = |why: String| runtime(format!("{what}: {name}: {why}"));
    if let Ok(text) = value.cast::<PyString>() {
        return parse_value(t, text.to_cow()?.trim()).map_err(|e| bad(e.to_string()));
    }
    to_value(value, t).map_err(|e| bad(e.to_string()))
}

/// Whether the signal a pin is linked to has a writer. An unlinked output
/// pin counts as its own writer. Raises NameError for an unknown pin.
#[pyfunction]
pub(crate) fn pin_has_writer(name: &str) -> PyResult<bool> {
    let inst = instance()?;
    let pin = inst
        .pin(name)
        .map_err(|e| runtime(e.to_string()))?
        .ok_or_else(|| PyNameError::new_err(format!("Pin `{name}' does not exist")))?;
    match pin.signal {
        None => Ok(pin.dir == PinDir::Out),
        Some(sig) => Ok(inst
            .signal(&sig)
            .map_err(|e| runtime(e.to_string()))?
            .is_some_and(|s| s.writers > 0)),
    }
}

/// Whether a component of that name exists.
#[pyfunction]
pub(crate) fn component_exists(name: &str) -> PyResult<bool> {
    let inst = instance()?;
    Ok(inst
        .component(name)
        .map_err(|e| runtime(e.to_string()))?
        .is_some())
}

/// Whether a component of that name exists and is ready.
#[pyfunction]
pub(crate) fn component_is_ready(name: &str) -> PyResult<bool> {
    let inst = instance()?;
    Ok(inst
        .component(name)
        .map_err(|e| runtime(e.to_string()))?
        .is_some_and(|c| c.ready))
}

/// Creates a signal. Returns False on success and True if the HAL refused
/// (LinuxCNC's convention); an unknown type raises RuntimeError.
#[pyfunction]
pub(crate) fn new_sig(name: &str, hal_type: i32) -> PyResult<bool> {
    let t =
        // Ports are made with halcmd (`newsig NAME port`), not from Python.
        codes::hal_type(hal_type as i64)
            .filter(|t| *t != hal_core::HalType::Port)
            .ok_or_else(|| runtime("not a valid HAL signal type"))?;
    Ok(instance()?.newsig(name, t).is_err())
}

/// Creates a signal of any type, ports included; raises `hal.error` with
/// the HAL's reason (for `pyhal`, which says which signal).
#[pyfunction]
#[pyo3(name = "_new_signal")]
pub(crate) fn new_signal(name: &str, hal_type: i32) -> PyResult<()> {
    let t = codes::hal_type(hal_type as i64).ok_or_else(|| {
        error::new_err(format!(
            "signal {name}: {hal_type} is not a HAL type number"
        ))
    })?;
    let inst = shared().map_err(hal_error)?;
    inst.newsig(name, t).map_err(hal_error)
}

/// Links a pin to a signal; raises `hal.error` with the HAL's reason (for
/// `pyhal`, which names both).
#[pyfunction]
#[pyo3(name = "_link")]
pub(crate) fn link(pin: &str, signal: &str) -> PyResult<()> {
    let inst = shared().map_err(hal_error)?;
    inst.link(pin, signal).map_err(hal_error)
}

/// Links a pin to a signal. Returns False on success, True on failure.
#[pyfunction]
pub(crate) fn connect(pin: &str, signal: &str) -> PyResult<bool> {
    Ok(instance()?.link(pin, signal).is_err())
}

/// Unlinks a pin from its signal. Returns False on success, True on
/// failure.
#[pyfunction]
pub(crate) fn disconnect(pin: &str) -> PyResult<bool> {
    Ok(instance()?.unlink(pin).is_err())
}

/// Sets a param, or an input pin that is not linked, from text (read as
/// `halcmd setp` reads it) or a number. Returns True; raises
/// RuntimeError if there is no such item, it may not be set, or the value
/// does not fit.
#[pyfunction]
pub(crate) fn set_p(name: &str, value: &Bound<'_, PyAny>) -> PyResult<bool> {
    let inst = instance()?;
    let fail = |e: hal_core::HalError| runtime(format!("set_p: {name}: {e}"));
    if let Some(p) = inst.param(name).map_err(fail)? {
        if p.dir == ParamDir::Ro {
            return Err(runtime("param not writable"));
        }
        let v = value_for("set_p", name, value, p.hal_type)?;
        inst.set_param(name, v).map_err(fail)?;
        return Ok(true);
    }
    let pin = inst
        .pin(name)
        .map_err(fail)?
        .ok_or_else(|| runtime("pin not found"))?;
    if pin.dir == PinDir::Out {
        return Err(runtime("pin not writable"));
    }
    if pin.signal.is_some() {
        return Err(runtime("pin connected to signal"));
    }
    let v = value_for("set_p", name, value, pin.hal_type)?;
    inst.set_pin(name, v).map_err(fail)?;
    Ok(true)
}

/// Sets a signal that has no writer, from text or a number; a port
/// signal (its value the size of the buffer to make) may have one, as in
/// LinuxCNC. Returns True; raises RuntimeError otherwise.
#[pyfunction]
pub(crate) fn set_s(name: &str, value: &Bound<'_, PyAny>) -> PyResult<bool> {
    let inst = instance()?;
    let fail = |e: hal_core::HalError| runtime(format!("set_s: {name}: {e}"));
    let sig = inst
        .signal(name)
        .map_err(fail)?
        .ok_or_else(|| runtime("signal not found"))?;
    if sig.writers > 0 && sig.hal_type != HalType::Port {
        return Err(runtime(format!("signal '{name}' already has writer(s)")));
    }
    let v = value_for("set_s", name, value, sig.hal_type)?;
    inst.set_signal(name, v).map_err(fail)?;
    Ok(true)
}

/// A param's or pin's value; `None` if neither exists.
fn item_value(inst: &Instance, name: &str) -> PyResult<Option<Value>> {
    let err = |e: hal_core::HalError| runtime(e.to_string());
    if let Some(p) = inst.param(name).map_err(err)? {
        return Ok(Some(p.value));
    }
    Ok(inst.pin(name).map_err(err)?.map(|p| p.value))
}

fn signal_value(inst: &Instance, name: &str) -> PyResult<Option<Value>> {
    Ok(inst
        .signal(name)
        .map_err(|e| runtime(e.to_string()))?
        .map(|s| s.value))
}

/// The value of a param, pin (its signal's, if linked) or signal, looked
/// up in that order.
#[pyfunction]
pub(crate) fn get_value(py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
    let inst = instance()?;
    let v = match item_value(&inst, name)? {
        Some(v) => Some(v),
        None => signal_value(&inst, name)?,
    };
    let v =
        v.ok_or_else(|| runtime(format!("get_value: {name}: pin, param or signal not found")))?;
    to_python(py, v)
}

/// The value of a param or pin.
#[pyfunction]
pub(crate) fn get_p(py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
    let v = item_value(&instance()?, name)?
        .ok_or_else(|| runtime(format!("get_p: {name}: pin or param not found")))?;
    to_python(py, v)
}

/// The value of a signal.
#[pyfunction]
pub(crate) fn get_s(py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
    let v = signal_value(&instance()?, name)?
        .ok_or_else(|| runtime(format!("get_s: {name}: signal not found")))?;
    to_python(py, v)
}

/// One entry of the `get_info_*` lists: `{'NAME', 'VALUE', key, 'TYPE'}`,
/// in that order, as LinuxCNC builds them.
fn info<'py>(
    py: Python<'py>,
    name: String,
    value: Value,
    (key, extra): (&str, Py<PyAny>),
    t: HalType,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("NAME", name)?;
    d.set_item("VALUE", to_python(py, value)?)?;
    d.set_item(key, extra)?;
    d.set_item("TYPE", codes::type_code(t))?;
    Ok(d)
}

/// Every pin, by name: `{'NAME', 'VALUE', 'DIRECTION', 'TYPE'}`.
#[pyfunction]
pub(crate) fn get_info_pins<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let pins = instance()?.pins().map_err(|e| runtime(e.to_string()))?;
    let list = PyList::empty(py);
    for p in pins {
        let dir = codes::pin_dir_code(p.dir).into_py_any(py)?;
        list.append(info(py, p.name, p.value, ("DIRECTION", dir), p.hal_type)?)?;
    }
    Ok(list)
}

/// Every signal, by name: `{'NAME', 'VALUE', 'DRIVER', 'TYPE'}`, the
/// driver being the output pin's name or None.
#[pyfunction]
pub(crate) fn get_info_signals<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let sigs = instance()?.signals().map_err(|e| runtime(e.to_string()))?;
    let list = PyList::empty(py);
    for s in sigs {
        let driver = s
            .pins
            .iter()
            .find(|(_, dir)| *dir == PinDir::Out)
            .map(|(name, _)| name.clone());
        let driver = driver.into_py_any(py)?;
        list.append(info(py, s.name, s.value, ("DRIVER", driver), s.hal_type)?)?;
    }
    Ok(list)
}

/// Every param, by name: `{'NAME', 'VALUE', 'DIRECTION', 'TYPE'}`.
#[pyfunction]
pub(crate) fn get_info_params<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let params = instance()?.params().map_err(|e| runtime(e.to_string()))?;
    let list = PyList::empty(py);
    for p in params {
        let dir = codes::param_dir_code(p.dir).into_py_any(py)?;
        list.append(info(py, p.name, p.value, ("DIRECTION", dir), p.hal_type)?)?;
    }
    Ok(list)
}
