#!/usr/bin/env python3
"""Makes component NAME with an output pin driving signal `held` and a
param, marks it ready, then ends the way MODE says: `wait` (until killed),
`return` (falls off the end without exit()), `os-exit` (os._exit, no
clean-up at all), `raise` (an uncaught exception)."""

import os
import sys
import time

import hal

name, mode = sys.argv[1], sys.argv[2]
c = hal.component(name)
c.newpin("out", hal.HAL_FLOAT, hal.HAL_OUT)
c.newparam("gain", hal.HAL_S32, hal.HAL_RW)
hal.new_sig("held", hal.HAL_FLOAT)
hal.connect(name + ".out", "held")
c["out"] = 3.5
c.ready()
print("ready", flush=True)
if mode == "wait":
    while True:
        time.sleep(1)
elif mode == "os-exit":
    sys.stdin.readline()
    os._exit(0)
elif mode == "raise":
    sys.stdin.readline()
    raise SystemError("deliberate")
else:
    sys.stdin.readline()
