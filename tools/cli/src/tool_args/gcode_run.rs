//! `gcode-run`'s command line (clap), here so the man page is built from it.

use std::path::PathBuf;

use clap::{Parser, ValueEnum};

/// The machine's linear units.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum UnitsArg {
    /// Millimetres.
    Mm,
    /// Inches.
    Inch,
}

/// Runs a G-code part program on a running HAL instance. Keys while
/// running: p (or space) pause, r resume, s single step (while paused),
/// a (or q, Ctrl-C) abort.
///
/// When a machine started by linuxcnc runs on the instance, the program
/// runs through its task (task-cmd mode auto, open, run): the whole
/// RS274NGC language (tools, offsets, canned cycles, parameters,
/// O-words), with task the one authority over the machine.
///
/// Otherwise (a bare halrun with motmod) it drives the motion controller
/// itself: the whole program is checked first, then queued as coordinated
/// moves. This standalone runner knows a subset: G0 G1 G2 G3 (I J K or R,
/// P turns) G4 G17 G18 G19 G20 G21 G61 G61.1 G64 P Q G90 G91 G90.1
/// G91.1, F (units per minute), M0 M1 M2 M30, N, comments; axis words X Y
/// Z A B C U V W. Anything else is refused with file:line:column before
/// anything moves.
#[derive(Debug, Parser)]
#[command(
    name = "gcode-run",
    version,
    after_help = "Examples:
  gcode-run pocket.ngc                  run on the instance in $HAL_INSTANCE
  gcode-run -i mill --units inch part.ngc
  gcode-run --check part.ngc            list every refusal of the program
  gcode-run --canon -I mill.ini part.ngc
                                        print its canonical calls (as rs274)
  gcode-run --preload -q --no-keys part.ngc
                                        queue it all first; quiet (scripts)
  echo r | gcode-run --optional-stop part.ngc
                                        resume after one M0/M1 stop

The machine must be enabled (and homed if its kinematics need it); the
runner switches it to coordinated mode. Exit status: 0 the program ran,
1 it was aborted or a move was refused, 2 the program or the arguments
are wrong or the machine cannot be reached."
)]
pub struct Args {
    /// The program file.
    pub file: PathBuf,
    /// HAL instance (default: $HAL_INSTANCE or 'default').
    #[arg(short, long)]
    pub instance: Option<String>,
    /// The machine's linear units (`[TRAJ]LINEAR_UNITS`).
    #[arg(long, value_enum, default_value = "mm")]
    pub units: UnitsArg,
    /// Only check the program with task's RS274NGC interpreter: every
    /// refusal, earliest first, as file:line:column: word: text; no
    /// machine needed.
    #[arg(long)]
    pub check: bool,
    /// Only print the program's canonical calls as LinuxCNC's rs274 does;
    /// no machine needed.
    #[arg(long, conflicts_with = "check")]
    pub canon: bool,
    /// The machine's INI file for --check and --canon: its [RS274NGC]
    /// settings and [EMCIO]TOOL_TABLE.
    #[arg(short = 'I', long, value_name = "INI")]
    pub ini: Option<PathBuf>,
    /// Stop at M1 too.
    #[arg(long)]
    pub optional_stop: bool,
    /// No progress line.
    #[arg(short, long)]
    pub quiet: bool,
    /// Ignore the keyboard (standard input).
    #[arg(long)]
    pub no_keys: bool,
    /// Queue the program (up to the queue's size or the first M0) before
    /// starting it, so the motion does not depend on how fast moves
    /// arrive (reproducible runs, tests).
    #[arg(long)]
    pub preload: bool,
}
