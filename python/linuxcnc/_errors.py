"""`linuxcnc.error` and `linuxcnc.error_channel`.

The error channel carries task's messages: a program run that failed,
motion's fault and limit messages, a program's MSG comments, operator
messages (`command.error_msg` ...), as `(kind, text)` with LinuxCNC's
kinds (OPERATOR_ERROR, OPERATOR_TEXT, OPERATOR_DISPLAY). A request task
refused in this process is reported here too, as OPERATOR_ERROR, before
task's own messages. A channel reports what arrived after it was opened.
"""

import collections as _collections

from ._constants import OPERATOR_ERROR

# The most refusals kept unread; older ones are dropped first.
_KEPT = 256


class error(Exception):  # noqa: N801  (LinuxCNC's name)
    """A request could not reach task (no machine runs, no answer)."""


_refusals = _collections.deque(maxlen=_KEPT)


def _report(text):
    """Keeps a refusal for the error channels of this process."""
    _refusals.append((OPERATOR_ERROR, text))


def _messages_after(seq):
    """Task's newest message number and its messages after `seq`."""
    from . import _session

    done, text = _session.request(["messages", seq])
    if not done:
        raise error("task refused its messages: " + text)
    lines = text.splitlines()
    if not lines or not lines[0].isdigit():
        raise error("task's messages answer does not start with a number: %r" % text[:80])
    newest = int(lines[0])
    found = []
    for line in lines[1:]:
        n, kind, rest = (line.split(" ", 2) + ["", ""])[:3]
        if not kind.lstrip("-").isdigit():
            raise error("task's message line is not SEQ KIND TEXT: %r" % line)
        found.append((int(kind), rest))
    return newest, found


class error_channel:  # noqa: N801  (LinuxCNC's name)
    """Task's messages from now on (`linuxcnc.error` if no machine runs)."""

    def __init__(self):
        self._seen, _ = _messages_after(2**63)
        self._queue = _collections.deque()

    def poll(self):
        """The next message as `(kind, text)`, or None if there is none."""
        if _refusals:
            return _refusals.popleft()
        if not self._queue:
            self._seen, found = _messages_after(self._seen)
            self._queue.extend(found)
        if self._queue:
            return self._queue.popleft()
        return None
