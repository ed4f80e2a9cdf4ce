//! `hal.component` and `hal.item`: a user-space component with its pins
//! and params, created from Python.
//!
//! Python code may hold an item after its component exited, or use a
//! component from several threads; every access therefore checks, under a
//! lock, that the component is still there, and a closed component raises
//! RuntimeError as LinuxCNC's does.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock, RwLock, RwLockReadGuard, Weak};

use hal_core::{Component, ComponentKind, HalType, In, Io, Out, RawParam, RawPin, Value};
use pyo3::exceptions::{PyAttributeError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyAny, PyDict, PyString};

use crate::codes;
use crate::convert::{to_python, to_value};
use crate::instance::{error, hal_error, shared};

/// How a pin or param is reached.
enum Handle {
    In(RawPin<In>),
    Out(RawPin<Out>),
    Io(RawPin<Io>),
    Param(RawParam),
}

/// One pin or param of a component.
pub(crate) struct Item {
    handle: Handle,
    hal_type: HalType,
    /// LinuxCNC's direction number.
    dir: i32,
}

impl Item {
    fn is_pin(&self) -> bool {
        !matches!(self.handle, Handle::Param(_))
    }

    fn value(&self) -> Value {
        let bits = match &self.handle {
            Handle::In(p) => p.get_bits(),
            Handle::Out(p) => p.get_bits(),
            Handle::Io(p) => p.get_bits(),
            Handle::Param(p) => p.get_bits(),
        };
        Value::from_bits(self.hal_type, bits)
    }

    /// Writes the item; its owner may write every direction, inputs and
    /// read-only params included, as in LinuxCNC.
    fn set(&self, v: Value) {
        let bits = v.to_bits();
        match &self.handle {
            Handle::In(p) => p.overwrite_bits(bits),
            Handle::Out(p) => p.set_bits(bits),
            Handle::Io(p) => p.set_bits(bits),
            Handle::Param(p) => p.set_bits(bits),
        }
    }
}

/// A component while it exists.
struct Live {
    comp: Component,
    /// The process that made it: a forked child inherits the object but
    /// must not remove its parent's component when it exits.
    pid: u32,
    prefix: String,
    items: BTreeMap<String, Arc<Item>>,
}

/// What a component object and its items share.
pub(crate) struct Shared {
    /// Name and HAL id, set once the component is made.
    made: OnceLock<(String, i32)>,
    /// The component while it exists: `None` before `__init__` and after
    /// `exit()`.
    live: RwLock<Option<Live>>,
}

/// Every component of this process, so that they can be removed when the
/// interpreter exits.
static ALL: Mutex<Vec<Weak<Shared>>> = Mutex::new(Vec::new());

fn closed() -> PyErr {
    PyRuntimeError::new_err("Invalid operation on closed HAL component")
}

fn no_item(name: &str) -> PyErr {
    PyAttributeError::new_err(format!("Pin or param '{name}' does not exist"))
}

