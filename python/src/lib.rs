//! The native part of the Python `hal` module (`hal._hal`): LinuxCNC's
//! Python HAL interface on this HAL. The pure-Python package `hal` (in
//! `python/hal/`) re-exports it and adds the `Pin`/`Param` wrappers,
//! `hal.Type` and `hal.Dir`, as LinuxCNC's `hal.py` does.
//!
//! * `component.rs`: `hal.component` and its pins and params (`hal.item`).
//! * `functions.rs`: functions on the whole instance (signals, values by
//!   name, listings).
//! * `stream.rs`: `hal.stream`, feeding a streamer and reading a sampler.
//! * `query.rs`: the dicts of `hal.query` (LinuxCNC 2.10's query API).
//! * `port.rs`: port pins, for the `pyhal` package.
//! * `task_client.rs`: task requests and INI files, for the `linuxcnc`
//!   package.
//! * `convert.rs`: Python objects to HAL values, with LinuxCNC's
//!   exceptions; `codes.rs`: LinuxCNC's numbers for types and directions.

mod codes;
mod component;
mod convert;
mod functions;
mod instance;
mod port;
mod query;
mod stream;
mod task_client;

use std::sync::atomic::{AtomicI32, Ordering::Relaxed};

use pyo3::prelude::*;

/// RTAPI message levels (`hal.MSG_ERR`, ...), as LinuxCNC numbers them.
const MSG_LEVELS: [(&str, i32); 6] = [
    ("MSG_NONE", 0),
    ("MSG_ERR", 1),
    ("MSG_WARN", 2),
    ("MSG_INFO", 3),
    ("MSG_DBG", 4),
    ("MSG_ALL", 5),
];

/// The level `set_msg_level` last set (LinuxCNC's default is MSG_ERR).
static MSG_LEVEL: AtomicI32 = AtomicI32::new(1);

/// Sets the RTAPI message level (kept for LinuxCNC's API; the HAL here
/// reports errors through return values and exceptions).
#[pyfunction]
fn set_msg_level(level: i32) -> PyResult<()> {
    if !(0..=5).contains(&level) {
        return Err(instance::error::new_err("Invalid argument"));
    }
    MSG_LEVEL.store(level, Relaxed);
    Ok(())
}

/// The RTAPI message level.
#[pyfunction]
fn get_msg_level() -> i32 {
    MSG_LEVEL.load(Relaxed)
}

/// Removes every component this process made; the package runs it at
/// interpreter exit.
#[pyfunction]
fn _exit_all() {
    component::close_all();
}

/// Whether HAL threads started now would run under realtime scheduling:
/// `HAL_NO_REALTIME` unset and SCHED_FIFO permitted.
fn realtime_available() -> bool {
    std::env::var_os("HAL_NO_REALTIME").is_none()
        && hal_core::realtime::probe_fifo(hal_core::TOP_PRIORITY).is_ok()
}

#[pymodule]
fn _hal(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("error", py.get_type::<instance::error>())?;
    m.add_class::<component::PyComponent>()?;
    m.add_class::<component::PyItem>()?;
    m.add_class::<stream::PyStream>()?;
    m.add_class::<port::PyPort>()?;
    m.add_function(wrap_pyfunction!(port::new_port, m)?)?;
    m.add_function(wrap_pyfunction!(functions::new_signal, m)?)?;
    m.add_function(wrap_pyfunction!(functions::link, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_pins, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_pin, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_params, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_param, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_signals, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_signal, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_signalpins, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_comps, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_comp, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_functs, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_funct, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_threads, m)?)?;
    m.add_function(wrap_pyfunction!(query::query_thread, m)?)?;
    m.add_function(wrap_pyfunction!(functions::pin_has_writer, m)?)?;
    m.add_function(wrap_pyfunction!(functions::component_exists, m)?)?;
    m.add_function(wrap_pyfunction!(functions::component_is_ready, m)?)?;
    m.add_function(wrap_pyfunction!(functions::new_sig, m)?)?;
    m.add_function(wrap_pyfunction!(functions::connect, m)?)?;
    m.add_function(wrap_pyfunction!(functions::disconnect, m)?)?;
    m.add_function(wrap_pyfunction!(functions::set_p, m)?)?;
    m.add_function(wrap_pyfunction!(functions::set_s, m)?)?;
    m.add_function(wrap_pyfunction!(functions::get_value, m)?)?;
    m.add_function(wrap_pyfunction!(functions::get_p, m)?)?;
    m.add_function(wrap_pyfunction!(functions::get_s, m)?)?;
    m.add_function(wrap_pyfunction!(functions::get_info_pins, m)?)?;
    m.add_function(wrap_pyfunction!(functions::get_info_signals, m)?)?;
    m.add_function(wrap_pyfunction!(functions::get_info_params, m)?)?;
    m.add_function(wrap_pyfunction!(set_msg_level, m)?)?;
    m.add_function(wrap_pyfunction!(get_msg_level, m)?)?;
    m.add_function(wrap_pyfunction!(_exit_all, m)?)?;
    m.add_function(wrap_pyfunction!(task_client::task_request, m)?)?;
    m.add_function(wrap_pyfunction!(task_client::ini_entries, m)?)?;
    for (name, code) in codes::TYPES.iter().chain(&codes::DIRS).chain(&MSG_LEVELS) {
        m.add(*name, *code)?;
    }
    // The newer spellings of the type constants.
    m.add("HAL_BOOL", 1)?;
    m.add("HAL_REAL", 2)?;
    m.add("HAL_SINT", 6)?;
    m.add("HAL_UINT", 7)?;
    let rt = realtime_available() as i32;
    m.add("is_rt", rt)?;
    m.add("is_sim", 1 - rt)?;
    m.add("is_kernelspace", 0)?;
    m.add("is_userspace", 1)?;
    m.add("streamer_base", codes::STREAMER_BASE)?;
    m.add("sampler_base", codes::SAMPLER_BASE)?;
    m.add("kernel_version", "Not Available")?;
    Ok(())
}
