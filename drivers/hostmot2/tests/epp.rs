//! `hm2_7i43` and `hm2_7i90`: the EPP cycles on the simulated parallel
//! port, register by register (set-up, address cycles, byte and 32-bit
//! data cycles, the timeout check and its clearing), and the modules
//! loading simulated boards with LinuxCNC's names, refusing bad
//! parameters, and moving a step generator through EPP in a thread.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;
use common::with_core;

use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::Value;
use hal_driver::sim::{self as layer_sim, Access, AccessLog, Dir, SimBoard, Width};
use hostmot2::epp::hal::{PortPlace, HM2_7I43_MODULE, HM2_7I90_MODULE};
use hostmot2::epp::{ecr, EppTransport};
use hostmot2::sim::epp::EppPortModel;
use hostmot2::sim::{machine, SimHm2};
use hostmot2::transport::{Transport, TransportError};

const BASE: u16 = 0x378;
const PLACE: PortPlace = PortPlace {
    base: BASE,
    base_hi: Some(BASE + 0x400),
    wide: true,
};

/// A simulated 7I43 behind a simulated port at 0x378, its accesses
/// logged, and a transport to it (set up unless `set_up` is false).
fn rig(wide: bool, set_up: bool) -> (Arc<SimBoard<EppPortModel>>, Arc<SimHm2>, EppTransport) {
    let spec = hostmot2::sim::epp::preset("7i43").unwrap();
    let (board, _) = hostmot2::sim::board(spec, Box::new(machine::preset("7i43")));
    let model = EppPortModel::new(BASE, BASE + 0x400, board.clone());
    let port = Arc::new(SimBoard::new(model).with_log(AccessLog::new(10_000)));
    let mut t = EppTransport::new(port.clone(), BASE, PLACE.base_hi, wide);
    if set_up {
        t.set_up().unwrap();
    }
    port.clear_log();
    (port, board, t)
}

/// The logged accesses as (dir, width, port, value).
fn cycles(port: &SimBoard<EppPortModel>) -> Vec<(Dir, Width, u16, u32)> {
    port.accesses()
        .into_iter()
        .map(|a: Access| (a.dir, a.width, a.addr as u16, a.value))
        .collect()
}

use Dir::{Read as R, Write as W};
use Width::{Byte as B, Long as L};

#[test]
fn set_up_selects_epp_mode_and_clears_a_stale_timeout() {
    let (port, _, mut t) = rig(true, false);
    // A timeout left over: the port was used in SPP mode before.
    let mut w = [0u32; 1];
    assert!(matches!(
        t.read(0x100, &mut w),
        Err(TransportError::EppTimeout {
            addr: 0x100,
            port: BASE
        })
    ));
    port.clear_log();
    port.with(|m| {
        assert!(!m.timed_out(), "the failed read cleared its timeout");
    });
    t.set_up().unwrap();
    assert_eq!(
        cycles(&port),
        [
            (W, B, 0x77A, ecr::EPP as u32),
            (W, B, 0x37A, 0x04),
            (R, B, 0x379, 0x78),
        ]
    );
    t.read(0x100, &mut w).unwrap();
    assert_eq!(w[0], 0x55AA_CAFE, "the cookie, through EPP");
}

#[test]
fn a_read_is_one_address_pair_then_a_data_cycle_per_register() {
    let (port, _, mut t) = rig(true, true);
    let mut w = [0u32; 3];
    t.read(0x104, &mut w).unwrap();
    assert_eq!(
        &w[..2],
        &[u32::from_le_bytes(*b"HOST"), u32::from_le_bytes(*b"MOT2")]
    );
    assert_eq!(
        cycles(&port),
        [
            (W, B, 0x37B, 0x04),
            (W, B, 0x37B, 0x81),
            (R, L, 0x37C, w[0]),
            (R, L, 0x37C, w[1]),
            (R, L, 0x37C, w[2]),
            (R, B, 0x379, 0x78),
        ]
    );
    assert_eq!(port.with(|m| m.data_cycles), 12, "four cycles per register");
}