impl Shared {
    fn read(&self) -> RwLockReadGuard<'_, Option<Live>> {
        self.live.read().unwrap_or_else(|e| e.into_inner())
    }

    /// Runs `f` on the live component, or raises RuntimeError. `f` must
    /// not run Python code: that may let another thread take the GIL and
    /// wait for this lock, while `f` waits for the GIL.
    fn with_live<T>(&self, f: impl FnOnce(&Live) -> PyResult<T>) -> PyResult<T> {
        f(self.read().as_ref().ok_or_else(closed)?)
    }

    fn item(&self, name: &str) -> PyResult<Arc<Item>> {
        self.with_live(|l| l.items.get(name).cloned().ok_or_else(|| no_item(name)))
    }

    /// An item's value, if the component still exists.
    fn read_value(&self, item: &Item) -> PyResult<Value> {
        self.with_live(|_| Ok(item.value()))
    }

    /// Writes an item, if the component still exists.
    fn write_value(&self, item: &Item, v: Value) -> PyResult<()> {
        self.with_live(|_| {
            item.set(v);
            Ok(())
        })
    }

    /// Writes a Python object to an item: converted first, then written
    /// under the lock.
    fn write_object(&self, item: &Item, obj: &Bound<'_, PyAny>) -> PyResult<()> {
        self.with_live(|_| Ok(()))?;
        let v = to_value(obj, item.hal_type)?;
        self.write_value(item, v)
    }

    /// Removes the component from the HAL; later uses raise RuntimeError.
    fn close(&self) {
        let live = self.live.write().unwrap_or_else(|e| e.into_inner()).take();
        drop(live);
    }

    /// Closes the component when its object is collected or the
    /// interpreter exits; in a forked child the parent's component stays.
    fn close_implicitly(&self) {
        let live = self.live.write().unwrap_or_else(|e| e.into_inner()).take();
        match live {
            Some(l) if l.pid != std::process::id() => std::mem::forget(l),
            other => drop(other),
        }
    }

    /// Whether the component still exists (for streams it owns).
    pub(crate) fn is_live(&self) -> bool {
        self.read().is_some()
    }

    /// Runs `f` on the HAL component and the full name of its item
    /// `name` (`prefix.name`), while the component exists.
    pub(crate) fn with_prefixed<T>(
        &self,
        name: &str,
        f: impl FnOnce(&Component, &str) -> PyResult<T>,
    ) -> PyResult<T> {
        self.with_live(|l| f(&l.comp, &format!("{}.{}", l.prefix, name)))
    }

    /// Runs `f` on the HAL component while it exists.
    pub(crate) fn with_component<T>(
        &self,
        f: impl FnOnce(&Component) -> PyResult<T>,
    ) -> PyResult<T> {
        self.with_live(|l| f(&l.comp))
    }
}

/// Removes every component of this process (at interpreter exit).
pub(crate) fn close_all() {
    let all = std::mem::take(&mut *ALL.lock().unwrap_or_else(|e| e.into_inner()));
    for s in all.iter().filter_map(Weak::upgrade) {
        s.close_implicitly();
    }
}

/// A HAL component made by this process. Pins and params are read and
/// written as `c["name"]` or `c.name`.
#[pyclass(subclass, frozen, name = "component", module = "hal")]
pub(crate) struct PyComponent {
    pub(crate) shared: Arc<Shared>,
}

impl Drop for PyComponent {
    fn drop(&mut self) {
        self.shared.close_implicitly();
    }
}

/// Which items a lookup accepts.
#[derive(Clone, Copy, PartialEq)]
enum Want {
    Any,
    Pin,
    Param,
}

impl PyComponent {
    fn lookup(&self, name: &str, want: Want) -> PyResult<PyItem> {
        let item = self.shared.item(name)?;
        let ok = match want {
            Want::Any => true,
            Want::Pin => item.is_pin(),
            Want::Param => !item.is_pin(),
        };
        if !ok {
            let kind = if want == Want::Pin { "Pin" } else { "Param" };
            return Err(PyAttributeError::new_err(format!(
                "{kind} '{name}' does not exist"
            )));
        }
        Ok(PyItem {
            comp: self.shared.clone(),
            item,
            name: name.to_string(),
        })
    }

    /// Creates a pin or param named `prefix.name`.
    fn new_item(
        &self,
        name: &str,
        kind: &str,
        make: impl FnOnce(&Component, &str) -> PyResult<Item>,
    ) -> PyResult<PyItem> {
        let mut guard = self.shared.live.write().unwrap_or_else(|e| e.into_inner());
        let live = guard.as_mut().ok_or_else(closed)?;
        if live.items.contains_key(name) {
            return Err(PyValueError::new_err(format!(
                "Duplicate {kind} name '{name}'"
            )));
        }
        let full = format!("{}.{}", live.prefix, name);
        let item = Arc::new(make(&live.comp, &full)?);
        live.items.insert(name.to_string(), item.clone());
        Ok(PyItem {
            comp: self.shared.clone(),
            item,
            name: name.to_string(),
        })
    }
}

