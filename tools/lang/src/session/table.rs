//! halcmd's command table: every command with the arguments it takes,
//! as in LinuxCNC's, and the check of a command's argument count.

use crate::error::{LangError, Result};

/// Words halcmd treats as arrows and drops (`=>`, `<=`, `<=>`, `==>`, ...):
/// any word starting with `<` or `=`, as LinuxCNC's parser.
pub(super) fn is_arrow(s: &str) -> bool {
    s.starts_with('<') || s.starts_with('=')
}

/// More arguments may follow the counted ones (LinuxCNC's `A_PLUS`).
const PLUS: u8 = 1;
/// Fewer arguments may be given (`A_OPTIONAL`).
const OPTIONAL: u8 = 2;
/// Arrows are dropped before counting (`A_REMOVE_ARROWS`).
const ARROWS: u8 = 4;

/// A command and the arguments it takes, as in LinuxCNC's command table.
pub(super) struct CommandSpec {
    pub(super) name: &'static str,
    /// How many arguments it takes.
    args: usize,
    /// [`PLUS`], [`OPTIONAL`], [`ARROWS`].
    flags: u8,
}

const fn cmd(name: &'static str, args: usize, flags: u8) -> CommandSpec {
    CommandSpec { name, args, flags }
}

/// Every command, with its argument count. `print` takes any words (they
/// are printed joined); `initf` takes no position, which this host does
/// not support.
pub(super) const COMMANDS: &[CommandSpec] = &[
    cmd("addf", 2, PLUS),
    cmd("alias", 3, 0),
    cmd("debug", 1, OPTIONAL),
    cmd("delf", 2, OPTIONAL),
    cmd("delsig", 1, 0),
    cmd("echo", 0, 0),
    cmd("exit", 0, OPTIONAL | PLUS),
    cmd("getp", 1, 0),
    cmd("gets", 1, 0),
    cmd("help", 1, OPTIONAL),
    cmd("initf", 2, 0),
    cmd("linkpp", 2, ARROWS),
    cmd("linkps", 2, ARROWS),
    cmd("linksp", 2, ARROWS),
    cmd("list", 1, PLUS),
    cmd("loadrt", 1, PLUS),
    cmd("loadusr", 0, PLUS),
    cmd("lock", 1, OPTIONAL),
    cmd("net", 1, PLUS | ARROWS),
    cmd("newsig", 2, 0),
    cmd("print", 0, PLUS),
    cmd("quit", 0, OPTIONAL | PLUS),
    cmd("ptype", 1, 0),
    cmd("save", 2, OPTIONAL),
    cmd("setexact_for_test_suite_only", 0, 0),
    cmd("setp", 2, 0),
    cmd("sets", 2, 0),
    cmd("setthread", 2, PLUS),
    cmd("show", 1, OPTIONAL | PLUS),
    cmd("source", 1, 0),
    cmd("start", 0, 0),
    cmd("status", 1, OPTIONAL),
    cmd("stop", 0, 0),
    cmd("stype", 1, 0),
    cmd("unalias", 2, 0),
    cmd("unecho", 0, 0),
    cmd("unlinkp", 1, 0),
    cmd("unload", 1, 0),
    cmd("unloadrt", 1, 0),
    cmd("unloadusr", 1, 0),
    cmd("unlock", 1, OPTIONAL),
    cmd("waitusr", 1, 0),
];

/// Every command's name, as `hal --commands` lists them.
pub fn command_names() -> Vec<String> {
    COMMANDS.iter().map(|c| c.name.to_string()).collect()
}

impl CommandSpec {
    /// The arguments of one use of the command (arrows dropped if it takes
    /// none), or LinuxCNC's message when there are too few or too many.
    pub(super) fn arguments<'w>(&self, words: &[&'w str]) -> Result<Vec<&'w str>> {
        let args: Vec<&str> = words
            .iter()
            .copied()
            .filter(|w| self.flags & ARROWS == 0 || !is_arrow(w))
            .collect();
        let given = args.len();
        let (plus, optional) = (self.flags & PLUS != 0, self.flags & OPTIONAL != 0);
        let bound = if given < self.args && !optional {
            if plus {
                "at least "
            } else {
                ""
            }
        } else if given > self.args && !plus {
            if optional {
                "at most "
            } else {
                ""
            }
        } else {
            return Ok(args);
        };
        Err(LangError::halcmd(format!(
            "{} requires {bound}{} arguments, {given} given",
            self.name, self.args
        )))
    }
}
