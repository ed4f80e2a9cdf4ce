//! The driver's register traffic, checked in the simulator's access log.

use std::sync::Arc;

use hal_driver::sim::{AccessLog, Dir, SimBoard, Width};

use super::*;
use crate::sim::StgModel;

fn logged(model: Model, dio: &str) -> (Arc<SimBoard<StgModel>>, Stg) {
    crate::test_board::board(model, dio, Some(AccessLog::new(10_000)))
}

/// The writes of the log as (offset from base, value).
fn writes(sim: &SimBoard<StgModel>) -> Vec<(u64, u32)> {
    sim.accesses()
        .iter()
        .filter(|a| a.dir == Dir::Write)
        .map(|a| (a.addr - 0x300, a.value))
        .collect()
}

#[test]
fn model1_init_sequence_and_no_stray_port() {
    let (sim, drv) = logged(Model::One, "IIOI");
    drv.init();
    let w = writes(&sim);
    let head: Vec<(u64, u32)> = w.iter().take(11).copied().collect();
    assert_eq!(
        head,
        [
            (0x407, 0x92), // 8255 #2: port D in, INTC out
            (0x405, 0x84), // INTC: auto-zero, IRQ5
            (0x409, 0x1A), // ICW1
            (0x40B, 0x00), // ICW2
            (0x40B, 0xFF), // mask all
            (0x409, 0x0A), // OCW3 read IRR: at the board, not port 0x0a
            (0x406, 0x92), // ports A, B in, C out
            (0x40B, 0xFF),
            (0x407, 0x92), // port D in
            (0x405, 0x84), // INTC restored
            (0x40B, 0xFF),
        ]
    );
    for k in 0..8u64 {
        let ctl = (2 * (k + 1) - k % 2, 0);
        let cmds: Vec<u32> = w.iter().filter(|a| a.0 == ctl.0).map(|a| a.1).collect();
        assert_eq!(cmds, [0x23, 0x68, 0x80, 0xC3], "counter {k}");
    }
    let dacs: Vec<(u64, u32)> = w
        .iter()
        .filter(|a| (0x10..0x20).contains(&a.0))
        .copied()
        .collect();
    assert_eq!(
        dacs,
        (0..8).map(|n| (0x10 + 2 * n, 0x1000)).collect::<Vec<_>>()
    );
    assert_eq!(w.last(), Some(&(0x407, 0x0F)), "auto-zero on last");
    assert!(
        sim.accesses().iter().all(|a| a.addr >= 0x300),
        "no port below the board"
    );
    assert_eq!(sim.with(|m| m.stray_accesses()), 0);
}

#[test]
fn model2_init_sequence() {
    let (sim, drv) = logged(Model::Two, "OIOO");
    drv.init();
    let w = writes(&sim);
    let head: Vec<(u64, u32)> = w.iter().take(10).copied().collect();
    assert_eq!(
        head,
        [
            (0x407, 0x8B),
            (0x409, 0x00), // IDLEN
            (0x40B, 0x00), // SELDI
            (0x401, 0x8C), // CNTRL0
            (0x406, 0x82), // A out, B in, C out
            (0x40F, 0xFF),
            (0x407, 0x82), // port D out
            (0x401, 0x8C), // CNTRL0 restored
            (0x40F, 0xFF), // CNTRL1: (old & 0x0f) | 0xf0 with old read 0xff
            (0x40D, 0x00), // no stale index flags
        ]
    );
    assert_eq!(sim.with(|m| m.stray_accesses()), 0);
}

#[test]
fn adc_start_selects_settles_and_starts() {
    let (sim, drv) = logged(Model::One, "IIOO");
    drv.init();
    sim.clear_log();
    drv.adc_start(6);
    let a: Vec<(Dir, u64, Width)> = sim
        .accesses()
        .iter()
        .map(|a| (a.dir, a.addr - 0x300, a.width))
        .collect();
    assert_eq!(
        a,
        [
            (Dir::Read, 0x41C, Width::Word),
            (Dir::Write, 0x41C, Width::Word)
        ]
    );
    let (sim, drv) = logged(Model::Two, "IIOO");
    drv.init();
    sim.clear_log();
    drv.adc_start(5);
    assert_eq!(writes(&sim), [(0x401, 0x8C | 5 << 4), (0x410, 0)]);
    assert_eq!(sim.with(|m| m.cntrl0()), 0xDC);
}

#[test]
fn counter_capture_is_a_latch_and_three_byte_reads() {
    let (sim, drv) = logged(Model::Two, "IIOO");
    drv.init();
    sim.with(|m| m.turn_to(6, 2.0 + 0x34 as f64 / 4000.0));
    sim.clear_log();
    assert_eq!(drv.latch_count(6), 8000 + 0x34);
    let a: Vec<(Dir, u64, u32)> = sim
        .accesses()
        .iter()
        .map(|a| (a.dir, a.addr - 0x300, a.value))
        .collect();
    assert_eq!(
        a,
        [
            (Dir::Write, 0x0E, 0x03),
            (Dir::Read, 0x0C, 0x74),
            (Dir::Read, 0x0C, 0x1F),
            (Dir::Read, 0x0C, 0x00)
        ]
    );
}
