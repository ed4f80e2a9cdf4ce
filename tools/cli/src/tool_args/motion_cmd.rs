//! `motion-cmd`'s command line (clap), here so the man page is built from
//! it. The options come before the command; the command and its words are
//! parsed by the tool itself, as they always were (`axis-jog-incr x 5
//! 12.5`, `set-homing-params 0 HOME_SEQUENCE=1`, negative numbers).

use clap::Parser;

const COMMANDS: &str = "\
Examples:
  motion-cmd status
  motion-cmd -i mill enable
  motion-cmd -t 60 wait all-homed
  motion-cmd jog-cont 0 -5                 # joint 0 at -5 units/s until jog-abort
  motion-cmd axis-jog-incr x 5 12.5
  motion-cmd set-homing-params 0 HOME_SEQUENCE=1 HOME_SEARCH_VEL=-10
  motion-cmd line 1 20 X=10 Y=-2           # coord mode: a feed move at 20 units/s
  motion-cmd watch -n 100 -c 50

Prints whether the command was accepted or rejected (with the reason).
Exit status: 0 accepted, 1 rejected, 2 usage or connection error.

status:
  status                print the status snapshot once
  watch [-n MS] [-c COUNT]
                        refresh the status every MS milliseconds (default
                        200), COUNT times (default: until interrupted)
  wait CONDITION        wait until CONDITION holds (exit 0) or --timeout
                        passes (default 60 s here; exit 1, status shown).
                        Only snapshots from two servo cycles after the
                        start count, so a command just sent has taken
                        effect. CONDITION: enabled, disabled, in-position,
                        homing-done, all-homed, homed JOINT

machine:
  enable | disable | abort
  free | teleop | coord         mode requests
  scale VALUE                   jog speed scale, 0..1
  override-limits JOINT         override tripped hard limits until the end
                                of the next jog (JOINT -1: end the override)

joints:
  activate JOINT | deactivate JOINT
  amp-enable JOINT | amp-disable JOINT
  jog-cont JOINT VEL            jog until jog-abort (sign of VEL = direction)
  jog-incr JOINT VEL DISTANCE   jog DISTANCE (>= 0) in the direction of VEL
  jog-abs JOINT VEL POSITION    jog to POSITION at speed |VEL|
  jog-abort JOINT               stop the jog of JOINT
  home JOINT                    home JOINT (its group if its HOME_SEQUENCE
                                is negative); JOINT -1: home all joints in
                                HOME_SEQUENCE order
  unhome JOINT                  forget the home of JOINT; -1 every joint,
                                -2 the VOLATILE_HOME joints

axes (teleop mode):
  AXIS is a letter x y z a b c u v w, or its number 0..8
  axis-jog-cont AXIS VEL        jog until axis-jog-abort (sign of VEL =
                                direction), at most to the axis limit
  axis-jog-incr AXIS VEL DIST   jog DIST (>= 0) in the direction of VEL
  axis-jog-abs AXIS VEL POS     jog to POS (clamped into the axis limits)
                                at speed |VEL|
  axis-jog-abort AXIS           stop the jog of AXIS
  set-axis-limits AXIS MIN MAX  axis position limits
  set-axis-vel-limit AXIS VEL   axis maximum velocity
  set-axis-acc-limit AXIS ACC   axis maximum acceleration
  set-axis-eoffset-ratio AXIS RATIO
                                OFFSET_AV_RATIO (0..0.9): the share of the
                                axis limits its external offset
                                (axis.L.eoffset-*) gets; only while disabled
  set-axis-locking-indexer AXIS JOINT
                                LOCKING_INDEXER_JOINT: JOINT (-1: none)
                                unlocks around each rapid of AXIS; it needs
                                unlock pins; only while disabled

configuration:
  set-limits JOINT MIN MAX      soft position limits
  set-vel-limit JOINT VEL       maximum velocity
  set-acc-limit JOINT ACC       maximum acceleration
  set-min-ferror JOINT VALUE    following-error limit at standstill
  set-max-ferror JOINT VALUE    following-error limit at maximum velocity
  set-backlash JOINT VALUE      backlash
  set-motor-offset JOINT VALUE  homing offset (motor = joint + offset)
  set-world-home X Y Z A B C U V W
                                world home pose
  set-homing-params JOINT [KEY=VALUE...]
                                the joint's whole homing configuration, with
                                the [JOINT_n] INI keys HOME_OFFSET, HOME,
                                HOME_SEARCH_VEL, HOME_LATCH_VEL,
                                HOME_FINAL_VEL, HOME_SEQUENCE, HOME_USE_INDEX,
                                HOME_INDEX_NO_ENCODER_RESET,
                                HOME_IGNORE_LIMITS, HOME_IS_SHARED,
                                HOME_ABSOLUTE_ENCODER (0, 1, 2),
                                VOLATILE_HOME and LOCKING_INDEXER; keys left
                                out take the INI defaults
  update-homing-params JOINT OFFSET HOME SEQUENCE
                                HOME_OFFSET, HOME and HOME_SEQUENCE only
  set-jerk-limit JOINT JERK     maximum jerk (S-curve planner; 0 none)
  set-axis-jerk-limit AXIS JERK axis maximum jerk (0 none)
  comp-entry JOINT NOMINAL FORWARD REVERSE
                                append one screw-compensation entry (trims;
                                nominals increasing; only while disabled)
  clear-comp JOINT              empty the joint's compensation table
  load-comp JOINT FILE TYPE     load a [JOINT_n]COMP_FILE of COMP_FILE_TYPE
                                0 or 1 (replaces the table; errors name the
                                file and line)
  set-num-joints N              [KINS]JOINTS: the joints commands may name
                                (1 to motmod's num_joints; the others are
                                made inactive); only while disabled
  set-num-spindles N            [TRAJ]SPINDLES likewise (1 to motmod's
                                num_spindles); only while disabled

