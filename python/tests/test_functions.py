"""The module's functions on a live instance: signals, links, values by
name, listings, and their exceptions."""

import pytest

import hal


@pytest.fixture
def comp(hal_instance):
    c = hal.component("f")
    c.newpin("out", hal.HAL_FLOAT, hal.HAL_OUT)
    c.newpin("in", hal.HAL_FLOAT, hal.HAL_IN)
    c.newpin("io", hal.HAL_S32, hal.HAL_IO)
    c.newpin("bit", hal.HAL_BIT, hal.HAL_IN)
    c.newpin("big", hal.HAL_U64, hal.HAL_IN)
    c.newparam("rw", hal.HAL_U32, hal.HAL_RW)
    c.newparam("ro", hal.HAL_S32, hal.HAL_RO)
    c.ready()
    return c


def test_signals_connect_and_disconnect(comp):
    # LinuxCNC's convention: False means it worked, True that it failed.
    assert hal.new_sig("speed", hal.HAL_FLOAT) is False
    assert hal.new_sig("speed", hal.HAL_FLOAT) is True, "duplicate"
    assert hal.new_sig("count", hal.Type.S32) is False
    with pytest.raises(RuntimeError, match="not a valid HAL signal type"):
        hal.new_sig("port", hal.HAL_PORT)
    with pytest.raises(RuntimeError):
        hal.new_sig("nothing", 42)
    assert hal.connect("f.out", "speed") is False
    assert hal.connect("f.in", "speed") is False
    assert hal.connect("f.io", "speed") is True, "type mismatch"
    assert hal.connect("f.nope", "speed") is True
    assert hal.connect("f.in", "nosig") is True
    comp["out"] = 4.25
    assert comp["in"] == 4.25 and hal.get_s("speed") == 4.25
    sigs = {s["NAME"]: s for s in hal.get_info_signals()}
    assert sigs["speed"] == {"NAME": "speed", "VALUE": 4.25, "DRIVER": "f.out", "TYPE": 2}
    assert sigs["count"] == {"NAME": "count", "VALUE": 0, "DRIVER": None, "TYPE": 3}
    assert hal.disconnect("f.in") is False
    assert hal.disconnect("f.in") is False, "an unlinked pin is left alone"
    assert hal.disconnect("f.nope") is True
    comp["out"] = 1.0
    assert comp["in"] == 4.25, "the unlinked input keeps the signal's last value"


def test_pin_has_writer(comp):
    with pytest.raises(NameError, match="Pin `f.nope' does not exist"):
        hal.pin_has_writer("f.nope")
    assert hal.pin_has_writer("f.in") is False
    # An unlinked output is its own writer.
    assert hal.pin_has_writer("f.out") is True
    hal.new_sig("s", hal.HAL_FLOAT)
    hal.connect("f.in", "s")
    assert hal.pin_has_writer("f.in") is False
    hal.connect("f.out", "s")
    assert hal.pin_has_writer("f.in") is True


def test_component_queries(comp):
    assert hal.component_exists("f") is True
    assert hal.component_exists("nope") is False
    assert hal.component_is_ready("f") is True
    assert hal.component_is_ready("nope") is False


def test_set_p_reads_text_as_halcmd_and_numbers_as_pins(comp):
    assert hal.set_p("f.rw", "0x10") is True
    assert comp["rw"] == 16
    assert hal.set_p("f.rw", " 42 ") is True
    assert hal.get_value("f.rw") == 42
    hal.set_p("f.in", "-1.5e3")
    assert comp["in"] == -1500.0
    hal.set_p("f.in", 7)
    assert comp["in"] == 7.0
    for text, want in [("1", True), ("0", False), ("TRUE", True), ("false", False)]:
        hal.set_p("f.bit", text)
        assert comp["bit"] is want
    hal.set_p("f.bit", True)
    assert comp["bit"] is True
    hal.set_p("f.io", "-2147483648")
    assert comp["io"] == -(2**31)
    hal.set_p("f.big", "18446744073709551615")
    assert comp["big"] == 2**64 - 1


def test_set_p_errors_are_runtime_errors(comp):
    cases = [
        ("f.nope", "1", "pin not found"),
        ("f.out", "1", "pin not writable"),
        ("f.ro", "1", "param not writable"),
        ("f.rw", "-1", "set_p: f.rw"),
        ("f.rw", "4294967296", "set_p: f.rw"),
        ("f.in", "abc", "set_p: f.in"),
        ("f.bit", "2", "set_p: f.bit"),
        ("f.io", 2**31, "set_p: f.io"),
        ("f.in", None, "set_p: f.in"),
    ]
    for name, value, message in cases:
        with pytest.raises(RuntimeError, match=message):
            hal.set_p(name, value)
    hal.new_sig("s", hal.HAL_FLOAT)
    hal.connect("f.in", "s")
    with pytest.raises(RuntimeError, match="pin connected to signal"):
        hal.set_p("f.in", "1")
    with pytest.raises(TypeError):
        hal.set_p("f.in")
    assert comp["rw"] == 0 and comp["in"] == 0.0


def test_set_s_and_the_getters(comp):
    hal.new_sig("free", hal.HAL_U32)
    hal.new_sig("driven", hal.HAL_FLOAT)
    hal.connect("f.out", "driven")
    assert hal.set_s("free", "123") is True
    assert hal.get_s("free") == 123 and hal.get_value("free") == 123
    assert hal.set_s("free", 7) is True
    assert hal.get_value("free") == 7
    with pytest.raises(RuntimeError, match="signal not found"):
        hal.set_s("nope", "1")
    with pytest.raises(RuntimeError, match="already has writer"):
        hal.set_s("driven", "1")
    with pytest.raises(RuntimeError, match="set_s: free"):
        hal.set_s("free", "-1")
    comp["out"] = 2.5
    # A linked pin reads its signal; params, pins and signals by name.
    assert hal.get_value("f.out") == 2.5 and hal.get_p("f.out") == 2.5
    assert hal.get_value("driven") == 2.5
    assert isinstance(hal.get_value("f.bit"), bool)
    assert isinstance(hal.get_value("f.rw"), int)
    for getter in (hal.get_value, hal.get_p, hal.get_s):
        with pytest.raises(RuntimeError, match="not found"):
            getter("nothing.here")
    with pytest.raises(RuntimeError):
        hal.get_p("free")
    with pytest.raises(RuntimeError):
        hal.get_s("f.out")


def test_listings_see_other_components(comp, hal_instance):
    hal_instance.halcmd("loadrt", "and2")
    hal_instance.halcmd("setp", "and2.0.in0", "1")
    pins = {p["NAME"]: p for p in hal.get_info_pins()}
    assert pins["and2.0.in0"] == {"NAME": "and2.0.in0", "VALUE": True, "DIRECTION": 16, "TYPE": 1}
    assert pins["and2.0.out"]["DIRECTION"] == hal.HAL_OUT
    names = [p["NAME"] for p in hal.get_info_pins()]
    assert names == sorted(names)
    params = {p["NAME"]: p for p in hal.get_info_params()}
    assert params["f.ro"] == {"NAME": "f.ro", "VALUE": 0, "DIRECTION": 64, "TYPE": 3}
    assert "and2.0.tmax" in params
    assert hal.component_exists("and2") and hal.component_is_ready("and2")


def test_message_level(hal_instance):
    old = hal.get_msg_level()
    hal.set_msg_level(hal.MSG_ALL)
    assert hal.get_msg_level() == hal.MSG_ALL
    with pytest.raises(hal.error):
        hal.set_msg_level(99)
    hal.set_msg_level(old)
