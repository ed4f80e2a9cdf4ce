#!/usr/bin/env python3
"""Creates a stream of depth 10 (room for 9 records) of bit, float, s32
and u32 columns, fills it, checks that a tenth record overruns, then
marks itself ready and waits for its reader."""

import time

import hal

c = hal.component("stream_writer")
s = hal.stream(c, hal.streamer_base + 5, 10, "bfsu")
assert (s.maxdepth, s.depth, s.element_types) == (10, 0, b"bfsu")
for i in range(9):
    assert s.writable
    s.write((i & 1, i / 4, -i, i * 1000))
assert not s.writable and s.depth == 9 and s.num_overruns == 0
try:
    s.write((1, 1, 1, 1))
except OSError:
    pass
else:
    raise AssertionError("a full stream took a record")
assert s.num_overruns == 1
c.ready()
try:
    while True:
        time.sleep(1)
except KeyboardInterrupt:
    pass
