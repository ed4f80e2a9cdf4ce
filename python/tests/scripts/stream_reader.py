#!/usr/bin/env python3
"""Reads the nine records stream_writer.py wrote, in order, then checks
that the empty stream underruns."""

import time

import hal

c = hal.component("stream_reader")
s = hal.stream(c, hal.streamer_base + 5, "bfsu")
for i in range(9):
    assert s.readable
    assert s.read() == (bool(i & 1), i / 4, -i, i * 1000)
    assert s.num_underruns == 0 and s.sampleno == i + 1
assert s.read() is None and s.num_underruns == 1
c.ready()
print("pass", flush=True)
try:
    while True:
        time.sleep(1)
except KeyboardInterrupt:
    pass
