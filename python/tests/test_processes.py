"""Python components as processes of their own: started by loadusr,
counting on a thread, ended by SIGTERM, and removed however they end."""

import signal
import subprocess
import time
import types

import pytest

import hal
from conftest import SCRIPTS, wait_for


def halcmd_file(hal_instance, name, tmp_path):
    """Runs halcmd -f NAME with its output into files of `tmp_path`: the
    programs loadusr starts outlive halcmd and keep its stdout and stderr,
    so a captured pipe would stay open as long as they run. Returns the
    result with `stdout` and `stderr` as halcmd left them (`out` and `err`
    are the files, which those programs may go on writing)."""
    out, err = tmp_path / "out", tmp_path / "err"
    with open(out, "w") as o, open(err, "w") as e:
        r = subprocess.run(
            ["halcmd", "-f", name],
            cwd=SCRIPTS,
            stdin=subprocess.DEVNULL,
            stdout=o,
            stderr=e,
            timeout=120,
        )
    result = types.SimpleNamespace(
        out=out, err=err, stdout=out.read_text(), stderr=err.read_text()
    )
    assert r.returncode == 0, result.stdout + result.stderr
    return result


def test_loadusr_waits_for_ready_and_the_programs_outlive_halcmd(hal_instance, tmp_path):
    r = halcmd_file(hal_instance, "loadusr.hal", tmp_path)
    # getp found the params, so loadusr -W waited for each program.
    lines = r.stdout.splitlines()
    assert lines[0] == "1" and lines[1] == "5", r.stdout
    assert "counter" in r.stdout and "User" in r.stdout
    # As in LinuxCNC, halcmd has exited and both programs still run ...
    assert hal.component_exists("counter") and hal.component_exists("other")
    assert "counter done" not in r.out.read_text()
    # ... until unloadusr stops them (SIGTERM), and they leave.
    hal_instance.halcmd("unloadusr", "all")
    wait_for(lambda: r.out.read_text().count("counter done") == 2, what="both programs to end")
    assert not hal.component_exists("counter") and not hal.component_exists("other")


def test_realtime_stop_ends_the_programs_loadusr_started(hal_instance, tmp_path):
    r = halcmd_file(hal_instance, "loadusr.hal", tmp_path)
    assert hal.component_exists("counter") and hal.component_exists("other")
    # The host stops them before it exits, and stop waits for the host.
    hal_instance.run("realtime", "stop")
    assert r.out.read_text().count("counter done") == 2


def test_a_component_counting_on_a_thread(hal_instance, children):
    p = hal_instance.script("counter.py")
    children.append(p)
    wait_for(lambda: hal.component_is_ready("counter"), what="counter ready")
    assert hal.get_value("counter.count") == 0
    hal.set_p("counter.step", "3")
    hal.set_p("counter.enable", "1")
    wait_for(lambda: hal.get_value("counter.count") >= 30, what="counting")
    hal.set_p("counter.enable", "0")
    stopped = hal.get_value("counter.count")
    time.sleep(0.05)
    assert hal.get_value("counter.count") == stopped
    assert stopped % 3 == 0
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=20)
    assert p.returncode == 0, err
    assert "counter done" in out
    assert not hal.component_exists("counter")


def test_pins_are_gone_after_the_process_is_killed(hal_instance, children):
    p = hal_instance.script("holder.py", "doomed", "wait")
    children.append(p)
    assert p.stdout.readline() == "ready\n"
    assert hal.pin_has_writer("doomed.out")
    assert hal.get_info_signals()[0]["DRIVER"] == "doomed.out"
    p.send_signal(signal.SIGKILL)
    p.wait()
    wait_for(lambda: not hal.component_exists("doomed"), what="the host to remove it")
    assert hal.get_info_pins() == [] and hal.get_info_params() == []
    assert hal.get_info_signals() == [
        {"NAME": "held", "VALUE": 3.5, "DRIVER": None, "TYPE": hal.HAL_FLOAT}
    ]
    # The name can be used again.
    hal.component("doomed").exit()


@pytest.mark.parametrize("mode", ["return", "os-exit", "raise"])
def test_pins_are_gone_however_the_process_ends(hal_instance, children, mode):
    p = hal_instance.script("holder.py", "leaver", mode)
    children.append(p)
    assert p.stdout.readline() == "ready\n"
    assert hal.component_exists("leaver")
    p.communicate(input="go\n", timeout=20)
    wait_for(lambda: not hal.component_exists("leaver"), what="the component to go")
    assert hal.get_info_pins() == []


def test_a_script_streams_into_a_streamer_and_reads_a_sampler(hal_instance, tmp_path):
    r = halcmd_file(hal_instance, "streaming.hal", tmp_path)
    assert "pass" in r.stdout, r.stdout + r.stderr


def test_a_python_stream_between_two_programs(hal_instance, tmp_path):
    r = halcmd_file(hal_instance, "pystreams.hal", tmp_path)
    assert r.stdout.splitlines() == ["pass"], r.stdout + r.stderr


def test_a_forked_child_leaves_its_parents_component_alone(hal_instance):
    import os

    c = hal.component("parent")
    c.newpin("x", hal.HAL_BIT, hal.HAL_OUT)
    pid = os.fork()
    if pid == 0:
        # What the child's interpreter exit does; it must not remove the
        # parent's component.
        import atexit

        atexit._run_exitfuncs()
        del c
        os._exit(0)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    assert hal.component_exists("parent") and c["x"] is False
