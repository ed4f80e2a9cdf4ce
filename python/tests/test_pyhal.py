"""The pyhal binding: its errors say what failed and where, as
HalException; ports refuse the wrong end and waits that cannot end."""

import pytest

import pyhal
from pyhal import HalException, halType, pinDir


@pytest.fixture
def comp(hal_instance):
    c = pyhal.component("ph")
    yield c
    c.exit()


def test_pins_signals_and_values(comp, hal_instance):
    out = comp.pinNew("out", halType.SIGNED, pinDir.OUT)
    inp = comp.pinNew("in", halType.SIGNED, pinDir.IN)
    assert comp.pins == {"out": out, "in": inp}
    assert out.fullname == "ph.out" and comp.id > 0
    comp.ready()
    comp.sigNew("s", halType.SIGNED)
    comp.sigLink("ph.out", "s")
    comp.sigLink("ph.in", "s")
    out.value = -12
    assert inp.value == -12
    assert hal_instance.halcmd("getp", "ph.in").stdout.strip() == "-12"


def test_bad_types_and_directions(comp):
    with pytest.raises(HalException, match=r'failed to create pin "ph.a": 9 is not a halType'):
        comp.pinNew("a", 9, pinDir.IN)
    with pytest.raises(HalException, match=r'"ph.a": 64 is not a pinDir'):
        comp.pinNew("a", halType.BIT, 64)
    with pytest.raises(HalException, match="a PORT pin is IN or OUT, not IO"):
        comp.pinNew("a", halType.PORT, pinDir.IO)
    with pytest.raises(HalException, match=r'failed to create signal "x": 0 is not a halType'):
        comp.sigNew("x", 0)
    assert comp.pins == {}, "nothing half made"


def test_the_hal_refusing_says_why(comp):
    comp.pinNew("a", halType.BIT, pinDir.IN)
    with pytest.raises(HalException, match=r'failed to create pin "ph.a": .+'):
        comp.pinNew("a", halType.BIT, pinDir.IN)
    comp.sigNew("b", halType.BIT)
    with pytest.raises(HalException, match=r'failed to create signal "b": .+'):
        comp.sigNew("b", halType.BIT)
    with pytest.raises(HalException, match=r'failed to link pin "ph.nope" to signal "b": .+'):
        comp.sigLink("ph.nope", "b")
    comp.sigNew("f", halType.FLOAT)
    with pytest.raises(HalException, match=r'failed to link pin "ph.a" to signal "f": .+'):
        comp.sigLink("ph.a", "f")


def test_values_of_the_wrong_type(comp):
    f = comp.pinNew("f", halType.FLOAT, pinDir.OUT)
    s = comp.pinNew("s", halType.SIGNED, pinDir.OUT)
    u = comp.pinNew("u", halType.UNSIGNED, pinDir.OUT)
    with pytest.raises(HalException, match=r"pin ph.f \(FLOAT\): cannot set 'abc'"):
        f.value = "abc"
    with pytest.raises(HalException, match=r"pin ph.s \(SIGNED\): cannot set 4294967296: .*out of range"):
        s.value = 1 << 32
    with pytest.raises(HalException, match=r"pin ph.u \(UNSIGNED\): cannot set -1"):
        u.value = -1
    assert (f.value, s.value, u.value) == (0.0, 0, 0), "refused values change nothing"


def test_ports_refuse_the_wrong_end(comp, hal_instance):
    rx = comp.pinNew("rx", halType.PORT, pinDir.IN)
    tx = comp.pinNew("tx", halType.PORT, pinDir.OUT)
    with pytest.raises(HalException, match="PORT pin has no value"):
        rx.value
    with pytest.raises(HalException, match="PORT pin has no value"):
        tx.value = 3
    with pytest.raises(HalException, match=r"port ph.tx: read: ph.tx is an output port"):
        tx.read(1)
    with pytest.raises(HalException, match=r"port ph.rx: write: ph.rx is an input port"):
        rx.write("x")
    # Unlinked, a port has no buffer: nothing moves, nothing waits for ever.
    assert (rx.size(), tx.writable(), tx.write("x"), rx.read(1)) == (0, 0, False, "")
    comp.sigNew("p", halType.PORT)
    comp.sigLink("ph.rx", "p")
    comp.sigLink("ph.tx", "p")
    hal_instance.halcmd("sets", "p", "4")
    with pytest.raises(HalException, match=r"waitWritable\(4\) would wait for ever: the buffer holds at most 3"):
        tx.waitWritable(4)
    with pytest.raises(HalException, match=r"waitReadable\(9\) would wait for ever"):
        rx.waitReadable(9)
    assert tx.write(b"abc") and not tx.write("d")
    rx.waitReadable(3)
    assert rx.peek(2) == b"ab" and rx.peek_commit(1) and rx.read(2) == b"bc"
    with pytest.raises(HalException, match="more than a port holds"):
        rx.read(1 << 30)


def test_an_exited_component(hal_instance):
    c = pyhal.component("gone")
    p = c.pinNew("x", halType.BIT, pinDir.OUT)
    port = c.pinNew("y", halType.PORT, pinDir.OUT)
    c.exit()
    c.exit()  # a second exit does nothing
    with pytest.raises(HalException, match="pinNew: component gone has exited"):
        c.pinNew("z", halType.BIT, pinDir.IN)
    with pytest.raises(HalException, match="ready: component gone has exited"):
        c.ready()
    with pytest.raises(HalException, match=r"pin gone.x: .*closed HAL component"):
        p.value
    with pytest.raises(HalException, match=r"pin gone.x \(BIT\): cannot set True: .*closed"):
        p.value = True
    with pytest.raises(HalException, match=r"port gone.y: .*closed HAL component"):
        port.writable()


def test_a_duplicate_component_name(comp):
    with pytest.raises(HalException, match='failed to make component "ph": .+'):
        pyhal.component("ph")


def test_a_port_signal_is_sized_with_its_writer_linked(comp):
    import hal

    rx = comp.pinNew("rx", halType.PORT, pinDir.IN)
    tx = comp.pinNew("tx", halType.PORT, pinDir.OUT)
    comp.sigNew("p", halType.PORT)
    comp.sigLink("ph.tx", "p")
    comp.sigLink("ph.rx", "p")
    # As LinuxCNC's: the writer drives the bytes, not the buffer's size.
    assert hal.set_s("p", 6) is True
    assert (tx.size(), rx.size(), tx.writable()) == (6, 6, 5)
    with pytest.raises(RuntimeError, match="set_s: p: port is already allocated with 6 bytes"):
        hal.set_s("p", 8)
    comp.sigNew("v", halType.FLOAT)
    comp.pinNew("out", halType.FLOAT, pinDir.OUT)
    comp.sigLink("ph.out", "v")
    with pytest.raises(RuntimeError, match="signal 'v' already has writer"):
        hal.set_s("v", 1.0)