#[pymethods]
impl PyComponent {
    /// Allocates the object; `__init__` makes the HAL component, so that
    /// subclasses may take arguments of their own and call
    /// `hal.component.__init__(self, name)`, as with LinuxCNC's class.
    #[new]
    #[pyo3(signature = (*_args, **_kwargs))]
    fn new(_args: &Bound<'_, PyAny>, _kwargs: Option<&Bound<'_, PyAny>>) -> Self {
        PyComponent {
            shared: Arc::new(Shared {
                made: OnceLock::new(),
                live: RwLock::new(None),
            }),
        }
    }

    /// Makes the HAL component `name`; pins and params get `prefix`
    /// (default: the name) before their own names.
    #[pyo3(signature = (name, prefix = None, /))]
    fn __init__(&self, name: &str, prefix: Option<&str>) -> PyResult<()> {
        let mut live = self.shared.live.write().unwrap_or_else(|e| e.into_inner());
        if self.shared.made.get().is_some() {
            return Err(error::new_err("the HAL component is already made"));
        }
        let inst = shared().map_err(hal_error)?;
        let comp = inst
            .new_component(name, ComponentKind::User)
            .map_err(hal_error)?;
        let _ = self.shared.made.set((name.to_string(), comp.id()));
        *live = Some(Live {
            comp,
            pid: std::process::id(),
            prefix: prefix.unwrap_or(name).to_string(),
            items: BTreeMap::new(),
        });
        let mut all = ALL.lock().unwrap_or_else(|e| e.into_inner());
        all.retain(|w| w.strong_count() > 0);
        all.push(Arc::downgrade(&self.shared));
        Ok(())
    }

    /// Creates a pin: `newpin(name, type, dir)`.
    fn newpin(&self, name: &str, hal_type: i32, dir: i32) -> PyResult<PyItem> {
        self.new_item(name, "pin", |comp, full| {
            // Python components make no port pins, as in LinuxCNC 2.9.
            let t = codes::hal_type(hal_type as i64)
                .filter(|t| *t != hal_core::HalType::Port)
                .ok_or_else(|| error::new_err(format!("Invalid pin type {hal_type}")))?;
            let d = codes::pin_dir(dir as i64)
                .ok_or_else(|| error::new_err(format!("Invalid pin direction {dir}")))?;
            let handle = match d {
                hal_core::PinDir::In => Handle::In(comp.pin_raw(full, t).map_err(hal_error)?),
                hal_core::PinDir::Out => Handle::Out(comp.pin_raw(full, t).map_err(hal_error)?),
                hal_core::PinDir::Io => Handle::Io(comp.pin_raw(full, t).map_err(hal_error)?),
            };
            Ok(Item {
                handle,
                hal_type: t,
                dir,
            })
        })
    }

    /// Creates a param: `newparam(name, type, dir)`.
    fn newparam(&self, name: &str, hal_type: i32, dir: i32) -> PyResult<PyItem> {
        self.new_item(name, "parameter", |comp, full| {
            let t = codes::hal_type(hal_type as i64)
                .filter(|t| *t != hal_core::HalType::Port)
                .ok_or_else(|| error::new_err(format!("Invalid param type {hal_type}")))?;
            let d = codes::param_dir(dir as i64)
                .ok_or_else(|| error::new_err(format!("Invalid param direction {dir}")))?;
            Ok(Item {
                handle: Handle::Param(comp.param_raw(full, t, d).map_err(hal_error)?),
                hal_type: t,
                dir,
            })
        })
    }

    /// The pin or param object named `name`.
    fn getitem(&self, name: &str) -> PyResult<PyItem> {
        self.lookup(name, Want::Any)
    }

    /// The pin object named `name`.
    fn getpin(&self, name: &str) -> PyResult<PyItem> {
        self.lookup(name, Want::Pin)
    }

    /// The param object named `name`.
    fn getparam(&self, name: &str) -> PyResult<PyItem> {
        self.lookup(name, Want::Param)
    }

