//! Interactive halcmd on a terminal: line editing, history kept per user
//! across sessions, and Tab completion of commands and of the live
//! instance's names (rustyline). Only on a terminal: commands from a pipe
//! or a file are read plainly ([`crate::cli::interactive`]).
//!
//! The history is `$XDG_CONFIG_HOME/hal/halcmd_history` (else
//! `~/.config/hal/halcmd_history`), the last 1000 commands.

mod complete;

use std::path::PathBuf;

use hal_core::Instance;
use hal_lang::Session;
use rustyline::completion::Completer;
use rustyline::error::ReadlineError;
use rustyline::{CompletionType, Config, Context, Editor};

pub use complete::{complete, Kind, Names};

/// The prompt, LinuxCNC's.
const PROMPT: &str = "halcmd: ";
/// How many commands the history keeps.
const HISTORY_SIZE: usize = 1000;

/// The names of a live instance, and the modules the host can load.
struct LiveNames {
    inst: Instance,
    modules: hal_core::Registry,
}

impl Names for LiveNames {
    fn names(&self, kind: Kind) -> Vec<String> {
        let inst = &self.inst;
        // A name list that cannot be read completes nothing.
        let names = match kind {
            Kind::Pin => inst.pins().map(|v| v.into_iter().map(|p| p.name).collect()),
            Kind::Param => inst
                .params()
                .map(|v| v.into_iter().map(|p| p.name).collect()),
            Kind::Signal => inst
                .signals()
                .map(|v| v.into_iter().map(|s| s.name).collect()),
            Kind::Funct => inst
                .functs()
                .map(|v| v.into_iter().map(|f| f.name).collect()),
            Kind::Thread => inst
                .threads()
                .map(|v| v.into_iter().map(|t| t.name).collect()),
            Kind::Comp => inst
                .components()
                .map(|v| v.into_iter().map(|c| c.name).collect()),
            Kind::Module => Ok(self
                .modules
                .names()
                .into_iter()
                .map(str::to_string)
                .collect()),
        };
        names.unwrap_or_default()
    }

    fn module_params(&self, module: &str) -> Vec<String> {
        self.modules
            .find(module)
            .map(|m| m.params.iter().map(|p| p.name.to_string()).collect())
            .unwrap_or_default()
    }
}

/// rustyline's helper: completion only (no hints, colours or
/// validation).
struct Helper {
    names: LiveNames,
    commands: Vec<String>,
}

impl Completer for Helper {
    type Candidate = String;

    fn complete(
        &self,
        line: &str,
        pos: usize,
        _ctx: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<String>)> {
        let before = line.get(..pos).unwrap_or(line);
        Ok(complete(before, &self.commands, &self.names))
    }
}

impl rustyline::hint::Hinter for Helper {
    type Hint = String;
}
impl rustyline::highlight::Highlighter for Helper {}
impl rustyline::validate::Validator for Helper {}
impl rustyline::Helper for Helper {}

/// Where the history is kept, if a home can be found.
pub fn history_path() -> Option<PathBuf> {
    let config = std::env::var_os("XDG_CONFIG_HOME")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
    Some(config.join("hal").join("halcmd_history"))
}

/// Reads and runs commands with line editing until end of input (Ctrl-D),
/// Ctrl-C or `quit`. Returns false if a command failed.
pub fn run(session: &mut Session<'_>) -> bool {
    let config = Config::builder()
        .max_history_size(HISTORY_SIZE)
        .and_then(|b| b.history_ignore_dups(true))
        .map(|b| {
            b.history_ignore_space(true)
                .completion_type(CompletionType::List)
                .auto_add_history(false)
                .build()
        });
    let editor = config
        .map_err(|e| e.to_string())
        .and_then(|c| Editor::with_config(c).map_err(|e| e.to_string()));
    let mut editor: Editor<Helper, rustyline::history::DefaultHistory> = match editor {
        Ok(e) => e,
        Err(e) => {
            eprintln!("halcmd: no line editing ({e}); reading plain lines");
            return crate::cli::plain_lines(session, true);
        }
    };
    editor.set_helper(Some(Helper {
        names: LiveNames {
            inst: session.instance().clone(),
            modules: hal_host::registry(),
        },
        commands: hal_lang::session::command_names(),
    }));
    let history = history_path();
    if let Some(path) = &history {
        // No history yet is the usual first start.
        let _ = editor.load_history(path);
    }
    let mut ok = true;
    let mut pending = String::new();
    loop {
        let line = match editor.readline(PROMPT) {
            Ok(line) => line,
            Err(ReadlineError::Eof | ReadlineError::Interrupted) => break,
            Err(e) => {
                eprintln!("halcmd: reading the terminal: {e}");
                ok = false;
                break;
            }
        };
        if !line.trim().is_empty() {
            let _ = editor.add_history_entry(line.as_str());
        }
        pending.push_str(&line);
        pending.push('\n');
        if line.ends_with('\\') {
            continue;
        }
        let text = std::mem::take(&mut pending);
        ok &= session.run_text(None, &text);
        if session.is_done() {
            break;
        }
    }
    if let Some(path) = &history {
        save_history(&mut editor, path);
    }
    ok
}

/// Writes the history, making its directory (private to the user) first.
fn save_history(editor: &mut Editor<Helper, rustyline::history::DefaultHistory>, path: &PathBuf) {
    if let Some(dir) = path.parent() {
        use std::os::unix::fs::DirBuilderExt;
        let _ = std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(dir);
    }
    if let Err(e) = editor.save_history(path) {
        eprintln!("halcmd: history not saved to {}: {e}", path.display());
    }
}
