"""hal.query's dicts as LinuxCNC 2.10 prints them: key order, the enum
reprs (Type, Dir, CompType) and each kind's fields, on the HAL of
data/gates.hal. LinuxCNC's own halmodule.3 test prints these dicts and
compares the text, so the repr is what must match, not only the values."""

import re
from pathlib import Path

import pytest

import hal

GATES = Path(__file__).resolve().parent / "data" / "gates.hal"


def shown(d):
    """repr of a query dict with the ids (which differ per run) as 'ID'."""
    d = dict(d)
    for key in ("comp_id", "id"):
        if key in d:
            d[key] = "ID"
    return repr(d)


@pytest.fixture
def gates(hal_instance):
    hal_instance.halcmd("-f", str(GATES))
    return hal_instance


def test_pins_and_params(gates):
    assert shown(hal.query.pin("and2.0.in0")) == (
        "{'haltype': 'pin', 'name': 'and2.0.in0', 'type': <Type.BOOL: 1>, "
        "'dir': <Dir.IN: 16>, 'value': False, 'alias': None, "
        "'signal': 'net-input-a', 'comp': 'and2', 'comp_id': 'ID'}"
    )
    assert "'type': <Type.SINT: 6>, 'dir': <Dir.OUT: 32>, " in shown(
        hal.query.pin("testthread.threadbeat")
    ), "a thread's beat pin is a 64-bit count the thread writes"
    assert shown(hal.query.param("and2.0.tmax-increased")) == (
        "{'haltype': 'parameter', 'name': 'and2.0.tmax-increased', "
        "'type': <Type.BOOL: 1>, 'dir': <Dir.RO: 64>, 'value': False, "
        "'alias': None, 'comp': 'and2', 'comp_id': 'ID'}"
    )
    assert hal.query.param("testthread.tmax")["dir"] is hal.Dir.RW
    assert hal.query.param("testthread.tmax")["comp"] == "__testthread"


def test_signals(gates):
    assert shown(hal.query.signal("net-xor-a")) == (
        "{'haltype': 'signal', 'name': 'net-xor-a', 'type': <Type.BOOL: 1>, "
        "'value': False, 'writers': 1, 'readers': 1, 'bidirs': 0, "
        "'driver': 'and2.0.out'}"
    )
    assert [p for p in hal.query.signalpins("net-xor-a")] == ["and2.0.out", "xor2.0.in0"]
    undriven = hal.query.signal("net-input-b")
    assert (undriven["writers"], undriven["readers"], undriven["driver"]) == (0, 2, None)


def test_components_functions_threads(gates):
    assert shown(hal.query.comp("or2")) == (
        "{'haltype': 'component', 'name': 'or2', 'type': <CompType.REALTIME: 1>, "
        "'id': 'ID', 'pid': 0, 'ready': True, 'insmod': 'count=1'}"
    )
    assert hal.query.comp("threads")["insmod"] == "name1=testthread period1=1000000"
    assert hal.query.comp("__testthread")["insmod"] is None
    assert shown(hal.query.funct("xor2.0")) == (
        "{'haltype': 'function', 'name': 'xor2.0', 'comp': 'xor2', "
        "'comp_id': 'ID', 'users': 1, 'reentrant': False}"
    )
    t = hal.query.thread("testthread")
    assert list(t) == [
        "haltype", "name", "comp", "comp_id", "priority", "period", "functions",
    ]
    assert t["period"] == 1000000
    assert [(f["name"], f["index"], f["is_init"]) for f in t["functions"]] == [
        ("and2.0", 0, False), ("or2.0", 1, False), ("xor2.0", 2, False),
    ]
    assert re.fullmatch(
        r"\{'haltype': 'threadfunction', 'name': 'and2\.0', 'index': 0, 'is_init': False\}",
        repr(t["functions"][0]),
    )


@pytest.mark.parametrize(
    "query, arg",
    [
        ("pin", "does-not-exist"),
        ("param", "does-not-exist"),
        ("signal", "does-not-exist"),
        ("comp", "does-not-exist"),
        ("comp", 65534),
        ("funct", "does-not-exist"),
        ("thread", "does-not-exist"),
        ("signalpins", "does-not-exist"),
    ],
)
def test_an_unknown_name_gives_none(gates, query, arg):
    assert getattr(hal.query, query)(arg) is None
