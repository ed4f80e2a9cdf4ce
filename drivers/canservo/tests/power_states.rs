//! Every CiA 402 power-state transition, in both directions, through the
//! typestate API over SDO against a simulated drive whose time runs in a
//! background thread.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;
use std::time::Duration;

use hal_canservo::bus::{Filters, SimBus, WallClock};
use hal_canservo::power::{
    AfterQuickStop, AnyPower, OperationEnabled, Power, PowerState, SwitchOnDisabled,
};
use hal_canservo::regs::obj;
use hal_canservo::sdo::SdoClient;
use hal_canservo::sim::Injection;

/// A drive whose simulated time follows the wall clock.
struct Running {
    bus: Arc<SimBus>,
    _time: WallClock,
}

impl Running {
    fn new(node: u8) -> Running {
        let bus = SimBus::with_drives(&[node]);
        let time = WallClock::run(bus.clone(), Duration::from_micros(500));
        Running { bus, _time: time }
    }
}

const T: Duration = Duration::from_secs(5);

#[test]
fn every_transition_both_ways() {
    let r = Running::new(1);
    let ep = r.bus.open(Filters::setup(&[1]));
    let sdo = SdoClient::new(&ep, 1, T);
    let AnyPower::SwitchOnDisabled(p) = AnyPower::read(&sdo, T).unwrap() else {
        panic!("a fresh drive is in Switch on disabled");
    };
    let state =
        |s: &SdoClient| PowerState::from_statusword(s.read_u16(obj::STATUSWORD, 0).unwrap());
    // 2, 7: shutdown and back.
    let p = p.shutdown().unwrap().disable_voltage().unwrap();
    // 2, 3, 10.
    let p = p
        .shutdown()
        .unwrap()
        .switch_on()
        .unwrap()
        .disable_voltage()
        .unwrap();
    // 2, 3, 6, 3, 4, 5, 4, 8.
    let p = p
        .shutdown()
        .unwrap()
        .switch_on()
        .unwrap()
        .shutdown()
        .unwrap();
    let p = p.switch_on().unwrap().enable_operation().unwrap();
    let p = p.disable_operation().unwrap().enable_operation().unwrap();
    let p = p.shutdown().unwrap();
    assert_eq!(state(&sdo), Some(PowerState::ReadyToSwitchOn));
    // 3 + 4 in one controlword is the planner's business; here 3, 4, 9.
    let p = p
        .switch_on()
        .unwrap()
        .enable_operation()
        .unwrap()
        .disable_voltage()
        .unwrap();
    // 11, 12: option 2 ends a quick stop in Switch on disabled by itself
    // once the axis stands.
    let q = p
        .shutdown()
        .unwrap()
        .switch_on()
        .unwrap()
        .enable_operation()
        .unwrap()
        .quick_stop()
        .unwrap();
    let p = match q {
        AfterQuickStop::Active(q) => q.disable_voltage().unwrap(),
        AfterQuickStop::Disabled(p) => p,
    };
    // 11, 12 by disable voltage, and 16, with quick stop option 6 (stay
    // in Quick stop active).
    sdo.write_i16(obj::QUICK_STOP_OPTION, 0, 6).unwrap();
    let AfterQuickStop::Active(q) = on(p).quick_stop().unwrap() else {
        panic!("option 6 stays in quick stop active");
    };
    let p = q.disable_voltage().unwrap();
    let AfterQuickStop::Active(q) = on(p).quick_stop().unwrap() else {
        panic!("option 6 stays in quick stop active");
    };
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(
        state(&sdo),
        Some(PowerState::QuickStopActive),
        "option 6 holds"
    );
    let e = q.enable_operation().unwrap();
    assert_eq!(e.state(), PowerState::OperationEnabled);
    // 13, 14, 15: a fault, then the reset edge.
    r.bus
        .with_drive(1, |d, out| d.inject(Injection::OverCurrent, out));
    let AnyPower::Fault(f) = AnyPower::read(&sdo, T).unwrap() else {
        panic!("faulted");
    };
    let _ = e; // the enabled handle is stale now: the drive faulted
    let p = f.fault_reset().unwrap();
    assert_eq!(p.state(), PowerState::SwitchOnDisabled);
    assert_eq!(sdo.read_u16(obj::ERROR_CODE, 0).unwrap(), 0);
}

#[test]
fn a_step_the_drive_refuses_times_out_with_its_statusword() {
    let r = Running::new(2);
    let ep = r.bus.open(Filters::setup(&[2]));
    let sdo = SdoClient::new(&ep, 2, T);
    r.bus
        .with_drive(2, |d, out| d.inject(Injection::UnderVoltage, out));
    let AnyPower::Fault(f) = AnyPower::read(&sdo, Duration::from_millis(100)).unwrap() else {
        panic!("faulted");
    };
    let e = f.fault_reset().unwrap_err().to_string();
    assert!(
        e.starts_with("node 2 did not reach switch on disabled within 100 ms (statusword 0x02"),
        "{e}"
    );
}

/// Transitions 2, 3, 4.
fn on<'a>(p: Power<'a, SwitchOnDisabled>) -> Power<'a, OperationEnabled> {
    p.shutdown()
        .unwrap()
        .switch_on()
        .unwrap()
        .enable_operation()
        .unwrap()
}
