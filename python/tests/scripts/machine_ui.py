#!/usr/bin/env python3
"""A display program for `linuxcnc`: drives the simulated mill through
the `linuxcnc` module (e-stop reset, machine on, homing, an MDI move, a
short program) and checks the status on the way. Prints what it checked
to stdout; exits 0 when every check held, else 1. With `--exit N` it
only checks that task answers and exits N."""

import os
import sys
import time

import linuxcnc
import linuxcnc_util


def fail(why):
    print("machine_ui: FAILED: " + why, flush=True)
    sys.exit(1)


def check(cond, why):
    if not cond:
        fail(why)
    print("machine_ui: ok: " + why, flush=True)


def wait(s, cond, what, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        s.poll()
        if cond():
            return
        time.sleep(0.02)
    fail("timed out waiting for " + what)


def near(a, b):
    return abs(a - b) < 1e-6


def ok_or_fail(c, e, what):
    r = c.wait_complete()
    msg = e.poll()
    if r != linuxcnc.RCS_DONE:
        fail("%s: wait_complete gave %r (%r)" % (what, r, msg))


def main(argv):
    check(argv[1:3] == ["-ini", os.environ.get("INI_FILE_NAME")],
          "started as PROGRAM -ini INIFILE: %r" % argv[1:])
    c = linuxcnc.command()
    s = linuxcnc.stat()
    e = linuxcnc.error_channel()
    util = linuxcnc_util.LinuxCNC(command=c, status=s, error=e)
    util.wait_for_linuxcnc_startup()
    check(s.task_state == linuxcnc.STATE_ESTOP and s.estop, "the machine starts in e-stop")
    if "--exit" in argv:
        sys.exit(int(argv[argv.index("--exit") + 1]))
    ini = linuxcnc.ini(s.ini_filename)
    check(ini.find("KINS", "JOINTS") == "3", "linuxcnc.ini finds [KINS]JOINTS")
    check(s.linear_units == 1.0 and s.cycle_time == 0.001 and s.max_acceleration == 500,
          "the INI settings show: %r" % ((s.linear_units, s.cycle_time, s.max_acceleration),))

    # Refused while in e-stop: reported, not raised.
    c.state(linuxcnc.STATE_ON)
    check(c.wait_complete() == linuxcnc.RCS_ERROR, "machine on in e-stop is refused")
    kind, text = e.poll()
    check(kind == linuxcnc.OPERATOR_ERROR and text,
          "the refusal is on the error channel: " + text)
    check(e.poll() is None, "and only once")

    c.state(linuxcnc.STATE_ESTOP_RESET)
    ok_or_fail(c, e, "estop reset")
    c.state(linuxcnc.STATE_ON)
    ok_or_fail(c, e, "machine on")
    s.poll()
    check(s.task_state == linuxcnc.STATE_ON and s.enabled and not s.estop, "the machine is on")

    c.mode(linuxcnc.MODE_MANUAL)
    ok_or_fail(c, e, "manual mode")
    # Joint by joint, one call after the other, as scripts often do.
    for joint in range(3):
        c.home(joint)
        ok_or_fail(c, e, "home joint %d" % joint)
    util.wait_for_home([1, 1, 1, 0, 0, 0, 0, 0, 0], timeout=60)
    check(s.joints == 3 and s.homed[3:] == (0,) * (len(s.homed) - 3), "three joints homed")
    wait(s, lambda: s.inpos, "homing to finish moving")
    # Homed and inside the travel: no limit bit in LinuxCNC's mask, no
    # soft limit on any joint; scripts of LinuxCNC 2.7 read `axes`.
    check(len(s.limit) == len(s.homed) and not any(s.limit), "no limit bits")
    check(not any(j["min_soft_limit"] or j["max_soft_limit"] for j in s.joint),
          "no joint at a soft limit")
    check(s.axes == 3, "stat.axes counts X Y Z")
    check(s.optional_stop == 1, "optional stop starts on, as LinuxCNC's")

    # traj_mode with LinuxCNC's constants; motion_mode follows.
    c.traj_mode(linuxcnc.TRAJ_MODE_FREE)
    ok_or_fail(c, e, "traj_mode free")
    wait(s, lambda: s.motion_mode == linuxcnc.TRAJ_MODE_FREE, "free mode")
    c.traj_mode(linuxcnc.TRAJ_MODE_TELEOP)
    ok_or_fail(c, e, "traj_mode teleop")
    wait(s, lambda: s.motion_mode == linuxcnc.TRAJ_MODE_TELEOP, "teleop mode")
    # One soft limit of Y at a time, the other kept.
    low, high = s.axis[1]["min_position_limit"], s.axis[1]["max_position_limit"]
    c.set_max_limit(1, high - 1.0)
    ok_or_fail(c, e, "set_max_limit")
    c.set_min_limit(1, low + 1.0)
    ok_or_fail(c, e, "set_min_limit")
    s.poll()
    check(near(s.axis[1]["max_position_limit"], high - 1.0)
          and near(s.axis[1]["min_position_limit"], low + 1.0),
          "set_min_limit and set_max_limit move Y's soft limits")
    c.set_max_limit(1, high)
    ok_or_fail(c, e, "set_max_limit back")
    c.set_min_limit(1, low)
    ok_or_fail(c, e, "set_min_limit back")

    # tool_offset with LinuxCNC's seven values sets the table entry.
    c.tool_offset(3, 42.5, 0.0, 5.2, 0.0, 0.0, 0)
    ok_or_fail(c, e, "tool_offset")
    s.poll()
    t3 = [t for t in s.tool_table if t.id == 3]
    check(len(t3) == 1 and near(t3[0].zoffset, 42.5) and near(t3[0].diameter, 5.2),
          "tool_offset sets tool 3's Z offset and diameter")

    c.mode(linuxcnc.MODE_MDI)
    ok_or_fail(c, e, "MDI mode")
    c.mdi("G64 P0.05 Q0.01")
    ok_or_fail(c, e, "G64 P0.05 Q0.01")
    s.poll()
    check(len(s.settings) == 5 and near(s.settings[3], 0.05) and near(s.settings[4], 0.01),
          "stat.settings holds the G64 tolerances: %r" % (s.settings,))
    # The override enables (M50/M51 from a GUI), off and on again.
    for on in (False, True):
        c.set_feed_override(on)
        ok_or_fail(c, e, "feed override enable %s" % on)
        c.set_spindle_override(on)
        ok_or_fail(c, e, "spindle override enable %s" % on)
    s.poll()
    check(s.task_mode == linuxcnc.MODE_MDI, "task is in MDI mode")
    c.mdi("G0 X2 Y1")
    ok_or_fail(c, e, "the MDI move")
    s.poll()
    check(near(s.position[0], 2.0) and near(s.position[1], 1.0),
          "the MDI move reached X2 Y1: %r" % (s.position[:3],))
    check(len(s.position) == 9 and len(s.actual_position) == 9, "positions have nine axes")
    check(s.interp_state == linuxcnc.INTERP_IDLE, "the interpreter is idle after MDI")
    check(s.queued_mdi_commands == 0 and s.lube_level in (0, 1),
          "no MDI waits; lube_level reads")
    check(s.spindles >= 1 and s.spindle[0]["enabled"] == 0 and s.spindle[0].orient_fault == 0,
          "spindle 0 is off")
    check(len(s.gcodes) == 17 and s.gcodes[5] == 210 and s.gcodes[6] == 900,
          "G21 and G90 are in LinuxCNC's places: %r" % (s.gcodes,))
    check(s.gcodes[8] == 540 and s.g5x_index == 1, "G54 is active")
    check(len(s.mcodes) == 10 and s.mcodes[2] == 5 and s.mcodes[4] == 9,
          "M5 and M9 are in LinuxCNC's places: %r" % (s.mcodes,))
    c.mdi("T2 M6")
    ok_or_fail(c, e, "the tool change")
    s.poll()
    check(s.tool_in_spindle == 2, "tool 2 is in the spindle: %r" % s.tool_in_spindle)
    check(any(t.id == 2 and t.diameter == 6.0 and t.zoffset == 20.5 for t in s.tool_table),
          "the tool table shows tool 2")
    c.spindle(linuxcnc.SPINDLE_FORWARD, 300)
    ok_or_fail(c, e, "spindle forward")
    wait(s, lambda: s.spindle[0]["enabled"] == 1 and s.spindle[0]["direction"] == 1
         and s.spindle[0]["speed"] == 300, "spindle 0 to turn forward at 300", timeout=5)
    c.spindle(linuxcnc.SPINDLE_OFF)
    ok_or_fail(c, e, "spindle off")
    wait(s, lambda: s.spindle[0]["enabled"] == 0, "spindle 0 to stop", timeout=5)
    c.flood(linuxcnc.FLOOD_ON)
    ok_or_fail(c, e, "flood on")
    s.poll()
    check(s.flood == linuxcnc.FLOOD_ON, "flood is on")
    c.flood(linuxcnc.FLOOD_OFF)
    ok_or_fail(c, e, "flood off")
    s.poll()
    check(s.flood == linuxcnc.FLOOD_OFF, "spindle and flood turn on and off")
    c.set_digital_output(1, 1)
    ok_or_fail(c, e, "setting digital output 1")
    wait(s, lambda: s.dout[1] == 1, "motion.digital-out-01 to show", timeout=5)
    c.set_digital_output(1, 0)
    wait(s, lambda: s.dout[1] == 0, "motion.digital-out-01 to clear", timeout=5)
    check(True, "set_digital_output sets and clears motion.digital-out-01")
    c.mdi("G91")
    ok_or_fail(c, e, "G91")
    s.poll()
    check(s.gcodes[6] == 910, "G91 is active")
    c.reset_interpreter()
    ok_or_fail(c, e, "resetting the interpreter")
    s.poll()
    check(s.gcodes[6] == 900, "the reset brought back G90")
    check(s.interpreter_errcode == 0, "no interpreter error yet")
    c.mdi("G2 X1")
    check(c.wait_complete() == linuxcnc.RCS_ERROR, "an arc without a centre fails")
    s.poll()
    check(s.interpreter_errcode == 5, "the interpreter's error code is INTERP_ERROR")
    kind, text = e.poll()
    check(kind == linuxcnc.OPERATOR_ERROR, "its error is on the error channel: " + text)
    c.display_msg("look here")
    check(e.poll() == (linuxcnc.OPERATOR_DISPLAY, "look here"), "display_msg reaches the channel")

    prog = os.path.join(os.path.dirname(s.ini_filename), "ui-test.ngc")
    with open(prog, "w") as f:
        f.write("G21 G90\nG1 X3 F600\n(MSG, halfway)\nG1 Y-1\nG0 Z0.5\nM2\n")
    c.mode(linuxcnc.MODE_AUTO)
    ok_or_fail(c, e, "AUTO mode")
    c.program_open(prog)
    ok_or_fail(c, e, "opening the program")
    s.poll()
    check(s.file == os.path.realpath(prog), "stat.file is the program: %r" % s.file)
    c.auto(linuxcnc.AUTO_RUN, 0)
    # As in LinuxCNC, wait_complete() after a run returns at its end (its
    # MSG stays on the error channel for the check below).
    check(c.wait_complete() == linuxcnc.RCS_DONE, "wait_complete() returns when the program ends")
    s.poll()
    check(s.interp_state == linuxcnc.INTERP_IDLE, "the interpreter is idle once it returned")
    wait(s, lambda: s.interp_state != linuxcnc.INTERP_IDLE or near(s.position[2], 0.5),
         "the program to start")
    wait(s, lambda: s.interp_state == linuxcnc.INTERP_IDLE, "the program to end")
    wait(s, lambda: s.inpos and s.queue == 0, "motion to settle")
    check(near(s.position[0], 3.0) and near(s.position[1], -1.0) and near(s.position[2], 0.5),
          "the program ended at X3 Y-1 Z0.5: %r" % (s.position[:3],))
    check(all(abs(a - b) < 1e-3 for a, b in zip(s.actual_position[:3], s.position[:3])),
          "feedback follows the command")
    m = e.poll()
    check(m is not None and m[0] == linuxcnc.OPERATOR_DISPLAY and m[1].strip() == "halfway",
          "the MSG comment was shown: %r" % (m,))
    check(e.poll() is None, "nothing else was reported")

    # A long move: pause, resume, then abort it.
    with open(prog, "w") as f:
        f.write("G21 G90\nG1 X40 F300\nM2\n")
    c.program_open(prog)
    ok_or_fail(c, e, "opening the long program")
    c.auto(linuxcnc.AUTO_RUN, 0)
    # As in LinuxCNC, wait_complete() after a run waits for its end: the
    # long program is still running when a short wait gives up.
    check(c.wait_complete(0.2) == -1, "wait_complete(0.2) gives up while the long program runs")
    check(e.poll() is None, "running the long program reported nothing")
    wait(s, lambda: s.position[0] > 3.5, "the long move to start")
    c.auto(linuxcnc.AUTO_PAUSE)
    ok_or_fail(c, e, "pausing")
    wait(s, lambda: s.paused and s.interp_state == linuxcnc.INTERP_PAUSED and s.task_paused,
         "the pause to show")
    wait(s, lambda: s.current_vel == 0.0, "the pause to stop the move", timeout=10)
    held = s.position[0]
    time.sleep(0.2)
    s.poll()
    check(s.position[0] == held and held < 40, "paused at X%.3f" % held)
    check(abs(s.dtg[0] - (40 - held)) < 1e-9 and s.dtg[1:] == (0.0,) * 8,
          "dtg shows what is left of the move: %r" % (s.dtg,))
    check(s.feed_override_enabled == 1 and s.feed_hold_enabled == 1
          and s.adaptive_feed_enabled == 0, "override enables as after start-up")
    check(s.kinematics_type == linuxcnc.KINEMATICS_IDENTITY, "trivkins is identity kinematics")
    check(s.call_level == 0 and s.rotation_xy == 0.0, "main program, no rotation")
    check(s.spindle[0].override_enabled == 1, "the spindle override is enabled")
    c.auto(linuxcnc.AUTO_RESUME)
    ok_or_fail(c, e, "resuming")
    wait(s, lambda: s.position[0] > held + 0.2, "the move to go on")
    c.abort()
    ok_or_fail(c, e, "abort")
    wait(s, lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.inpos, "the abort to stop it")
    check(s.position[0] < 40, "the abort stopped the move at X%.3f" % s.position[0])
    c.set_analog_output(0, 2.5)
    ok_or_fail(c, e, "setting analog output 0")
    wait(s, lambda: s.aout[0] == 2.5, "motion.analog-out-00 to show", timeout=5)
    check(True, "set_analog_output sets motion.analog-out-00")


    try:
        s.delay_left
        fail("stat.delay_left gave a value")
    except NotImplementedError as err:
        check("delay_left" in str(err), "an unsupplied stat value says so: %s" % err)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
