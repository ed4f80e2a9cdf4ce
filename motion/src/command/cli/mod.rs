//! Commands as command-line words (`motion-cmd jog-cont 0 -5`): each
//! command's CLI forms are part of its one description in the command
//! table, as a name and, for every field, the argument kind it is read
//! from ([`args`]); the table generates [`parse`](super::parse),
//! [`Command::to_cli`](super::Command::to_cli) and
//! [`Command::name`](super::Command::name) from them.
//!
//! `motion-cmd` has two groups of commands ([`CliGroup`]) that differ in
//! small ways, kept so that its errors stay as they were: the basic ones
//! check their word count after reading the words (so a missing word is
//! named) and call a bad integer "not an integer"; the planner ones
//! (queueing and planner settings) are read against the goal, check the
//! count first and call every bad number "not a number".

use crate::kins::Pose;

pub(crate) mod args;
mod homing_keys;
mod words;

/// Which of `motion-cmd`'s two groups a command line belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CliGroup {
    /// Machine, joint, axis and configuration commands: the word count is
    /// checked after the words are read.
    Basic,
    /// Queueing and planner commands: read against the goal (where the
    /// last queued move ends), the word count checked first.
    Planner,
}

/// What is wrong with a command line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CliError {
    /// No command has this name.
    #[error("unknown command '{name}'")]
    UnknownCommand {
        /// The name given.
        name: String,
    },
    /// Too many or too few words.
    #[error("'{name}' takes {takes} argument(s), {given} given")]
    WrongCount {
        /// The command.
        name: String,
        /// How many it takes.
        takes: usize,
        /// How many were given.
        given: usize,
    },
    /// Too few words for a command that takes more after them.
    #[error("'{name}' takes at least {at_least} arguments")]
    TooFew {
        /// The command.
        name: String,
        /// How many it takes at least.
        at_least: usize,
    },
    /// A word is missing.
    #[error("missing {what}")]
    Missing {
        /// What the word is.
        what: &'static str,
    },
    /// A word that should be an integer.
    #[error("{what} must be an integer, not '{text}'")]
    NotInteger {
        /// What the word is.
        what: &'static str,
        /// The word.
        text: String,
    },
    /// A word that should be a number.
    #[error("{what} must be a number, not '{text}'")]
    NotNumber {
        /// What the word is (an `AXIS=` or `KEY=` word: the key as given).
        what: String,
        /// The word.
        text: String,
    },
    /// An axis word that is neither a letter nor a number.
    #[error("AXIS must be one of x y z a b c u v w or a number, not '{text}'")]
    NotAxis {
        /// The word.
        text: String,
    },
    /// An on/off word that is neither.
    #[error("{what} must be 0 or 1, not '{text}'")]
    NotFlag {
        /// What the word is.
        what: &'static str,
        /// The word.
        text: String,
    },
    /// An end-point word without `=`.
    #[error("'{word}' is not AXIS=VALUE")]
    NotAxisValue {
        /// The word.
        word: String,
    },
    /// An end-point axis given twice.
    #[error("axis {axis} given twice")]
    AxisTwice {
        /// The axis letter.
        axis: char,
    },
    /// A `KEY=VALUE` word of a move with a key it does not take.
    #[error("unknown word '{key}' (axes are X Y Z A B C U V W{})", also_text(.also))]
    UnknownWord {
        /// The key as given.
        key: String,
        /// The other keys the command takes.
        also: &'static [&'static str],
    },
    /// A value that should be three numbers separated by commas.
    #[error("{what} needs three numbers separated by commas, not '{text}'")]
    NotTriple {
        /// The key.
        what: &'static str,
        /// The value.
        text: String,
    },
    /// One of the three numbers is none.
    #[error("{what}: '{item}' is not a number")]
    TripleItem {
        /// The key.
        what: &'static str,
        /// The item.
        item: String,
    },
    /// An arc without its centre.
    #[error("'arc' needs center=X,Y,Z")]
    MissingCenter,
    /// A probe type that is not one of G38.2 to G38.5.
    #[error("probe TYPE must be G38.2, G38.3, G38.4 or G38.5, not '{text}'")]
    NotProbeType {
        /// The word, upper case.
        text: String,
    },
    /// A termination condition that is not one.
    #[error("term-cond needs stop, exact or blend, not {given:?}")]
    NotTermCond {
        /// The word, if any.
        given: Option<String>,
    },
    /// A homing word without `=`.
    #[error("'{word}' is not KEY=VALUE")]
    NotKeyValue {
        /// The word.
        word: String,
    },
    /// A homing key that does not exist.
    #[error("unknown homing key '{key}'")]
    UnknownHomingKey {
        /// The key, upper case.
        key: String,
    },
    /// A homing yes/no value that is neither.
    #[error("{key} must be YES or NO, not '{text}'")]
    NotYesNo {
        /// The key, upper case.
        key: String,
        /// The value.
        text: String,
    },
    /// A HOME_ABSOLUTE_ENCODER value other than 0, 1 or 2.
    #[error("HOME_ABSOLUTE_ENCODER must be 0, 1 or 2, not '{text}'")]
    NotAbsoluteEncoder {
        /// The value.
        text: String,
    },
}

