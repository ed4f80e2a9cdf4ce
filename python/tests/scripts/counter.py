#!/usr/bin/env python3
"""A component that counts on a thread of its own: while `enable` is set,
`count` grows by `step` every millisecond. Ends on SIGTERM (halcmd
unload), which the hal module turns into KeyboardInterrupt."""

import sys
import threading
import time

import hal

name = sys.argv[1] if len(sys.argv) > 1 else "counter"
c = hal.component(name)
c.newpin("count", hal.HAL_U32, hal.HAL_OUT)
c.newpin("enable", hal.HAL_BIT, hal.HAL_IN)
c.newparam("step", hal.HAL_U32, hal.HAL_RW)
c["step"] = 1
stop = threading.Event()


def count():
    while not stop.is_set():
        if c["enable"]:
            c["count"] = (c["count"] + c["step"]) & 0xFFFFFFFF
        time.sleep(0.001)


worker = threading.Thread(target=count)
worker.start()
c.ready()
try:
    while True:
        time.sleep(1)
except KeyboardInterrupt:
    pass
finally:
    stop.set()
    worker.join()
print("counter done", flush=True)
