//! The native half of `hal.query` (LinuxCNC 2.10's query API): every pin,
//! param, signal, component, function and thread of the instance as a
//! dict, with the keys and key order LinuxCNC's dicts have. Types,
//! directions and component kinds are the plain numbers here; the
//! pure-Python `hal/query.py` turns them into `hal.Type`, `hal.Dir` and
//! `hal.CompType` members. A name that is not there gives None; a HAL
//! that cannot be read raises RuntimeError naming the query.

use hal_core::{
    ComponentInfo, ComponentKind, FunctInfo, Instance, ParamInfo, PinInfo, SignalInfo, ThreadInfo,
};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::codes;
use crate::convert::to_python;
use crate::instance::shared;

/// LinuxCNC's component kinds (`hal.CompType`).
const COMP_USER: i32 = 0;
const COMP_REALTIME: i32 = 1;

/// The instance, or RuntimeError saying which query found no HAL.
fn instance(query: &str) -> PyResult<Instance> {
    shared().map_err(|e| PyRuntimeError::new_err(format!("hal.query.{query}: {e}")))
}

/// A HAL failure while reading, as RuntimeError naming the query.
fn failed(query: &str) -> impl Fn(hal_core::HalError) -> PyErr + '_ {
    move |e| PyRuntimeError::new_err(format!("hal.query.{query}: {e}"))
}

/// Whether threads here run under SCHED_FIFO; without it a thread's
/// priority is 0, the only SCHED_OTHER priority, as LinuxCNC reports it.
fn threads_realtime(py: Python<'_>) -> bool {
    py.import("hal._hal")
        .and_then(|m| m.getattr("is_rt"))
        .and_then(|v| v.extract::<i32>())
        .is_ok_and(|v| v != 0)
}

fn pin_dict<'py>(py: Python<'py>, p: PinInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("haltype", "pin")?;
    d.set_item("name", p.name)?;
    d.set_item("type", codes::type_code(p.hal_type))?;
    d.set_item("dir", codes::pin_dir_code(p.dir))?;
    // A port pin's value is its buffer's size, as the Value holds it.
    d.set_item("value", to_python(py, p.value)?)?;
    // LinuxCNC's `alias` is the name before aliasing; `name` the current one.
    d.set_item("alias", p.orig_name)?;
    d.set_item("signal", p.signal)?;
    d.set_item("comp", p.owner)?;
    d.set_item("comp_id", p.owner_id)?;
    Ok(d)
}

fn param_dict<'py>(py: Python<'py>, p: ParamInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("haltype", "parameter")?;
    d.set_item("name", p.name)?;
    d.set_item("type", codes::type_code(p.hal_type))?;
    d.set_item("dir", codes::param_dir_code(p.dir))?;
    d.set_item("value", to_python(py, p.value)?)?;
    d.set_item("alias", p.orig_name)?;
    d.set_item("comp", p.owner)?;
    d.set_item("comp_id", p.owner_id)?;
    Ok(d)
}

fn signal_dict<'py>(py: Python<'py>, s: SignalInfo) -> PyResult<Bound<'py, PyDict>> {
    // The driver is the output pin, and there is one only with a writer.
    let driver = s
        .pins
        .iter()
        .find(|(_, dir)| *dir == hal_core::PinDir::Out)
        .filter(|_| s.writers > 0)
        .map(|(name, _)| name.clone());
    let d = PyDict::new(py);
    d.set_item("haltype", "signal")?;
    d.set_item("name", s.name)?;
    d.set_item("type", codes::type_code(s.hal_type))?;
    d.set_item("value", to_python(py, s.value)?)?;
    d.set_item("writers", s.writers)?;
    d.set_item("readers", s.readers)?;
    d.set_item("bidirs", s.bidirs)?;
    d.set_item("driver", driver)?;
    Ok(d)
}

