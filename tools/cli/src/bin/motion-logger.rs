//! `motion-logger`: stands in for the motion controller and logs every
//! command task sends it, one line each (see `motion::logger`).

use std::fs::File;
use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, HalError, Instance, Io, Pin};
use hal_tools::ToolsError;
use motion::logger::{Logger, USAGE};

/// How long the loop sleeps between looks at the command ring.
const POLL: Duration = Duration::from_millis(2);

/// Where the lines go.
struct Log {
    path: Option<PathBuf>,
    file: Option<File>,
}

impl Log {
    fn write(&mut self, line: &str) -> Result<(), ToolsError> {
        let Some(path) = &self.path else {
            let mut out = std::io::stdout().lock();
            writeln!(out, "{line}")?;
            out.flush()?;
            return Ok(());
        };
        let file = match &mut self.file {
            Some(f) => f,
            None => self
                .file
                .insert(File::create(path).map_err(|source| ToolsError::File {
                    path: path.display().to_string(),
                    source,
                })?),
        };
        writeln!(file, "{line}")
            .and_then(|()| file.flush())
            .map_err(|source| ToolsError::File {
                path: path.display().to_string(),
                source,
            })
    }
}

fn serve(args: &[String]) -> Result<(), ToolsError> {
    let path = match args {
        [] => None,
        [one] if !one.starts_with('-') => Some(PathBuf::from(one)),
        _ => {
            return Err(ToolsError::usage(format!(
                "expected at most one LOGFILE, got '{}'",
                args.join(" ")
            )))
        }
    };
    let signals = ExitSignals::install()?;
    let inst = Instance::attach(&hal_core::instance_from_env())?;
    let comp = inst.new_component("motion-logger", ComponentKind::User)?;
    let reopen: Pin<bool, Io> = comp.pin("motion-logger.reopen-log")?;
    let mut logger = Logger::create(&inst, &comp).map_err(|e| match e {
        HalError::Duplicate { kind, name } => ToolsError::usage(format!(
            "motion's command channel ({kind} '{name}') exists already: motmod or another \
             motion-logger is loaded, and motion-logger takes its place, not its side"
        )),
        e => e.into(),
    })?;
    comp.ready()?;
    let mut log = Log { path, file: None };
    let mut failed = None;
    let mut last = Instant::now();
    let mut alive_asked = Instant::now();
    while !signals.requested() && failed.is_none() {
        if reopen.get() {
            log.file = None;
            reopen.set(false);
        }
        logger.serve(&mut |line| {
            if failed.is_none() {
                failed = log.write(line).err();
            }
        });
        let now = Instant::now();
        logger.tick(now.duration_since(last).as_secs_f64());
        last = now;
        if alive_asked.elapsed() > Duration::from_millis(500) {
            if !inst.host_alive() {
                break;
            }
            alive_asked = Instant::now();
        }
        std::thread::sleep(POLL);
    }
    failed.map_or(Ok(()), Err)
}

fn run(args: &[String]) -> i32 {
    match serve(args) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("motion-logger: {e}");
            if matches!(e, ToolsError::Usage(_)) {
                2
            } else {
                1
            }
        }
    }
}

fn main() {
    hal_tools::conventions::user_program_main("motion-logger", USAGE, run)
}
