//! halmeter: watch one pin, signal or parameter live in a terminal.

use std::io::Write;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{instance_from_env, Instance};
use hal_tools::meter::{line, read, Kind};
use hal_tools::ToolsError;

const USAGE: &str = "usage: halmeter [-n COUNT] [-p PERIOD_MS] [pin|sig|param] NAME";

fn main() {
    std::process::exit(match run() {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("halmeter: {e}");
            1
        }
    });
}

fn run() -> Result<(), ToolsError> {
    let mut count: Option<u64> = None;
    let mut period = Duration::from_millis(100);
    let mut words = Vec::new();
    let mut args = hal_tools::stdio::args_or_exit("halmeter", 1).into_iter();
    while let Some(a) = args.next() {
        match a.as_str() {
            "-n" => {
                count = Some(
                    args.next()
                        .and_then(|v| v.parse().ok())
                        .ok_or_else(|| ToolsError::usage("-n needs a count"))?,
                )
            }
            "-p" => {
                let ms: u64 = args
                    .next()
                    .and_then(|v| v.parse().ok())
                    .ok_or_else(|| ToolsError::usage("-p needs milliseconds"))?;
                period = Duration::from_millis(ms.max(1));
            }
            "-h" | "--help" => {
                hal_tools::outln!("{USAGE}");
                return Ok(());
            }
            _ => words.push(a),
        }
    }
    let (kind, name) = match words.as_slice() {
        [name] => (None, name.clone()),
        [k, name] => (
            Some(
                Kind::from_word(k)
                    .ok_or_else(|| ToolsError::usage(format!("unknown kind '{k}'; {USAGE}")))?,
            ),
            name.clone(),
        ),
        _ => return Err(ToolsError::usage(USAGE)),
    };
    let exit = ExitSignals::install()?;
    let inst = Instance::attach(&instance_from_env())?;
    let mut out = hal_tools::stdio::stdout();
    let tty = out.is_terminal();
    let mut shown = 0u64;
    while count.is_none_or(|n| shown < n) && !exit.requested() {
        let (_, v) = read(&inst, kind, &name)?;
        let text = line(&name, v);
        if tty {
            write!(out, "\r\x1b[K{text}")?;
        } else {
            writeln!(out, "{text}")?;
        }
        out.flush()?;
        shown += 1;
        if count.is_none_or(|n| shown < n) {
            std::thread::sleep(period);
        }
    }
    if tty {
        writeln!(out)?;
    }
    Ok(())
}
