//! Python objects to HAL values and back, with the rules and exceptions
//! of LinuxCNC's module: an integer out of a pin's range is an
//! OverflowError, a non-number for a float a TypeError, text that is no
//! number a ValueError.

use hal_core::{HalType, Value};
use pyo3::exceptions::{PyOverflowError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyString};
use pyo3::IntoPyObjectExt;

/// `int(obj)` unless `obj` already is an int.
fn as_int<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    if obj.is_instance_of::<PyInt>() {
        Ok(obj.clone())
    } else {
        obj.py().get_type::<PyInt>().call1((obj,))
    }
}

/// The value as a C `long long`; Python raises OverflowError past it.
fn long_long(obj: &Bound<'_, PyAny>) -> PyResult<i64> {
    as_int(obj)?.extract::<i64>()
}

fn out_of_range(v: i64) -> PyErr {
    PyOverflowError::new_err(format!("Value {v} out of range"))
}

/// Text LinuxCNC accepts for a bit, case-insensitively.
fn bit_word(text: &str) -> Option<bool> {
    match text.to_ascii_lowercase().as_str() {
        "1" | "true" | "on" | "yes" => Some(true),
        "0" | "false" | "off" | "no" => Some(false),
        _ => None,
    }
}

fn to_bit(obj: &Bound<'_, PyAny>) -> PyResult<bool> {
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(b.is_true());
    }
    if let Ok(s) = obj.cast::<PyString>() {
        if let Some(b) = bit_word(&s.to_cow()?) {
            return Ok(b);
        }
    }
    if let Ok(f) = obj.cast::<PyFloat>() {
        return Ok(f.value() != 0.0);
    }
    as_int(obj)?.is_truthy()
}

fn to_float(obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    if obj.is_instance_of::<PyFloat>() || obj.is_instance_of::<PyInt>() {
        // An int too large for a double raises OverflowError here.
        return obj.extract::<f64>();
    }
    obj.py()
        .get_type::<PyFloat>()
        .call1((obj,))
        .and_then(|f| f.extract::<f64>())
        .map_err(|_| {
            let name = obj
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default();
            PyTypeError::new_err(format!("Number expected, not {name}"))
        })
}

/// Converts `obj` to a value of type `t`.
pub(crate) fn to_value(obj: &Bound<'_, PyAny>, t: HalType) -> PyResult<Value> {
    Ok(match t {
        HalType::Bit => Value::Bit(to_bit(obj)?),
        HalType::Float => Value::Float(to_float(obj)?),
        HalType::S32 => {
            let v = long_long(obj)?;
            Value::S32(i32::try_from(v).map_err(|_| out_of_range(v))?)
        }
        HalType::U32 => {
            let v = long_long(obj)?;
            Value::U32(u32::try_from(v).map_err(|_| out_of_range(v))?)
        }
        HalType::S64 => Value::S64(long_long(obj)?),
        // Python raises OverflowError for a negative or too large int.
        HalType::U64 => Value::U64(as_int(obj)?.extract::<u64>()?),
        // A port's value is its buffer's size.
        HalType::Port => {
            let v = long_long(obj)?;
            Value::Port(u32::try_from(v).map_err(|_| out_of_range(v))?)
        }
    })
}

/// A value as the Python object LinuxCNC returns: bool, float or int.
pub(crate) fn to_python(py: Python<'_>, v: Value) -> PyResult<Py<PyAny>> {
    match v {
        Value::Bit(b) => b.into_py_any(py),
        Value::Float(f) => f.into_py_any(py),
        Value::S32(x) => x.into_py_any(py),
        Value::U32(x) | Value::Port(x) => x.into_py_any(py),
        Value::S64(x) => x.into_py_any(py),
        Value::U64(x) => x.into_py_any(py),
    }
}

#[cfg(test)]
mod tests {
    use super::bit_word;

    #[test]
    fn bit_words_are_case_insensitive() {
        for (w, b) in [("TRUE", true), ("Yes", true), ("on", true), ("1", true)] {
            assert_eq!(bit_word(w), Some(b));
        }
        for (w, b) in [
            ("False", false),
            ("NO", false),
            ("off", false),
            ("0", false),
        ] {
            assert_eq!(bit_word(w), Some(b));
        }
        assert_eq!(bit_word("2"), None);
        assert_eq!(bit_word("maybe"), None);
    }
}