coordinated moves (coord mode; END is AXIS=VALUE words, e.g. X=10 Y=-2;
axes left out stay where the last queued move ends):
  line ID VEL END...            straight feed move at VEL (units/s)
  rapid ID END...               straight rapid (as fast as the axes allow)
  arc ID VEL center=CX,CY,CZ [normal=NX,NY,NZ] [turns=N] END...
                                arc or helix counter-clockwise about the
                                normal (default 0,0,1); turns < 0 clockwise
                                (G2 P n is turns=-n, G3 P n is turns=n-1)
  probe ID VEL G38.2|G38.3|G38.4|G38.5 END...
                                probing move
  dwell ID SECONDS              wait, after the moves before have stopped
  clear-probe                   forget the last probe result
  term-cond stop|exact|blend [TOLERANCE]
                                how the next moves end: G61.1, G61, G64 P
  pause | resume | step         step: run to the end of the current id
  feed-scale S | rapid-scale S | max-feed-override S
  feed-scale-enable 0|1 | feed-hold-enable 0|1 | adaptive-feed-enable 0|1
  spindle-scale-enable 0|1      M50 M53 M52 M51: for the moves queued next
  set-traj-vel V | set-traj-acc A | set-traj-jerk J
                                [TRAJ] MAX_LINEAR_VELOCITY, _ACCELERATION,
                                _JERK
  planner-type 0|1              trapezoidal or S-curve (PLANNER_TYPE)
  set-vel VEL INI-MAXVEL        SET_VEL: the trajectory velocity and the INI
                                (default) velocity, kept; no move is limited
                                by them
  arc-blends 0|1 0|1 DEPTH GAP-CYCLES RAMP-FREQ
                                [TRAJ]ARC_BLEND_ENABLE, _FALLBACK_ENABLE,
                                _OPTIMIZATION_DEPTH, _GAP_CYCLES, _RAMP_FREQ;
                                without arc blends G64 runs as G61
  tool-offset X Y Z A B C U V W the tool offset (G43), on motion.tooloffset.L
  feed-per-rev SPINDLE UNITS    G95: the next feed moves go UNITS per
                                revolution of SPINDLE (its speed-in); 0 off
  spindle-sync SPINDLE UNITS 0|1
                                G33 (0): the next feed moves wait for the
                                spindle's index and follow its revs, UNITS
                                per revolution; 1 as feed-per-rev; 0 off
  rigid-tap ID VEL SCALE END...  G33.1 under spindle-sync: tap to END's X Y Z
                                and back, the spindle reversed at SCALE
  spindle-css SPINDLE FACTOR X-OFFSET
                                G96: the spindle turns at FACTOR / |X -
                                X-OFFSET| rpm, at most its spindle-on speed
                                (FACTOR: surface speed / 2 pi); 0 off
  spindle-params SPINDLE MAX-FORWARD MIN-FORWARD MAX-REVERSE MIN-REVERSE
                                the speed range, rpm (the reverse ones 0 or
                                less): SPINDLE-ON speeds are held within it
";

/// Sends one command to the motion controller (motmod) of a running HAL
/// instance through its shared-memory command channel, or shows its status.
#[derive(Parser, Debug)]
#[command(name = "motion-cmd", version, after_help = COMMANDS)]
pub struct Cli {
    /// HAL instance (default: $HAL_INSTANCE or 'default').
    #[arg(short, long, value_name = "NAME")]
    pub instance: Option<String>,
    /// Print nothing when a command is accepted (a refusal is still
    /// printed, and the exit status says which it was).
    #[arg(short, long)]
    pub quiet: bool,
    /// How long to wait for the answer (default 1; `wait`: 60).
    #[arg(short, long, value_name = "SECONDS")]
    pub timeout: Option<String>,
    /// The command and its arguments (see below).
    #[arg(
        value_name = "COMMAND",
        required = true,
        trailing_var_arg = true,
        allow_hyphen_values = true
    )]
    pub command: Vec<String>,
}
