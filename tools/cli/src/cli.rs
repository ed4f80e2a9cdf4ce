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
    /// `--version`: print the version and exit.
    pub version: bool,
    /// `--instance NAME`: the instance to use instead of `$HAL_INSTANCE`.
    pub instance: Option<String>,
}

/// What `halcmd -h` prints: the options, then every command.
pub fn halcmd_usage() -> String {
    let mut text = String::from(
        "Usage:\n  halcmd [options] [COMMAND [ARGS...]]\n\n\
         Manipulates a running HAL instance with LinuxCNC's HAL commands: one\n\
         command given on the command line, the commands of a file (-f), one per\n\
         line, or an interactive session. On a terminal the session has line\n\
         editing, Tab completion of commands and of the instance's names, and a\n\
         history kept in $XDG_CONFIG_HOME/hal/halcmd_history (else\n\
         ~/.config/hal/halcmd_history). 'realtime start' or halrun starts the\n\
         instance first.\n\n\
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
         \x20 --instance NAME\n\
         \x20               the HAL instance (default $HAL_INSTANCE, else 'default')\n\
         \x20 -h, --help [COMMAND]\n\
         \x20               print this help, or the help of COMMAND, and exit\n\
         \x20 --version     print the version and exit\n\n\
         Commands:\n",
    );
    text.push_str(&hal_lang::format::help(None).unwrap_or_default());
    text
}

/// Parses halcmd's options (LinuxCNC's `-f`, `-i`, `-k`, `-q`, `-Q`,
/// `-s`, `-v`, `-V`, `-e`, `-R`, `-h`, and the suite's `--help`,
/// `--version` and `--instance`); the first non-option word starts the
/// command.
pub fn parse_halcmd_args(args: &[String]) -> Result<HalcmdArgs, ToolsError> {
    let args = &unbundle(args);
    let mut out = HalcmdArgs::default();
    let mut i = 0;
    while i < args.len() {
        let a = args[i].as_str();
        // halcmd's -i is LinuxCNC's INI file: the instance is long only.
        if let Some(found) = hal_core::userspace::instance_option(args, i, false) {
            let (name, words) = found.map_err(|e| ToolsError::Usage(e.to_string()))?;
            out.instance = Some(name);
            i += words;
            continue;
        }
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
            "-h" | "--help" => {
                out.help = Some(args.get(i + 1).cloned());
                return Ok(out);
            }
            "--version" => {
                out.version = true;
                return Ok(out);
            }
            _ if a.starts_with('-') && out.command.is_empty() => {
                return Err(ToolsError::usage(format!(
                    "unknown option '{a}' (see halcmd --help)"
                )))
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

/// halcmd's single-letter options, as LinuxCNC's getopt takes them.
const LETTERS: &str = "efikqQsvVRh";

/// Splits bundled letters as getopt does (`-kf` is `-k -f`; `-iFILE` is
/// `-i FILE`), in the options before the command: the command's own words
/// (`loadusr -Wn name prog`) are left alone.
fn unbundle(args: &[String]) -> Vec<String> {
    let mut out: Vec<String> = Vec::with_capacity(args.len());
    let mut i = 0;
    while let Some(a) = args.get(i) {
        i += 1;
        if a.starts_with("--") {
            // The suite's long options; --instance takes the next word.
            out.push(a.clone());
            if a == "--instance" {
                out.extend(args.get(i).cloned());
                i += 1;
            }
            continue;
        }
        let letters = a.strip_prefix('-').filter(|b| !b.is_empty());
        let Some(letters) = letters else {
            // The first word that is no option starts the command.
            out.extend(args[i - 1..].iter().cloned());
            break;
        };
        let mut value_follows = false;
        for (at, c) in letters.char_indices() {
            if !LETTERS.contains(c) {
                // Not halcmd's: left whole for the error to name.
                out.push(if at == 0 {
                    a.clone()
                } else {
                    format!("-{}", &letters[at..])
                });
                break;
            }
            out.push(format!("-{c}"));
            let tail = &letters[at + 1..];
            if c == 'i' {
                if tail.is_empty() {
                    value_follows = true;
                } else {
                    out.push(tail.to_string());
                }
                break;
            }
            // -f takes the next word as its file unless it is an option.
            value_follows = c == 'f' && tail.is_empty();
        }
        let next_is_value = args
            .get(i)
            .is_some_and(|n| out.last().is_some_and(|l| l == "-i") || !n.starts_with('-'));
        if value_follows && next_is_value {
            out.push(args[i].clone());
            i += 1;
        }
    }
    out
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
        // `-f` without a file reads standard input: a terminal gets the
        // prompt and line editing (halrun -I runs `halcmd -kf` in
        // LinuxCNC), anything else plain lines.
        Some(None) => interactive(&mut session, true),
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

/// Reads commands from stdin until EOF or `quit`. On a terminal (and with
/// `prompt`) with line editing, history and completion
/// ([`crate::line_editor`]); otherwise plain lines, as from a file.
/// Returns false if a command failed.
pub fn interactive(session: &mut Session<'_>, prompt: bool) -> bool {
    if prompt && std::io::stdin().is_terminal() && std::io::stdout().is_terminal() {
        crate::line_editor::run(session)
    } else {
        plain_lines(session, prompt)
    }
}

/// Reads commands from stdin as plain lines until EOF or `quit`, with a
/// prompt when `prompt` and stdin is a terminal. Returns false if a
/// command failed.
pub fn plain_lines(session: &mut Session<'_>, prompt: bool) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn bundled_letters_split_as_getopt_splits_them() {
        for (given, want) in [
            (&["-kf"][..], &["-k", "-f"][..]),
            (&["-kf", "x.hal"], &["-k", "-f", "x.hal"]),
            (&["-ix.ini", "-kf"], &["-i", "x.ini", "-k", "-f"]),
            (&["-ki", "x.ini", "show"], &["-k", "-i", "x.ini", "show"]),
            (&["-i", "-odd.ini", "-s"], &["-i", "-odd.ini", "-s"]),
            (&["-f", "-k"], &["-f", "-k"]),
            (&["-kx"], &["-k", "-x"]),
            (&["--help", "-kf"], &["--help", "-k", "-f"]),
            (
                &["--instance", "-x", "-kf"],
                &["--instance", "-x", "-k", "-f"],
            ),
            (
                &["loadusr", "-Wn", "a", "prog"],
                &["loadusr", "-Wn", "a", "prog"],
            ),
            (&["-s", "show", "-kf"], &["-s", "show", "-kf"]),
        ] {
            assert_eq!(unbundle(&words(given)), words(want), "{given:?}");
        }
    }

    #[test]
    fn bundles_parse_like_the_letters_alone() {
        let a = parse_halcmd_args(&words(&["-kf"])).unwrap();
        assert!(a.opts.keep_going);
        assert_eq!(a.file, Some(None));
        let a = parse_halcmd_args(&words(&["-sv", "show", "pin"])).unwrap();
        assert!(a.opts.script && a.opts.verbose);
        assert_eq!(a.command, ["show", "pin"]);
        let e = parse_halcmd_args(&words(&["-kz"])).unwrap_err().to_string();
        assert!(e.contains("'-z'"), "{e}");
    }
}
