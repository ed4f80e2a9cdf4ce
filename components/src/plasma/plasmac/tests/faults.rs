//! Every error path: what it leaves in `state-out`, `stop-type-out` and
//! the program pins.

use super::Bench;
use crate::plasma::plasmac::state::{Fault, State, StopType};

/// Checks the state after fault `f`.
fn check(b: &Bench, f: Fault, stop: StopType) {
    assert_eq!(b.faults, [f]);
    assert_eq!(b.p.state, State::MaxHeight);
    assert_eq!(b.p.o.state_out, State::MaxHeight as i32);
    assert_eq!(b.p.o.stop_type_out, stop as i32);
    assert!(!b.p.o.torch_on);
    match stop {
        StopType::Stop => assert!(b.p.o.program_stop && !b.p.o.program_pause),
        _ => assert!(b.p.o.program_pause && !b.p.o.program_stop),
    }
}

#[test]
fn a_sensor_on_before_probing_stops_the_program() {
    let mut b = Bench::new();
    b.i.breakaway = true;
    b.i.cutting_start = true;
    b.run(2);
    check(&b, Fault::SensorBeforeProbe, StopType::Stop);
}

#[test]
fn no_stock_probes_to_the_minimum_limit_and_stops() {
    let mut b = Bench::new();
    b.surface = -500.0;
    b.i.cutting_start = true;
    b.until(100_000, "fault", |b| !b.faults.is_empty());
    check(&b, Fault::ProbeMinLimit, StopType::Stop);
    assert!((b.z() - -100.0).abs() < 1e-3);
    // Stopped: the program ends, the offset goes back.
    b.i.program_is_running = false;
    b.i.program_is_idle = true;
    b.i.cutting_start = false;
    b.until(50_000, "idle", |b| {
        b.p.state == State::Idle && b.p.z.counts == 0
    });
    assert!(!b.p.o.program_stop, "halui carried the stop out");
}

#[test]
fn a_probe_test_at_the_minimum_limit_only_flags_it() {
    let mut b = Bench::new();
    b.surface = -500.0;
    b.i.probe_test = true;
    b.until(100_000, "flag", |b| b.p.o.probe_test_error);
    assert!(b.faults.is_empty());
    assert!(!b.p.o.program_stop);
}

#[test]
fn no_arc_after_the_maximum_starts_pauses() {
    let mut b = Bench::new();
    b.arc_dead = true;
    b.i.cutting_start = true;
    b.until(100_000, "fault", |b| !b.faults.is_empty());
    check(&b, Fault::NoArc, StopType::Wait);
    assert_eq!(b.p.o.pierce_count, 3);
}

#[test]
fn breakaway_and_float_switch_while_cutting_pause() {
    let mut b = Bench::new();
    b.cut();
    b.i.breakaway = true;
    b.tick();
    check(&b, Fault::Breakaway, StopType::Wait);

    let mut b = Bench::new();
    b.cut();
    b.travel = -10.0; // the switch trips now
    b.tick();
    b.tick();
    check(&b, Fault::FloatSwitch, StopType::Wait);
}

#[test]
fn thc_past_the_z_minimum_limit_stops() {
    let mut b = Bench::new();
    b.cut();
    b.until(1000, "thc active", |b| b.p.o.thc_active);
    b.i.axis_z_min_limit = b.z() - 0.05;
    b.volts_error = 50.0; // reads far too high: THC dives
    b.until(1000, "fault", |b| !b.faults.is_empty());
    check(&b, Fault::ThcMinLimit, StopType::Stop);
    // The THC's indicators go out with the cut, though it never ended.
    b.tick();
    let o = &b.p.o;
    assert!(!o.thc_active && !o.led_up && !o.led_down, "{o:?}");
    assert!(!o.cornerlock_is_locked && !o.voidlock_is_locked);
}

#[test]
fn thc_past_the_z_maximum_limit_stops() {
    let mut b = Bench::new();
    b.cut();
    b.until(1000, "thc active", |b| b.p.o.thc_active);
    b.i.axis_z_max_limit = b.z() + 0.05;
    b.i.max_offset = 0;
    b.volts_error = -50.0;
    b.until(1000, "fault", |b| !b.faults.is_empty());
    check(&b, Fault::ThcMaxLimit, StopType::Stop);
}

#[test]
fn an_unhomed_machine_does_not_cut() {
    let mut b = Bench::new();
    b.i.homed = false;
    b.i.cutting_start = true;
    b.run(2);
    check(&b, Fault::NotHomed, StopType::Stop);
}

#[test]
fn a_manual_cut_error_stops_the_spindle_not_the_program() {
    let mut b = Bench::new();
    b.i.program_is_running = false;
    b.i.program_is_idle = true;
    b.cut();
    b.arc_dead = true;
    b.until_state(100, State::MaxHeight);
    assert_eq!(b.faults, [Fault::ArcLost]);
    assert!(b.p.o.cutting_stop);
    assert!(!b.p.o.program_pause && !b.p.o.program_stop);
    b.i.cutting_start = false;
    b.until(50_000, "idle", |b| {
        b.p.state == State::Idle && b.p.z.counts == 0
    });
    assert!(!b.p.o.cutting_stop);
}

#[test]
fn machine_off_drops_everything() {
    let mut b = Bench::new();
    b.cut();
    b.i.machine_is_on = false;
    b.tick();
    assert_eq!(b.p.state, State::Idle);
    assert!(!b.p.o.torch_on && !b.p.o.feed_hold);
    assert_eq!(b.p.o.z_offset_counts, 0);
}