    /// Every pin and param with its value, by name.
    fn getpins<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let values: Vec<(String, Value)> = self.shared.with_live(|l| {
            Ok(l.items
                .iter()
                .map(|(name, item)| (name.clone(), item.value()))
                .collect())
        })?;
        let d = PyDict::new(py);
        for (name, v) in values {
            d.set_item(name, to_python(py, v)?)?;
        }
        Ok(d)
    }

    /// Marks the component ready (`loadusr -W` waits for this).
    fn ready(&self) -> PyResult<()> {
        self.shared.with_live(|l| l.comp.ready().map_err(hal_error))
    }

    /// Marks the component not ready again.
    fn unready(&self) -> PyResult<()> {
        self.shared
            .with_live(|l| l.comp.unready().map_err(hal_error))
    }

    /// Removes the component and everything it owns from the HAL.
    fn exit(&self) {
        self.shared.close();
    }

    /// The prefix of pins and params created from now on.
    fn getprefix(&self) -> PyResult<String> {
        self.shared.with_live(|l| Ok(l.prefix.clone()))
    }

    /// Sets the prefix of pins and params created from now on.
    fn setprefix(&self, prefix: &str) -> PyResult<()> {
        let mut guard = self.shared.live.write().unwrap_or_else(|e| e.into_inner());
        guard.as_mut().ok_or_else(closed)?.prefix = prefix.to_string();
        Ok(())
    }

    /// Attribute lookup: every attribute of a closed component raises
    /// RuntimeError, as in LinuxCNC.
    fn __getattribute__<'py>(
        slf: &Bound<'py, Self>,
        name: &Bound<'py, PyString>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if !slf.get().shared.is_live() {
            return Err(closed());
        }
        let object = slf.py().get_type::<PyAny>();
        object.getattr("__getattribute__")?.call1((slf, name))
    }

    /// `c.name` for a pin or param, once normal lookup found nothing.
    fn __getattr__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        let item = self.shared.item(name)?;
        to_python(py, self.shared.read_value(&item)?)
    }

    /// `c.name = value` writes a pin or param; there are no other
    /// attributes to set.
    fn __setattr__(&self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let item = self.shared.item(name)?;
        self.shared.write_object(&item, value)
    }

    /// `c["name"]` reads as `c.name` does (so methods are found first).
    fn __getitem__<'py>(
        slf: &Bound<'py, Self>,
        name: &Bound<'py, PyString>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.as_any().getattr(name)
    }

    /// `c["name"] = value` writes a pin or param.
    fn __setitem__(&self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.__setattr__(name, value)
    }

    fn __len__(&self) -> PyResult<usize> {
        self.shared.with_live(|l| Ok(l.items.len()))
    }

    fn __repr__(&self) -> String {
        let live = self.shared.read();
        let (name, id) = self.shared.made.get().cloned().unwrap_or_default();
        let (id, n) = live.as_ref().map_or((0, 0), |l| (id, l.items.len()));
        format!("<hal component {name}({id}) with {n} pins and params>")
    }
}

/// A pin or param of a component made by this process.
#[pyclass(frozen, name = "item", module = "hal")]
pub(crate) struct PyItem {
    comp: Arc<Shared>,
    item: Arc<Item>,
    name: String,
}

#[pymethods]
impl PyItem {
    #[new]
    #[pyo3(signature = (*_args, **_kwargs))]
    fn new(_args: &Bound<'_, PyAny>, _kwargs: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        Err(PyRuntimeError::new_err("Cannot be constructed directly"))
    }

    /// Writes the value.
    fn set(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.comp.write_object(&self.item, value)
    }

    /// The current value.
    fn get(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_python(py, self.comp.read_value(&self.item)?)
    }

    /// The type number (`hal.HAL_FLOAT`, ...).
    fn get_type(&self) -> i32 {
        codes::type_code(self.item.hal_type)
    }

    /// The direction number (`hal.HAL_OUT`, `hal.HAL_RW`, ...).
    fn get_dir(&self) -> i32 {
        self.item.dir
    }

    /// The name given at creation, without the prefix.
    fn get_name(&self) -> String {
        self.name.clone()
    }

    /// True for a pin, false for a param.
    fn is_pin(&self) -> bool {
        self.item.is_pin()
    }

    fn __repr__(&self) -> String {
        format!(
            "<hal {} \"{}\" {}-{}>",
            if self.item.is_pin() { "pin" } else { "param" },
            self.name,
            codes::type_label(self.item.hal_type),
            codes::dir_label(self.item.dir)
        )
    }
}