#[test]
fn byte_cycles_when_epp_wide_is_off() {
    let (port, board, mut t) = rig(false, true);
    t.write(0x1100, &[0x00AB_CDEF]).unwrap();
    assert_eq!(
        cycles(&port),
        [
            (W, B, 0x37B, 0x00),
            (W, B, 0x37B, 0x91),
            (W, B, 0x37C, 0xEF),
            (W, B, 0x37C, 0xCD),
            (W, B, 0x37C, 0xAB),
            (W, B, 0x37C, 0x00),
            (R, B, 0x379, 0x78),
        ]
    );
    assert_eq!(board.with(|m| m.read32(0x1100)), 0x00AB_CDEF);
    let mut w = [0u32; 1];
    port.clear_log();
    t.read(0x1100, &mut w).unwrap();
    assert_eq!(w[0], 0x00AB_CDEF);
    assert_eq!(cycles(&port).len(), 2 + 4 + 1);
}

#[test]
fn a_pulled_cable_is_a_timeout_and_the_next_transfer_works_again() {
    let (port, _, mut t) = rig(true, true);
    port.with(|m| m.connected = false);
    let mut w = [0u32; 2];
    let e = t.read(0x100, &mut w).unwrap_err();
    assert_eq!(
        e.to_string(),
        "EPP timeout at 0x0100 on the parallel port at 0x378: the board did not answer (cable, power, or the port not in EPP mode)"
    );
    assert_eq!(w, [u32::MAX; 2], "a timed-out read reads all ones");
    // The transport cleared the bit (writing it as 1, then 0).
    let log = cycles(&port);
    assert!(log.contains(&(W, B, 0x379, 0x79)), "{log:x?}");
    assert_eq!(t.timeouts(), 1);
    port.with(|m| m.connected = true);
    t.read(0x100, &mut w).unwrap();
    assert_eq!(w[0], 0x55AA_CAFE);
    // EPP carries 15 address bits.
    assert!(matches!(
        t.read(0x7FFC, &mut w),
        Err(TransportError::EppRange { .. })
    ));
}

#[test]
fn simulated_7i43_and_7i90_load_with_linuxcncs_names() {
    let h = with_core("epp-load");
    h.rt_log().set_level(hal_core::MsgLevel::All);
    h.loadrt(
        &HM2_7I43_MODULE,
        &[
            "sim=7i43",
            "ioaddr=0x278",
            "epp_wide=0",
            "config=num_encoders=2 num_pwmgens=1 num_stepgens=4",
        ],
    )
    .unwrap();
    h.loadrt(&HM2_7I90_MODULE, &["sim=7i90", "debug_epp=1"])
        .unwrap();
    let inst = h.instance();
    let functs: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
    for f in [
        "hm2_7i43.0.read",
        "hm2_7i43.0.write",
        "hm2_7i43.0.pet_watchdog",
        "hm2_7i90.0.read",
        "hm2_7i90.0.write",
    ] {
        assert!(functs.iter().any(|n| n == f), "{f} in {functs:?}");
    }
    assert!(
        !functs.iter().any(|n| n.ends_with("read_gpio")),
        "EPP is not thread-safe: {functs:?}"
    );
    for pin in [
        "hm2_7i43.0.encoder.01.position",
        "hm2_7i43.0.pwmgen.00.value",
        "hm2_7i43.0.stepgen.03.position-fb",
        "hm2_7i43.0.gpio.047.in",
        "hm2_7i43.0.led.CR08",
        "hm2_7i90.0.stepgen.04.position-fb",
        "hm2_7i90.0.gpio.071.in",
    ] {
        assert!(inst.pin(pin).unwrap().is_some(), "{pin}");
    }
    assert!(inst
        .pin("hm2_7i43.0.encoder.02.position")
        .unwrap()
        .is_none());
    h.flush_rt_log();
    let said: Vec<String> = h.rt_log().history().into_iter().map(|(_, t)| t).collect();
    assert!(
        said.iter()
            .any(|l| l == "hm2_7i43: hm2_7i43.0 on the parallel port at 0x278 (simulated)"),
        "{said:?}"
    );
    assert!(said.iter().any(|l| l.starts_with("hm2_7i90: debug_epp:")));
}

