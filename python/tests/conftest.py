"""Live HAL instances for the tests of the `hal` module.

Each test gets an instance of its own (started with `realtime start`,
stopped afterwards), named uniquely so that tests and test runs can run
side by side. `HAL_INSTANCE` is set to it for the test process and every
program the test starts, and PATH begins with the directory of this
Python, so that `#!/usr/bin/env python3` scripts started by `loadusr` find
the same `hal` module.

The HAL tools are taken from `HAL_BIN_DIR` if set, else from the
workspace's target/debug (what `cargo test` builds) or target/release.
"""

import itertools
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).resolve().parent / "scripts"


def _bin_dir():
    if os.environ.get("HAL_BIN_DIR"):
        return Path(os.environ["HAL_BIN_DIR"])
    for profile in ("debug", "release"):
        d = REPO / "target" / profile
        if (d / "halcmd").exists() and (d / "hal-host").exists():
            return d
    pytest.exit("HAL tools not built: run `cargo build --workspace` or set HAL_BIN_DIR")


BIN = _bin_dir()
os.environ["PATH"] = os.pathsep.join(
    [str(Path(sys.executable).parent), str(BIN), os.environ.get("PATH", "")]
)
# Never ask for realtime scheduling in tests: they run side by side.
os.environ["HAL_NO_REALTIME"] = "1"

_names = itertools.count()


def wait_for(cond, timeout=20.0, what="condition"):
    """Waits until cond() is true; fails the test after `timeout` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return
        time.sleep(0.005)
    pytest.fail("timed out waiting for " + what)


class Hal:
    """A running HAL instance and ways to drive it from outside Python."""

    def __init__(self, name):
        self.name = name

    def run(self, *args, check=True, timeout=120, **kw):
        """Runs a HAL tool (`halcmd`, `halrun`, ...) on this instance."""
        r = subprocess.run(
            [str(a) for a in args], capture_output=True, text=True, timeout=timeout, **kw
        )
        if check and r.returncode != 0:
            pytest.fail("%s failed (%d):\n%s%s" % (args, r.returncode, r.stdout, r.stderr))
        return r

    def halcmd(self, *args, check=True):
        return self.run("halcmd", *args, check=check)

    def script(self, name, *args):
        """Starts one of the test scripts as a process of its own."""
        return subprocess.Popen(
            [str(SCRIPTS / name), *map(str, args)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )


@pytest.fixture
def hal_instance():
    import hal

    name = "pyt-%d-%d" % (os.getpid(), next(_names))
    os.environ["HAL_INSTANCE"] = name
    inst = Hal(name)
    inst.run("realtime", "start")
    try:
        yield inst
    finally:
        hal._hal._exit_all()
        inst.run("realtime", "stop", check=False)


@pytest.fixture
def hal_instance_name():
    """A unique instance name in HAL_INSTANCE, for a test whose program
    starts the instance itself; stopped afterwards whatever happened."""
    import hal

    name = "pyt-%d-%d" % (os.getpid(), next(_names))
    os.environ["HAL_INSTANCE"] = name
    try:
        yield name
    finally:
        hal._hal._exit_all()
        subprocess.run(["realtime", "stop"], capture_output=True, timeout=120)


@pytest.fixture
def children():
    """Processes a test starts; killed at the end if still running."""
    procs = []
    yield procs
    for p in procs:
        if p.poll() is None:
            p.send_signal(signal.SIGKILL)
        p.wait()
