"""The `linuxcnc` module: constants, INI files, the stat snapshot's
parsing, and a whole machine driven by a display program that `linuxcnc`
starts from `[DISPLAY]DISPLAY`, whose exit status becomes linuxcnc's."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import linuxcnc
from linuxcnc import _stat

from conftest import BIN, REPO, SCRIPTS

PEER = REPO / "target" / "linuxcnc-peer"


def _peer(code):
    """The lines `code` prints with LinuxCNC's own module importable, or
    None when the peer (scripts/linuxcnc-peer) is not extracted or cannot
    load here."""
    dist = PEER / "usr" / "lib" / "python3" / "dist-packages"
    if not dist.is_dir():
        return None
    env = dict(os.environ)
    env["PYTHONPATH"] = str(dist)
    env["LD_LIBRARY_PATH"] = os.pathsep.join(
        str(PEER / d) for d in ("usr/lib", "usr/lib/x86_64-linux-gnu")
    )
    r = subprocess.run(
        ["python3", "-c", "import linuxcnc\n" + code],
        env=env, capture_output=True, text=True, timeout=60,
    )
    if r.returncode != 0:
        return None
    return r.stdout.splitlines()


def _peer_constants():
    """LinuxCNC's own module's upper-case names and values, or None."""
    lines = _peer(
        "for n in dir(linuxcnc):\n"
        "    v = getattr(linuxcnc, n)\n"
        "    if n.isupper() and isinstance(v, int): print(n, v)\n"
    )
    if lines is None:
        return None
    return {n: int(v) for n, v in (line.split() for line in lines)}


def test_every_linuxcnc_stat_and_command_name_is_known():
    stat_names = _peer("print(*[n for n in dir(linuxcnc.stat) if not n.startswith('_')])")
    cmd_names = _peer("print(*[n for n in dir(linuxcnc.command) if not n.startswith('_')])")
    if stat_names is None or cmd_names is None:
        pytest.skip("LinuxCNC's module is not here to compare with (run scripts/linuxcnc-peer)")
    from linuxcnc import _command

    peer_stat = set(stat_names[0].split()) - {"poll"}
    assert peer_stat == set(_stat._LINUXCNC_NAMES)
    for name in cmd_names[0].split():
        assert hasattr(linuxcnc.command, name) or name in _command._NOT_SUPPLIED, name


def test_constants_match_linuxcncs_module():
    peer = _peer_constants()
    if peer is None:
        pytest.skip("LinuxCNC's module is not here to compare with (run scripts/linuxcnc-peer)")
    ours = {n: getattr(linuxcnc, n) for n in dir(linuxcnc) if n.isupper()}
    assert ours, "the module has no constants"
    for name, value in ours.items():
        assert name in peer, "%s is not one of LinuxCNC's names" % name
        assert value == peer[name], "%s: ours %r, LinuxCNC's %r" % (name, value, peer[name])
    for name in ("STATE_ESTOP_RESET", "MODE_MDI", "INTERP_IDLE", "RCS_ERROR", "NML_ERROR",
                 "OPERATOR_DISPLAY", "JOG_INCREMENT", "SPINDLE_REVERSE", "AUTO_RUN"):
        assert name in ours, name


def test_constants_have_the_documented_values():
    # The values scripts most often compare against, as LinuxCNC documents them.
    assert (linuxcnc.STATE_ESTOP, linuxcnc.STATE_ESTOP_RESET,
            linuxcnc.STATE_OFF, linuxcnc.STATE_ON) == (1, 2, 3, 4)
    assert (linuxcnc.MODE_MANUAL, linuxcnc.MODE_AUTO, linuxcnc.MODE_MDI) == (1, 2, 3)
    assert (linuxcnc.INTERP_IDLE, linuxcnc.INTERP_READING,
            linuxcnc.INTERP_PAUSED, linuxcnc.INTERP_WAITING) == (1, 2, 3, 4)
    assert (linuxcnc.RCS_DONE, linuxcnc.RCS_EXEC, linuxcnc.RCS_ERROR) == (1, 2, 3)
    assert (linuxcnc.NML_ERROR, linuxcnc.NML_TEXT, linuxcnc.NML_DISPLAY) == (1, 2, 3)


def test_ini_find_and_findall(tmp_path):
    p = tmp_path / "m.ini"
    p.write_text("[HAL]\nHALFILE = a.hal\nHALFILE = b.hal\n[EMC]\nMACHINE = test  mill\n")
    ini = linuxcnc.ini(str(p))
    assert ini.find("EMC", "MACHINE") == "test  mill"
    assert ini.find("EMC", "NOPE") is None
    # As LinuxCNC's: the third argument is which occurrence, from 1.
    assert ini.find("HAL", "HALFILE", 2) == "b.hal"
    assert ini.find("HAL", "HALFILE", 3) is None
    with pytest.raises(TypeError):
        ini.find("EMC", "NOPE", "x")
    assert ini.findall("HAL", "HALFILE") == ["a.hal", "b.hal"]
    assert ini.findall("HAL", "NOPE") == []
    with pytest.raises(linuxcnc.error, match="missing.ini"):
        linuxcnc.ini(str(tmp_path / "missing.ini"))


def test_stat_lines_become_attributes_and_records():
    v = _stat.parse(
        "task_state=i:4\nfile=s:/a b.ngc\nposition=F:1 -2.5 0\nhomed=I:1 0\n"
        "joint.1.homed=i:0\njoint.0.homed=i:1\njoint.0.input=f:0.25\n"
        "tool_table.0.id=i:-1\n"
    )
    assert v["task_state"] == 4
    assert v["file"] == "/a b.ngc"
    assert v["position"] == (1.0, -2.5, 0.0)
    assert v["homed"] == (1, 0)
    assert v["joint"] == ({"homed": 1, "input": 0.25}, {"homed": 0})
    assert v["tool_table"][0].id == -1
    with pytest.raises(ValueError, match="line 1"):
        _stat.parse("task_state 4\n")
    with pytest.raises(ValueError, match="unknown kind"):
        _stat.parse("a=q:1\n")


def test_stat_gives_bools_and_record_fields_as_linuxcnc_29_does():
    # LinuxCNC 2.9's stat (read on the 2.9 peer) has these as bools, and a
    # printed record lists its fields in the module's order: its
    # hard-limits test prints both.
    v = _stat.parse(
        "enabled=i:1\ninpos=i:0\npaused=i:0\nqueue_full=i:1\n"
        "task_state=i:4\njoint.0.override_limits=i:0\njoint.0.homed=i:1\n"
        "joint.0.input=f:0.5\njoint.0.min_position_limit=f:-10\n"
        "joint.0.extra=i:3\nspindle.0.homed=i:0\n"
        "spindle.0.override_enabled=i:1\nspindle.0.speed=f:0\n"
    )
    flags = (v["enabled"], v["inpos"], v["paused"], v["queue_full"])
    assert flags == (True, False, False, True)
    assert repr(v["enabled"]) == "True"
    assert type(v["task_state"]) is int
    assert list(v["joint"][0]) == [
        "min_position_limit",
        "input",
        "homed",
        "override_limits",
        "extra",
    ]
    shown = str(v["joint"][0])
    assert shown.startswith("{'min_position_limit': -10.0, 'input': 0.5,")
    s = v["spindle"][0]
    assert list(s) == ["override_enabled", "speed", "homed"]
    assert (s["override_enabled"], s["homed"], type(s["speed"])) == (True, False, float)


def test_stat_has_older_linuxcncs_axes_count():
    # Scripts written for LinuxCNC 2.7 wait until `axes` is not 0.
    assert _stat.parse("axis_mask=i:7\n")["axes"] == 3
    assert _stat.parse("axis_mask=i:%d\n" % 0b100100111)["axes"] == 5
    assert "axes" not in _stat.parse("task_state=i:1\n")


def test_without_a_machine_stat_and_command_say_so(hal_instance_name):
    with pytest.raises(linuxcnc.error, match=hal_instance_name):
        linuxcnc.stat().poll()
    with pytest.raises(linuxcnc.error, match="no machine runs"):
        linuxcnc.command().state(linuxcnc.STATE_ESTOP_RESET)
    with pytest.raises(NotImplementedError, match="set_adaptive_feed"):
        linuxcnc.command().set_adaptive_feed(1)


def _mill(tmp_path, display):
    """A copy of the simulated mill whose DISPLAY is `display`, with the
    test display program beside it."""
    src = REPO / "configs" / "sim" / "mill"
    for f in src.iterdir():
        if f.is_file() and not f.name.startswith("sim.var"):
            shutil.copy(f, tmp_path / f.name)
    shutil.copy(SCRIPTS / "machine_ui.py", tmp_path / "machine_ui.py")
    ini = tmp_path / "mill.ini"
    text = ini.read_text()
    assert "\nDISPLAY = axis\n" in text
    ini.write_text(text.replace("\nDISPLAY = axis\n", "\nDISPLAY = %s\n" % display))
    return ini


def _run_linuxcnc(ini):
    if not (BIN / "linuxcnc").exists() or not (BIN / "halui").exists():
        pytest.skip("linuxcnc and halui are not built in %s" % BIN)
    return subprocess.run(
        [str(BIN / "linuxcnc"), str(ini)],
        cwd=str(ini.parent),
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_a_display_program_drives_the_machine(tmp_path, hal_instance_name):
    r = _run_linuxcnc(_mill(tmp_path, "./machine_ui.py"))
    out = r.stdout + "\n--- stderr:\n" + r.stderr
    assert r.returncode == 0, out
    assert "machine_ui: ok: the program ended at X3 Y-1 Z0.5" in r.stdout, out
    assert "the display program exited" in r.stderr, out
    assert "GUI './machine_ui.py'" not in r.stderr, out
    # As in LinuxCNC, the POSTGUI files are the display's to run.
    assert "POSTGUI_HALFILE is left to the display program" in r.stderr, out
    assert "pyvcp.spindle-rpm" not in r.stderr, out


def test_linuxcnc_exits_with_the_display_programs_status(tmp_path, hal_instance_name):
    r = _run_linuxcnc(_mill(tmp_path, "./machine_ui.py --exit 3"))
    assert r.returncode == 3, r.stdout + r.stderr
    assert "machine_ui: ok: the machine starts in e-stop" in r.stdout, r.stdout + r.stderr


def test_a_display_that_cannot_start_stops_the_machine_with_status_1(
    tmp_path, hal_instance_name
):
    r = _run_linuxcnc(_mill(tmp_path, "./no-such-ui"))
    assert r.returncode == 1, r.stdout + r.stderr
    assert "can't execute DISPLAY program" in r.stderr, r.stderr


def test_linuxcncs_guis_are_still_skipped(tmp_path, hal_instance_name):
    # axis is a GUI: not run; the machine runs until stopped.
    ini = _mill(tmp_path, "axis")
    if not (BIN / "linuxcnc").exists():
        pytest.skip("linuxcnc is not built in %s" % BIN)
    p = subprocess.Popen(
        [str(BIN / "linuxcnc"), str(ini)], cwd=str(tmp_path),
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        import time

        end = time.monotonic() + 120
        while time.monotonic() < end:
            try:
                ok, text = linuxcnc._session.request(["stat"], timeout=5)
                break
            except linuxcnc.error:
                assert p.poll() is None, p.communicate()
                time.sleep(0.1)
        else:
            pytest.fail("the machine did not come up")
        s = linuxcnc.stat()
        s.poll()
        assert s.task_state == linuxcnc.STATE_ESTOP
    finally:
        p.terminate()
        out, err = p.communicate(timeout=120)
    assert p.returncode == 0, err
    assert "GUI 'axis' ([DISPLAY]DISPLAY)" in err, err


def test_an_ini_reached_through_a_link_keeps_the_links_directory(tmp_path, hal_instance_name):
    # LinuxCNC's test directories link a shared INI file into each case;
    # the case's directory (holding its display program and tables) is the
    # configuration's, as LinuxCNC's script takes `pwd`/FILE unresolved.
    shared = tmp_path / "shared"
    shared.mkdir()
    ini = _mill(shared, "./machine_ui.py --exit 5")
    case = tmp_path / "case"
    case.mkdir()
    for f in shared.iterdir():
        if f.name != "mill.ini":
            f.rename(case / f.name)
    (case / "mill.ini").symlink_to("../shared/mill.ini")
    r = _run_linuxcnc(case / "mill.ini")
    out = r.stdout + r.stderr
    assert r.returncode == 5, out
    assert "Machine configuration directory is '%s'" % case in out, out
    assert "can't execute DISPLAY program" not in out, out
