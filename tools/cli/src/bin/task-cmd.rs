//! task-cmd: send a running machine (`linuxcnc MACHINE.ini`) the requests
//! LinuxCNC's task would get from a GUI: e-stop reset, machine on, tool
//! change, coolant, status. Exit status: 0 done, 1 refused, 2 usage or
//! connection error.

use std::process::ExitCode;
use std::time::Duration;

use hal_launcher::{request, TaskAnswer, TaskClientError};
use hal_tools::conventions::Common;

/// The longest wait `-t` accepts: a day.
const MAX_TIMEOUT_S: f64 = 86_400.0;

fn main() -> ExitCode {
    let args = hal_tools::stdio::args_or_exit("task-cmd", 2);
    let mut instance = hal_core::instance_from_env();
    let mut timeout = Duration::from_secs(30);
    let mut i = 0;
    while let Some(a) = args.get(i) {
        match hal_tools::conventions::common(&args, i, true) {
            Ok(Some(Common::Help)) => {
                hal_tools::outln!("{}", hal_tools::usage::task_cmd());
                return ExitCode::SUCCESS;
            }
            Ok(Some(Common::Version)) => {
                hal_tools::conventions::print_version("task-cmd");
                return ExitCode::SUCCESS;
            }
            Ok(Some(Common::Instance(name, n))) => {
                instance = name;
                i += n;
                continue;
            }
            Ok(None) => {}
            Err(e) => return usage_error(&e.to_string()),
        }
        match a.as_str() {
            "-t" | "--timeout" => {
                let text = args.get(i + 1).map_or("", String::as_str);
                match hal_tools::stdio::parse_seconds("-t", text, MAX_TIMEOUT_S) {
                    Ok(t) => timeout = t,
                    Err(e) => return usage_error(&e.to_string()),
                }
            }
            option if option.starts_with('-') => {
                return usage_error(&format!("unknown option '{option}'"))
            }
            _ => break,
        }
        i += 2;
    }
    let words = &args[i..];
    if words.is_empty() {
        return usage_error("no request given");
    }
    match request(&instance, words, timeout) {
        Ok(TaskAnswer::Done(text)) => {
            if !text.is_empty() {
                hal_tools::outln!("{text}");
            }
            ExitCode::SUCCESS
        }
        Ok(TaskAnswer::Refused(text)) => {
            eprintln!("task-cmd: {text}");
            ExitCode::from(1)
        }
        Err(TaskClientError::Io(e))
            if matches!(
                e.kind(),
                std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
            ) =>
        {
            eprintln!(
                "task-cmd: no answer within {:.1} s; the request goes on (see task-cmd status)",
                timeout.as_secs_f64()
            );
            ExitCode::from(1)
        }
        Err(e) => {
            eprintln!("task-cmd: {e}");
            ExitCode::from(2)
        }
    }
}

fn usage_error(msg: &str) -> ExitCode {
    eprintln!("task-cmd: {msg}\n\n{}", hal_tools::usage::task_cmd());
    ExitCode::from(2)
}
