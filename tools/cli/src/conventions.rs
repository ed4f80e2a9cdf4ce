//! The command-line conventions every program of the suite keeps, for the
//! programs that read their command line by hand (LinuxCNC's option
//! letters must keep their meaning, which clap cannot always express):
//! `-h`/`--help` prints the help on standard output, `--version` the
//! version, an option the program does not have is named in the error,
//! and the instance is `--instance NAME` (with `-i NAME` too where `-i`
//! is not LinuxCNC's INI file).

use crate::ToolsError;

/// A word of the command line that every program treats alike.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Common {
    /// `-h` or `--help`.
    Help,
    /// `--version`.
    Version,
    /// The instance option: the name, and how many words it took.
    Instance(String, usize),
}

/// What `args[i]` is under the conventions, if anything. `short_instance`
/// lets `-i NAME` name the instance.
pub fn common(
    args: &[String],
    i: usize,
    short_instance: bool,
) -> Result<Option<Common>, ToolsError> {
    if let Some(found) = hal_core::userspace::instance_option(args, i, short_instance) {
        let (name, words) = found.map_err(|e| ToolsError::Usage(e.to_string()))?;
        hal_core::userspace::select_instance(&name)
            .map_err(|e| ToolsError::usage(format!("--instance: {e}")))?;
        return Ok(Some(Common::Instance(name, words)));
    }
    Ok(match args.get(i).map(String::as_str) {
        Some("-h" | "--help") => Some(Common::Help),
        Some("--version") => Some(Common::Version),
        _ => None,
    })
}

/// The error for an option `tool` does not have.
pub fn unknown_option(tool: &str, word: &str) -> ToolsError {
    ToolsError::usage(format!("unknown option '{word}' (see {tool} --help)"))
}

/// Prints `tool`'s version line.
pub fn print_version(tool: &str) {
    crate::outln!("{}", hal_core::userspace::version_line(tool));
}

/// The `main` of a user program that lives in a library (halui,
/// z_level_compensation): `--help` prints `usage`, `--version` the version
/// line, `--instance NAME` selects the instance, and every other word goes
/// to `run`, whose status is the exit status.
pub fn user_program_main(tool: &str, usage: &str, run: fn(&[String]) -> i32) -> ! {
    let args = crate::stdio::args_or_exit(tool, 2);
    let mut rest = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, false) {
            Ok(Some(Common::Help)) => {
                crate::outln!("{usage}");
                std::process::exit(0);
            }
            Ok(Some(Common::Version)) => {
                print_version(tool);
                std::process::exit(0);
            }
            Ok(Some(Common::Instance(_, n))) => {
                i += n;
                continue;
            }
            Ok(None) => rest.push(args[i].clone()),
            Err(e) => {
                eprintln!("{tool}: {e}");
                std::process::exit(2);
            }
        }
        i += 1;
    }
    std::process::exit(run(&rest))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn common_words_are_recognised() {
        let a = words(&["-h", "--help", "--version", "-i", "x", "name"]);
        assert_eq!(common(&a, 0, true).unwrap(), Some(Common::Help));
        assert_eq!(common(&a, 1, true).unwrap(), Some(Common::Help));
        assert_eq!(common(&a, 2, true).unwrap(), Some(Common::Version));
        assert_eq!(common(&a, 3, false).unwrap(), None);
        assert_eq!(common(&a, 5, true).unwrap(), None);
        let bad = words(&["--instance", "../x"]);
        assert!(common(&bad, 0, true).is_err());
        let e = unknown_option("halmeter", "--foo").to_string();
        assert_eq!(e, "unknown option '--foo' (see halmeter --help)");
    }
}
