//! A move's end point as `AXIS=VALUE` words (`X=10 Y=-2.5`): the axes
//! left out stay at the goal (where the last queued move ends), so
//! nothing moves by accident. An arc also takes `center=CX,CY,CZ`,
//! `normal=NX,NY,NZ` (default 0,0,1) and `turns=N` (default 0) among
//! them.

use super::args::CliArg;
use super::{Arity, CliError, Reader, Writer};
use crate::kins::{Pose, AXIS_LETTERS};

/// The keys an arc takes besides the axes.
const ARC_KEYS: &[&str] = &["center", "normal", "turns"];

/// An arc's own words, once read.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ArcWords {
    center: Option<[f64; 3]>,
    normal: Option<[f64; 3]>,
    turns: Option<i32>,
}

/// The end point from word `from` on; for an arc, the arc's own words too.
pub(crate) struct EndWords {
    pub(super) from: usize,
    pub(super) arc: bool,
}

impl CliArg for EndWords {
    type Value = Pose;
    fn arity(&self) -> Arity {
        Arity::AtLeast(self.from)
    }

    /// Reads the axis words, in order; then the arc's own words, in order
    /// (so errors come in that order).
    fn read(&self, r: &mut Reader<'_>) -> Result<Pose, CliError> {
        let also: &'static [&'static str] = if self.arc { ARC_KEYS } else { &[] };
        let mut end = r.goal;
        let mut seen = [false; AXIS_LETTERS.len()];
        let mut extra = Vec::new();
        for word in r.words.get(self.from..).unwrap_or_default() {
            let (k, v) = word
                .split_once('=')
                .ok_or_else(|| CliError::NotAxisValue { word: word.clone() })?;
            let key = k.to_ascii_lowercase();
            if let Some(i) = axis_of_key(&key) {
                if seen[i] {
                    return Err(CliError::AxisTwice {
                        axis: AXIS_LETTERS[i].to_ascii_uppercase(),
                    });
                }
                seen[i] = true;
                end.0[i] = v.parse().map_err(|_| CliError::NotNumber {
                    what: k.to_string(),
                    text: v.to_string(),
                })?;
            } else if also.contains(&key.as_str()) {
                extra.push((key, v));
            } else {
                return Err(CliError::UnknownWord {
                    key: k.to_string(),
                    also,
                });
            }
        }
        for (key, v) in extra {
            match key.as_str() {
                "center" => r.arc.center = Some(triple(v, "center")?),
                "normal" => r.arc.normal = Some(triple(v, "normal")?),
                _ => {
                    r.arc.turns = Some(v.parse().map_err(|_| CliError::NotInteger {
                        what: "turns",
                        text: v.to_string(),
                    })?)
                }
            }
        }
        Ok(end)
    }

    /// Writes every axis, so the line does not depend on the goal.
    fn write(&self, v: &Pose, w: &mut Writer) -> Option<()> {
        for (letter, c) in AXIS_LETTERS.iter().zip(v.0) {
            w.push(format!("{}={c}", letter.to_ascii_uppercase()));
        }
        Some(())
    }
}

/// The axis of a one-letter key (lower case).
fn axis_of_key(key: &str) -> Option<usize> {
    let mut chars = key.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) => AXIS_LETTERS.iter().position(|&l| l == c),
        _ => None,
    }
}

/// Three numbers separated by commas (`1,2.5,0`).
fn triple(s: &str, what: &'static str) -> Result<[f64; 3], CliError> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(CliError::NotTriple {
            what,
            text: s.to_string(),
        });
    }
    let mut out = [0.0; 3];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p.trim().parse().map_err(|_| CliError::TripleItem {
            what,
            item: p.to_string(),
        })?;
    }
    Ok(out)
}

/// The three numbers of a triple word.
fn triple_text(v: &[f64; 3]) -> String {
    format!("{},{},{}", v[0], v[1], v[2])
}

/// Which of the arc's own words a field is.
#[derive(Clone, Copy)]
pub(crate) enum ArcWord {
    /// `center=`, required.
    Center,
    /// `normal=`, default 0,0,1.
    Normal,
}

/// The arc's `center=` word (read by [`super::args::arc_words`]).
pub(crate) const fn arc_center() -> ArcWord {
    ArcWord::Center
}

/// The arc's `normal=` word (read by [`super::args::arc_words`]).
pub(crate) const fn arc_normal() -> ArcWord {
    ArcWord::Normal
}

impl CliArg for ArcWord {
    type Value = [f64; 3];
    fn arity(&self) -> Arity {
        Arity::NONE
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<[f64; 3], CliError> {
        match self {
            ArcWord::Center => r.arc.center.ok_or(CliError::MissingCenter),
            ArcWord::Normal => Ok(r.arc.normal.unwrap_or([0.0, 0.0, 1.0])),
        }
    }
    fn write(&self, v: &[f64; 3], w: &mut Writer) -> Option<()> {
        let key = match self {
            ArcWord::Center => "center",
            ArcWord::Normal => "normal",
        };
        w.push(format!("{key}={}", triple_text(v)));
        Some(())
    }
}

/// The arc's `turns=` word, default 0 (read by [`super::args::arc_words`]).
pub(crate) struct ArcTurns;

/// The arc's `turns=` word.
pub(crate) const fn arc_turns() -> ArcTurns {
    ArcTurns
}

impl CliArg for ArcTurns {
    type Value = i32;
    fn arity(&self) -> Arity {
        Arity::NONE
    }
    fn read(&self, r: &mut Reader<'_>) -> Result<i32, CliError> {
        Ok(r.arc.turns.unwrap_or(0))
    }
    fn write(&self, v: &i32, w: &mut Writer) -> Option<()> {
        w.push(format!("turns={v}"));
        Some(())
    }
}
