//! halmeter: watch one pin, signal or parameter live in a terminal.

use std::io::Write;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{instance_from_env, Instance};
use hal_tools::conventions::{common, print_version, unknown_option, Common};
use hal_tools::meter::{line, read, Kind};
use hal_tools::ToolsError;

fn main() {
    std::process::exit(match run() {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("halmeter: {e}");
            1
        }
    });
}

/// The usage line of the help.
fn synopsis() -> &'static str {
    hal_tools::usage::HALMETER
        .lines()
        .next()
        .unwrap_or_default()
}

fn run() -> Result<(), ToolsError> {
    let mut count: Option<u64> = None;
    let mut period = Duration::from_millis(100);
    let mut words = Vec::new();
    let args = hal_tools::stdio::args_or_exit("halmeter", 1);
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, true)? {
            Some(Common::Help) => {
                hal_tools::outln!("{}", hal_tools::usage::HALMETER);
                return Ok(());
            }
            Some(Common::Version) => {
                print_version("halmeter");
                return Ok(());
            }
            Some(Common::Instance(_, n)) => {
                i += n;
                continue;
            }
            None => {}
        }
        let value = args.get(i + 1).and_then(|v| v.parse::<u64>().ok());
        match args[i].as_str() {
            "-n" => {
                count = Some(value.ok_or_else(|| ToolsError::usage("-n needs a count"))?);
                i += 1;
            }
            "-p" => {
                let ms = value.ok_or_else(|| ToolsError::usage("-p needs milliseconds"))?;
                period = Duration::from_millis(ms.max(1));
                i += 1;
            }
            o if o.starts_with('-') && o.len() > 1 => return Err(unknown_option("halmeter", o)),
            _ => words.push(args[i].clone()),
        }
        i += 1;
    }
    let (kind, name) =
        match words.as_slice() {
            [name] => (None, name.clone()),
            [k, name] => (
                Some(Kind::from_word(k).ok_or_else(|| {
                    ToolsError::usage(format!("unknown kind '{k}'; {}", synopsis()))
                })?),
                name.clone(),
            ),
            _ => return Err(ToolsError::usage(synopsis())),
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
