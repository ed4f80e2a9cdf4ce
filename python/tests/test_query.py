"""hal.query on a live instance: what it reports for user-space
components, aliases and ports, and its errors."""

import os

import pytest

import hal


@pytest.fixture
def comp(hal_instance):
    c = hal.component("q")
    c.newpin("out", hal.HAL_FLOAT, hal.HAL_OUT)
    c.newpin("in", hal.HAL_U32, hal.HAL_IN)
    c.newparam("gain", hal.HAL_S32, hal.HAL_RW)
    c.ready()
    return c


def test_a_user_component_and_its_items(comp):
    comp["out"] = 2.5
    comp["gain"] = -7
    c = hal.query.comp("q")
    assert c["type"] is hal.CompType.USER
    assert c["pid"] == os.getpid() and c["ready"] is True and c["insmod"] is None
    assert hal.query.comp(c["id"]) == c, "found by id as by name"
    out = hal.query.pin("q.out")
    assert list(out) == [
        "haltype", "name", "type", "dir", "value", "alias", "signal", "comp", "comp_id",
    ]
    assert (out["type"], out["dir"], out["value"]) == (hal.Type.REAL, hal.Dir.OUT, 2.5)
    assert out["comp"] == "q" and out["comp_id"] == c["id"] and out["signal"] is None
    gain = hal.query.param("q.gain")
    assert "signal" not in gain
    assert (gain["haltype"], gain["dir"], gain["value"]) == ("parameter", hal.Dir.RW, -7)
    assert set(hal.query.pins()) >= {"q.out", "q.in"}
    assert hal.query.params()["q.gain"] == gain


def test_signals_and_their_pins(comp):
    hal.new_sig("speed", hal.HAL_FLOAT)
    hal.connect("q.out", "speed")
    assert hal.query.signal("speed")["driver"] == "q.out"
    assert list(hal.query.signalpins("speed")) == ["q.out"]
    assert hal.query.pin("q.out")["signal"] == "speed"
    hal.new_sig("idle", hal.HAL_U32)
    hal.connect("q.in", "idle")
    idle = hal.query.signals()["idle"]
    assert (idle["writers"], idle["readers"], idle["driver"]) == (0, 1, None)
    assert hal.query.signalpins("nothing") is None


def test_an_aliased_pin_is_found_by_both_names(comp, hal_instance):
    hal_instance.halcmd("alias", "pin", "q.in", "q-input")
    by_alias = hal.query.pin("q-input")
    assert (by_alias["name"], by_alias["alias"]) == ("q-input", "q.in")
    assert hal.query.pin("q.in") == by_alias


def test_a_port_pin_reads_as_its_buffer_size(hal_instance):
    import pyhal

    c = pyhal.component("qp")
    c.pinNew("rx", pyhal.halType.PORT, pyhal.pinDir.IN)
    c.sigNew("bytes", pyhal.halType.PORT)
    c.sigLink("qp.rx", "bytes")
    assert hal.query.pin("qp.rx")["value"] == 0
    hal_instance.halcmd("sets", "bytes", "32")
    assert hal.query.pin("qp.rx")["type"] is hal.Type.PORT
    assert hal.query.pin("qp.rx")["value"] == 32
    assert hal.query.signal("bytes")["value"] == 32
    c.exit()


def test_threads_and_functions(hal_instance):
    hal_instance.halcmd("loadrt", "threads", "name1=slow", "period1=2000000")
    hal_instance.halcmd("loadrt", "and2", "count=1")
    hal_instance.halcmd("addf", "and2.0", "slow")
    t = hal.query.thread("slow")
    assert (t["comp"], t["period"], t["priority"]) == ("__slow", 2000000, 0)
    assert t["comp_id"] == hal.query.comp("__slow")["id"]
    assert t["functions"] == [
        {"haltype": "threadfunction", "name": "and2.0", "index": 0, "is_init": False}
    ]
    f = hal.query.funct("and2.0")
    assert (f["comp"], f["users"], f["reentrant"]) == ("and2", 1, False)
    assert hal.query.comps()["and2"]["insmod"] == "count=1"
    assert hal.query.comps()["__slow"]["type"] is hal.CompType.REALTIME
    assert list(hal.query.threads()) == ["slow"]


def test_unknown_names_are_none(hal_instance):
    for lookup in ("pin", "param", "signal", "comp", "funct", "thread", "signalpins"):
        assert getattr(hal.query, lookup)("no-such-thing") is None, lookup
    assert hal.query.comp(-5) is None


@pytest.mark.parametrize(
    "lookup", ["pin", "param", "signal", "funct", "thread", "signalpins"]
)
def test_a_name_that_is_no_str_is_a_type_error(hal_instance, lookup):
    with pytest.raises(TypeError, match=r"hal\.query\.%s: the name must be a str, not int" % lookup):
        getattr(hal.query, lookup)(3)


def test_a_component_key_is_a_str_or_an_int(hal_instance):
    for key in (1.5, None, True, b"q"):
        with pytest.raises(TypeError, match="hal.query.comp: a component is named by str or int id"):
            hal.query.comp(key)


def test_no_hal_is_a_runtime_error_naming_the_query(monkeypatch):
    monkeypatch.setenv("HAL_INSTANCE", "pyt-nothing-runs-here")
    with pytest.raises(RuntimeError, match=r"^hal\.query\.pins: "):
        hal.query.pins()
    with pytest.raises(RuntimeError, match=r"^hal\.query\.comp: "):
        hal.query.comp("x")
