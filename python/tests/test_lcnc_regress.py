"""scripts/lcnc-regress: test directories in LinuxCNC's layout, judged as
LinuxCNC's runner judges them (exit status, `expected`, `checkresult`,
`skip`, `xfail`), with our programs first on PATH."""

import os
import subprocess
import sys

import pytest

from conftest import BIN, REPO

RUNNER = REPO / "scripts" / "lcnc-regress"
# A checkresult that takes any output (a test needs one, or `expected`).
ACCEPT = "#!/bin/sh\nexit 0\n"


def _case(root, name, files):
    d = root / name
    d.mkdir(parents=True)
    for fname, text in files.items():
        f = d / fname
        f.write_text(text)
        # A `skip` is executable only when it is a script (an executable
        # skip decides by its exit status).
        if fname in ("test.sh", "test", "checkresult") or text.startswith("#!"):
            f.chmod(0o755)
    return d


def _run(*dirs, env=None):
    if not (BIN / "linuxcnc").exists():
        pytest.skip("linuxcnc is not built in %s" % BIN)
    return subprocess.run(
        [sys.executable, str(RUNNER), "--bin", str(BIN), "--timeout", "30", *map(str, dirs)],
        capture_output=True, text=True, timeout=120, env=env,
    )


def test_verdicts_follow_linuxcncs_runner(tmp_path):
    _case(tmp_path, "a-status-ok", {"test.sh": "exit 0\n"})
    _case(tmp_path, "b-status-bad", {"test.sh": "echo why >&2\nexit 3\n"})
    _case(tmp_path, "c-expected-same", {"test.sh": "echo hello\n", "expected": "hello\n"})
    _case(tmp_path, "d-expected-differs", {"test.sh": "echo hullo\n", "expected": "hello\n"})
    _case(tmp_path, "e-checkresult", {
        "test.sh": "echo 42\n",
        "checkresult": "#!/bin/sh\ngrep -qx 42 \"$1\"\n",
    })
    _case(tmp_path, "f-skipped", {"test.sh": "exit 1\n", "skip": ""})
    _case(tmp_path, "g-xfail", {"test.sh": "exit 1\n", "xfail": ""})
    # An executable skip that exits 0 lets the test run; one that exits
    # non-zero skips it.
    _case(tmp_path, "h-skip-says-run", {
        "test.sh": "echo 1\n", "expected": "1\n", "skip": "#!/bin/sh\nexit 0\n"})
    _case(tmp_path, "i-skip-says-skip", {"test.sh": "exit 1\n", "skip": "#!/bin/sh\nexit 1\n"})
    # checkresult is asked before expected.
    _case(tmp_path, "j-checkresult-first", {
        "test.sh": "echo 42\n", "expected": "41\n",
        "checkresult": "#!/bin/sh\ngrep -qx 42 \"$1\"\n"})
    r = _run(tmp_path)
    out = r.stdout
    assert r.returncode == 1, out + r.stderr
    lines = {l.split()[1].rsplit("/", 1)[-1].rstrip(":"): l.split()[0]
             for l in out.splitlines() if l[:5].strip() in ("PASS", "FAIL", "SKIP", "XFAIL")}
    assert lines == {
        "a-status-ok": "FAIL", "b-status-bad": "FAIL", "c-expected-same": "PASS",
        "d-expected-differs": "FAIL", "e-checkresult": "PASS", "f-skipped": "SKIP",
        "g-xfail": "XFAIL", "h-skip-says-run": "PASS", "i-skip-says-skip": "SKIP",
        "j-checkresult-first": "PASS",
    }, out
    assert "exit status 3" in out and "why" in out, out
    assert "-hello" in out and "+hullo" in out, out
    assert "neither expected nor checkresult" in out, out
    assert "4 passed, 3 failed, 2 skipped, 1 failed as expected" in out, out
    # The test's output stays in its directory, as LinuxCNC's runner leaves it.
    assert (tmp_path / "c-expected-same" / "result").read_text() == "hello\n"


def test_our_programs_come_first_with_a_hal_instance_of_their_own(tmp_path):
    d = _case(tmp_path, "env", {
        "test.sh": "command -v halcmd\necho \"$HAL_INSTANCE\"\n"
                   "python3 -c 'import linuxcnc, hal; print(\"modules ok\")'\n",
        "checkresult": ACCEPT,
    })
    r = _run(d)
    assert r.returncode == 0, r.stdout + r.stderr
    got = (d / "result").read_text().splitlines()
    assert got[0] == str(BIN / "halcmd"), got
    assert got[1].startswith("lcnc-regress-"), got
    assert got[2] == "modules ok", got


def test_emc2_home_is_the_top_of_the_tree_the_test_lies_in(tmp_path):
    # LinuxCNC's checkresult scripts read $EMC2_HOME/tests/motion/g0/....
    d = _case(tmp_path / "tree" / "tests" / "motion", "g0", {
        "test.sh": "echo \"$EMC2_HOME\"\n",
        "checkresult": ACCEPT,
    })
    env = {k: v for k, v in os.environ.items() if k != "EMC2_HOME"}
    r = _run(d, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (d / "result").read_text() == "%s\n" % (tmp_path / "tree").resolve()
    # Outside such a tree it is left unset.
    e = _case(tmp_path, "plain", {"test.sh": "echo \"${EMC2_HOME-unset}\"\n"})
    r = _run(e, env=env)
    assert (e / "result").read_text() == "unset\n", r.stdout + r.stderr


def test_bad_arguments_are_refused(tmp_path):
    r = _run(tmp_path / "missing")
    assert r.returncode == 2 and "not a directory" in r.stderr, r.stderr
    r = _run(tmp_path)
    assert r.returncode == 2 and "no test directories" in r.stderr, r.stderr
