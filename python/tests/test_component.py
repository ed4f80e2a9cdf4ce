"""hal.component, its pins and params, on a live instance."""

import sys
import threading

import pytest

import hal

INT_TYPES = [hal.HAL_S32, hal.HAL_U32, hal.HAL_S64, hal.HAL_U64]


def test_constants_have_linuxcnc_numbers():
    assert (hal.HAL_BIT, hal.HAL_FLOAT, hal.HAL_S32, hal.HAL_U32) == (1, 2, 3, 4)
    assert (hal.HAL_PORT, hal.HAL_S64, hal.HAL_U64) == (5, 6, 7)
    assert (hal.HAL_IN, hal.HAL_OUT, hal.HAL_IO) == (16, 32, 48)
    assert (hal.HAL_RO, hal.HAL_RW) == (64, 192)
    assert hal.Type.REAL == hal.HAL_FLOAT and hal.Type.BOOL == hal.HAL_BIT
    assert hal.Type.FLOAT is hal.Type.REAL and hal.Type.U64 is hal.Type.UINT
    assert [m.name for m in hal.Type] == ["BOOL", "SINT", "UINT", "REAL", "PORT", "S32", "U32"]
    assert hal.Dir.IO == hal.Dir.IN | hal.Dir.OUT and hal.Dir.RW == hal.Dir.RO | hal.Dir.WO
    assert hal.is_userspace == 1 and hal.is_kernelspace == 0
    assert hal.is_rt + hal.is_sim == 1
    assert (hal.streamer_base, hal.sampler_base) == (0x48535430, 0x48534130)
    assert issubclass(hal.error, Exception)


def test_pins_and_params_of_every_type_and_direction(hal_instance):
    c = hal.component("comp")
    made = {}
    for t in (hal.HAL_BIT, hal.HAL_FLOAT) + tuple(INT_TYPES):
        for d in (hal.HAL_IN, hal.HAL_OUT, hal.HAL_IO):
            made["p%d-%d" % (t, d)] = (c.newpin("p%d-%d" % (t, d), t, d), t, d, True)
        for d in (hal.HAL_RO, hal.HAL_RW):
            made["r%d-%d" % (t, d)] = (c.newparam("r%d-%d" % (t, d), t, d), t, d, False)
    c.ready()
    for name, (obj, t, d, is_pin) in made.items():
        assert isinstance(obj, hal.Pin if is_pin else hal.Param)
        assert (obj.get_name(), obj.get_type(), obj.get_dir(), obj.is_pin()) == (name, t, d, is_pin)
        assert (obj.name, obj.type, obj.dir) == (name, t, d)
        assert obj.get() == 0 and obj.value == 0
        item = c.getitem(name)
        assert isinstance(item, hal.item) and item.get_name() == name
    pins = {p["NAME"]: p for p in hal.get_info_pins()}
    params = {p["NAME"]: p for p in hal.get_info_params()}
    assert len(pins) == 18 and len(params) == 12
    assert pins["comp.p2-48"] == {"NAME": "comp.p2-48", "VALUE": 0.0, "DIRECTION": 48, "TYPE": 2}
    assert params["comp.r1-64"] == {"NAME": "comp.r1-64", "VALUE": False, "DIRECTION": 64, "TYPE": 1}
    assert len(c) == 30


def test_values_are_read_and_written_every_way(hal_instance):
    c = hal.component("rw")
    f = c.newpin("f", hal.HAL_FLOAT, hal.HAL_OUT)
    b = c.newpin("b", hal.HAL_BIT, hal.HAL_IN)
    u = c.newparam("u", hal.HAL_U64, hal.HAL_RO)
    c["f"] = 1.5
    assert c["f"] == 1.5 and c.f == 1.5 and f.get() == 1.5 and f.value == 1.5
    c.f = -2
    assert isinstance(c.f, float) and c.f == -2.0
    f.value = 3
    assert hal.get_value("rw.f") == 3.0
    # The owner writes its own input pins and read-only params.
    c.b = True
    assert c.b is True and hal.get_value("rw.b") is True
    b.set(0)
    assert b.get() is False
    u.set(2**64 - 1)
    assert c["u"] == 2**64 - 1 and hal.get_p("rw.u") == 2**64 - 1
    assert c.getpins() == {"b": False, "f": 3.0, "u": 2**64 - 1}
    # Methods come before items of the same name, as in LinuxCNC.
    assert callable(c["newpin"])