fn comp_dict<'py>(py: Python<'py>, c: ComponentInfo) -> PyResult<Bound<'py, PyDict>> {
    // A thread's pseudo-component lives in the realtime host, as
    // LinuxCNC's does: it is realtime, with no process of its own.
    let (kind, pid) = match c.kind {
        ComponentKind::User => (COMP_USER, c.pid),
        ComponentKind::Realtime | ComponentKind::Other => (COMP_REALTIME, 0),
    };
    let d = PyDict::new(py);
    d.set_item("haltype", "component")?;
    d.set_item("name", c.name)?;
    d.set_item("type", kind)?;
    d.set_item("id", c.id)?;
    d.set_item("pid", pid)?;
    d.set_item("ready", c.ready)?;
    // The `loadrt` arguments without the module's name before them.
    let insmod = c
        .loadrt_args
        .map(|a| a.split_once(' ').map_or("", |(_, args)| args).to_string());
    d.set_item("insmod", insmod)?;
    Ok(d)
}

fn funct_dict<'py>(py: Python<'py>, f: FunctInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("haltype", "function")?;
    d.set_item("name", f.name)?;
    d.set_item("comp", f.owner)?;
    d.set_item("comp_id", f.owner_id)?;
    d.set_item("users", f.users)?;
    d.set_item("reentrant", f.reentrant)?;
    Ok(d)
}

/// One entry of a thread's function list.
fn thread_funct<'py>(
    py: Python<'py>,
    name: &str,
    index: usize,
    is_init: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("haltype", "threadfunction")?;
    d.set_item("name", name)?;
    d.set_item("index", index)?;
    d.set_item("is_init", is_init)?;
    Ok(d)
}

fn thread_dict<'py>(
    py: Python<'py>,
    inst: &Instance,
    t: ThreadInfo,
    realtime: bool,
) -> PyResult<Bound<'py, PyDict>> {
    // The thread's pseudo-component is `__NAME`, as in LinuxCNC.
    let comp = format!("__{}", t.name);
    let comp_id = inst
        .component(&comp)
        .map_err(failed("thread"))?
        .map_or(0, |c| c.id);
    let functs = PyList::empty(py);
    for (i, f) in t.functs.iter().enumerate() {
        functs.append(thread_funct(py, f, i, false)?)?;
    }
    for (i, f) in t.init_functs.iter().enumerate() {
        functs.append(thread_funct(py, f, i, true)?)?;
    }
    let d = PyDict::new(py);
    d.set_item("haltype", "thread")?;
    d.set_item("name", &t.name)?;
    d.set_item("comp", comp)?;
    d.set_item("comp_id", comp_id)?;
    d.set_item("priority", if realtime { t.priority } else { 0 })?;
    d.set_item("period", t.period)?;
    d.set_item("functions", functs)?;
    Ok(d)
}

/// A dict of `build(item)` by each item's name, in the given order.
fn by_name<'py, T>(
    py: Python<'py>,
    items: Vec<T>,
    name: impl Fn(&T) -> String,
    mut build: impl FnMut(T) -> PyResult<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for item in items {
        let key = name(&item);
        d.set_item(key, build(item)?)?;
    }
    Ok(d)
}

/// Every pin, by name.
#[pyfunction]
#[pyo3(name = "_query_pins")]
pub(crate) fn query_pins<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let pins = instance("pins")?.pins().map_err(failed("pins"))?;
    by_name(py, pins, |p| p.name.clone(), |p| pin_dict(py, p))
}

/// One pin, by its name or its name before aliasing; None if not there.
#[pyfunction]
#[pyo3(name = "_query_pin")]
pub(crate) fn query_pin<'py>(py: Python<'py>, name: &str) -> PyResult<Option<Bound<'py, PyDict>>> {
    let pin = instance("pin")?.pin(name).map_err(failed("pin"))?;
    pin.map(|p| pin_dict(py, p)).transpose()
}

/// Every param, by name.
#[pyfunction]
#[pyo3(name = "_query_params")]
pub(crate) fn query_params<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let params = instance("params")?.params().map_err(failed("params"))?;
    by_name(py, params, |p| p.name.clone(), |p| param_dict(py, p))
}

/// One param; None if not there.
#[pyfunction]
#[pyo3(name = "_query_param")]
pub(crate) fn query_param<'py>(
    py: Python<'py>,
    name: &str,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let param = instance("param")?.param(name).map_err(failed("param"))?;
    param.map(|p| param_dict(py, p)).transpose()
}

