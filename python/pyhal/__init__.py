"""LinuxCNC's newer `pyhal` binding, on this HAL.

A user-space component with pins of the five classic types, signals and
links, all in one object; errors are `HalException`s saying what failed
and where.

    from pyhal import component, halType, pinDir
    c = component("hello")
    out = c.pinNew("out", halType.FLOAT, pinDir.OUT)
    c.ready()
    out.value = 1.5

Port pins (`halType.PORT`) are `port` objects: the output end writes bytes
(`write`, `writable`), the input end reads them (`read`, `peek`,
`peek_commit`, `readable`, `clear`); the signal between them gets its
buffer from `halcmd sets SIGNAL SIZE`, and holds SIZE - 1 bytes, as
LinuxCNC's does. A read or peek of more bytes than wait gives '' and
takes nothing.

The instance is the one `HAL_INSTANCE` names (`default` if unset).
"""

import sys as _sys
import time as _time

import hal as _halpkg
from hal import _hal

__all__ = ["HalException", "halType", "pinDir", "pin", "port", "component"]


class HalException(Exception):
    """A HAL operation of `pyhal` failed; the message says which and why."""


class halType:
    """Pin and signal types, LinuxCNC's numbers."""

    BIT = 1
    FLOAT = 2
    SIGNED = 3
    UNSIGNED = 4
    PORT = 5

    values = [BIT, FLOAT, SIGNED, UNSIGNED, PORT]


class pinDir:
    """Pin directions, LinuxCNC's numbers."""

    IN = 16
    OUT = 32
    IO = IN | OUT

    values = [IN, OUT, IO]


_TYPE_NAMES = {1: "BIT", 2: "FLOAT", 3: "SIGNED", 4: "UNSIGNED", 5: "PORT"}
_DIR_NAMES = {16: "IN", 32: "OUT", 48: "IO"}


def _is_code(v, codes):
    return isinstance(v, int) and not isinstance(v, bool) and v in codes


class pin:
    """A pin of a `component`: `value` reads and writes it (a linked pin
    reads and writes its signal)."""

    def __init__(self, component, name, type, dir, item):
        self.comp = component
        self.name = name
        self.type = type
        self.dir = dir
        self._item = item

    @property
    def fullname(self):
        """The pin's name in the HAL: `component.pin`."""
        return "%s.%s" % (self.comp.name, self.name)

    @property
    def value(self):
        try:
            return self._item.get()
        except RuntimeError as e:
            raise HalException("pin %s: %s" % (self.fullname, e)) from e

    @value.setter
    def value(self, val):
        try:
            self._item.set(val)
        except (TypeError, ValueError, OverflowError, RuntimeError) as e:
            raise HalException(
                "pin %s (%s): cannot set %r: %s"
                % (self.fullname, _TYPE_NAMES[self.type], val, e)
            ) from e

    def __repr__(self):
        return "<pyhal pin %s %s %s>" % (
            self.fullname,
            _TYPE_NAMES[self.type],
            _DIR_NAMES[self.dir],
        )


class port(pin):
    """A port pin: one end of a byte stream through a port signal."""

    @property
    def value(self):
        raise HalException("pin %s: a PORT pin has no value; use read/write" % self.fullname)

    @value.setter
    def value(self, val):
        raise HalException("pin %s: a PORT pin has no value; use read/write" % self.fullname)

    def _call(self, what, *args):
        try:
            return getattr(self._item, what)(*args)
        except (TypeError, ValueError, RuntimeError) as e:
            raise HalException("port %s: %s" % (self.fullname, e)) from e

    def read(self, count):
        """Takes exactly `count` bytes; '' (nothing taken) when fewer wait."""
        got = self._call("read", count)
        return "" if got is None else got

    def peek(self, count):
        """Copies exactly `count` bytes without taking them; '' when fewer
        wait."""
        got = self._call("peek", count)
        return "" if got is None else got

    def peek_commit(self, count):
        """Takes `count` bytes already peeked at; False when fewer wait."""
        return self._call("peek_commit", count)

    def write(self, data):
        """Appends all of `data` (bytes, or str as UTF-8); False (nothing
        written) when it does not fit."""
        if isinstance(data, str):
            data = data.encode()
        return self._call("write", data)

    def readable(self):
        """Bytes waiting to be read."""
        return self._call("readable")

    def writable(self):
        """Room for bytes."""
        return self._call("writable")

    def size(self):
        """The signal's buffer size (0 while it has none)."""
        return self._call("size")

    def clear(self):
        """Drops every waiting byte."""
        self._call("clear")

    def _wait(self, what, count, ready):
        # A buffer of size bytes holds size - 1: more can never come.
        size = self.size()
        if size and count > size - 1:
            raise HalException(
                "port %s: %s(%d) would wait for ever: the buffer holds at most %d bytes"
                % (self.fullname, what, count, size - 1)
            )
        while ready() < count:
            _time.sleep(0.01)

    def waitReadable(self, count):
        """Waits until `count` bytes wait to be read."""
        self._wait("waitReadable", count, self.readable)

    def waitWritable(self, count):
        """Waits until there is room for `count` bytes."""
        self._wait("waitWritable", count, self.writable)


