"""A pymodbus server for mb2hal's tests (tests/mb2hal_pymodbus.rs).

    pymodbus_server.py tcp PORT     Modbus TCP on 127.0.0.1:PORT
    pymodbus_server.py rtu BAUD     Modbus RTU on a pseudo-terminal

For RTU two pseudo-terminal pairs are bridged: pymodbus opens one with
pyserial, the client opens the other, whose path is printed first as
"pty PATH". Then "ready". On standard input, "KIND ADDRESS COUNT"
(KIND: the write function code, 5, 6, 15 or 16) prints "KIND ADDRESS
v1 v2 ..." : the last value each address received from a write with
that function, or -1 for none yet. End of input ends the server.

The datastore: discrete inputs 1,0,1,1,0,0,1,0 repeated; coils 0,1
repeated; holding registers 100 + address; input registers 200 +
address (pymodbus blocks start at 1 for protocol address 0).
"""
import asyncio
import os
import sys
import threading
import tty

from pymodbus import FramerType
from pymodbus.datastore import (
    ModbusDeviceContext,
    ModbusSequentialDataBlock as Block,
    ModbusServerContext,
)
from pymodbus.server import StartAsyncSerialServer, StartAsyncTcpServer

BLOCKS = {
    "di": Block(1, [1, 0, 1, 1, 0, 0, 1, 0] * 8),
    "co": Block(1, [0, 1] * 32),
    "hr": Block(1, list(range(100, 164))),
    "ir": Block(1, list(range(200, 264))),
}
CONTEXT = ModbusServerContext(devices=ModbusDeviceContext(**BLOCKS), single=True)
WRITTEN = {}


async def record(function_code, _start, address, _count, _registers, values):
    """pymodbus's access hook: notes what each write brought."""
    if values is not None:
        for i, v in enumerate(values):
            WRITTEN[(function_code, address + i)] = int(v)
    return None


CONTEXT.simdevices[0].action = record


def bridge():
    """Two raw pty pairs whose masters are joined; returns the slave
    paths (server's, client's). The slave descriptors stay open so the
    pairs live while either side closes and reopens."""
    pairs = [os.openpty(), os.openpty()]
    for _, slave in pairs:
        tty.setraw(slave)

    def pump(src, dst):
        while True:
            try:
                data = os.read(src, 4096)
            except OSError:
                return
            if not data:
                return
            os.write(dst, data)

    (m1, s1), (m2, s2) = pairs
    for a, b in ((m1, m2), (m2, m1)):
        threading.Thread(target=pump, args=(a, b), daemon=True).start()
    return os.ttyname(s1), os.ttyname(s2)


async def commands():
    loop = asyncio.get_running_loop()
    while True:
        line = await loop.run_in_executor(None, sys.stdin.readline)
        if not line:
            os._exit(0)
        kind, address, count = line.split()
        a = int(address)
        values = [WRITTEN.get((int(kind), a + i), -1) for i in range(int(count))]
        print(kind, address, *values, flush=True)


async def main():
    if sys.argv[1] == "tcp":
        server = StartAsyncTcpServer(
            context=CONTEXT, address=("127.0.0.1", int(sys.argv[2]))
        )
    else:
        ours, theirs = bridge()
        print("pty", theirs, flush=True)
        server = StartAsyncSerialServer(
            context=CONTEXT,
            framer=FramerType.RTU,
            port=ours,
            baudrate=int(sys.argv[2]),
            bytesize=8,
            parity="N",
            stopbits=1,
        )
    asyncio.get_running_loop().create_task(server)
    await asyncio.sleep(0.3)
    print("ready", flush=True)
    await commands()


asyncio.run(main())
