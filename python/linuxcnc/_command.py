"""`linuxcnc.command`: requests to task in LinuxCNC's method names.

Each method sends one request and returns once task has answered (an
e-stop reset waits for the e-stop chain, a mode change for motion); a
refusal goes to the error channel and makes `wait_complete()` return
RCS_ERROR, as in LinuxCNC. `wait_complete()` after `mdi()` waits until
the MDI line has run, and after `auto(AUTO_RUN)` until the program has
ended (LinuxCNC's task reports a run as executing until its interpreter
is idle again), or -1 once its timeout passes. Methods task has no request for raise
NotImplementedError naming them.
"""

import os

from . import _constants as k
from . import _errors, _session

_AXES = "xyzabcuvw"

_STATES = {
    k.STATE_ESTOP: ["estop"],
    k.STATE_ESTOP_RESET: ["estop-reset"],
    k.STATE_ON: ["machine-on"],
    k.STATE_OFF: ["machine-off"],
}
_MODES = {k.MODE_MANUAL: "manual", k.MODE_AUTO: "auto", k.MODE_MDI: "mdi"}
_AUTO = {k.AUTO_PAUSE: "pause", k.AUTO_RESUME: "resume", k.AUTO_STEP: "step"}


def _on_off(v):
    return "on" if v else "off"


def _choice(table, value, what):
    try:
        return table[value]
    except (KeyError, TypeError):
        raise ValueError("linuxcnc.command.%s: unknown value %r" % (what, value)) from None


