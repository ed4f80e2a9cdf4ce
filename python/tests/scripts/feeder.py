#!/usr/bin/env python3
"""Streams records into streamer channel 0 and reads them back from
sampler channel 0, which samples what the streamer puts on its pins (see
streaming.hal). Prints `pass` when every record came back in order."""

import sys
import time

import hal

N = 200
c = hal.component("feeder")
out = hal.stream(c, hal.streamer_base, "fbsulk")
back = hal.stream(c, hal.sampler_base, "fbsulk")
assert out.element_types == b"fbsulk" and back.element_types == b"fbsulk"


def record(i):
    return (i * 0.5, bool(i & 1), -i, i * 7, -(2**40) - i, 2**63 + i)


sent = got = 0
deadline = time.monotonic() + 60
while got < N:
    if time.monotonic() > deadline:
        sys.exit("timed out: sent %d, got %d" % (sent, got))
    while sent < N and out.writable:
        out.write(record(sent))
        sent += 1
    r = back.read()
    if r is None:
        time.sleep(0.002)
        continue
    if r != record(got):
        sys.exit("record %d came back as %r" % (got, r))
    if back.sampleno != got + 1:
        sys.exit("record %d has sample number %d" % (got, back.sampleno))
    got += 1
c.ready()
print("pass", flush=True)
