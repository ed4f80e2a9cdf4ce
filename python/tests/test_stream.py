"""hal.stream in one process: creating, attaching, reading and writing,
and the exceptions of each."""

import errno

import pytest

import hal


def test_a_stream_round_trips_every_type(hal_instance):
    c = hal.component("st")
    w = hal.stream(c, 0x1234, 4, "BFSULK")
    assert repr(w) == "<stream 0x1234 creator>"
    assert (w.maxdepth, w.depth, w.readable, w.writable) == (4, 0, False, True)
    assert w.element_types == b"bfsulk"
    r = hal.stream(c, 0x1234)
    assert repr(r) == "<stream 0x1234>" and r.element_types == b"bfsulk"
    rows = [
        (True, -0.5, -(2**31), 2**32 - 1, -(2**63), 2**64 - 1),
        (False, 1e300, 7, 0, 2**63 - 1, 0),
        (1, 2, "3", 4.9, True, 5),
    ]
    for row in rows:
        w.write(row)
    assert (w.depth, w.writable, r.readable) == (3, False, True)
    with pytest.raises(OSError) as e:
        w.write(rows[0])
    assert e.value.errno == errno.ENOSPC and w.num_overruns == 1
    assert r.read() == rows[0] and r.sampleno == 1
    assert r.read() == rows[1] and r.sampleno == 2
    got = r.read()
    assert got == (True, 2.0, 3, 4, 1, 5) and isinstance(got[0], bool)
    # The overrun used up sample number 4; the next record gets 5.
    w.write(rows[1])
    assert r.read() == rows[1] and r.sampleno == 5
    assert r.read() is None and r.num_underruns == 1 and r.sampleno == 5
    assert (r.depth, r.readable) == (0, False)


def test_bad_streams_and_records(hal_instance):
    c = hal.component("bad")
    for types in ("xx", "", "f" * 22):
        with pytest.raises(OSError) as e:
            hal.stream(c, 0x10, 8, types)
        assert e.value.errno == errno.EINVAL
    with pytest.raises(FileNotFoundError):
        hal.stream(c, 0x11)
    with pytest.raises(OSError):
        hal.stream(c, 0x12, 1, "f")
    hal.stream(c, 0x13, 8, "fb")
    with pytest.raises(FileExistsError):
        hal.stream(c, 0x13, 8, "fb")
    with pytest.raises(OSError) as e:
        hal.stream(c, 0x13, "bf")
    assert e.value.errno == errno.EINVAL
    s = hal.stream(c, 0x13, "FB")
    with pytest.raises(ValueError):
        s.write((1.0,))
    with pytest.raises(ValueError):
        s.write((1.0, True, 3))
    with pytest.raises(TypeError):
        s.write([1.0, True])
    with pytest.raises(TypeError):
        s.write(("x", True))
    with pytest.raises(TypeError):
        hal.stream("not a component", 0x13)
    with pytest.raises(TypeError):
        hal.stream(c)
    u = hal.stream(c, 0x14, 8, "u")
    with pytest.raises(OverflowError):
        u.write((-1,))
    assert u.depth == 0, "a refused record is not written"


def test_a_stream_dies_with_its_component(hal_instance):
    c = hal.component("owner")
    s = hal.stream(c, 0x20, 8, "f")
    s.write((1.0,))
    c.exit()
    for use in (lambda: s.write((2.0,)), lambda: s.read(), lambda: s.depth):
        with pytest.raises(RuntimeError):
            use()


def test_reading_a_sampler_and_feeding_a_streamer_in_process(hal_instance):
    # No thread runs: the streamer's FIFO keeps what is written, and the
    # sampler's stays empty.
    hal_instance.halcmd("loadrt", "streamer", "depth=8", "cfg=fu")
    hal_instance.halcmd("loadrt", "sampler", "depth=8", "cfg=bs")
    c = hal.component("me")
    feed = hal.stream(c, hal.streamer_base, "fu")
    assert feed.maxdepth == 8 and feed.element_types == b"fu"
    feed.write((1.5, 3))
    assert hal.get_value("streamer.0.curr-depth") == 0, "updated only when the funct runs"
    assert feed.depth == 1
    with pytest.raises(OSError):
        hal.stream(c, hal.streamer_base, "uf")
    samples = hal.stream(c, hal.sampler_base)
    assert samples.element_types == b"bs"
    assert samples.read() is None and samples.num_underruns == 1
    with pytest.raises(FileNotFoundError):
        hal.stream(c, hal.sampler_base + 1)