/// The "; also ..." of [`CliError::UnknownWord`].
fn also_text(also: &[&str]) -> String {
    if also.is_empty() {
        String::new()
    } else {
        format!("; also {}", also.join(", "))
    }
}

/// How many words a command line takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Arity {
    /// Exactly this many.
    Exact(usize),
    /// At least this many.
    AtLeast(usize),
    /// The argument kinds check the count themselves.
    Own,
}

impl Arity {
    /// No words.
    pub const NONE: Arity = Arity::Exact(0);

    /// The arity of a form that has the words of both.
    pub fn and(self, other: Arity) -> Arity {
        use Arity::*;
        match (self, other) {
            (Own, _) | (_, Own) => Own,
            (Exact(a), Exact(b)) => Exact(a.max(b)),
            (AtLeast(a), Exact(b) | AtLeast(b)) | (Exact(a), AtLeast(b)) => AtLeast(a.max(b)),
        }
    }
}

/// The words of one command line as the argument kinds read them.
pub(crate) struct Reader<'a> {
    name: &'a str,
    words: &'a [String],
    group: CliGroup,
    /// Where the last queued move ends: an end point's axes left out.
    goal: Pose,
    /// An arc's `center=`, `normal=` and `turns=` words, once read.
    arc: words::ArcWords,
}

impl<'a> Reader<'a> {
    /// Word `i`.
    pub fn word(&self, i: usize) -> Option<&'a String> {
        self.words.get(i)
    }

    /// Word `i`, which is `what`.
    pub fn require(&self, i: usize, what: &'static str) -> Result<&'a String, CliError> {
        self.word(i).ok_or(CliError::Missing { what })
    }

    /// How many words there are.
    pub fn len(&self) -> usize {
        self.words.len()
    }

    /// The error for a word count other than `takes`.
    pub fn wrong_count(&self, takes: usize) -> CliError {
        CliError::WrongCount {
            name: self.name.to_string(),
            takes,
            given: self.words.len(),
        }
    }

    /// Whether the count fits `arity`.
    fn check(&self, arity: Arity) -> Result<(), CliError> {
        match arity {
            Arity::Exact(n) if self.len() != n => Err(self.wrong_count(n)),
            Arity::AtLeast(n) if self.len() < n => Err(CliError::TooFew {
                name: self.name.to_string(),
                at_least: n,
            }),
            _ => Ok(()),
        }
    }
}

/// Reads one command line with the form `build` of group `group`, whose
/// words are `arity`.
pub(crate) fn read_form<T>(
    name: &str,
    words: &[String],
    goal: Pose,
    (group, arity): (CliGroup, Arity),
    build: impl FnOnce(&mut Reader<'_>) -> Result<T, CliError>,
) -> Result<T, CliError> {
    let mut r = Reader {
        name,
        words,
        group,
        goal,
        arc: words::ArcWords::default(),
    };
    if group == CliGroup::Planner {
        r.check(arity)?;
    }
    let value = build(&mut r)?;
    if group == CliGroup::Basic {
        r.check(arity)?;
    }
    Ok(value)
}

/// A command line being written back from a command.
pub(crate) struct Writer {
    /// The words at fixed positions.
    at: Vec<Option<String>>,
    /// The `KEY=VALUE` words after them.
    rest: Vec<String>,
}

impl Writer {
    /// Word `i` is `text`.
    pub fn put(&mut self, i: usize, text: String) {
        if self.at.len() <= i {
            self.at.resize(i + 1, None);
        }
        self.at[i] = Some(text);
    }

    /// One more word after the fixed ones.
    pub fn push(&mut self, text: String) {
        self.rest.push(text);
    }

    /// Word `i`, if written.
    pub fn word(&self, i: usize) -> Option<&str> {
        self.at.get(i).and_then(|w| w.as_deref())
    }
}

/// The command line `name` and the words `write` writes; `None` if they
/// cannot say the command or leave a gap.
pub(crate) fn write_form(
    name: &str,
    write: impl FnOnce(&mut Writer) -> Option<()>,
) -> Option<Vec<String>> {
    let mut w = Writer {
        at: Vec::new(),
        rest: Vec::new(),
    };
    write(&mut w)?;
    let mut line = vec![name.to_string()];
    for word in w.at {
        line.push(word?);
    }
    line.extend(w.rest);
    Some(line)
}

/// The first name whose form fits, else the first name.
pub(crate) fn first_fitting(forms: &[(&'static str, bool)]) -> &'static str {
    forms
        .iter()
        .find(|f| f.1)
        .or(forms.first())
        .map_or("", |f| f.0)
}

/// Whether every field fits.
pub(crate) fn all(fits: &[bool]) -> bool {
    fits.iter().all(|&f| f)
}
