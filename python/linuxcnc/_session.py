"""What `command` and `stat` share in this process: the requests to task,
the serial number of the last command and how it ended."""

from hal import _hal

from ._constants import RCS_DONE
from ._errors import error

# The serial number of the last command sent, and its status (RCS_DONE
# or RCS_ERROR: task answers every request before the call returns).
serial = 0
status = RCS_DONE

# How long one request may take: task answers most at once, an e-stop
# reset or a mode change within a second or two.
REQUEST_TIMEOUT = 30.0


def request(words, timeout=REQUEST_TIMEOUT):
    """Sends `words` to task: `(done, text)`; `linuxcnc.error` when no
    machine runs or the answer does not come."""
    try:
        return _hal._task_request([str(w) for w in words], float(timeout))
    except OSError as e:
        raise error(str(e)) from e
