//! The cut cycle on the bench.

use super::Bench;
use crate::plasma::plasmac::state::{Fault, State, StopType};

#[test]
fn a_full_cut_probes_pierces_cuts_with_thc_and_ends() {
    let mut b = Bench::new();
    b.cut();
    assert!(
        b.visited_in_order(&[
            State::Idle,
            State::ProbeHeight,
            State::ProbeDown,
            State::ProbeUp,
            State::ZeroHeight,
            State::PierceHeight,
            State::TorchOn,
            State::ArcOk,
            State::PierceDelay,
            State::CutHeight,
            State::CutMode01,
        ]),
        "{:?}",
        b.states
    );
    // Zero is the top of the stock: the float switch released at
    // `surface - travel`, plus the travel.
    let zero = f64::from(b.p.zero) * b.p.o.offset_scale;
    assert!((zero - b.surface).abs() < 1e-3, "zero {zero}");
    assert_eq!(b.p.o.pierce_count, 1);
    assert!(b.p.o.torch_on && b.p.o.arc_ok_out);
    assert!(!b.p.o.feed_hold);
    assert!(b.p.o.z_offset_enable);
    assert!(
        (b.z() - (b.surface + 1.5)).abs() < 1e-3,
        "cut height {}",
        b.z()
    );

    // THC activates after its delay at the cut feed rate, at cut-volts.
    b.until(1000, "thc active", |b| b.p.o.thc_active);
    assert_eq!(b.p.o.target_volts, 100.0);
    // The voltage reads 5 V high (the torch is too high): THC moves the
    // torch down until the error is within the threshold.
    b.volts_error = 5.0;
    let before = b.z();
    b.tick();
    assert!(b.p.o.led_down && !b.p.o.led_up);
    b.until(5000, "voltage corrected", |b| {
        (b.p.o.arc_voltage_out - 100.0).abs() < 1.0 && !b.p.o.led_down
    });
    let moved = before - b.z();
    assert!((0.4..=0.5).contains(&moved), "moved down {moved}");
    // Corner lock: slowing below the threshold holds THC.
    b.i.cornerlock_enable = true;
    b.i.cornerlock_threshold = 90.0;
    b.i.feed_override = 2.0; // asks twice the speed the machine runs
    b.tick();
    assert!(b.p.o.cornerlock_is_locked);
    let held = b.p.z.counts;
    b.volts_error = 20.0;
    b.run(20);
    assert_eq!(b.p.z.counts, held);
    b.i.feed_override = 1.0;
    b.volts_error = 0.0;

    // End of cut: torch off, safe height, then idle while the program
    // runs, Z kept there for the next cut.
    b.i.cutting_start = false;
    b.until_state(5000, State::Idle);
    assert!(b.visited_in_order(&[
        State::CutMode01,
        State::SafeHeight,
        State::EndCut,
        State::Idle
    ]));
    assert!(!b.p.o.torch_on && !b.p.o.thc_active);
    assert!(
        (b.z() - (b.surface + 20.0)).abs() < 1e-3,
        "safe height {}",
        b.z()
    );
    assert!(b.faults.is_empty(), "{:?}", b.faults);
    assert!(b.p.o.cut_length > 0.0 || b.p.o.cut_time > 0.0);

    // The program ends: the offset is taken back.
    b.i.program_is_running = false;
    b.i.program_is_idle = true;
    b.until(20_000, "offset back", |b| {
        b.p.state == State::Idle && b.p.o.z_offset_counts == 0
    });
    assert!(b.visited_in_order(&[State::EndJob, State::Idle]));
    assert!(!b.p.o.z_offset_enable);
}

#[test]
fn arc_lost_pauses_at_the_top_and_resume_probes_again() {
    let mut b = Bench::new();
    b.cut();
    b.arc_dead = true;
    b.until_state(100, State::MaxHeight);
    assert_eq!(b.faults, [Fault::ArcLost]);
    assert!(!b.p.o.torch_on);
    assert!(b.p.o.program_pause);
    assert_eq!(b.p.o.stop_type_out, StopType::Wait as i32);
    b.until(20_000, "at the top", |b| b.p.job.waiting);
    assert!((b.z() - 5.0).abs() < 1e-3, "top {}", b.z()); // 10 - max-offset 5
    b.i.program_is_paused = true;
    b.run(3);
    assert!(!b.p.o.program_pause, "halui carried the pause out");
    // Resume: the cut starts again from the probe.
    b.arc_dead = false;
    b.i.program_is_paused = false;
    b.states.clear();
    b.until_state(20_000, State::CutMode01);
    assert!(b.visited_in_order(&[State::ProbeHeight, State::ProbeDown, State::TorchOn]));
    assert_eq!(b.p.o.stop_type_out, StopType::None as i32);
    assert_eq!(b.p.o.pierce_count, 2);
}

