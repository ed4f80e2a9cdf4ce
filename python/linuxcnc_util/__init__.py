"""LinuxCNC's `linuxcnc_util` helpers for test scripts, on this machine's
`linuxcnc` module: `LinuxCNC(command, status, error)` with waits for the
start-up, homing, an axis at rest, the interpreter's state and a tool in
the spindle, and a continuous jog to a target. A wait that runs out of
time raises `LinuxCNC_Exception` (`RuntimeError` for the start-up, as in
LinuxCNC)."""

import math
import time

import linuxcnc

_AXES = "xyzabcuvw"


class LinuxCNC_Exception(Exception):  # noqa: N801  (LinuxCNC's name)
    """A wait ran out of time, or a jog moved what it should not."""


def _axis(letter):
    try:
        return _AXES.index(letter.lower())
    except ValueError:
        raise ValueError("not an axis letter: %r (one of %s)" % (letter, _AXES)) from None


class LinuxCNC:
    """A command, stat and error channel (made if not given) and waits."""

    def __init__(self, command=None, status=None, error=None):
        self.command = command or linuxcnc.command()
        self.status = status or linuxcnc.stat()
        self.error = error or linuxcnc.error_channel()

    def _until(self, done, timeout, pause):
        """Polls until done() holds; False if `timeout` ran out first."""
        end = time.time() + timeout
        while time.time() < end:
            self.status.poll()
            if done():
                return True
            time.sleep(pause)
        return False

    def wait_for_linuxcnc_startup(self, timeout=10.0):
        """Returns once the status looks like a machine that has started
        (in e-stop, idle, at rest, its settings known)."""
        s = self.status

        def started():
            settings = (s.angular_units, s.linear_units, s.cycle_time, s.max_acceleration,
                        s.max_velocity, s.program_units, s.rapidrate, s.axis_mask)
            return (all(v != 0 for v in settings)
                    and s.exec_state == linuxcnc.EXEC_DONE
                    and s.interp_state == linuxcnc.INTERP_IDLE
                    and s.inpos
                    and s.state == linuxcnc.RCS_DONE
                    and s.task_state == linuxcnc.STATE_ESTOP)

        if not self._until(started, timeout, 0.1):
            raise RuntimeError("the machine did not start within %s seconds" % timeout)

    def all_joints_homed(self, joints):
        """Whether every joint whose entry in `joints` is true is homed."""
        self.status.poll()
        return all(self.status.homed[i] for i, want in enumerate(joints[:9]) if want)

    def wait_for_home(self, joints, timeout=10.0):
        """Waits until the joints `joints` marks are homed."""
        end = time.time() + timeout
        while time.time() < end:
            if self.all_joints_homed(joints):
                return
            time.sleep(0.1)
        raise LinuxCNC_Exception(
            "timeout waiting for homing to complete:\nstatus.homed:%s\nstatus.position:%s"
            % (self.status.homed, self.status.position)
        )

    def wait_for_axis_to_stop(self, axis_letter, timeout=10.0):
        """Waits until the axis's commanded position stays put for 0.1 s."""
        i = _axis(axis_letter)
        print("waiting for axis", axis_letter.lower(), "to stop")
        self.status.poll()
        last = self.status.position[i]
        end = time.time() + timeout
        while time.time() < end:
            time.sleep(0.1)
            self.status.poll()
            now = self.status.position[i]
            if now == last:
                return
            last = now
        raise LinuxCNC_Exception(
            "axis %s is still moving after %.3f seconds (at %.3f)"
            % (axis_letter, timeout, self.status.position[i])
        )

    def jog_axis(self, axis_letter, target, vel=5.0, timeout=10.0):
        """Jogs the axis continuously towards `target`, stops it once past,
        waits for it to stop; no other axis may move."""
        self.status.poll()
        i = _axis(axis_letter)
        start = self.status.position
        print("jogging axis %s from %.3f to %.3f" % (axis_letter.lower(), start[i], target))
        upwards = start[i] < target

        def past():
            p = self.status.position[i]
            return p > target if upwards else p < target

        speed = abs(vel) if upwards else -abs(vel)
        self.command.jog(linuxcnc.JOG_CONTINUOUS, 0, i, speed)
        reached = past() or self._until(past, timeout, 0.1)
        self.command.jog(linuxcnc.JOG_STOP, 0, i)
        if not reached:
            raise LinuxCNC_Exception(
                "failed to jog axis %s to %.3f: at %.3f after %.3f seconds"
                % (axis_letter, target, self.status.position[i], timeout)
            )
        print("    jogged axis %d past target %.3f" % (i, target))
        self.wait_for_axis_to_stop(axis_letter)
        for j in range(9):
            if j != i and start[j] != self.status.position[j]:
                raise LinuxCNC_Exception(
                    "axis %s moved from %.3f to %.3f but should not have"
                    % (_AXES[j], start[j], self.status.position[j])
                )

    def wait_for_axis_to_stop_at(self, axis_letter, target, timeout=10.0, tolerance=0.0001):
        """Waits until the axis is at rest within `tolerance` of `target`."""
        i = _axis(axis_letter)
        self.status.poll()
        last = self.status.position[i]
        end = time.time() + timeout
        while time.time() < end:
            self.status.poll()
            now = self.status.position[i]
            if math.fabs(now - target) < tolerance and now == last:
                print("axis %s stopped at %.3f" % (axis_letter.lower(), target))
                return
            last = now
            time.sleep(0.1)
        raise LinuxCNC_Exception(
            "timeout waiting for axis %s to stop at %.3f (at %.3f)"
            % (axis_letter, target, self.status.position[i])
        )

    def wait_for_interp_state(self, target_state, timeout=10.0):
        """Waits until the interpreter is in `target_state` (INTERP_*)."""
        if not self._until(lambda: self.status.interp_state == target_state, timeout, 0.001):
            raise LinuxCNC_Exception(
                "interpreter state %d did not reach target state %d"
                % (self.status.interp_state, target_state)
            )

    def wait_for_tool_in_spindle(self, expected_tool, timeout=10.0):
        """Waits until `expected_tool` is in the spindle."""
        begun = time.time()
        if not self._until(lambda: self.status.tool_in_spindle == expected_tool, timeout, 0.1):
            raise LinuxCNC_Exception(
                "the tool in the spindle is %d, expected %d"
                % (self.status.tool_in_spindle, expected_tool)
            )
        print(
            "the Stat buffer's toolInSpindle reached the value of %d after %f seconds"
            % (expected_tool, time.time() - begun)
        )
