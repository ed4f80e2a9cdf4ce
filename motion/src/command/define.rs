//! [`commands!`]: generates everything about a command from its one
//! description in [`super::table`]:
//!
//! ```text
//! /// docs
//! Variant {
//!     /// docs
//!     [slot] field: Type,     // the record's slot word (joint, axis or id)
//!     /// docs
//!     field: Type,            // float argument words, in this order
//! } = opcode,
//!     cli basic "name" { field: kind(...), ... },   // one or more CLI forms
//!     cli planner "name" { ... };
//! ```
//!
//! From it come the enum itself, [`Command::opcode`](super::Command::opcode),
//! the record's slot and argument words and back (`write_args`,
//! `from_args`; [`super::wire`]), [`Command::name`](super::Command::name),
//! [`parse`](super::parse), [`cli_group`](super::cli_group),
//! [`CLI_NAMES`](super::CLI_NAMES) and
//! [`Command::to_cli`](super::Command::to_cli). A CLI form lists every
//! field once, in the order its words are read (which decides which error
//! a line with several mistakes gets), each with its argument kind
//! ([`super::cli::args`]).

/// Writes one field into an [`ArgWriter`](super::wire::ArgWriter).
macro_rules! put_field {
    ($w:ident, $v:ident, slot) => {
        $w.slot = Some($v)
    };
    ($w:ident, $v:ident) => {
        $w.arg(&$v)
    };
}

/// Reads one field from an [`ArgReader`](super::wire::ArgReader).
macro_rules! get_field {
    ($r:ident, slot) => {
        $r.slot()
    };
    ($r:ident) => {
        $r.arg()?
    };
}

/// The [`CliGroup`](super::cli::CliGroup) of a form's group word.
macro_rules! cli_group {
    (basic) => {
        $crate::command::cli::CliGroup::Basic
    };
    (planner) => {
        $crate::command::cli::CliGroup::Planner
    };
}

/// See the module documentation.
macro_rules! commands {
    (
        $(#[doc = $doc:literal])*
        #[derive($($derive:ident),*)]
        pub enum $name:ident {
            $(
                $(#[doc = $vdoc:literal])*
                $variant:ident $({
                    $(
                        $(#[doc = $fdoc:literal])*
                        $([$role:ident])? $field:ident : $ty:ty
                    ),+ $(,)?
                })? = $opcode:literal
                $(, cli $group:ident $cli:literal { $($cfield:ident : $kind:expr),* $(,)? })+;
            )+
        }
    ) => {
        $(#[doc = $doc])*
        #[derive($($derive),*)]
        pub enum $name {
            $(
                $(#[doc = $vdoc])*
                $variant $({
                    $(
                        $(#[doc = $fdoc])*
                        $field: $ty,
                    )+
                })?,
            )+
        }

        impl $name {
            /// The opcode on the wire.
            pub fn opcode(&self) -> u64 {
                match self {
                    $($name::$variant { .. } => $opcode,)+
                }
            }

            /// The command's name on the command line (`motion-cmd`), as
            /// logs print it.
            pub fn name(&self) -> &'static str {
                use $crate::command::cli::args::CliArg;
                use $crate::command::cli::{all, first_fitting};
                match *self {
                    $($name::$variant { $($($field,)+)? } => first_fitting(&[$((
                        $cli,
                        all(&[$(CliArg::fits(&$kind, &$cfield)),*]),
                    )),+]),)+
                }
            }

            /// The command as command-line words, name first, as
            /// [`parse`] reads them; `None` if no form can say it (a
            /// rapid with a velocity, option bits no INI key sets). A NaN
            /// is written `NaN`, without its sign.
            pub fn to_cli(self) -> Option<Vec<String>> {
                use $crate::command::cli::args::CliArg;
                use $crate::command::cli::write_form;
                match self {
                    $($name::$variant { $($($field,)+)? } => {
                        $(
                            let line = write_form($cli, |_w| {
                                $(CliArg::write(&$kind, &$cfield, _w)?;)*
                                Some(())
                            });
                            if line.is_some() {
                                return line;
                            }
                        )+
                        None
                    })+
                }
            }

            /// Writes the slot and argument words (`args` zeroed); returns
            /// (opcode, slot, argument words used).
            pub(crate) fn write_args(&self, args: &mut [f64]) -> (u64, Option<i32>, usize) {
                let mut w = $crate::command::wire::ArgWriter::new(args);
                let opcode = match *self {
                    $($name::$variant { $($($field,)+)? } => {
                        $($($crate::command::define::put_field!(w, $field $(, $role)?);)+)?
                        $opcode
                    })+
                };
                (opcode, w.slot, w.len)
            }

            /// The command of `opcode` from its slot and argument words,
            /// with whether it has a slot and how many argument words it
            /// reads; `Ok(None)` for an unknown opcode, `Err(i)` if
            /// argument word `i` does not hold the whole number it should.
            #[allow(clippy::type_complexity)]
            pub(crate) fn from_args(
                opcode: u64,
                slot: i32,
                args: &[f64],
            ) -> Result<Option<($name, bool, usize)>, usize> {
                let mut r = $crate::command::wire::ArgReader::new(slot, args);
                let command = match opcode {
                    $($opcode => $name::$variant {
                        $($($field: $crate::command::define::get_field!(r $(, $role)?),)+)?
                    },)+
                    _ => return Ok(None),
                };
                Ok(Some((command, r.takes_slot, r.len)))
            }
        }

        /// Parses command line `name` `words`; `goal` is where the last
        /// queued move ends (the axes a move's end point leaves out keep
        /// it).
        pub fn parse(
            name: &str,
            words: &[String],
            goal: $crate::kins::Pose,
        ) -> Result<$name, $crate::command::cli::CliError> {
            use $crate::command::cli::args::CliArg;
            use $crate::command::cli::{read_form, Arity, CliError};
            match name {
                $($(
                    $cli => read_form(
                        name,
                        words,
                        goal,
                        ($crate::command::define::cli_group!($group), Arity::NONE $(.and(CliArg::arity(&$kind)))*),
                        |_r| Ok($name::$variant { $($cfield: CliArg::read(&$kind, _r)?),* }),
                    ),
                )+)+
                _ => Err(CliError::UnknownCommand { name: name.to_string() }),
            }
        }

        /// Which group command line `name` belongs to; `None` if no
        /// command has that name.
        pub fn cli_group(name: &str) -> Option<$crate::command::cli::CliGroup> {
            match name {
                $($($cli => Some($crate::command::define::cli_group!($group)),)+)+
                _ => None,
            }
        }

        /// Every command-line name, in table order.
        pub const CLI_NAMES: &[&str] = &[$($($cli,)+)+];
    };
}

pub(crate) use {cli_group, commands, get_field, put_field};
