"""LinuxCNC's Python HAL interface, on this HAL.

Creates user-space HAL components in Python, with pins and parameters of
every HAL type, and works on the HAL instance as a whole (signals, values
by name, listings, sampler and streamer FIFOs). `hal.query` describes every
pin, param, signal, component, function and thread as dicts.

Typical use:

    import hal, time
    h = hal.component("passthrough")
    h.newpin("in", hal.HAL_FLOAT, hal.HAL_IN)
    h.newpin("out", hal.HAL_FLOAT, hal.HAL_OUT)
    h.ready()
    try:
        while True:
            time.sleep(0.1)
            h["out"] = h["in"]
    except KeyboardInterrupt:
        pass

`halcmd unload` (SIGTERM) raises KeyboardInterrupt in the main thread. The
instance is the one `HAL_INSTANCE` names (`default` if unset); `loadusr`
sets it for the programs it starts. A component is removed from the HAL
when it is garbage-collected, when `exit()` is called, when the
interpreter exits, and, by the HAL host, when the process dies in any
other way.
"""

import atexit as _atexit
import enum as _enum
import signal as _signal

from . import _hal
from ._hal import *  # noqa: F401,F403  (the module's API, as LinuxCNC's)
from ._hal import error, item, stream  # noqa: F401

# hal.Type and hal.Dir: the type and direction numbers as IntEnums. The
# first spelling of a value is the canonical member, later ones aliases.
Type = _enum.IntEnum(
    "Type",
    [
        ("BOOL", HAL_BOOL),  # noqa: F405
        ("SINT", HAL_SINT),  # noqa: F405
        ("UINT", HAL_UINT),  # noqa: F405
        ("REAL", HAL_REAL),  # noqa: F405
        ("PORT", HAL_PORT),  # noqa: F405
        ("BIT", HAL_BIT),  # noqa: F405
        ("S32", HAL_S32),  # noqa: F405
        ("U32", HAL_U32),  # noqa: F405
        ("FLOAT", HAL_FLOAT),  # noqa: F405
        ("S64", HAL_S64),  # noqa: F405
        ("U64", HAL_U64),  # noqa: F405
    ],
    module=__name__,
)
Dir = _enum.IntEnum(
    "Dir",
    [
        ("IN", HAL_IN),  # noqa: F405
        ("OUT", HAL_OUT),  # noqa: F405
        ("IO", HAL_IO),  # noqa: F405
        ("RO", HAL_RO),  # noqa: F405
        ("WO", HAL_WO),  # noqa: F405
        ("RW", HAL_RW),  # noqa: F405
    ],
    module=__name__,
)

# hal.CompType: the kinds of component `hal.query` reports, LinuxCNC's
# numbers.
CompType = _enum.IntEnum(
    "CompType",
    [("UNKNOWN", -1), ("USER", 0), ("REALTIME", 1), ("OTHER", 2)],
    module=__name__,
)


class _ItemWrap:
    """A pin or param as `newpin`/`newparam` return it: the item's methods
    plus `name`, `type`, `dir` and a read-write `value` property."""

    __slots__ = ("_item",)

    def __init__(self, it):
        if not isinstance(it, item):
            raise TypeError("Constructor argument must be hal.item: %s" % type(it))
        self._item = it

    def get(self):
        return self._item.get()

    def set(self, value):
        return self._item.set(value)

    def get_type(self):
        return self._item.get_type()

    def get_name(self):
        return self._item.get_name()

    def get_dir(self):
        return self._item.get_dir()

    def is_pin(self):
        return self._item.is_pin()

    def __repr__(self):
        return repr(self._item)

    name = property(lambda self: self._item.get_name())
    type = property(lambda self: self._item.get_type())
    dir = property(lambda self: self._item.get_dir())
    value = property(lambda self: self._item.get(), lambda self, v: self._item.set(v))


class Pin(_ItemWrap):
    """A pin of a component made in Python."""

    __slots__ = ()

    def __init__(self, it):
        _ItemWrap.__init__(self, it)
        if not it.is_pin():
            raise TypeError("Must be constructed from pin object")


class Param(_ItemWrap):
    """A parameter of a component made in Python."""

    __slots__ = ()

    def __init__(self, it):
        _ItemWrap.__init__(self, it)
        if it.is_pin():
            raise TypeError("Must be constructed from param object")


class component(_hal.component):
    """A HAL component: `component(name[, prefix])`. Pins and params are
    created with `newpin(name, type, dir)` and `newparam(name, type, dir)`
    under `prefix.name` (the prefix defaults to the component's name), and
    read and written as `c["name"]` or `c.name`."""

    def newpin(self, *a, **kw):
        return Pin(_hal.component.newpin(self, *a, **kw))

    def newparam(self, *a, **kw):
        return Param(_hal.component.newparam(self, *a, **kw))

    def getpin(self, *a, **kw):
        return Pin(_hal.component.getpin(self, *a, **kw))

    def getparam(self, *a, **kw):
        return Param(_hal.component.getparam(self, *a, **kw))


# hal.query needs Type, Dir and CompType above.
from . import query  # noqa: E402,F401

# Components leave the HAL when the interpreter exits, however it exits.
_atexit.register(_hal._exit_all)

# `halcmd unload` sends SIGTERM: raise KeyboardInterrupt, as LinuxCNC does,
# so that the usual `except KeyboardInterrupt` loop ends cleanly. Only the
# main thread may install handlers; a program that imports hal elsewhere
# keeps its own.
try:
    if _signal.getsignal(_signal.SIGTERM) == _signal.SIG_DFL:
        _signal.signal(_signal.SIGTERM, _signal.default_int_handler)
except ValueError:
    pass
