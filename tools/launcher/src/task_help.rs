//! `task-cmd`'s list of requests, for its help text and man page.

/// The words `task-cmd` accepts, for its help text.
pub const REQUESTS: &str = "\
\x20 estop                 assert the e-stop
  estop-reset           release the e-stop (user-enable-out on, a pulse on
                        user-request-enable); waits for emc-enable-in
  machine-on | machine-off
  abort                 stop motion, coolant and any tool handshake
  tool-change TOOL      prepare TOOL and change to it (T<n> M6)
  tool-prepare TOOL     prepare TOOL (T<n>)
  tool-load             change to the prepared tool (M6)
  set-tool TOOL         declare TOOL in the spindle (M61)
  coolant mist|flood on|off
  lube on|off
  reload-tool-table     read the tool table file again
  reset-interpreter     start the interpreter afresh: its start-up modal
                        state, the parameter file as saved (nothing may run)
  status                machine state, mode, tool, coolant, motion, program
  mode manual|auto|mdi  switch mode (AUTO and MDI need the machine on and,
                        unless [TRAJ]NO_FORCE_HOMING, homed joints)
  open FILE             open a G-code program
  run [LINE]            run it (AUTO), from LINE on if given (the lines
                        before run through the interpreter, moving nothing)
  pause | resume | step the running program (step: while paused)
  mdi G-CODE...         run a line of G-code (MDI mode)
  wait-done             answer once the program or MDI line has ended
  home JOINT|all        home a joint or every joint (MANUAL mode)
  unhome JOINT|all      forget a joint's home (MANUAL mode)
  jog-cont JOINT|AXIS VEL
                        jog a joint (a number; free mode) or an axis (a
                        letter; teleop) at VEL until jog-stop (MANUAL mode)
  jog-incr JOINT|AXIS VEL DISTANCE
                        jog a joint or an axis by DISTANCE (MANUAL mode)
  jog-stop JOINT|AXIS   stop a joint's or an axis's jog
  feed-override SCALE   the feed override (1 = 100 %, at most
                        [DISPLAY]MAX_FEED_OVERRIDE)
  rapid-override SCALE  the rapid override (0 to 1)
  max-velocity VEL      the tool-tip speed limit ([TRAJ]MAX_LINEAR_VELOCITY)
  state                 the state as key=value lines, for programs
  stat                  the state as NAME=KIND:VALUE lines in LinuxCNC's
                        names (the Python linuxcnc module's stat)
  set-dout N on|off     set motion.digital-out-NN at once (as M64/M65)
  set-aout N VALUE      set motion.analog-out-NN at once (as M68)
  messages SEQ          the error channel's messages after number SEQ: the
                        newest number, then SEQ KIND TEXT lines
  message error|text|display TEXT
                        add an operator message to the error channel
  optional-stop on|off  M1 stops the program (off: M1 is passed over)
  block-delete on|off   lines that start with / are skipped (on) or run
  teleop on|off         MANUAL mode's jogs move world axes (on) or joints
  feed-hold on|off      whether motion.feed-hold holds the moves (M53)
  feed-override-enable on|off
                        whether the feed and rapid overrides apply to the
                        moves queued next (M50)
  spindle-override-enable on|off
                        whether the spindle override applies (M51)
  clear-probe           forget the last probe result (the tripped flag)
  tool-offset TOOL Z X DIAMETER FRONT BACK ORIENTATION
                        set a tool's values in the tool table (saved), as
                        G10 L1 does (nothing running)
  traj-mode free|coord|teleop
                        the trajectory mode: joints one by one, coordinated,
                        or jogs in world axes (free and teleop: MANUAL mode)
  axis-limit AXIS min|max VALUE
                        one soft position limit of world axis AXIS (0-8,
                        X Y Z A B C U V W), the other kept
  override-limits [on|off]
                        override the joints' tripped hard limits until
                        the next jog ends, or end the override (MANUAL
                        mode only)
  spindle [N] forward|reverse [RPM]
                        start spindle N (default 0) at RPM, else the S in
                        effect, else 500 (machine on, nothing running)
  spindle [N] off|increase|decrease
                        stop it (brake on), or 100 rpm faster or slower
  spindle [N] brake on|off
  spindle [N] override SCALE
                        the spindle override (1 = 100 %, within
                        [DISPLAY]MIN/MAX_SPINDLE_OVERRIDE)";