def test_range_and_type_errors_raise_linuxcnc_exceptions(hal_instance):
    c = hal.component("x")
    c.newpin("s", hal.HAL_S32, hal.HAL_OUT)
    c.newpin("u", hal.HAL_U32, hal.HAL_OUT)
    c.newpin("f", hal.HAL_FLOAT, hal.HAL_OUT)
    c.newpin("l", hal.HAL_S64, hal.HAL_OUT)
    c.newpin("k", hal.HAL_U64, hal.HAL_OUT)
    c.newpin("b", hal.HAL_BIT, hal.HAL_OUT)
    accepted = [
        ("s", -1), ("s", 0x7FFFFFFF), ("s", -0x80000000), ("s", True),
        ("u", 0), ("u", 0xFFFFFFFF),
        ("f", 0), ("f", -1.0), ("f", 1 << 1023),
        ("l", -(2**63)), ("l", 2**63 - 1),
        ("k", 0), ("k", 2**64 - 1),
    ]
    for name, v in accepted:
        c[name] = v
        assert c[name] == v, (name, v)
    overflow = [
        ("s", 0x80000000), ("s", -0x80000001), ("u", -1), ("u", 1 << 32),
        ("f", 1 << 1024), ("l", 2**63), ("k", -1), ("k", 2**64),
    ]
    for name, v in overflow:
        with pytest.raises(OverflowError):
            c[name] = v
    with pytest.raises(TypeError):
        c["f"] = None
    with pytest.raises(TypeError):
        c["f"] = "not a number"
    with pytest.raises(TypeError):
        c["s"] = None
    with pytest.raises(ValueError):
        c["s"] = "twelve"
    c["s"] = "12"
    assert c["s"] == 12
    c["f"] = "2.5"
    assert c["f"] == 2.5
    c["s"] = 7.9
    assert c["s"] == 7, "floats are truncated as int() does"
    # Bits: booleans, numbers, and the words LinuxCNC accepts.
    for v, want in [(True, True), (0, False), (2, True), (0.0, False), (0.5, True),
                    ("TRUE", True), ("off", False), ("Yes", True), ("0", False)]:
        c["b"] = v
        assert c["b"] is want, v
    with pytest.raises(ValueError):
        c["b"] = "maybe"
    # A failed write leaves the old value.
    c["u"] = 5
    with pytest.raises(OverflowError):
        c["u"] = -5
    assert c["u"] == 5


def test_missing_and_duplicate_items_and_bad_types(hal_instance):
    c = hal.component("dup")
    c.newpin("a", hal.HAL_BIT, hal.HAL_IN)
    c.newparam("p", hal.HAL_S32, hal.HAL_RW)
    with pytest.raises(ValueError, match="Duplicate pin name 'a'"):
        c.newpin("a", hal.HAL_BIT, hal.HAL_IN)
    with pytest.raises(ValueError, match="Duplicate parameter name 'p'"):
        c.newparam("p", hal.HAL_BIT, hal.HAL_RW)
    with pytest.raises(AttributeError, match="Pin or param 'zz' does not exist"):
        c["zz"]
    with pytest.raises(AttributeError):
        c.zz
    with pytest.raises(AttributeError):
        c.zz = 1
    with pytest.raises(AttributeError):
        c.getitem("zz")
    with pytest.raises(AttributeError, match="Pin 'p' does not exist"):
        c.getpin("p")
    with pytest.raises(AttributeError, match="Param 'a' does not exist"):
        c.getparam("a")
    assert isinstance(c.getpin("a"), hal.Pin) and isinstance(c.getparam("p"), hal.Param)
    with pytest.raises(hal.error, match="Invalid pin type 5"):
        c.newpin("port", hal.HAL_PORT, hal.HAL_IN)
    with pytest.raises(hal.error, match="Invalid pin type 99"):
        c.newpin("t", 99, hal.HAL_IN)
    with pytest.raises(hal.error):
        c.newpin("d", hal.HAL_BIT, hal.HAL_RW)
    with pytest.raises(hal.error, match="Invalid param type 0"):
        c.newparam("t", 0, hal.HAL_RW)
    with pytest.raises(hal.error):
        c.newparam("d", hal.HAL_BIT, hal.HAL_IN)
    with pytest.raises(TypeError):
        c.newpin("t", "bit", hal.HAL_IN)
    with pytest.raises(TypeError):
        c.newpin("t", hal.HAL_BIT)
    # A name the HAL refuses; nothing is left of the attempt.
    with pytest.raises(hal.error):
        c.newpin("bad name", hal.HAL_BIT, hal.HAL_IN)
    assert sorted(c.getpins()) == ["a", "p"]
    with pytest.raises(RuntimeError, match="Cannot be constructed directly"):
        hal.item()
    # Two components may not share a name.
    with pytest.raises(hal.error):
        hal.component("dup")


def test_prefix_readiness_repr_and_exit(hal_instance):
    c = hal.component("pre", "other")
    assert c.getprefix() == "other"
    p = c.newpin("in", hal.HAL_FLOAT, hal.HAL_IN)
    c.setprefix("third")
    c.newparam("gain", hal.HAL_FLOAT, hal.HAL_RW)
    names = [x["NAME"] for x in hal.get_info_pins() + hal.get_info_params()]
    assert names == ["other.in", "third.gain"]
    assert repr(p) == '<hal pin "in" FLOAT-IN>'
    assert repr(c.getitem("gain")) == '<hal param "gain" FLOAT-RW>'
    assert repr(c).startswith("<hal component pre(") and repr(c).endswith("with 2 pins and params>")
    assert hal.component_exists("pre") and not hal.component_is_ready("pre")
    c.ready()
    assert hal.component_is_ready("pre")
    c.unready()
    assert not hal.component_is_ready("pre")
    c.exit()
    assert not hal.component_exists("pre")
    assert hal.get_info_pins() == [] and hal.get_info_params() == []
    for use in (lambda: c["in"], lambda: c.newpin("x", 1, 16), lambda: p.get(),
                lambda: p.set(1), lambda: c.ready(), lambda: len(c), lambda: c.getprefix()):
        with pytest.raises(RuntimeError, match="closed HAL component"):
            use()
    # The name is free again.
    hal.component("pre").exit()