#[test]
fn a_program_pause_is_a_pause_stop_type_with_paused_motion() {
    let mut b = Bench::new();
    b.cut();
    b.i.program_is_paused = true;
    b.tick();
    assert_eq!(b.p.state, State::MaxHeight);
    assert_eq!(b.p.o.stop_type_out, StopType::Pause as i32);
    assert!(!b.p.o.torch_on);
    b.until(20_000, "at the top", |b| b.p.job.waiting);
    b.i.paused_motion_speed = -0.5;
    b.tick();
    assert_eq!(b.p.state, State::PausedMotion);
    assert!(b.p.o.program_resume);
    b.tick();
    assert!(b.p.o.paused_motion);
    assert_eq!(b.p.o.adaptive_feed, -0.5);
    b.i.paused_motion_speed = 0.0;
    b.tick();
    assert_eq!(b.p.state, State::MaxHeight);
    assert!(b.p.o.program_pause && !b.p.o.paused_motion);
    assert!(b.faults.is_empty());
}

#[test]
fn consumable_change_moves_xy_away_and_back_while_paused() {
    let mut b = Bench::new();
    b.cut();
    b.i.program_is_paused = true;
    b.until(20_000, "at the top", |b| b.p.job.waiting);
    b.i.consumable_change = true;
    b.i.x_offset = 5000;
    b.i.y_offset = -3000;
    b.i.xy_feed_rate = 600.0;
    b.until(100, "xy away", |b| {
        b.p.o.x_offset_counts == 5000 && b.p.o.y_offset_counts == -3000
    });
    assert_eq!(b.p.state, State::ConsumableChangeOn);
    assert!(b.p.o.consumable_changing && b.p.o.xy_offset_enable);
    b.i.consumable_change = false;
    b.until_state(100, State::MaxHeight);
    assert_eq!((b.p.o.x_offset_counts, b.p.o.y_offset_counts), (0, 0));
    assert!(!b.p.o.consumable_changing);
}

#[test]
fn hole_overcut_turns_the_torch_off_and_thc_holds() {
    let mut b = Bench::new();
    b.cut();
    b.until(1000, "thc active", |b| b.p.o.thc_active);
    b.i.torch_off = true;
    b.tick();
    assert!(!b.p.o.torch_on, "torch off for the over-cut");
    assert_eq!(b.p.state, State::CutMode01, "motion goes on");
    b.run(50);
    assert!(b.faults.is_empty(), "no arc lost with the torch off");
    assert!(!b.p.o.thc_active);
}

#[test]
fn mode_2_follows_the_up_and_down_inputs() {
    let mut b = Bench::new();
    b.i.mode = 2;
    b.i.cutting_start = true;
    b.until_state(20_000, State::CutMode2);
    b.until(1000, "thc active", |b| b.p.o.thc_active);
    let z = b.p.z.counts;
    b.i.move_up = true;
    b.tick();
    // 600 mm/min for 1 ms: 0.01 mm, 1000 counts.
    assert_eq!(b.p.z.counts, z + 1000);
    assert!(b.p.o.led_up);
}

#[test]
fn torch_pulse_fires_for_its_time() {
    let mut b = Bench::new();
    b.i.torch_pulse_time = 0.005;
    b.i.torch_pulse_start = true;
    b.tick();
    b.tick();
    assert_eq!(b.p.state, State::TorchPulse);
    assert!(b.p.o.torch_on);
    b.until_state(20, State::Idle);
    assert!(!b.p.o.torch_on);
}

#[test]
fn mode_0_takes_arc_ok_from_the_voltage_window() {
    let mut b = Bench::new();
    b.i.mode = 0;
    b.i.arc_ok_low = 60.0;
    b.i.arc_ok_high = 250.0;
    b.i.ok_sample_counts = 3;
    b.i.ok_sample_threshold = 10.0;
    b.cut();
    assert!(b.p.o.arc_ok_out);
    assert!(b.faults.is_empty(), "{:?}", b.faults);
    // A voltage out of the window is a lost arc.
    b.volts_error = 200.0;
    b.until_state(100, State::MaxHeight);
    assert_eq!(b.faults, [Fault::ArcLost]);
}
