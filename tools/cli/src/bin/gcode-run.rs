//! `gcode-run`: runs a G-code part program on the motion controller of a
//! running HAL instance (see `--help`).

use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Parser;
use hal_launcher::part_program::interp::{interpret, Units};
use hal_launcher::part_program::run::{run, Keys, Outcome, RunOptions};
use hal_tools::gcode_task::{run_through_task, TaskRun};
use hal_tools::tool_args::gcode_run::{Args, UnitsArg};
use hal_tools::ToolsError;
use motion::{Command, MotionClient, Pose};

fn main() -> ExitCode {
    let args = Args::parse();
    let units = match args.units {
        UnitsArg::Mm => Units::Mm,
        UnitsArg::Inch => Units::Inch,
    };
    let name = args.file.display().to_string();
    if args.check {
        return match hal_tools::gcode_check::check(&args.file, args.ini.as_deref()) {
            Ok(refusals) if refusals.is_empty() => {
                println!("{name}: ok");
                ExitCode::SUCCESS
            }
            Ok(refusals) => {
                for r in refusals {
                    eprintln!("{r}");
                }
                ExitCode::from(2)
            }
            Err(e) => {
                eprintln!("gcode-run: {e}");
                ExitCode::from(2)
            }
        };
    }
    if args.canon {
        let out = Box::new(std::io::BufWriter::new(std::io::stdout()));
        return match hal_tools::gcode_check::canon(&args.file, args.ini.as_deref(), out) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("{e}");
                ExitCode::from(2)
            }
        };
    }
    let text = match hal_core::files::read_user_file(
        &args.file,
        hal_core::files::limits::PROGRAM,
        "part program",
    ) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("gcode-run: {e}");
            return ExitCode::from(2);
        }
    };
    let lines = text.split(|&b| b == b'\n').count();
    let instance = args
        .instance
        .clone()
        .unwrap_or_else(hal_core::instance_from_env);
    if hal_tools::gcode_task::task_runs(&instance) {
        return through_task(&instance, &args, &name);
    }
    let mut client = match MotionClient::attach(&instance) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("gcode-run: instance '{instance}': {e}");
            return ExitCode::from(2);
        }
    };
    let start = match enter_coord(&mut client) {
        Ok(p) => p,
        Err(m) => {
            eprintln!("gcode-run: {m}");
            return ExitCode::from(2);
        }
    };
    let steps = match interpret(&name, &text, start, units) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let _ = signal_hook::flag::register(signal_hook::consts::SIGINT, stop.clone());
    let keys = if args.no_keys {
        Keys::none()
    } else {
        Keys::start()
    };
    let opts = RunOptions {
        optional_stop: args.optional_stop,
        preload: args.preload,
        progress: !args.quiet && std::io::IsTerminal::is_terminal(&std::io::stderr()),
    };
    let outcome = run(&mut client, &name, lines, &steps, opts, &keys, &stop);
    drop(keys);
    match outcome {
        Outcome::Done { seconds } => {
            if !args.quiet {
                println!("{name}: done in {seconds:.3} s");
            }
            ExitCode::SUCCESS
        }
        Outcome::Aborted { line } => {
            println!("{name}: aborted at line {line}");
            ExitCode::from(1)
        }
        Outcome::Failed(m) => {
            eprintln!("{m}");
            ExitCode::from(1)
        }
    }
}

/// Runs the program through the task of `instance` (a machine started by
/// `linuxcnc`): task is then the one authority over the machine.
fn through_task(instance: &str, args: &Args, name: &str) -> ExitCode {
    let stop = Arc::new(AtomicBool::new(false));
    let _ = signal_hook::flag::register(signal_hook::consts::SIGINT, stop.clone());
    let keys = if args.no_keys {
        Keys::none()
    } else {
        Keys::start()
    };
    let progress = !args.quiet && std::io::IsTerminal::is_terminal(&std::io::stderr());
    let outcome = run_through_task(instance, &args.file, &keys, &stop, progress);
    drop(keys);
    match outcome {
        TaskRun::Done(_) => {
            if !args.quiet {
                println!("{name}: done (through task)");
            }
            ExitCode::SUCCESS
        }
        TaskRun::Aborted(why) => {
            println!("{name}: {why}");
            ExitCode::from(1)
        }
        TaskRun::Failed(why) => {
            eprintln!("gcode-run: {why}");
            ExitCode::from(1)
        }
    }
}

/// Puts the machine in coordinated mode (it must be enabled) and returns
/// where its queue starts.
fn enter_coord(client: &mut MotionClient) -> Result<Pose, ToolsError> {
    let s = client.status()?;
    if !s.enabled {
        return Err(ToolsError::NotEnabled);
    }
    if s.mode != "COORD" {
        client
            .send(Command::Coord)
            .map_err(|r| ToolsError::Coord { source: r.reason })?;
    }
    // A snapshot two cycles later shows the mode and the queue's start.
    let deadline = Instant::now() + Duration::from_secs(5);
    let beat = client.status()?.heartbeat;
    loop {
        let s = client.status()?;
        if s.heartbeat.wrapping_sub(beat) >= 2 && s.mode == "COORD" {
            return Ok(Pose(s.traj.goal));
        }
        if Instant::now() > deadline {
            return Err(ToolsError::CoordTimeout);
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}
