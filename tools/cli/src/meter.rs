//! What halmeter watches and how it reads it.

use hal_core::{Instance, Value};
use hal_lang::format::get_value;

use crate::ToolsError;

/// The kind of object a meter watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `pin NAME`.
    Pin,
    /// `sig NAME`.
    Signal,
    /// `param NAME`.
    Param,
}

impl Kind {
    /// The word halmeter takes for it.
    pub fn from_word(w: &str) -> Option<Kind> {
        match w {
            "pin" => Some(Kind::Pin),
            "sig" | "signal" => Some(Kind::Signal),
            "param" | "parameter" => Some(Kind::Param),
            _ => None,
        }
    }
}

/// Reads the current value of `name` (of `kind`, or the first kind that
/// has it: pin, signal, param).
pub fn read(inst: &Instance, kind: Option<Kind>, name: &str) -> Result<(Kind, Value), ToolsError> {
    let kinds = match kind {
        Some(k) => vec![k],
        None => vec![Kind::Pin, Kind::Signal, Kind::Param],
    };
    for k in kinds {
        let v = match k {
            Kind::Pin => inst.pin_value(name),
            Kind::Signal => inst.signal_value(name),
            Kind::Param => inst.param_value(name),
        };
        if let Ok(v) = v {
            return Ok((k, v));
        }
    }
    Err(ToolsError::NotFound {
        name: name.to_string(),
    })
}

/// One meter reading as printed.
pub fn line(name: &str, v: Value) -> String {
    format!("{name} = {}", get_value(v))
}
