//! Locks, puddle jump, skipped IHS, cut recovery, scribing and spotting
//! on the bench.

use super::Bench;
use crate::plasma::plasmac::state::State;

#[test]
fn void_lock_holds_thc_while_the_voltage_climbs_fast() {
    let mut b = Bench::new();
    b.i.voidlock_enable = true;
    b.cut();
    b.until(1000, "thc active", |b| b.p.o.thc_active);
    // 1 V a period is 1000 V/s, over the 500 V/s slope.
    b.volts_error += 1.0;
    b.tick();
    b.volts_error += 1.0;
    b.tick();
    assert!(b.p.o.voidlock_is_locked);
    let held = b.p.z.counts;
    for _ in 0..20 {
        b.volts_error += 1.0;
        b.tick();
    }
    assert_eq!(b.p.z.counts, held, "no correction while locked");
    // Steady again: unlocked after voidlock-off-cycles periods.
    b.run(9);
    assert!(b.p.o.voidlock_is_locked);
    b.run(2);
    assert!(!b.p.o.voidlock_is_locked);
    assert!(b.faults.is_empty());
}

#[test]
fn puddle_jump_holds_at_its_share_of_the_pierce_height() {
    let mut b = Bench::new();
    b.i.puddle_jump_height = 50.0;
    b.i.puddle_jump_delay = 0.05;
    b.i.cutting_start = true;
    b.until_state(20_000, State::PuddleJump);
    assert!(!b.p.o.feed_hold, "motion runs during the puddle jump");
    let at = b.surface + 1.9;
    b.until(100, "at the puddle jump height", |b| {
        (b.z() - at).abs() < 1e-3
    });
    assert_eq!(b.p.state, State::PuddleJump);
    b.until_state(1000, State::CutMode01);
}

#[test]
fn a_cut_near_the_last_one_skips_the_probe() {
    let mut b = Bench::new();
    b.i.skip_ihs_distance = 5.0;
    b.cut();
    b.i.cutting_start = false;
    b.until_state(5000, State::Idle);
    b.base_x = 3.0;
    b.states.clear();
    b.cut();
    assert!(!b.states.contains(&State::ProbeHeight), "{:?}", b.states);
    assert!(!b.states.contains(&State::ProbeDown));
    b.i.cutting_start = false;
    b.until_state(5000, State::Idle);
    // Farther away: probed again.
    b.base_x = 30.0;
    b.states.clear();
    b.cut();
    assert!(b.states.contains(&State::ProbeDown));
}

#[test]
fn cut_recovery_restarts_at_the_offset_and_returns_to_the_path() {
    let mut b = Bench::new();
    b.i.xy_feed_rate = 600.0;
    b.i.cut_feed_rate = 600.0;
    b.cut();
    b.arc_dead = true;
    b.until(20_000, "at the top", |b| b.p.job.waiting);
    b.i.program_is_paused = true;
    b.arc_dead = false;
    b.i.cut_recovery = true;
    b.i.x_offset = 2000;
    b.until(100, "moved", |b| b.p.o.x_offset_counts == 2000);
    assert_eq!(b.p.state, State::CutRecoveryOn);
    assert!(b.p.o.cut_recovering && b.p.o.xy_offset_enable);
    // Resume: pierce again there, then back to the path while cutting.
    b.i.program_is_paused = false;
    b.until_state(20_000, State::CutRecoveryOff);
    b.tick();
    assert!(b.p.o.torch_on && b.p.o.feed_hold);
    b.until_state(1000, State::CutMode01);
    assert_eq!(b.p.o.x_offset_counts, 0);
    assert!(!b.p.o.cut_recovering && !b.p.o.feed_hold);
}

#[test]
fn consumable_change_stays_within_the_axis_limits() {
    let mut b = Bench::new();
    b.i.axis_x_min_limit = 0.0;
    b.i.axis_x_max_limit = 0.01; // 1000 counts of room
    b.i.xy_feed_rate = 6000.0;
    b.cut();
    b.i.program_is_paused = true;
    b.until(20_000, "at the top", |b| b.p.job.waiting);
    b.i.consumable_change = true;
    b.i.x_offset = 5000;
    b.run(20);
    assert_eq!(b.p.o.x_offset_counts, 1000);
}

#[test]
fn scribing_arms_then_turns_on_then_releases_motion() {
    let mut b = Bench::new();
    b.i.scribe_arm_delay = 0.003;
    b.i.scribe_on_delay = 0.003;
    b.i.scribe_start = true;
    b.run(2);
    assert_eq!(b.p.state, State::Scribing);
    assert!(b.p.o.scribe_arm && !b.p.o.scribe_on && b.p.o.feed_hold);
    b.run(3);
    assert!(b.p.o.scribe_on && b.p.o.feed_hold);
    b.run(4);
    assert!(!b.p.o.feed_hold);
    b.i.scribe_start = false;
    b.run(2);
    assert_eq!(b.p.state, State::Idle);
    assert!(!b.p.o.scribe_arm && !b.p.o.scribe_on);
}

#[test]
fn a_spot_ends_its_time_after_the_threshold_voltage() {
    let mut b = Bench::new();
    b.i.spotting_threshold = 90.0;
    b.i.spotting_time = 5.0; // ms
    b.i.spotting_start = true;
    b.until(20_000, "torch on", |b| b.p.o.torch_on);
    b.until(200, "spot over", |b| !b.p.o.torch_on);
    assert!(b.visited_in_order(&[State::CutMode01, State::SafeHeight]));
    b.until_state(5000, State::Idle);
    // Still held: no second spot until it is asked for again.
    b.run(20);
    assert_eq!(b.p.state, State::Idle);
    assert_eq!(b.p.o.pierce_count, 1);
    assert!(b.faults.is_empty());
}
