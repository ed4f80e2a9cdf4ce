//! Setting values and connecting pins: `setp`, `net` and the checks that
//! make a failing `net` change nothing.

use hal_core::{HalError, PinDir};

use super::{CmdResult, Session};
use crate::error::LangError;
use crate::values::parse_value;

impl Session<'_> {
    /// `setp NAME VALUE` (and `NAME = VALUE`).
    pub(super) fn setp(&mut self, name: &str, value: &str) -> CmdResult {
        // A param wins over a pin of the same name.
        let (_, t, is_param) =
            crate::format::lookup(&self.inst, name)?.ok_or_else(|| LangError::NoPinOrParam {
                name: name.to_string(),
            })?;
        let what = if is_param { "parameter" } else { "pin" };
        let v = parse_value(t, value).map_err(|source| LangError::BadValue {
            what,
            name: name.to_string(),
            source,
        })?;
        let r = if is_param {
            self.inst.set_param(name, v)
        } else {
            self.inst.set_pin(name, v)
        };
        r.map_err(|e| match e {
            HalError::ParamReadOnly { .. }
            | HalError::PinIsOutput { .. }
            | HalError::PinConnected { .. } => LangError::NotWritable {
                what,
                name: name.to_string(),
            },
            HalError::Locked { .. } => LangError::halcmd(format!("{what} '{name}': {e}")),
            other => other.into(),
        })
    }

    /// `net SIGNAL PIN...` (arrows already removed): the user-facing
    /// checks, then [`Self::connect`].
    pub(super) fn net(&mut self, signal: &str, pins: &[&str]) -> CmdResult {
        if pins.is_empty() {
            return Err(LangError::halcmd(
                "'net' requires at least one pin, none given",
            ));
        }
        if self.inst.pin(signal)?.is_some() {
            return Err(LangError::halcmd(format!(
                "Signal name '{signal}' must not be the same as a pin.  Did you omit the signal name?"
            )));
        }
        self.connect(signal, pins)
    }

    /// Links `pins` to `signal`, creating it with the first pin's type.
    /// Everything is checked before anything changes.
    pub(super) fn connect(&mut self, signal: &str, pins: &[&str]) -> CmdResult {
        // Check everything first, so that a failing net changes nothing.
        let existing = self.inst.signal(signal)?;
        let mut sig_type = existing.as_ref().map(|s| s.hal_type);
        let mut writer: Option<String> = existing.as_ref().and_then(|s| {
            s.pins
                .iter()
                .find(|(_, d)| *d == PinDir::Out)
                .map(|(n, _)| n.clone())
        });
        let mut bidir: Option<String> = existing.as_ref().and_then(|s| {
            s.pins
                .iter()
                .find(|(_, d)| *d == PinDir::Io)
                .map(|(n, _)| n.clone())
        });
        for p in pins {
            let info = self
                .inst
                .pin(p)?
                .ok_or_else(|| LangError::halcmd(format!("Pin '{p}' does not exist")))?;
            if let Some(s) = &info.signal {
                if s != signal {
                    return Err(LangError::halcmd(format!(
                        "Pin '{p}' was already linked to signal '{s}'"
                    )));
                }
                continue;
            }
            match sig_type {
                Some(t) if t != info.hal_type => {
                    return Err(LangError::halcmd(format!(
                        "Signal '{signal}' of type '{t}' cannot add pin '{p}' of type '{}'",
                        info.hal_type
                    )))
                }
                _ => sig_type = Some(info.hal_type),
            }
            match info.dir {
                PinDir::Out => {
                    if let Some(w) = &writer {
                        return Err(LangError::halcmd(format!(
                            "Signal '{signal}' can not add OUT pin '{p}', it already has OUT pin '{w}'"
                        )));
                    }
                    if let Some(b) = &bidir {
                        return Err(LangError::halcmd(format!(
                            "Signal '{signal}' can not add OUT pin '{p}', it already has I/O pin '{b}'"
                        )));
                    }
                    writer = Some(p.to_string());
                }
                PinDir::Io => {
                    if let Some(w) = &writer {
                        return Err(LangError::halcmd(format!(
                            "Signal '{signal}' can not add I/O pin '{p}', it already has OUT pin '{w}'"
                        )));
                    }
                    bidir.get_or_insert_with(|| p.to_string());
                }
                PinDir::In => {}
            }
        }
        if existing.is_none() {
            let t = sig_type.ok_or_else(|| {
                LangError::halcmd(format!(
                    "net: signal '{signal}' does not exist and no pin gives its type"
                ))
            })?;
            self.inst.newsig(signal, t)?;
        }
        for p in pins {
            self.inst.link(p, signal)?;
        }
        Ok(())
    }
}