#[test]
fn refused_loads_say_which_parameter_and_leave_nothing() {
    let h = with_core("epp-refused");
    for (module, args, want) in [
        (
            &HM2_7I43_MODULE,
            &["sim=7i90"][..],
            "hm2_7i43: parameter 'sim'",
        ),
        (
            &HM2_7I43_MODULE,
            &["sim=7i43", "epp_wide=2"][..],
            "hm2_7i43: parameter 'epp_wide': item 0 \"2\": must be 0 or 1",
        ),
        (
            &HM2_7I43_MODULE,
            &["sim=7i43", "ioaddr=0x10000"][..],
            "ioaddr",
        ),
        (
            &HM2_7I43_MODULE,
            &["sim=7i43", "ioaddr_hi=-7"][..],
            "parameter 'ioaddr_hi': item 0 \"-7\": not a port address, 0 or -1",
        ),
        (
            &HM2_7I90_MODULE,
            &["sim=7i90", "config=num_stepgens=6"][..],
            "config.num_stepgens=6, but only 5",
        ),
        (
            &HM2_7I43_MODULE,
            &["sim=7i43,7i43,7i43,7i43,7i43"][..],
            "hm2_7i43: parameter 'sim': can only take 4 arguments",
        ),
    ] {
        let e = h.loadrt(module, args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert_eq!(h.loaded_components(), ["hostmot2"], "{args:?}");
    }
}

#[test]
fn a_step_generator_moves_through_epp_in_a_thread() {
    let h = with_core("epp-thread");
    h.loadrt(
        &HM2_7I43_MODULE,
        &[
            "sim=7i43",
            "config=num_encoders=0 num_pwmgens=0 num_stepgens=1",
        ],
    )
    .unwrap();
    let inst = h.instance();
    let board = layer_sim::find::<SimHm2>(inst.name(), "hm2_7i43.0").unwrap();
    let s = "hm2_7i43.0.stepgen.00";
    inst.set_param(&format!("{s}.position-scale"), Value::Float(100.0))
        .unwrap();
    inst.set_param(&format!("{s}.maxaccel"), Value::Float(0.0))
        .unwrap();
    inst.set_pin(&format!("{s}.enable"), Value::Bit(true))
        .unwrap();
    inst.set_pin(&format!("{s}.position-cmd"), Value::Float(2.0))
        .unwrap();
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("hm2_7i43.0.read", "servo", -1).unwrap();
    h.addf("hm2_7i43.0.write", "servo", -1).unwrap();
    h.start().unwrap();
    let end = Instant::now() + Duration::from_secs(30);
    let fb = || match inst.pin_value(&format!("{s}.position-fb")).unwrap() {
        Value::Float(f) => f,
        v => panic!("{v:?}"),
    };
    // Until the move's last step is counted: waiting for position-fb to
    // come within 0.01 (one step) let the wait end at 199 counts.
    let counts = || inst.pin_value(&format!("{s}.counts")).unwrap();
    while counts() != Value::S32(200) {
        assert!(
            Instant::now() < end,
            "counts stayed at {:?}, position-fb at {}",
            counts(),
            fb()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!((fb() - 2.0).abs() < 0.01, "position-fb {}", fb());
    h.stop();
    // 100 steps per unit, read back from the board through EPP.
    assert_eq!(
        inst.pin_value(&format!("{s}.counts")).unwrap(),
        Value::S32(200)
    );
    assert!(board.with(|m| m.now_ns()) > 0, "the board's time moved");
    assert_eq!(
        inst.param_value("hm2_7i43.0.io_error").unwrap(),
        Value::Bit(false)
    );
}
