"""`linuxcnc.stat`: task's status snapshot as attributes.

`poll()` asks task for its `stat` snapshot, lines of `NAME=KIND:VALUE`
in LinuxCNC's names; every name that arrives becomes an attribute, and
`LIST.INDEX.FIELD` names become a tuple of records (dicts whose fields
also read as attributes). A LinuxCNC status name that task does not
supply raises NotImplementedError naming it.
"""

import os

from . import _session

# LinuxCNC's status names (its stat's attributes). One that task's
# snapshot does not hold (not supplied yet, or no motion controller is
# loaded) raises NotImplementedError naming it.
_LINUXCNC_NAMES = frozenset(
    """acceleration active_queue actual_position adaptive_feed_enabled ain
    angular_units aout axis axis_mask block_delete call_level command
    current_line current_vel cycle_time debug delay_left din
    distance_to_go dout dtg echo_serial_number enabled estop exec_state
    feed_hold_enabled feed_override_enabled feedrate file flood g5x_index
    g5x_offset g92_offset gcodes homed ini_filename inpos input_timeout
    interp_state interpreter_errcode joint joint_actual_position
    joint_position joints kinematics_type limit linear_units lube
    lube_level max_acceleration max_velocity mcodes misc_error mist
    motion_id motion_line motion_mode motion_type num_extrajoints
    optional_stop paused pocket_prepped position probe_tripped probe_val
    probed_position probing program_units queue queue_full
    queued_mdi_commands rapidrate read_line rotation_xy settings spindle
    spindles state task_mode task_paused task_state tool_from_pocket
    tool_in_spindle tool_offset tool_table velocity""".split()
)


# The status names LinuxCNC 2.9's module gives as Python bools (True or
# False, printed so), read from its stat on the 2.9 peer; task sends them
# as integers.
_BOOL_NAMES = frozenset(
    """adaptive_feed_enabled block_delete enabled feed_hold_enabled
    feed_override_enabled inpos input_timeout optional_stop paused
    probe_tripped probing queue_full""".split()
)

# The fields of list records that are bools there, per list.
_BOOL_FIELDS = {"spindle": frozenset(("override_enabled", "homed"))}

# The order of a list record's fields in LinuxCNC 2.9's module (a printed
# record lists them so); fields task sends that are not named here follow.
_FIELD_ORDER = {
    "joint": """jointType units backlash min_position_limit
    max_position_limit max_ferror min_ferror ferror_current ferror_highmark
    output input velocity inpos homing homed fault enabled min_soft_limit
    max_soft_limit min_hard_limit max_hard_limit override_limits""".split(),
    "axis": "velocity min_position_limit max_position_limit".split(),
    "spindle": """brake direction enabled override_enabled speed override
    homed orient_state orient_fault""".split(),
}


class _Record(dict):
    """A record of a status list: a dict whose keys read as attributes."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None


def _value(kind, text):
    if kind == "i":
        return int(text)
    if kind == "f":
        return float(text)
    if kind == "s":
        return text
    if kind == "I":
        return tuple(int(w) for w in text.split())
    if kind == "F":
        return tuple(float(w) for w in text.split())
    raise ValueError("unknown kind %r" % kind)


def _as_linuxcncs(lst, record):
    """`record` of list `lst` with LinuxCNC's field order and bools."""
    order = _FIELD_ORDER.get(lst, ())
    bools = _BOOL_FIELDS.get(lst, ())
    out = _Record()
    known = [f for f in order if f in record]
    for field in known + [f for f in record if f not in order]:
        v = record[field]
        out[field] = bool(v) if field in bools else v
    return out


def parse(text):
    """The snapshot's lines as a dict of attribute values."""
    values = {}
    lists = {}
    for n, line in enumerate(text.splitlines(), 1):
        name, sep, rest = line.partition("=")
        kind, sep2, raw = rest.partition(":")
        if not (sep and sep2):
            raise ValueError("stat line %d is not NAME=KIND:VALUE: %r" % (n, line))
        v = _value(kind, raw)
        parts = name.split(".")
        if len(parts) == 3:
            lst, index, field = parts
            lists.setdefault(lst, {}).setdefault(int(index), _Record())[field] = v
        else:
            values[name] = v
    for lst, records in lists.items():
        values[lst] = tuple(
            _as_linuxcncs(lst, records[i]) for i in sorted(records)
        )
    for name in _BOOL_NAMES.intersection(values):
        values[name] = bool(values[name])
    if "axis_mask" in values:
        # LinuxCNC 2.7's name, gone from 2.9's module but still read by
        # many of its test scripts: how many axes the machine has.
        values["axes"] = bin(values["axis_mask"]).count("1")
    return values


class stat:  # noqa: N801  (LinuxCNC's name)
    """Task's status; `poll()` brings it up to date."""

    def __init__(self):
        self._values = None

    def poll(self):
        """Reads task's status now (`linuxcnc.error` if no machine runs)."""
        done, text = _session.request(["stat"])
        if not done:
            raise _session.error("task refused its status: " + text)
        values = parse(text)
        values["state"] = _session.status
        values["echo_serial_number"] = _session.serial
        values["ini_filename"] = os.environ.get("INI_FILE_NAME", "")
        self._values = values

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        if self._values is None:
            self.poll()
        try:
            return self._values[name]
        except KeyError:
            pass
        if name in _LINUXCNC_NAMES:
            raise NotImplementedError(
                "linuxcnc.stat.%s is not supplied by this machine's task" % name
            )
        raise AttributeError("linuxcnc.stat has no attribute %r" % name)

    def __dir__(self):
        if self._values is None:
            return ["poll"]
        return ["poll"] + sorted(self._values)
