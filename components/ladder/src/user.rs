//! `loadusr classicladder [--nogui] FILE.clp`: reads a ClassicLadder
//! project bundle, checks it against the sizes `classicladder_rt` was
//! loaded with, and hands the program to the module, which runs it from
//! its next refresh. Without `--nogui` LinuxCNC's would open its editor
//! window; there is no window here, so the program is loaded all the
//! same (if a file is given) and the loader says so. It exits once the
//! program is handed over, so `loadusr -w` goes on: after waiting up to
//! [`ACK_WAIT`] for the module's answer (a refusal is an error; no answer
//! is not, as the refresh funct may not run yet).

use std::path::Path;

use hal_core::Instance;

use crate::error::LadderError;
use crate::{clp, compile, handoff};

/// The help text.
pub const USAGE: &str = "\
Usage: classicladder [--nogui] [--instance NAME] FILE.clp

Loads a ClassicLadder project (a .clp bundle) into classicladder_rt,
which must be loaded first (loadrt classicladder_rt). The project is
checked against the module's sizes (numRungs, numBits, ...); an error
names the line of the file. Without --nogui LinuxCNC's opens its editor;
no window is opened here, the program is loaded all the same.

Options:
  --nogui            do not open the editor (the usual headless use)
  --modmaster        accepted; Modbus I/O is not run here
  --modbus_port=N    accepted; Modbus I/O is not run here
  --config=FILE      accepted; the project's own sizes are not used
  -h, --help         this help
  --version          the version";

/// The largest project file read.
pub const MAX_FILE: u64 = 16 << 20;

/// The loader's command line.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Args {
    /// `--nogui`.
    pub nogui: bool,
    /// The project file.
    pub file: Option<String>,
    /// Options accepted and ignored, for a note.
    pub ignored: Vec<String>,
}

/// Parses the words after the common options.
pub fn parse_args(args: &[String]) -> Result<Args, LadderError> {
    let mut a = Args::default();
    for w in args {
        match w.as_str() {
            "--nogui" => a.nogui = true,
            "--modmaster" | "--debug" => a.ignored.push(w.clone()),
            s if s.starts_with("--modbus_port=") || s.starts_with("--config=") => {
                a.ignored.push(w.clone())
            }
            s if s.starts_with('-') && s.len() > 1 => {
                return Err(LadderError::Usage(format!(
                    "unknown option '{s}' (see classicladder --help)"
                )))
            }
            _ if a.file.is_some() => {
                return Err(LadderError::Usage(format!(
                    "one project file only ('{w}' is a second)"
                )))
            }
            _ => a.file = Some(w.clone()),
        }
    }
    Ok(a)
}

/// The program's `main` after the common options: the exit status.
pub fn main(args: &[String]) -> i32 {
    match run(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("classicladder: {e}");
            1
        }
    }
}

fn run(args: &[String]) -> Result<(), LadderError> {
    let a = parse_args(args)?;
    for w in &a.ignored {
        eprintln!("classicladder: note: {w} is accepted but Modbus and --config are not run here");
    }
    if !a.nogui {
        eprintln!("classicladder: no editor window here (headless); the ladder runs without it");
    }
    let Some(file) = a.file else {
        if a.nogui {
            return Err(LadderError::Usage(
                "no project file given (classicladder --nogui FILE.clp)".into(),
            ));
        }
        return Ok(());
    };
    let instance = hal_core::instance_from_env();
    let inst = Instance::attach(&instance)?;
    let notes = load(&inst, &instance, Path::new(&file))?;
    for n in notes {
        eprintln!("classicladder: note: {file}: {n}");
    }
    Ok(())
}

/// Reads, checks and hands over the project at `path`; returns the notes
/// on parts not run.
pub fn load(inst: &Instance, instance: &str, path: &Path) -> Result<Vec<String>, LadderError> {
    let text = hal_core::files::read_user_text(path, MAX_FILE, "ClassicLadder project")?;
    let region = inst
        .region(handoff::REGION)
        .map_err(|source| LadderError::NotLoaded {
            instance: instance.to_string(),
            source,
        })?;
    let words = region.words();
    let sizes = handoff::read_sizes(words).ok_or_else(|| LadderError::Handoff {
        region: handoff::REGION.into(),
        what: "not written by classicladder_rt (wrong magic word or sizes)".into(),
    })?;
    let project = clp::parse(&text).map_err(|e| in_file(path, e))?;
    let compiled = compile::compile(&project, &sizes).map_err(|e| in_file(path, e))?;
    let body = handoff::encode(&compiled.program, &sizes);
    let seq = handoff::publish(words, &body).ok_or_else(|| LadderError::Handoff {
        region: handoff::REGION.into(),
        what: "smaller than the program".into(),
    })?;
    answer(words, seq, ACK_WAIT)?;
    Ok(compiled.notes)
}

/// How long the loader waits for the module to take the program.
pub const ACK_WAIT: std::time::Duration = std::time::Duration::from_millis(500);

/// Waits up to `wait` for the module's answer to program `seq`: a
/// refusal is an error; no answer is not (the refresh funct may not be
/// in a running thread yet: HAL files often `addf` it, or `start`, after
/// the `loadusr`), and the module takes the program when it first runs.
fn answer(
    words: &[std::sync::atomic::AtomicU64],
    seq: u64,
    wait: std::time::Duration,
) -> Result<(), LadderError> {
    let end = std::time::Instant::now() + wait;
    loop {
        match handoff::status(words) {
            handoff::Status::Running(s) if s == seq => return Ok(()),
            handoff::Status::Refused(s, part, item) if s == seq => {
                return Err(LadderError::Refused {
                    what: format!("{part} {item} did not pass its checks"),
                })
            }
            _ if std::time::Instant::now() >= end => return Ok(()),
            _ => std::thread::sleep(std::time::Duration::from_millis(2)),
        }
    }
}

/// Puts the file's name before a parse error.
fn in_file(path: &Path, e: LadderError) -> LadderError {
    match e {
        LadderError::Structure { what } => LadderError::Structure {
            what: format!("{}: {what}", path.display()),
        },
        LadderError::Syntax { line, part, what } => LadderError::Syntax {
            line,
            part: format!("{}: {part}", path.display()),
            what,
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn command_line() {
        let a = parse_args(&w(&["--nogui", "x.clp"])).unwrap();
        assert!(a.nogui);
        assert_eq!(a.file.as_deref(), Some("x.clp"));
        assert!(parse_args(&w(&["--bogus"]))
            .unwrap_err()
            .to_string()
            .contains("--bogus"));
        assert!(parse_args(&w(&["a.clp", "b.clp"])).is_err());
        assert_eq!(parse_args(&w(&["--modmaster"])).unwrap().ignored.len(), 1);
    }

    #[test]
    fn the_modules_answer() {
        use std::sync::atomic::AtomicU64;
        use std::time::Duration;
        let s = crate::model::Sizes::default();
        let words: Vec<AtomicU64> = (0..handoff::region_words(&s))
            .map(|_| AtomicU64::new(0))
            .collect();
        handoff::init(&words, &s);
        assert!(answer(&words, 2, Duration::ZERO).is_ok(), "no answer yet");
        handoff::set_status(&words, handoff::Status::Running(2));
        assert!(answer(&words, 2, Duration::from_secs(5)).is_ok());
        handoff::set_status(&words, handoff::Status::Refused(4, handoff::Part::Rung, 7));
        let e = answer(&words, 4, Duration::from_secs(5))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "classicladder_rt refused the program: rung 7 did not pass its checks"
        );
    }
}
