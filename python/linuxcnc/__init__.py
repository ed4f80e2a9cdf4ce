"""LinuxCNC's Python interface (`import linuxcnc`), on this machine's task.

    import linuxcnc
    c = linuxcnc.command()
    s = linuxcnc.stat()
    e = linuxcnc.error_channel()
    c.state(linuxcnc.STATE_ESTOP_RESET)
    c.state(linuxcnc.STATE_ON)
    c.home(-1)
    s.poll()
    print(s.task_state, s.homed, s.position)

It talks to the task of the machine `linuxcnc MACHINE.ini` runs on the
HAL instance `HAL_INSTANCE` names (`default` if unset); the launcher sets
it for the display program it starts. `stat` takes whatever status task
supplies; LinuxCNC's names that task does not supply, and `command`
methods it has no request for, raise NotImplementedError naming them.
`linuxcnc.ini(path)` reads an INI file.
"""

from ._command import command  # noqa: F401
from ._constants import *  # noqa: F401,F403
from ._errors import error, error_channel  # noqa: F401
from ._ini import ini  # noqa: F401
from ._stat import stat  # noqa: F401