def test_a_dropped_component_leaves_the_hal(hal_instance):
    c = hal.component("gone")
    pin = c.newpin("x", hal.HAL_BIT, hal.HAL_OUT)
    del c
    assert not hal.component_exists("gone")
    with pytest.raises(RuntimeError):
        pin.get()


def test_an_input_keeps_its_value_through_link_and_unlink(hal_instance):
    c = hal.component("linktest")
    c.newpin("in", hal.HAL_FLOAT, hal.HAL_IN)
    c.newpin("inout", hal.HAL_FLOAT, hal.HAL_IO)
    c.ready()
    c["in"], c["inout"] = 42, 43
    hal_instance.halcmd("setp", "linktest.in", "4712")
    hal_instance.halcmd("setp", "linktest.inout", "4713")
    assert (c["in"], c["inout"]) == (4712, 4713)
    hal_instance.halcmd("newsig", "insig", "float")
    hal_instance.halcmd("newsig", "inoutsig", "float")
    hal_instance.halcmd("net", "insig", "linktest.in")
    hal_instance.halcmd("net", "inoutsig", "linktest.inout")
    assert (c["in"], c["inout"]) == (4712, 4713)
    c["in"], c["inout"] = 815, 816
    assert hal.get_s("insig") == 815 and hal.get_s("inoutsig") == 816
    hal_instance.halcmd("unlinkp", "linktest.in")
    hal_instance.halcmd("unlinkp", "linktest.inout")
    assert (c["in"], c["inout"]) == (815, 816)


def test_without_a_running_hal(monkeypatch):
    monkeypatch.setenv("HAL_INSTANCE", "pyt-nobody-runs-this")
    with pytest.raises(hal.error, match="realtime not running"):
        hal.component("lonely")
    for f, args in [(hal.get_info_pins, ()), (hal.component_exists, ("x",)),
                    (hal.get_value, ("x",)), (hal.new_sig, ("s", hal.HAL_BIT))]:
        with pytest.raises(RuntimeError, match="realtime not running"):
            f(*args)


def test_subclasses_make_the_component_in_their_own_init(hal_instance):
    class Spindle(hal.component):
        def __init__(self, rpm):
            hal.component.__init__(self, "spindle")
            self.newpin("rpm", hal.HAL_FLOAT, hal.HAL_OUT).set(rpm)

    s = Spindle(3000)
    assert hal.get_value("spindle.rpm") == 3000.0 and s["rpm"] == 3000.0
    with pytest.raises(hal.error):
        hal.component.__init__(s, "again")
    # An object whose component was never made is unusable, not broken.
    raw = hal.component.__new__(hal.component)
    with pytest.raises(RuntimeError, match="closed HAL component"):
        raw.newpin("x", hal.HAL_BIT, hal.HAL_IN)
    # The native class works on its own too.
    n = hal._hal.component("native", "pfx")
    assert isinstance(n.newpin("x", hal.HAL_BIT, hal.HAL_IN), hal.item)
    assert hal.pin_has_writer("pfx.x") is False


EXIT_DURING_SLOW_WRITE = """
import threading, time, hal
c = hal.component("slow")
c.newpin("s", hal.HAL_S32, hal.HAL_OUT)
inside = threading.Event()
class Slow:
    def __index__(self):
        inside.set()
        time.sleep(0.05)  # lets the main thread run while converting
        return 7
outcome = []
def write():
    try:
        c["s"] = Slow()
        outcome.append("written")
    except RuntimeError as e:
        outcome.append("closed")
t = threading.Thread(target=write)
t.start()
inside.wait()
c.exit()
t.join()
print(outcome[0])
"""


def test_exit_while_another_thread_converts_a_value(hal_instance):
    # A conversion may run Python code and let other threads run; exit()
    # from one of them must neither deadlock nor let the write land.
    r = hal_instance.run(sys.executable, "-c", EXIT_DURING_SLOW_WRITE, timeout=30)
    assert r.stdout.strip() == "closed", r.stdout + r.stderr


def test_threads_share_a_component(hal_instance):
    c = hal.component("shared")
    c.newpin("n", hal.HAL_S64, hal.HAL_OUT)
    errors = []

    def bump():
        try:
            for _ in range(2000):
                c.getpin("n").set(c["n"] + 1)
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    workers = [threading.Thread(target=bump) for _ in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert errors == [] and 0 < c["n"] <= 8000
