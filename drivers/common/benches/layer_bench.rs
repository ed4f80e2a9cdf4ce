//! Prints what the layer's pieces cost per call, for drivers sizing
//! their cycle budgets: simulated-board accesses (single and burst),
//! mapped-file accesses (what a PCI BAR costs minus the bus), the
//! realtime log and the fault latch's fast path.
//!
//! `cargo bench -p hal-driver`

use std::hint::black_box;

use hal_core::RtLog;
use hal_driver::bus::{MmapWindow, RegWindow};
use hal_driver::fault::{Fault, FaultLatch};
use hal_driver::sim::{AccessLog, BoardModel, MemModel, SimBoard};

const N: u64 = 1_000_000;

fn per_call(what: &str, f: impl FnMut(u64)) {
    hal_driver::bench::per_call(what, N, f);
}

/// 64 KiB of plain registers.
struct Ram(Vec<u32>);
impl BoardModel for Ram {}
impl MemModel for Ram {
    fn len(&self) -> usize {
        self.0.len() * 4
    }
    fn read32(&mut self, offset: usize) -> u32 {
        self.0[offset / 4]
    }
    fn write32(&mut self, offset: usize, value: u32) {
        self.0[offset / 4] = value;
    }
}

static FAULT: Fault = Fault::new(1, "bench");

fn main() {
    println!("hal-driver per call ({N} calls each)");
    let board = SimBoard::new(Ram(vec![0; 0x4000]));
    per_call("SimBoard read32", |i| {
        black_box(board.read32((i as usize * 4) & 0xfffc));
    });
    per_call("SimBoard write32", |i| {
        board.write32((i as usize * 4) & 0xfffc, i as u32);
    });
    let mut buf = [0u32; 64];
    per_call("SimBoard read_burst of 64 words", |_| {
        board.read_burst(0x1000, black_box(&mut buf));
    });
    let logged = SimBoard::new(Ram(vec![0; 0x4000])).with_log(AccessLog::new(4096));
    per_call("SimBoard read32 with an access log", |i| {
        black_box(logged.read32((i as usize * 4) & 0xfffc));
    });

    let path = std::env::temp_dir().join(format!("hal-driver-bench-{}", std::process::id()));
    if std::fs::write(&path, vec![0u8; 0x10000]).is_ok() {
        if let Ok(w) = MmapWindow::open(&path) {
            per_call("MmapWindow read32 (mapped file)", |i| {
                black_box(w.read32((i as usize * 4) & 0xfffc));
            });
            per_call("MmapWindow write32 (mapped file)", |i| {
                w.write32((i as usize * 4) & 0xfffc, i as u32);
            });
            per_call("MmapWindow read_burst of 64 words", |_| {
                w.read_burst(0x1000, black_box(&mut buf));
            });
        }
        let _ = std::fs::remove_file(&path);
    }

    let log = RtLog::new(1 << 16);
    let mut n = 0u64;
    per_call("RtLog::err, formatted, then drained every 4096", |i| {
        log.err(format_args!("hm2_5i25.0: watchdog has bit ({i})"));
        n += 1;
        if n % 4096 == 0 {
            log.drain(|_, t| {
                black_box(t);
            });
        }
    });
    let latch = FaultLatch::new("bench.0");
    per_call("FaultLatch::is_tripped (clear)", |_| {
        black_box(latch.is_tripped());
    });
    latch.trip(&FAULT);
    per_call("FaultLatch::trip (already tripped)", |_| {
        black_box(latch.trip(&FAULT));
    });
}