/// Every signal, by name.
#[pyfunction]
#[pyo3(name = "_query_signals")]
pub(crate) fn query_signals<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let sigs = instance("signals")?.signals().map_err(failed("signals"))?;
    by_name(py, sigs, |s| s.name.clone(), |s| signal_dict(py, s))
}

/// One signal; None if not there.
#[pyfunction]
#[pyo3(name = "_query_signal")]
pub(crate) fn query_signal<'py>(
    py: Python<'py>,
    name: &str,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let sig = instance("signal")?.signal(name).map_err(failed("signal"))?;
    sig.map(|s| signal_dict(py, s)).transpose()
}

/// The pins linked to a signal, by name; None if there is no such signal.
#[pyfunction]
#[pyo3(name = "_query_signalpins")]
pub(crate) fn query_signalpins<'py>(
    py: Python<'py>,
    name: &str,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let inst = instance("signalpins")?;
    let Some(sig) = inst.signal(name).map_err(failed("signalpins"))? else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    for (pin, _) in sig.pins {
        // A pin unlinked since the signal was read is left out.
        if let Some(p) = inst.pin(&pin).map_err(failed("signalpins"))? {
            let key = p.name.clone();
            d.set_item(key, pin_dict(py, p)?)?;
        }
    }
    Ok(Some(d))
}

/// Every component, newest first (LinuxCNC's list order).
#[pyfunction]
#[pyo3(name = "_query_comps")]
pub(crate) fn query_comps<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let mut comps = instance("comps")?.components().map_err(failed("comps"))?;
    comps.sort_by_key(|c| std::cmp::Reverse(c.id));
    by_name(py, comps, |c| c.name.clone(), |c| comp_dict(py, c))
}

/// One component, by name or by id; None if not there.
#[pyfunction]
#[pyo3(name = "_query_comp")]
pub(crate) fn query_comp<'py>(
    py: Python<'py>,
    key: &Bound<'py, PyAny>,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let inst = instance("comp")?;
    let found = if let Ok(id) = key.extract::<i64>() {
        let comps = inst.components().map_err(failed("comp"))?;
        comps.into_iter().find(|c| i64::from(c.id) == id)
    } else if let Ok(name) = key.extract::<String>() {
        inst.component(&name).map_err(failed("comp"))?
    } else {
        let t = key.get_type().name()?.to_string();
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "hal.query.comp: a component is named by str or int id, not {t}"
        )));
    };
    found.map(|c| comp_dict(py, c)).transpose()
}

/// Every function, by name.
#[pyfunction]
#[pyo3(name = "_query_functs")]
pub(crate) fn query_functs<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let functs = instance("functs")?.functs().map_err(failed("functs"))?;
    by_name(py, functs, |f| f.name.clone(), |f| funct_dict(py, f))
}

/// One function; None if not there.
#[pyfunction]
#[pyo3(name = "_query_funct")]
pub(crate) fn query_funct<'py>(
    py: Python<'py>,
    name: &str,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let functs = instance("funct")?.functs().map_err(failed("funct"))?;
    let found = functs.into_iter().find(|f| f.name == name);
    found.map(|f| funct_dict(py, f)).transpose()
}

/// Every thread with its functions, by name (slowest first, LinuxCNC's
/// order).
#[pyfunction]
#[pyo3(name = "_query_threads")]
pub(crate) fn query_threads<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let inst = instance("threads")?;
    let threads = inst.threads().map_err(failed("threads"))?;
    let rt = threads_realtime(py);
    by_name(
        py,
        threads,
        |t| t.name.clone(),
        |t| thread_dict(py, &inst, t, rt),
    )
}

/// One thread; None if not there.
#[pyfunction]
#[pyo3(name = "_query_thread")]
pub(crate) fn query_thread<'py>(
    py: Python<'py>,
    name: &str,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let inst = instance("thread")?;
    let threads = inst.threads().map_err(failed("thread"))?;
    let rt = threads_realtime(py);
    let found = threads.into_iter().find(|t| t.name == name);
    found.map(|t| thread_dict(py, &inst, t, rt)).transpose()
}
