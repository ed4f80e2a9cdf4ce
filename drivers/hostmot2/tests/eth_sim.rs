//! `loadrt hm2_eth sim=BOARD`: simulated Ethernet boards inside the HAL
//! process, reached through the transport's LBP16 datagrams with no
//! socket: names as LinuxCNC's, a running thread moving a step
//! generator and a servo channel, the board counting the cycle's
//! datagrams, and refused loads that say why.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::Mutex;
use std::time::{Duration, Instant};

use common::with_core;
use hal_core::{Host, MsgLevel, Value};
use hostmot2::eth::hal::HM2_ETH_MODULE;
use hostmot2::sim::eth::EthBoard;

fn float(h: &Host, pin: &str) -> f64 {
    match h.instance().pin_value(pin).unwrap() {
        Value::Float(f) => f,
        v => panic!("{pin} is {v:?}"),
    }
}

fn set(h: &Host, pin: &str, v: Value) {
    h.instance().set_pin(pin, v).unwrap();
}

/// Waits (up to 20 s of wall time) until `cond` holds.
fn wait(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(20);
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn history(h: &Host) -> Vec<String> {
    h.flush_rt_log();
    h.rt_log().history().into_iter().map(|(_, t)| t).collect()
}

#[test]
fn two_simulated_boards_run_a_thread_without_a_network() {
    let h = with_core("hm2-eth-sim-run");
    h.rt_log().set_level(MsgLevel::All);
    h.loadrt(
        &HM2_ETH_MODULE,
        &[
            "board_ip=10.10.10.10,10.10.10.11",
            "sim=7i93,7i96s",
            "config=num_encoders=3 num_pwmgens=3 num_stepgens=2,num_encoders=0 num_stepgens=1",
        ],
    )
    .unwrap();
    let log = history(&h);
    for want in [
        "hm2_eth: discovered 7I93 (simulated)",
        "hm2_eth: discovered 7I96S (simulated)",
        "hm2_7i93.0: initialized AnyIO board (simulated at 10.10.10.10:27181)",
    ] {
        assert!(log.iter().any(|l| l == want), "{want} in {log:?}");
    }
    let inst = h.instance();
    for pin in [
        "hm2_7i93.0.encoder.02.position",
        "hm2_7i93.0.pwmgen.02.value",
        "hm2_7i93.0.stepgen.01.position-fb",
        "hm2_7i93.0.gpio.047.in",
        "hm2_7i93.0.packet-error-total",
        "hm2_7i96s.0.stepgen.00.position-fb",
    ] {
        assert!(inst.pin(pin).unwrap().is_some(), "{pin}");
    }
    assert!(inst.pin("hm2_7i93.0.stepgen.02.enable").unwrap().is_none());

    h.create_thread("servo-thread", 1_000_000, true, None)
        .unwrap();
    for board in ["hm2_7i93.0", "hm2_7i96s.0"] {
        h.addf(&format!("{board}.read-request"), "servo-thread", -1)
            .unwrap();
    }
    for board in ["hm2_7i93.0", "hm2_7i96s.0"] {
        h.addf(&format!("{board}.read"), "servo-thread", -1)
            .unwrap();
    }
    for board in ["hm2_7i93.0", "hm2_7i96s.0"] {
        h.addf(&format!("{board}.write"), "servo-thread", -1)
            .unwrap();
    }
    set(&h, "hm2_7i93.0.stepgen.00.position-cmd", Value::Float(0.5));
    set(&h, "hm2_7i93.0.stepgen.00.enable", Value::Bit(true));
    // The 7i93's servos have their leads swapped, as LinuxCNC's samples
    // expect: a negative duty turns encoder 1 forward.
    inst.set_param("hm2_7i93.0.encoder.01.scale", Value::Float(4000.0))
        .unwrap();
    set(&h, "hm2_7i93.0.pwmgen.01.value", Value::Float(-0.5));
    set(&h, "hm2_7i93.0.pwmgen.01.enable", Value::Bit(true));
    h.start().unwrap();
    wait("the step generator to reach 0.5", || {
        (float(&h, "hm2_7i93.0.stepgen.00.position-fb") - 0.5).abs() < 0.011
    });
    wait("the servo to turn", || {
        float(&h, "hm2_7i93.0.encoder.01.position") > 1.0
    });
    h.stop();
    assert_eq!(
        inst.pin_value("hm2_7i93.0.packet-error-total").unwrap(),
        Value::U32(0)
    );
    let board =
        hal_driver::sim::find::<Mutex<EthBoard>>(inst.name(), "hm2_7i93.0").expect("published");
    let (cycles, now, ip) = {
        let mut b = board.lock().unwrap();
        (b.cycles(), b.model().now_ns(), b.identity().ip)
    };
    assert!(cycles > 10, "one read request per cycle: {cycles}");
    // One period per cycle, once the thread's period is known (the
    // registration's and the first cycle's requests come before it).
    assert_eq!(now % 1_000_000, 0, "{now} ns");
    assert!(
        (cycles - 3..cycles).contains(&(now / 1_000_000)),
        "a period per cycle: {now} ns, {cycles} cycles"
    );
    assert_eq!(ip, [10, 10, 10, 10]);
    // Unloading makes the board safe: the watchdog bites.
    h.unloadrt("hm2_eth").unwrap();
    assert_eq!(board.lock().unwrap().model().read32(0x1100), 0);
}

#[test]
fn refused_sim_loads_name_the_boards() {
    let h = with_core("hm2-eth-sim-refused");
    for (args, want) in [
        (
            &["sim=7i99"][..],
            "not a simulated Ethernet board (7i96s, 7i76e, 7i93, 7i92, 7i95)",
        ),
        (
            &["sim="],
            "no board named: sim=BOARD, one of 7i96s, 7i76e, 7i93, 7i92, 7i95",
        ),
        (
            &["sim"],
            "expected sim=VALUE: simulated boards in this process instead of the network (7i96s, 7i76e, 7i93, 7i92, 7i95)",
        ),
        (
            &["sim=7i93,7i96s", "board_ip=10.10.10.10"],
            "2 simulated boards for 1 board_ip addresses",
        ),
        (
            &["sim=7i93", "config=num_stepgens=9"],
            "config.num_stepgens=9, but only 8 are available",
        ),
    ] {
        let e = h.loadrt(&HM2_ETH_MODULE, args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert_eq!(h.loaded_components(), ["hostmot2"], "{args:?}");
    }
    // Without board_ip the boards are named by the factory address.
    h.loadrt(&HM2_ETH_MODULE, &["sim=7i92,7i92"]).unwrap();
    let inst = h.instance();
    assert!(inst
        .pin("hm2_7i92.1.stepgen.09.position-fb")
        .unwrap()
        .is_some());
    assert!(inst
        .pin("hm2_7i92.0.encoder.01.position")
        .unwrap()
        .is_some());
}
