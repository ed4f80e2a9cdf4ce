//! Port pins from Python (`hal._hal.port`), for LinuxCNC's `pyhal`
//! binding: a byte stream from one component's output port through a
//! signal to another's input port. `hal.component` itself makes no port
//! pins (LinuxCNC 2.9's does not); `pyhal` makes them with
//! `_hal._new_port(component, name, dir)`.
//!
//! Each access holds the component's lock, so a port of a component that
//! exited raises RuntimeError instead of touching a removed pin.

use std::sync::Arc;

use hal_core::{PortIn, PortOut};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::codes;
use crate::component::{PyComponent, Shared};
use crate::instance::{error, hal_error};

/// The end of the stream a pin is.
enum End {
    In(PortIn),
    Out(PortOut),
}

/// A port pin of a component made by this process.
#[pyclass(frozen, name = "port", module = "hal")]
pub(crate) struct PyPort {
    comp: Arc<Shared>,
    end: End,
    /// The pin's full name, for messages.
    name: String,
}

/// Makes the port pin `name` (under the component's prefix) of direction
/// `dir` (`HAL_IN` or `HAL_OUT`); raises `hal.error` if the HAL refuses.
#[pyfunction]
#[pyo3(name = "_new_port")]
pub(crate) fn new_port(comp: &Bound<'_, PyComponent>, name: &str, dir: i32) -> PyResult<PyPort> {
    let shared = comp.get().shared.clone();
    let (end, full) = shared.with_prefixed(name, |c, full| {
        let end = match codes::pin_dir(dir as i64) {
            Some(hal_core::PinDir::In) => End::In(c.port_in(full).map_err(hal_error)?),
            Some(hal_core::PinDir::Out) => End::Out(c.port_out(full).map_err(hal_error)?),
            _ => {
                return Err(error::new_err(format!(
                    "port pin {full}: direction {dir} is not HAL_IN (16) or HAL_OUT (32)"
                )))
            }
        };
        Ok((end, full.to_string()))
    })?;
    Ok(PyPort {
        comp: shared,
        end,
        name: full,
    })
}

impl PyPort {
    /// Runs `f` on the reading end, while the component exists.
    fn reader<T>(&self, what: &str, f: impl FnOnce(&PortIn) -> T) -> PyResult<T> {
        match &self.end {
            End::In(p) => self.comp.with_component(|_| Ok(f(p))),
            End::Out(_) => Err(PyTypeError::new_err(format!(
                "{what}: {} is an output port; only its reader may {what}",
                self.name
            ))),
        }
    }

    /// Runs `f` on the writing end, while the component exists.
    fn writer<T>(&self, what: &str, f: impl FnOnce(&PortOut) -> T) -> PyResult<T> {
        match &self.end {
            End::Out(p) => self.comp.with_component(|_| Ok(f(p))),
            End::In(_) => Err(PyTypeError::new_err(format!(
                "{what}: {} is an input port; only its writer may {what}",
                self.name
            ))),
        }
    }

    /// A buffer for `count` bytes, refusing counts past any port's size.
    fn buffer(&self, what: &str, count: usize) -> PyResult<Vec<u8>> {
        if count > hal_core::MAX_PORT_SIZE as usize {
            return Err(PyValueError::new_err(format!(
                "{what}: {}: {count} bytes is more than a port holds ({})",
                self.name,
                hal_core::MAX_PORT_SIZE
            )));
        }
        Ok(vec![0; count])
    }
}

#[pymethods]
impl PyPort {
    /// Takes exactly `count` bytes; None (nothing taken) when fewer wait.
    fn read<'py>(&self, py: Python<'py>, count: usize) -> PyResult<Option<Bound<'py, PyBytes>>> {
        let mut buf = self.buffer("read", count)?;
        let ok = self.reader("read", |p| p.read(&mut buf))?;
        Ok(ok.then(|| PyBytes::new(py, &buf)))
    }

    /// Copies exactly `count` bytes without taking them; None when fewer
    /// wait.
    fn peek<'py>(&self, py: Python<'py>, count: usize) -> PyResult<Option<Bound<'py, PyBytes>>> {
        let mut buf = self.buffer("peek", count)?;
        let ok = self.reader("peek", |p| p.peek(&mut buf))?;
        Ok(ok.then(|| PyBytes::new(py, &buf)))
    }

    /// Takes `count` bytes already peeked at; False (nothing taken) when
    /// fewer wait.
    fn peek_commit(&self, count: u32) -> PyResult<bool> {
        self.reader("peek_commit", |p| p.peek_commit(count))
    }

    /// Drops every waiting byte.
    fn clear(&self) -> PyResult<()> {
        self.reader("clear", PortIn::clear)
    }

    /// Bytes waiting to be read.
    fn readable(&self) -> PyResult<u32> {
        self.reader("readable", PortIn::readable)
    }

    /// Appends all of `data`; False (nothing written) when it does not fit.
    fn write(&self, data: &[u8]) -> PyResult<bool> {
        self.writer("write", |p| p.write(data))
    }

    /// Room for bytes.
    fn writable(&self) -> PyResult<u32> {
        self.writer("writable", PortOut::writable)
    }

    /// The size of the signal's buffer (0 while there is none).
    fn size(&self) -> PyResult<u32> {
        match &self.end {
            End::In(p) => self.comp.with_component(|_| Ok(p.buffer_size())),
            End::Out(p) => self.comp.with_component(|_| Ok(p.buffer_size())),
        }
    }

    /// Whether this is the reading end.
    fn is_input(&self) -> bool {
        matches!(self.end, End::In(_))
    }

    /// The pin's full name.
    fn get_name(&self) -> String {
        self.name.clone()
    }

    fn __repr__(&self) -> String {
        let dir = if self.is_input() { "IN" } else { "OUT" };
        format!("<hal port \"{}\" {dir}>", self.name)
    }
}