class command:  # noqa: N801  (LinuxCNC's name)
    """Sends commands to task."""

    def __init__(self):
        self._waits_for_run = False

    @property
    def serial(self):
        """The serial number of the last command sent from this process."""
        return _session.serial

    def _send(self, words, waits_for_run=False):
        _session.serial += 1
        done, text = _session.request(words)
        self._waits_for_run = done and waits_for_run
        _session.status = k.RCS_DONE if done else k.RCS_ERROR
        if not done:
            _errors._report(text)

    def wait_complete(self, timeout=5.0):
        """RCS_DONE or RCS_ERROR for the last command, -1 if an MDI line
        or program run it started has not ended within `timeout` seconds."""
        if not self._waits_for_run or _session.status != k.RCS_DONE:
            return _session.status
        try:
            done, text = _session.request(["wait-done"], timeout=timeout)
        except _errors.error:
            return -1
        self._waits_for_run = False
        if not done:
            # The failure itself is on task's error channel already.
            _session.status = k.RCS_ERROR
        return _session.status

    # The machine and its modes.

    def state(self, state):
        """STATE_ESTOP, STATE_ESTOP_RESET, STATE_ON or STATE_OFF."""
        self._send(_choice(_STATES, state, "state"))

    def mode(self, mode):
        """MODE_MANUAL, MODE_AUTO or MODE_MDI."""
        self._send(["mode", _choice(_MODES, mode, "mode")])

    def abort(self):
        """Stops motion, the program and any tool handshake."""
        self._send(["abort"])

    def teleop_enable(self, enable):
        """Jogs move world axes (true) or joints (false)."""
        self._send(["teleop", _on_off(enable)])

    # Programs and MDI.

    def mdi(self, text):
        """Runs a line of G-code (MDI mode)."""
        self._send(["mdi", text], waits_for_run=True)

    def program_open(self, path):
        """Opens a G-code program (a relative path from the current directory)."""
        self._send(["open", os.path.abspath(os.fspath(path))])

    def auto(self, what, line=0):
        """AUTO_RUN (from `line`), AUTO_PAUSE, AUTO_RESUME or AUTO_STEP."""
        if what == k.AUTO_RUN:
            return self._send(["run", int(line)], waits_for_run=True)
        if what in (k.AUTO_REVERSE, k.AUTO_FORWARD):
            raise NotImplementedError(
                "linuxcnc.command.auto(AUTO_REVERSE/AUTO_FORWARD): task cannot run backwards"
            )
        self._send([_choice(_AUTO, what, "auto")])

    def set_optional_stop(self, on):
        """M1 stops the program (true) or is passed over."""
        self._send(["optional-stop", _on_off(on)])

    def set_block_delete(self, on):
        """Lines starting with / are skipped (true) or run."""
        self._send(["block-delete", _on_off(on)])

    def set_feed_hold(self, on):
        """Whether motion.feed-hold holds the moves (M53)."""
        self._send(["feed-hold", _on_off(on)])

    # Homing and jogging (MANUAL mode).

    def home(self, joint):
        """Homes a joint, or every joint for -1."""
        self._send(["home", "all" if joint == -1 else int(joint)])

    def unhome(self, joint):
        """Forgets a joint's home, or every joint's for -1."""
        self._send(["unhome", "all" if joint == -1 else int(joint)])

    def jog(self, kind, joint_mode, index, velocity=None, distance=None):
        """JOG_STOP, JOG_CONTINUOUS (velocity) or JOG_INCREMENT (velocity,
        distance) of joint `index` (joint_mode true) or axis `index`."""
        if joint_mode:
            what = str(int(index))
        elif 0 <= int(index) < len(_AXES):
            what = _AXES[int(index)]
        else:
            raise ValueError("linuxcnc.command.jog: axis index %r is not 0..8" % index)
        if kind == k.JOG_STOP:
            return self._send(["jog-stop", what])
        if velocity is None:
            raise ValueError("linuxcnc.command.jog: a velocity is needed")
        if kind == k.JOG_CONTINUOUS:
            return self._send(["jog-cont", what, float(velocity)])
        if kind == k.JOG_INCREMENT:
            if distance is None:
                raise ValueError("linuxcnc.command.jog(JOG_INCREMENT): a distance is needed")
            return self._send(["jog-incr", what, float(velocity), float(distance)])
        raise ValueError("linuxcnc.command.jog: unknown jog kind %r" % kind)

    def override_limits(self):
        """Overrides tripped hard limits until the next jog ends."""
        self._send(["override-limits"])

    def tool_offset(self, toolno, z_offset, x_offset, diameter, frontangle, backangle,
                    orientation):
        """Sets a tool's values in the tool table (saved), as G10 L1 does."""
        words = [str(int(toolno))]
        words += [repr(float(v)) for v in (z_offset, x_offset, diameter, frontangle, backangle)]
        words.append(str(int(orientation)))
        self._send(["tool-offset"] + words)

    def traj_mode(self, mode):
        """The trajectory mode: TRAJ_MODE_FREE, TRAJ_MODE_COORD or
        TRAJ_MODE_TELEOP."""
        words = {
            k.TRAJ_MODE_FREE: "free",
            k.TRAJ_MODE_COORD: "coord",
            k.TRAJ_MODE_TELEOP: "teleop",
        }
        if mode not in words:
            raise ValueError("linuxcnc.command.traj_mode: unknown mode %r" % (mode,))
        self._send(["traj-mode", words[mode]])

    def set_min_limit(self, axis, limit):
        """The lower soft limit of world axis `axis` (0-8, X..W)."""
        self._send(["axis-limit", str(int(axis)), "min", repr(float(limit))])

    def set_max_limit(self, axis, limit):
        """The upper soft limit of world axis `axis` (0-8, X..W)."""
        self._send(["axis-limit", str(int(axis)), "max", repr(float(limit))])

    # Overrides.

    def feedrate(self, scale):
        """The feed override (1.0 = 100 %)."""
        self._send(["feed-override", float(scale)])

    def rapidrate(self, scale):
        """The rapid override (0 to 1)."""
        self._send(["rapid-override", float(scale)])

    def set_feed_override(self, enable):
        """Whether the feed and rapid overrides apply (as M50)."""
        self._send(["feed-override-enable", _on_off(enable)])

    def set_spindle_override(self, enable, spindle=0):
        """Whether the spindle override applies (as M51). Motion keeps
        one enable for every spindle, so only spindle 0 is named."""
        if int(spindle) != 0:
            raise NotImplementedError(
                "linuxcnc.command.set_spindle_override: one enable covers every "
                "spindle here; name spindle 0"
            )
        self._send(["spindle-override-enable", _on_off(enable)])

    def maxvel(self, velocity):
        """The tool-tip speed limit, machine units per second."""
        self._send(["max-velocity", float(velocity)])

    # Spindle, coolant, outputs, tools.

    def spindle(self, direction, speed=None, number=0, wait_for_speed=None):
        """SPINDLE_FORWARD, SPINDLE_REVERSE (at `speed`, else the S in
        effect), SPINDLE_OFF, SPINDLE_INCREASE or SPINDLE_DECREASE of
        spindle `number`, as LinuxCNC's (direction, speed, spindle, wait).
        Starting a spindle answers at once: `wait_for_speed` changes nothing."""
        number = int(number)
        if direction in (k.SPINDLE_FORWARD, k.SPINDLE_REVERSE):
            words = ["spindle", number, "forward" if direction > 0 else "reverse"]
            if speed is not None:
                words.append(abs(float(speed)))
            return self._send(words)
        if direction == k.SPINDLE_CONSTANT:
            raise NotImplementedError("linuxcnc.command.spindle(SPINDLE_CONSTANT)")
        actions = {
            k.SPINDLE_OFF: "off",
            k.SPINDLE_INCREASE: "increase",
            k.SPINDLE_DECREASE: "decrease",
        }
        self._send(["spindle", number, _choice(actions, direction, "spindle")])

    def brake(self, what, number=0):
        """BRAKE_ENGAGE or BRAKE_RELEASE of a spindle."""
        on = _choice({k.BRAKE_ENGAGE: "on", k.BRAKE_RELEASE: "off"}, what, "brake")
        self._send(["spindle", int(number), "brake", on])

    def spindleoverride(self, scale, number=0):
        """A spindle's override (1.0 = 100 %)."""
        self._send(["spindle", int(number), "override", float(scale)])

    def flood(self, on):
        """FLOOD_ON or FLOOD_OFF."""
        self._send(["coolant", "flood", _on_off(on == k.FLOOD_ON)])

    def mist(self, on):
        """MIST_ON or MIST_OFF."""
        self._send(["coolant", "mist", _on_off(on == k.MIST_ON)])

    def set_digital_output(self, index, value):
        """motion.digital-out-NN, at once."""
        self._send(["set-dout", int(index), _on_off(value)])

    def set_analog_output(self, index, value):
        """motion.analog-out-NN, at once."""
        self._send(["set-aout", int(index), float(value)])

    def reset_interpreter(self):
        """Starts the interpreter afresh (refused while something runs)."""
        self._send(["reset-interpreter"])

    def load_tool_table(self):
        """Reads the tool table file again."""
        self._send(["reload-tool-table"])

    # Operator messages, for every error channel.

    def error_msg(self, text):
        """An OPERATOR_ERROR message."""
        self._send(["message", "error", text])

    def text_msg(self, text):
        """An OPERATOR_TEXT message."""
        self._send(["message", "text", text])

    def display_msg(self, text):
        """An OPERATOR_DISPLAY message."""
        self._send(["message", "display", text])

    def __getattr__(self, name):
        if name in _NOT_SUPPLIED:
            raise NotImplementedError(
                "linuxcnc.command.%s is not supported by this machine's task" % name
            )
        raise AttributeError("linuxcnc.command has no attribute %r" % name)


# LinuxCNC's command methods task has no request for (yet).
_NOT_SUPPLIED = frozenset(
    """debug set_adaptive_feed task_plan_synch""".split()
)
