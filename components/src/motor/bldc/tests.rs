//! Tests of bldc: the configuration letters, each feedback type and
//! output type, and the pins each configuration creates.

use super::tables::COMMUTATION;
use super::*;
use crate::testing::TestHost;
use hal_core::Value::{Bit, Float, S32};

/// A controller for `cfg` past its set-up call, with the params'
/// defaults.
fn motor(cfg: &str) -> (Bldc, BldcVars) {
    let mut b = Bldc::new(cfg_bits(cfg).unwrap());
    let mut v = BldcVars {
        in_type: -1,
        out_type: -1,
        lead_angle: 90.0,
        initvalue: 0.2,
        scale: 512,
        poles: 4,
        pattern: 25,
        output_pattern: 25,
        ..Default::default()
    };
    assert_eq!(b.step(&mut v, 1_000_000), None);
    (b, v)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

#[test]
fn cfg_letters_set_personality_bits() {
    assert_eq!(cfg_bits("qi6").unwrap(), QUADRATURE | INDEX | SIX);
    assert_eq!(cfg_bits("aH").unwrap(), ABSOLUTE | HALL_OUT);
    assert_eq!(cfg_bits("n").unwrap(), 0);
    assert_eq!(cfg_bits("hBT").unwrap(), HALL | BITS_OUT | TRAPEZOIDAL);
    assert!(cfg_bits("x").is_err());
    assert!(cfg_bits("").is_err());
}

#[test]
fn first_call_sets_the_types_up() {
    let (_, v) = motor("qi6");
    assert_eq!((v.in_type, v.out_type), (0x0c, 0x200));
    assert!(v.index_enable, "index modes arm the encoder index");
}

#[test]
fn free_running_vfd_mode_turns_at_the_frequency() {
    let (mut b, mut v) = motor("n");
    v.frequency = 10.0;
    v.value = 2.0;
    b.step(&mut v, 1_000_000);
    assert!(close(v.phase_angle, 0.01) && v.rotor_angle == v.phase_angle);
    assert_eq!((v.out, v.out_abs, v.out_dir), (2.0, 2.0, false));
    let w = (0.01 * std::f64::consts::TAU).cos();
    assert_eq!(v.value_out[0], 2.0 * w);
    // The three phases sum to zero.
    assert!(v.value_out.iter().sum::<f64>().abs() < 1e-12);
    // rev reverses the sign of the drive.
    v.rev = true;
    b.step(&mut v, 1_000_000);
    assert_eq!((v.out, v.out_dir, v.out_abs), (-2.0, true, 2.0));
}

#[test]
fn hall_sensors_commutate_trapezoidally() {
    let (mut b, mut v) = motor("h");
    v.value = 1.5;
    // Pattern 25 shows Hall 101 while exciting B-A: B high, A low.
    v.hall = [true, false, true];
    b.step(&mut v, 1_000_000);
    assert_eq!(v.value_out, [-1.5, 1.5, 0.0]);
    assert!(close(v.rotor_angle, 6.0 / 36.0));
    // An impossible Hall state (all on) excites nothing.
    v.hall = [true, true, true];
    b.step(&mut v, 1_000_000);
    assert_eq!(v.value_out, [0.0; 3]);
    // A pattern past 47 is refused and reset.
    v.pattern = 48;
    assert_eq!(
        b.step(&mut v, 1_000_000),
        Some(control::Message::BadPattern)
    );
    assert_eq!(v.pattern, 0);
}

#[test]
fn hall_error_flags_a_jump_between_unrelated_states() {
    let (mut b, mut v) = motor("h");
    v.hall = [true, false, true]; // B-A (024)
    b.step(&mut v, 1_000_000);
    assert!(!v.hall_error, "a new pattern clears the flag");
    v.hall = [false, true, false]; // A-B (042): no common driver
    b.step(&mut v, 1_000_000);
    assert!(v.hall_error);
}

#[test]
fn emulated_hall_output_reproduces_the_hall_input() {
    let (mut b, mut v) = motor("hH");
    for hall in 0..8u8 {
        let h = [hall & 4 != 0, hall & 2 != 0, hall & 1 != 0];
        v.hall = h;
        b.step(&mut v, 1_000_000);
        if COMMUTATION[25 * 8 + hall as usize] != 0 {
            assert_eq!(v.hall_out, h, "hall state {hall:03b}");
        }
    }
}

#[test]
fn absolute_encoder_gives_the_electrical_angle() {
    let (mut b, mut v) = motor("a");
    v.value = 1.0;
    // 512 counts per turn, 4 poles: 256 counts per electrical turn.
    v.rawcounts = 64;
    b.step(&mut v, 1_000_000);
    // Lag compensation adds half the last step: 64 + 32 = 96 counts.
    assert!(close(v.rotor_angle, 96.0 * 2.0 / 512.0));
    assert!(
        close(v.phase_angle, 96.0 * 2.0 / 512.0 + 0.25),
        "90 degree lead"
    );
    b.step(&mut v, 1_000_000);
    assert!(close(v.rotor_angle, 0.25), "no motion: no compensation");
    // The sinusoidal outputs follow the phase angle.
    let c = (v.phase_angle * std::f64::consts::TAU).cos();
    assert_eq!(v.value_out[0], c);
    // Counts wrap through the s32 range without a jump.
    let (mut b, mut v) = motor("a");
    v.rawcounts = i32::MAX;
    b.step(&mut v, 1_000_000);
    v.rawcounts = i32::MIN;
    b.step(&mut v, 1_000_000);
    b.step(&mut v, 1_000_000);
    let want = ((i64::from(i32::MAX) + 1) * 4 / 2) as f64 / 512.0;
    assert!(close(v.rotor_angle, want - want.floor()));
}

#[test]
fn index_homing_turns_until_the_encoder_latches() {
    let (mut b, mut v) = motor("qi");
    v.init = true;
    v.initvalue = 0.3;
    b.step(&mut v, 1_000_000);
    assert!(close(v.rotor_angle, 0.001));
    assert_eq!(v.out, 0.3, "homing current");
    b.step(&mut v, 1_000_000);
    assert!(close(v.rotor_angle, 0.002));
    v.rawcounts = 77;
    v.index_enable = false; // the encoder found its index
    b.step(&mut v, 1_000_000);
    assert!(v.init_done);
    assert_eq!((v.in_type, v.offset_measured), (0x02, 77));
}

#[test]
fn magnetic_homing_runs_the_alignment_sequence() {
    let (mut b, mut v) = motor("q");
    v.value = 5.0;
    v.init = true;
    let mut calls = 0;
    while !v.init_done {
        b.step(&mut v, 1_000_000);
        calls += 1;
        assert!(calls < 3000);
        if calls == 1 {
            assert_eq!(v.out, 0.0, "starts with no current");
        }
        if calls == 1000 {
            assert!(close(v.out, 0.2), "full homing current mid-way");
        }
    }
    // 2.4 s of 1 ms steps, then the call that finishes.
    assert!((2400..=2402).contains(&calls), "{calls}");
    assert_eq!(v.in_type, 0x02);
    // A new rising edge of init starts over.
    v.init = false;
    b.step(&mut v, 1_000_000);
    v.init = true;
    b.step(&mut v, 1_000_000);
    // (and the same call sets the input type up again)
    assert!(!v.init_done && v.in_type == 0x04);
}

#[test]
fn contradictory_feedback_is_reported() {
    let (mut b, mut v) = motor("ai");
    assert_eq!(
        b.step(&mut v, 1_000_000),
        Some(control::Message::AbsoluteAndIndex)
    );
    assert_eq!(v.in_type, 0x02);
    let (mut b, mut v) = motor("aq");
    assert_eq!(
        b.step(&mut v, 1_000_000),
        Some(control::Message::TwoEncoders)
    );
    assert_eq!(b.step(&mut v, 1_000_000), None, "disabled: silent");
    assert_eq!(v.in_type, -2);
    let (mut b, mut v) = motor("nHB");
    assert_eq!(
        b.step(&mut v, 1_000_000),
        Some(control::Message::HallAndBits)
    );
    assert_eq!(v.out_type, 0x400);
}

#[test]
fn six_wire_and_bit_outputs() {
    let (mut b, mut v) = motor("h6");
    v.value = -2.0; // reversed: sources and sinks swap
    v.hall = [true, false, true]; // B-A
    b.step(&mut v, 1_000_000);
    assert_eq!((v.value_out, v.low), ([2.0, 0.0, 0.0], [0.0, 2.0, 0.0]));
    let (mut b, mut v) = motor("h6B");
    v.hall = [true, false, true];
    b.step(&mut v, 1_000_000);
    assert_eq!(
        (v.high_on, v.low_on),
        ([false, true, false], [true, false, false])
    );
}

#[test]
fn pins_follow_the_cfg() {
    let h = TestHost::new("bldc-pins");
    h.load(&MODULE, &["cfg=qi6,aH"]).unwrap();
    h.check_pins(
        "bldc.0",
        &[
            "value float in 0",
            "lead-angle float in 90",
            "rev bit in 0",
            "initvalue float in 0.2",
            "rawcounts s32 in 0",
            "index-enable bit io 0",
            "init bit in 0",
            "init-done bit out 0",
            "A-high float out 0",
            "B-high float out 0",
            "C-high float out 0",
            "A-low float out 0",
            "B-low float out 0",
            "C-low float out 0",
            "phase-angle float out 0",
            "rotor-angle float out 0",
            "out float out 0",
            "out-dir bit out 0",
            "out-abs float out 0",
        ],
    );
    h.check_params(
        "bldc.0",
        &[
            "in-type s32 ro -1",
            "out-type s32 ro -1",
            "scale s32 rw 512",
            "poles s32 rw 4",
            "encoder-offset s32 rw 0",
            "offset-measured s32 ro 0",
            "drive-offset float rw 0",
        ],
    );
    h.check_pins(
        "bldc.1",
        &[
            "value float in 0",
            "lead-angle float in 90",
            "rev bit in 0",
            "rawcounts s32 in 0",
            "hall1-out bit out 0",
            "hall2-out bit out 0",
            "hall3-out bit out 0",
            "phase-angle float out 0",
            "rotor-angle float out 0",
            "out float out 0",
            "out-dir bit out 0",
            "out-abs float out 0",
        ],
    );
    h.check_params(
        "bldc.1",
        &[
            "in-type s32 ro -1",
            "out-type s32 ro -1",
            "scale s32 rw 512",
            "poles s32 rw 4",
            "encoder-offset s32 rw 0",
            "drive-offset float rw 0",
            "output-pattern u32 rw 25",
        ],
    );
}

#[test]
fn hall_and_fanuc_pins() {
    let h = TestHost::new("bldc-hall");
    h.load(&MODULE, &["cfg=hF,fB"]).unwrap();
    for p in ["hall1", "hall2", "hall3", "hall-error", "C1-out", "C8-out"] {
        assert_eq!(h.items(&format!("bldc.0.{p}")).len(), 1, "{p}");
    }
    for p in ["C1", "C2", "C4", "C8", "A-on", "B-on", "C-on"] {
        assert_eq!(h.items(&format!("bldc.1.{p}")).len(), 1, "{p}");
    }
    assert_eq!(h.items("bldc.0.pattern").len(), 1);
    assert!(h.items("bldc.0.frequency").is_empty());
    // Phase values exist only without any other output letter.
    assert!(h.items("bldc.0.A-value").is_empty());
}

#[test]
fn bad_cfg_leaves_nothing() {
    let h = TestHost::new("bldc-bad");
    for bad in [&[][..], &["cfg=qx"], &["cfg=q,,a"], &["count=1"]] {
        h.check_load_fails(&MODULE, bad);
    }
}

#[test]
fn runs_in_a_thread() {
    let mut h = TestHost::new("bldc-run");
    h.load(&MODULE, &["cfg=a"]).unwrap();
    h.thread(&["bldc.0"]);
    h.set("bldc.0.value", Float(-1.0));
    h.expect(
        &[("bldc.0.rawcounts", S32(128))],
        "bldc.0.out-dir",
        Bit(true),
    );
    assert_eq!(h.getp("bldc.0.in-type"), S32(2));
    // 128 counts of 256 per electrical turn.
    assert_eq!(h.get("bldc.0.rotor-angle"), Float(0.5));
}