class component:
    """A user-space HAL component: `component(name)`. Its pins are named
    `name.pin`; `pins` holds them by their short names."""

    def __init__(self, name):
        self.name = name
        self.pins = {}
        self.id = -1
        try:
            self._comp = _halpkg.component(name)
        except (_halpkg.error, RuntimeError, TypeError) as e:
            raise HalException('failed to make component "%s": %s' % (name, e)) from e
        made = _halpkg.query.comp(name)
        self.id = made["id"] if made else -1

    def __del__(self):
        # At interpreter exit the hal package's own exit handler has
        # removed every component already.
        if _sys.is_finalizing():
            return
        try:
            self.exit()
        except (HalException, RuntimeError):
            pass

    def exit(self):
        """Removes the component and its pins from the HAL."""
        comp = self.__dict__.pop("_comp", None)
        self.id = -1
        if comp is not None:
            comp.exit()

    def _live(self, what):
        comp = self.__dict__.get("_comp")
        if comp is None:
            raise HalException("%s: component %s has exited" % (what, self.name))
        return comp

    def ready(self):
        """Marks the component ready (`loadusr -W` waits for this)."""
        try:
            self._live("ready").ready()
        except (_halpkg.error, RuntimeError) as e:
            raise HalException("ready: component %s: %s" % (self.name, e)) from e

    def pinNew(self, name, type, dir):
        """Makes pin `name.NAME` of `type` (halType) and `dir` (pinDir)."""
        full = "%s.%s" % (self.name, name)
        if not _is_code(type, halType.values):
            raise HalException(
                'failed to create pin "%s": %r is not a halType (%s)'
                % (full, type, ", ".join("%s=%d" % (n, v) for v, n in _TYPE_NAMES.items()))
            )
        if not _is_code(dir, pinDir.values):
            raise HalException(
                'failed to create pin "%s": %r is not a pinDir (IN=16, OUT=32, IO=48)'
                % (full, dir)
            )
        comp = self._live("pinNew")
        try:
            if type == halType.PORT:
                if dir == pinDir.IO:
                    raise HalException(
                        'failed to create pin "%s": a PORT pin is IN or OUT, not IO' % full
                    )
                made = port(self, name, type, dir, _hal._new_port(comp, name, dir))
            else:
                made = pin(self, name, type, dir, comp.newpin(name, type, dir)._item)
        except (_halpkg.error, RuntimeError, ValueError) as e:
            raise HalException('failed to create pin "%s": %s' % (full, e)) from e
        self.pins[name] = made
        return made

    def sigNew(self, name, type):
        """Makes signal `name` of `type` (halType)."""
        if not _is_code(type, halType.values):
            raise HalException(
                'failed to create signal "%s": %r is not a halType' % (name, type)
            )
        try:
            _hal._new_signal(name, type)
        except (_halpkg.error, RuntimeError) as e:
            raise HalException('failed to create signal "%s": %s' % (name, e)) from e

    def sigLink(self, pin_name, sig_name):
        """Links pin `pin_name` (its full name) to signal `sig_name`."""
        try:
            _hal._link(pin_name, sig_name)
        except (_halpkg.error, RuntimeError) as e:
            raise HalException(
                'failed to link pin "%s" to signal "%s": %s' % (pin_name, sig_name, e)
            ) from e

    def __repr__(self):
        return "<pyhal component %s with %d pins>" % (self.name, len(self.pins))
