"""LinuxCNC's own Python HAL tests, run unchanged against this HAL.

The scripts and the expected output are LinuxCNC's (see
third_party/linuxcnc/README.md); this file is the harness that runs them
as LinuxCNC's test runner would: the query test's standard output must
equal LinuxCNC's `expected` byte for byte, and the pyhal test (which has
no expected output) must exit with status 0.
"""

import difflib
import os
import subprocess
import sys
from pathlib import Path

LINUXCNC = Path(__file__).resolve().parent / "third_party" / "linuxcnc"


def _run(script, cwd, timeout=120):
    """Runs one of LinuxCNC's scripts with this Python (whose `hal` and
    `pyhal` are the ones under test) on the instance HAL_INSTANCE names."""
    return subprocess.run(
        [sys.executable, str(script)],
        cwd=str(cwd),
        capture_output=True,
        timeout=timeout,
        env=os.environ.copy(),
    )


def _explain(r):
    return "exit status %d\n--- stdout\n%s\n--- stderr\n%s" % (
        r.returncode,
        r.stdout.decode(errors="replace"),
        r.stderr.decode(errors="replace"),
    )


def test_halmodule_3_query_output_matches_linuxcnc(hal_instance):
    here = LINUXCNC / "halmodule.3"
    hal_instance.halcmd("-f", str(here / "setup.hal"))
    r = _run(here / "halquerytest.py", here)
    assert r.returncode == 0, _explain(r)
    expected = (here / "expected").read_bytes()
    if r.stdout != expected:
        diff = difflib.unified_diff(
            expected.decode().splitlines(keepends=True),
            r.stdout.decode(errors="replace").splitlines(keepends=True),
            "LinuxCNC's expected",
            "ours",
        )
        raise AssertionError("halmodule.3 output differs:\n" + "".join(diff))


def test_pyhal_test_passes(hal_instance_name):
    # The script starts the instance itself (`realtime start`) and stops it
    # (`halrun -U`); the fixture stops it if the script did not get there.
    here = LINUXCNC / "pyhal"
    r = _run(here / "test", here)
    assert r.returncode == 0, _explain(r)
