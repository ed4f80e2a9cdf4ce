//! The argument kinds of the CLI forms in the command table: what one
//! field is read from ([`CliArg::read`]), how it is written back
//! ([`CliArg::write`]) and which words it takes ([`CliArg::arity`]). The
//! table builds them with the functions of this module (`num(1, "VEL")`).

use super::words::{self, EndWords};
use super::{homing_keys, Arity, CliError, CliGroup, Reader, Writer};
use crate::command::{ProbeType, TermCond};
use crate::kins::{Pose, AXIS_LETTERS, NUM_AXES};
use crate::vocab::HomingConfig;

/// One field of a CLI form.
pub(crate) trait CliArg {
    /// The field's type.
    type Value;
    /// Which words it takes.
    fn arity(&self) -> Arity;
    /// Reads it.
    fn read(&self, r: &mut Reader<'_>) -> Result<Self::Value, CliError>;
    /// Writes it; `None` if the form cannot say this value.
    fn write(&self, v: &Self::Value, w: &mut Writer) -> Option<()>;
    /// Whether the form can say this value (only fixed values cannot).
    fn fits(&self, _v: &Self::Value) -> bool {
        true
    }
}

/// The arity of a word at position `at`.
fn at_position(at: usize) -> Arity {
    Arity::Exact(at + 1)
}

/// A float at word `at`.
pub(crate) struct Num {
    at: usize,
    what: &'static str,
}

/// A float at word `at`, called `what` in errors.
pub(crate) const fn num(at: usize, what: &'static str) -> Num {
    Num { at, what }
}

/// Reads float word `at`, called `what`.
pub(super) fn read_float(r: &Reader<'_>, at: usize, what: &'static str) -> Result<f64, CliError> {
    let s = r.require(at, what)?;
    s.parse().map_err(|_| CliError::NotNumber {
        what: what.to_string(),
        text: s.clone(),
    })
}

impl CliArg for Num {
    type Value = f64;
    fn arity(&self) -> Arity {
        at_position(self.at)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<f64, CliError> {
        read_float(r, self.at, self.what)
    }
    fn write(&self, v: &f64, w: &mut Writer) -> Option<()> {
        w.put(self.at, v.to_string());
        Some(())
    }
}

/// An integer at word `at`.
pub(crate) struct Int {
    at: usize,
    what: &'static str,
}

/// An integer at word `at`, called `what` in errors.
pub(crate) const fn int(at: usize, what: &'static str) -> Int {
    Int { at, what }
}

impl CliArg for Int {
    type Value = i32;
    fn arity(&self) -> Arity {
        at_position(self.at)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<i32, CliError> {
        let s = r.require(self.at, self.what)?;
        s.parse().map_err(|_| match r.group {
            CliGroup::Basic => CliError::NotInteger {
                what: self.what,
                text: s.clone(),
            },
            CliGroup::Planner => CliError::NotNumber {
                what: self.what.to_string(),
                text: s.clone(),
            },
        })
    }
    fn write(&self, v: &i32, w: &mut Writer) -> Option<()> {
        w.put(self.at, v.to_string());
        Some(())
    }
}

/// A world axis at word `at`: its letter (either case) or its number.
/// Numbers out of range pass, for the controller to refuse.
pub(crate) struct Axis {
    at: usize,
}

/// A world axis at word `at`.
pub(crate) const fn world_axis(at: usize) -> Axis {
    Axis { at }
}

/// An axis word: its letter (either case) or its number.
fn parse_axis(s: &str) -> Result<i32, CliError> {
    let mut chars = s.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        let c = c.to_ascii_lowercase();
        if let Some(i) = AXIS_LETTERS.iter().position(|&l| l == c) {
            // At most 8.
            return Ok(i as i32);
        }
    }
    s.parse().map_err(|_| CliError::NotAxis {
        text: s.to_string(),
    })
}

impl CliArg for Axis {
    type Value = i32;
    fn arity(&self) -> Arity {
        at_position(self.at)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<i32, CliError> {
        parse_axis(r.require(self.at, "AXIS")?)
    }
    fn write(&self, v: &i32, w: &mut Writer) -> Option<()> {
        let letter = usize::try_from(*v).ok().and_then(|a| AXIS_LETTERS.get(a));
        w.put(
            self.at,
            letter.map_or_else(|| v.to_string(), char::to_string),
        );
        Some(())
    }
}

/// An on/off word at word `at`: 1, on or yes; 0, off or no.
pub(crate) struct Flag {
    at: usize,
    what: &'static str,
}

/// An on/off word at word `at`, called `what` in errors.
pub(crate) const fn flag(at: usize, what: &'static str) -> Flag {
    Flag { at, what }
}

impl CliArg for Flag {
    type Value = bool;
    fn arity(&self) -> Arity {
        at_position(self.at)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<bool, CliError> {
        match r.require(self.at, self.what)?.as_str() {
            "1" | "on" | "yes" => Ok(true),
            "0" | "off" | "no" => Ok(false),
            o => Err(CliError::NotFlag {
                what: self.what,
                text: o.to_string(),
            }),
        }
    }
    fn write(&self, v: &bool, w: &mut Writer) -> Option<()> {
        w.put(self.at, if *v { "1" } else { "0" }.to_string());
        Some(())
    }
}

/// A value the form fixes: no word; the form says only this value.
pub(crate) struct Fixed<T>(T);

/// The field is `value` (another form says other values).
pub(crate) const fn fixed<T>(value: T) -> Fixed<T> {
    Fixed(value)
}

impl<T: Copy + PartialEq> CliArg for Fixed<T> {
    type Value = T;
    fn arity(&self) -> Arity {
        Arity::NONE
    }
    fn read(&self, _r: &mut Reader<'_>) -> Result<T, CliError> {
        Ok(self.0)
    }
    fn write(&self, v: &T, _w: &mut Writer) -> Option<()> {
        self.fits(v).then_some(())
    }
    fn fits(&self, v: &T) -> bool {
        *v == self.0
    }
}

/// A pose as nine floats from word `at` on.
pub(crate) struct Coordinates {
    at: usize,
    what: &'static str,
}

/// Nine floats from word `at` on, each called `what` in errors.
pub(crate) const fn coordinates(at: usize, what: &'static str) -> Coordinates {
    Coordinates { at, what }
}

impl CliArg for Coordinates {
    type Value = Pose;
    fn arity(&self) -> Arity {
        at_position(self.at + NUM_AXES - 1)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<Pose, CliError> {
        let mut pose = Pose::ZERO;
        for (i, v) in pose.0.iter_mut().enumerate() {
            *v = read_float(r, self.at + i, self.what)?;
        }
        Ok(pose)
    }
    fn write(&self, v: &Pose, w: &mut Writer) -> Option<()> {
        for (i, c) in v.0.iter().enumerate() {
            w.put(self.at + i, c.to_string());
        }
        Some(())
    }
}

/// A move's end point as `AXIS=VALUE` words from word `from` on (see
/// [`words`]).
pub(crate) const fn end_words(from: usize) -> EndWords {
    EndWords { from, arc: false }
}

/// An arc's end point as `AXIS=VALUE` words from word `from` on, among
/// which its `center=`, `normal=` and `turns=` words.
pub(crate) const fn arc_words(from: usize) -> EndWords {
    EndWords { from, arc: true }
}

pub(crate) use words::{arc_center, arc_normal, arc_turns};

/// A probe type at word `at`: G38.2 to G38.5.
pub(crate) struct Probe {
    at: usize,
}

/// A probe type at word `at`.
pub(crate) const fn probe_type(at: usize) -> Probe {
    Probe { at }
}

impl CliArg for Probe {
    type Value = ProbeType;
    fn arity(&self) -> Arity {
        at_position(self.at)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<ProbeType, CliError> {
        let text = r.require(self.at, "TYPE")?.to_ascii_uppercase();
        [
            ProbeType::G38_2,
            ProbeType::G38_3,
            ProbeType::G38_4,
            ProbeType::G38_5,
        ]
        .into_iter()
        .find(|p| p.gcode() == text)
        .ok_or(CliError::NotProbeType { text })
    }
    fn write(&self, v: &ProbeType, w: &mut Writer) -> Option<()> {
        w.put(self.at, v.gcode().to_string());
        Some(())
    }
}

/// A termination condition at word `at`: stop, exact or blend. The count
/// is checked by [`blend_tolerance`].
pub(crate) struct Cond {
    at: usize,
}

/// A termination condition at word `at`.
pub(crate) const fn term_cond(at: usize) -> Cond {
    Cond { at }
}

/// The words of the termination conditions.
const TERM_CONDS: [(&str, TermCond); 3] = [
    ("stop", TermCond::Stop),
    ("exact", TermCond::ExactPath),
    ("blend", TermCond::Blend),
];

impl CliArg for Cond {
    type Value = TermCond;
    fn arity(&self) -> Arity {
        Arity::Own
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<TermCond, CliError> {
        let given = r.word(self.at);
        TERM_CONDS
            .iter()
            .find(|(w, _)| given.is_some_and(|g| g == w))
            .map(|&(_, c)| c)
            .ok_or_else(|| CliError::NotTermCond {
                given: given.cloned(),
            })
    }
    fn write(&self, v: &TermCond, w: &mut Writer) -> Option<()> {
        let (word, _) = TERM_CONDS.iter().find(|(_, c)| c == v)?;
        w.put(self.at, word.to_string());
        Some(())
    }
}

/// The blend tolerance at word `at`, right after the condition word: only
/// after `blend`, and optional there (0); otherwise the condition is the
/// only word.
pub(crate) struct BlendTolerance {
    at: usize,
}

/// The blend tolerance at word `at`.
pub(crate) const fn blend_tolerance(at: usize) -> BlendTolerance {
    BlendTolerance { at }
}

impl BlendTolerance {
    /// Whether the condition word before is `blend`.
    fn after_blend(&self, word: Option<&str>) -> bool {
        word == Some("blend")
    }
}

impl CliArg for BlendTolerance {
    type Value = f64;
    fn arity(&self) -> Arity {
        Arity::Own
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<f64, CliError> {
        let cond = self.at.checked_sub(1).and_then(|i| r.word(i));
        if self.after_blend(cond.map(String::as_str)) && r.len() == self.at + 1 {
            read_float(r, self.at, "TOLERANCE")
        } else if r.len() != self.at {
            Err(r.wrong_count(self.at))
        } else {
            Ok(0.0)
        }
    }
    fn write(&self, v: &f64, w: &mut Writer) -> Option<()> {
        let cond = self.at.checked_sub(1).and_then(|i| w.word(i));
        if self.after_blend(cond) {
            w.put(self.at, v.to_string());
        } else if *v != 0.0 {
            return None;
        }
        Some(())
    }
}

/// A joint's homing configuration as `KEY=VALUE` words from word `from`
/// on, with the `[JOINT_n]` INI keys; keys left out take the INI
/// defaults.
pub(crate) struct HomingKeys {
    from: usize,
}

/// The homing configuration from word `from` on.
pub(crate) const fn homing_keys(from: usize) -> HomingKeys {
    HomingKeys { from }
}

impl CliArg for HomingKeys {
    type Value = HomingConfig;
    fn arity(&self) -> Arity {
        Arity::AtLeast(self.from)
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<HomingConfig, CliError> {
        homing_keys::read(r.words.get(self.from..).unwrap_or_default())
    }
    fn write(&self, v: &HomingConfig, w: &mut Writer) -> Option<()> {
        for word in homing_keys::write(v)? {
            w.push(word);
        }
        Some(())
    }
}
