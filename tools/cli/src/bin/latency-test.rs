//! latency-test: LinuxCNC's latency test, headless (see
//! `hal_scope::latency`).

use std::process::ExitCode;

use hal_core::userspace::ExitSignals;
use hal_scope::latency::args::{parse, Parsed, HELP};
use hal_scope::latency::session::Session;
use hal_scope::latency::{measure, report, LatencyError};

fn main() -> ExitCode {
    let args = hal_tools::stdio::args_or_exit("latency-test", 2);
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(LatencyError::Usage(m)) => {
            eprintln!("latency-test: {m} (see latency-test --help)");
            ExitCode::from(2)
        }
        Err(e) => {
            eprintln!("latency-test: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &[String]) -> Result<(), LatencyError> {
    let cfg = match parse(args)? {
        Parsed::Help => {
            hal_tools::out!("{HELP}");
            return Ok(());
        }
        Parsed::Version => {
            hal_tools::conventions::print_version("latency-test");
            return Ok(());
        }
        Parsed::Run(cfg) => cfg,
    };
    let signals = ExitSignals::install().map_err(|e| LatencyError::Host(e.into()))?;
    // A private instance: nothing else runs on it, and it goes with us.
    let instance = format!("latency-test-{}", std::process::id());
    let session = Session::start(&instance, &cfg)?;
    // A closed stdout ends the test quietly, as `yes | head` ends `yes`.
    let mut out = hal_tools::stdio::stdout();
    let tty = out.is_terminal();
    match cfg.duration {
        Some(d) => hal_tools::outln!(
            "latency-test: measuring for {:.1} s (Ctrl-C ends it early)",
            d.as_secs_f64()
        ),
        None => hal_tools::outln!("latency-test: measuring until Ctrl-C"),
    }
    let (threads, perms) = measure(&session, &cfg, &mut out, tty, &|| signals.requested())?;
    session.finish()?;
    report(&threads, &perms, &cfg, &mut out)?;
    Ok(())
}
