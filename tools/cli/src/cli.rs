//! Command-line handling shared by `halcmd` and `halrun`.

use std::io::{IsTerminal, Write};

use hal_core::Instance;
use hal_lang::ini::Ini;
use hal_lang::lexer::{hal_text, read_text};
use hal_lang::{Options, Session};

use crate::ToolsError;

/// What halcmd's command line asked for.
#[derive(Debug, Default)]
pub struct HalcmdArgs {
    /// `-k`, `-q`/`-Q`, `-v`, `-s` and `-i`, as the session runs with them.
    pub opts: Options,
    /// `-f [FILE]`: `Some(None)` reads stdin.
    pub file: Option<Option<String>>,
    /// A single command given on the command line.
    pub command: Vec<String>,
    /// `-e`: echo commands.
    pub echo: bool,
    /// `-h [COMMAND]`: print the usage (or COMMAND's help) and exit.
    pub help: Option<Option<String>>,
}

/// What `halcmd -h` prints: the options, then every command.
pub fn halcmd_usage() -> String {
    let mut text = String::from(
        "Usage:\n  halcmd [options] [COMMAND [ARGS...]]\n\n\
         Options:\n\
         \x20 -e            echo each command before it runs\n\
         \x20 -f [FILE]     read commands from FILE, one per line (standard input\n\
         \x20               without FILE) instead of the command line\n\
         \x20 -i INIFILE    replace [SECTION]KEY in commands by values from INIFILE\n\
         \x20 -k            keep going after a command fails (the default is to stop)\n\
         \x20 -q            print errors only (the default)\n\
         \x20 -Q            print nothing\n\
         \x20 -R            release the HAL lock after a crash (accepted: the lock\n\
         \x20               recovers by itself here)\n\
         \x20 -s            script-friendly output: no headers, one line per item\n\
         \x20 -v, -V        verbose: report the result of every command\n\
         \x20 -h [COMMAND]  print this help, or the help of COMMAND, and exit\n\n\
         Commands:\n",
    );
    text.push_str(&hal_lang::format::help(None).unwrap_or_default());
    text
}

/// Parses halcmd's options (`-f`, `-i`, `-k`, `-q`, `-Q`, `-s`, `-v`,
/// `-V`, `-e`, `-R`); the first non-option word starts the command.
pub fn parse_halcmd_args(args: &[String]) -> Result<HalcmdArgs, ToolsError> {
    let mut out = HalcmdArgs::default();
    let mut i = 0;
    while i < args.len() {
        let a = args[i].as_str();
        match a {
            "-f" => {
                let file = args.get(i + 1).filter(|n| !n.starts_with('-')).cloned();
                if file.is_some() {
                    i += 1;
                }
                out.file = Some(file);
            }
            "-i" => {
                let path = args
                    .get(i + 1)
                    .ok_or_else(|| ToolsError::usage("-i needs an INI file"))?;
                let ini = Ini::load(std::path::Path::new(path))?;
                out.opts.ini = Some(ini);
                i += 1;
            }
            "-k" => out.opts.keep_going = true,
            "-q" => out.opts.silent = false,
            "-Q" => out.opts.silent = true,
            "-s" => out.opts.script = true,
            "-v" | "-V" => out.opts.verbose = true,
            "-e" => out.echo = true,
            "-R" => {}
            "-h" => {
                out.help = Some(args.get(i + 1).cloned());
                return Ok(out);
            }
            _ if a.starts_with('-') && out.command.is_empty() => {
                return Err(ToolsError::usage(format!("unknown option '{a}'")))
            }
            _ => {
                out.command = args[i..].to_vec();
                break;
            }
        }
        i += 1;
    }
    Ok(out)
}

/// Runs halcmd as its command line asks, on an attached instance. Returns
/// the exit status.
pub fn run_halcmd(inst: Instance, args: HalcmdArgs, interactive_after: bool) -> i32 {
    let mut stdout = crate::stdio::stdout();
    let mut stderr = std::io::stderr();
    let mut session = Session::new(inst, args.opts, &mut stdout, &mut stderr);
    if args.echo {
        session.run_words(&["echo".to_string()]);
    }
    let mut ok = match &args.file {
        Some(Some(path)) => match read_text(path) {
            Ok(text) => session.run_text(Some(path), &text),
            Err(e) => {
                eprintln!("halcmd: cannot read {path}: {e}");
                return 1;
            }
        },
        Some(None) => interactive(&mut session, false),
        None if !args.command.is_empty() => session.run_words(&args.command),
        None => interactive(&mut session, true),
    };
    if interactive_after {
        // As halrun -I: the interactive session follows the file even if
        // the file ended with `quit`.
        session.resume();
        ok &= interactive(&mut session, true);
    }
    if ok {
        0
    } else {
        1
    }
}

/// The longest command read from standard input, continuation lines
/// included.
const LINE_LIMIT: usize = 1 << 20;

/// Reads commands from stdin until EOF or `quit`, with a prompt when
/// `prompt` and stdin is a terminal. Returns false if a command failed.
pub fn interactive(session: &mut Session<'_>, prompt: bool) -> bool {
    let stdin = std::io::stdin();
    let prompt = prompt && stdin.is_terminal();
    let mut ok = true;
    let mut pending = String::new();
    loop {
        if prompt {
            crate::out!("halcmd: ");
            let _ = std::io::stdout().flush();
        }
        let mut line = Vec::new();
        match hal_core::files::read_line_within(&mut stdin.lock(), &mut line, LINE_LIMIT) {
            Ok(0) => break,
            Ok(_) => {}
            Err(e) => {
                eprintln!("halcmd: reading standard input: {e}");
                ok = false;
                break;
            }
        }
        pending.push_str(&hal_text(&line));
        if pending.len() > LINE_LIMIT {
            eprintln!(
                "halcmd: reading standard input: a command continued past the limit of 1 MiB"
            );
            ok = false;
            break;
        }
        if pending.trim_end_matches('\n').ends_with('\\') {
            continue;
        }
        let text = std::mem::take(&mut pending);
        if !session.run_text(None, &text) {
            ok = false;
            if !session.opts.keep_going && !prompt {
                break;
            }
        }
        if session.is_done() {
            break;
        }
    }
    ok
}
