"""`linuxcnc.error` and `linuxcnc.error_channel`.

Task answers every request of `linuxcnc.command` at once; a refusal is
kept here, in this process, and `error_channel().poll()` returns it as
`(NML_ERROR, text)`, as LinuxCNC's error channel reports task's refusals.
"""

import collections as _collections

from ._constants import NML_ERROR

# The most refusals kept unread; older ones are dropped first.
_KEPT = 256


class error(Exception):  # noqa: N801  (LinuxCNC's name)
    """A request could not reach task (no machine runs, no answer)."""


_pending = _collections.deque(maxlen=_KEPT)


def _report(text):
    """Keeps a refusal for the error channels of this process."""
    _pending.append((NML_ERROR, text))


class error_channel:  # noqa: N801  (LinuxCNC's name)
    """The messages task's refusals left, oldest first."""

    def poll(self):
        """The next message as `(kind, text)`, or None if there is none."""
        if _pending:
            return _pending.popleft()
        return None
