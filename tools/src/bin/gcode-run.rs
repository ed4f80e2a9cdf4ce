//! `gcode-run`: runs a G-code part program on the motion controller of a
//! running HAL instance (see `--help`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Parser, ValueEnum};
use hal_tools::part_program::interp::{interpret, Step, Units};
use hal_tools::part_program::run::{run, Keys, Outcome, RunOptions};
use motion::{Command, MotionClient, Pose};

/// The machine's linear units.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum UnitsArg {
    /// Millimetres.
    Mm,
    /// Inches.
    Inch,
}

/// Runs a G-code part program on the motion controller (motmod) of a
/// running HAL instance: the whole program is checked first, then queued
/// as coordinated moves while it runs. Keys while running: p (or space)
/// pause, r resume, s single step (while paused), a (or q, Ctrl-C) abort.
///
/// The G-code subset: G0 G1 G2 G3 (I J K or R, P turns) G4 G17 G18 G19
/// G20 G21 G61 G61.1 G64 P Q G90 G91 G90.1 G91.1, F (units per minute),
/// M0 M1 M2 M30, N, comments; axis words X Y Z A B C U V W. Anything else
/// is refused with file:line:column before anything moves.
#[derive(Debug, Parser)]
#[command(
    name = "gcode-run",
    version,
    after_help = "Examples:
  gcode-run pocket.ngc                  run on the instance in $HAL_INSTANCE
  gcode-run -i mill --units inch part.ngc
  gcode-run --check part.ngc            only check the program
  gcode-run --preload -q --no-keys part.ngc
                                        queue it all first; quiet (scripts)
  echo r | gcode-run --optional-stop part.ngc
                                        resume after one M0/M1 stop

The machine must be enabled (and homed if its kinematics need it); the
runner switches it to coordinated mode. Exit status: 0 the program ran,
1 it was aborted or a move was refused, 2 the program or the arguments
are wrong or the machine cannot be reached."
)]
struct Args {
    /// The program file.
    file: PathBuf,
    /// HAL instance (default: $HAL_INSTANCE or 'default').
    #[arg(short, long)]
    instance: Option<String>,
    /// The machine's linear units (`[TRAJ]LINEAR_UNITS`).
    #[arg(long, value_enum, default_value = "mm")]
    units: UnitsArg,
    /// Only check the program (from X0 Y0 Z0); no machine needed.
    #[arg(long)]
    check: bool,
    /// Stop at M1 too.
    #[arg(long)]
    optional_stop: bool,
    /// No progress line.
    #[arg(short, long)]
    quiet: bool,
    /// Ignore the keyboard (standard input).
    #[arg(long)]
    no_keys: bool,
    /// Queue the program (up to the queue's size or the first M0) before
    /// starting it, so the motion does not depend on how fast moves
    /// arrive (reproducible runs, tests).
    #[arg(long)]
    preload: bool,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let units = match args.units {
        UnitsArg::Mm => Units::Mm,
        UnitsArg::Inch => Units::Inch,
    };
    let name = args.file.display().to_string();
    let text = match std::fs::read(&args.file) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("gcode-run: {name}: {e}");
            return ExitCode::from(2);
        }
    };
    let lines = text.split(|&b| b == b'\n').count();
    if args.check {
        return match interpret(&name, &text, Pose::ZERO, units) {
            Ok(steps) => {
                let moves = steps.iter().filter(|s| matches!(s, Step::Send(..))).count();
                println!("{name}: ok ({moves} commands)");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("{e}");
                ExitCode::from(2)
            }
        };
    }
    let instance = args.instance.unwrap_or_else(hal_core::instance_from_env);
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

/// Puts the machine in coordinated mode (it must be enabled) and returns
/// where its queue starts.
fn enter_coord(client: &mut MotionClient) -> Result<Pose, String> {
    let s = client.status().map_err(|e| e.to_string())?;
    if !s.enabled {
        return Err("the machine is not enabled (motion-cmd enable)".into());
    }
    if s.mode != "COORD" {
        client
            .send(Command::Coord)
            .map_err(|r| format!("can't enter coordinated mode: {}", r.reason))?;
    }
    // A snapshot two cycles later shows the mode and the queue's start.
    let deadline = Instant::now() + Duration::from_secs(5);
    let beat = client.status().map_err(|e| e.to_string())?.heartbeat;
    loop {
        let s = client.status().map_err(|e| e.to_string())?;
        if s.heartbeat.wrapping_sub(beat) >= 2 && s.mode == "COORD" {
            return Ok(Pose(s.traj.goal));
        }
        if Instant::now() > deadline {
            return Err("the controller did not enter coordinated mode".into());
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}
