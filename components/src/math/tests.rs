//! Tests of the math family: the arithmetic directly, then the HAL glue.

use super::*;
use crate::testing::TestHost;
use hal_core::Value::{Bit, Float, S32, S64};

#[test]
fn abs_float_keeps_negative_zero_and_negates_nan() {
    let r = abs_f64(-0.25);
    assert_eq!(
        r,
        AbsOut {
            out: 0.25,
            sign: true,
            is_positive: false,
            is_negative: true
        }
    );
    let r = abs_f64(64.0);
    assert_eq!(
        (r.out, r.sign, r.is_positive, r.is_negative),
        (64.0, false, true, false)
    );
    // -0.0 >= 0.0: passes through with its sign bit.
    let r = abs_f64(-0.0);
    assert!(r.out == 0.0 && r.out.is_sign_negative() && !r.sign);
    // NaN takes the negative branch.
    let r = abs_f64(f64::NAN);
    assert!(r.out.is_nan() && r.out.is_sign_negative() && r.sign);
    assert!(!r.is_positive && !r.is_negative);
}

#[test]
fn abs_float_flags_have_a_dead_zone() {
    for (x, pos, neg) in [
        (0.000001, false, false),
        (0.0000011, true, false),
        (-0.000001, false, false),
        (-0.0000011, false, true),
        (0.0, false, false),
    ] {
        let r = abs_f64(x);
        assert_eq!((r.is_positive, r.is_negative), (pos, neg), "{x}");
        assert_eq!(r.sign, x < 0.0);
    }
}

#[test]
fn abs_integers_wrap_at_the_minimum() {
    assert_eq!(abs_i32(-5).out, 5);
    assert!(abs_i32(-5).sign && abs_i32(-5).is_negative);
    assert_eq!(abs_i32(i32::MIN).out, i32::MIN);
    assert!(abs_i32(i32::MIN).sign);
    assert_eq!(abs_i32(i32::MAX).out, i32::MAX);
    let z = abs_i32(0);
    assert!(!z.sign && !z.is_positive && !z.is_negative);
    assert_eq!(abs_i64(i64::MIN).out, i64::MIN);
    assert_eq!(abs_i64(-7).out, 7);
    assert!(abs_i64(7).is_positive && !abs_i64(7).sign);
}

#[test]
fn div2_floors_the_deadband_and_substitutes_the_divisor() {
    let mut d = Div2::default();
    // Default deadband 0 is floored to 1e-12 and written back.
    let r = d.update(1.0, 2.0, 0.0);
    assert_eq!(r.out, 0.5);
    assert_eq!(r.deadband, Some(1e-12));
    assert_eq!(r.message, None);
    // A large enough deadband is kept as is.
    let r = d.update(1.0, 4.0, 0.05);
    assert_eq!((r.out, r.deadband), (0.25, None));
    // Inside the band: the signed deadband replaces the divisor.
    let r = d.update(1.0, -0.04, 0.05);
    assert_eq!(r.out, 1.0 / -0.05);
    assert_eq!(r.message, Some(Div2Message::NearNegativeZero));
    // An exact zero (and -0.0) counts as positive.
    let r = d.update(1.0, 0.0, 0.05);
    assert_eq!(r.out, 1.0 / 0.05);
    let r = d.update(1.0, -0.0, 0.05);
    assert_eq!(r.out, 1.0 / 0.05);
    // The band edges belong outside.
    assert_eq!(d.update(1.0, -0.05, 0.05).out, 1.0 / -0.05);
    assert_eq!(d.update(1.0, 0.05, 0.05).out, 1.0 / 0.05);
    assert_eq!(band(-0.05, 0.05), Band::Outside);
    assert_eq!(band(0.05, 0.05), Band::Outside);
    assert_eq!(band(f64::NAN, 0.05), Band::Outside);
}

#[test]
fn div2_message_is_printed_once_until_the_divisor_leaves_the_band() {
    let mut d = Div2::default();
    let msgs: Vec<_> = [-1.0, -0.04, -0.02, 0.0, 0.02, 0.06, 0.01, 0.0, -0.01, 2.0]
        .iter()
        .map(|&x| d.update(1.0, x, 0.05).message)
        .collect();
    use Div2Message::*;
    assert_eq!(
        msgs,
        [
            None,
            Some(NearNegativeZero),
            None,
            None, // one flag for both sides
            None,
            None, // re-armed
            Some(NearPositiveZero),
            None,
            None,
            None
        ]
    );
}

#[test]
fn div2_message_text_matches_linuxcnc() {
    assert_eq!(
        DIV2_TEXTS[Div2Message::NearNegativeZero as usize],
        "\n \n DIV2 DIVISOR IS TOO CLOSE TO -ZERO,\n THEREFORE -DEADBAND IS USED.\n INCREASE THE DIVISOR, in1.\n \n \n"
    );
    assert!(DIV2_TEXTS[Div2Message::NearPositiveZero as usize].contains("+ZERO"));
}

#[test]
fn invert_uses_the_same_deadband_rule() {
    assert_eq!(invert(4.0, 0.0), (0.25, Some(1e-12)));
    assert_eq!(invert(0.0, 0.0), (1e12, Some(1e-12)));
    assert_eq!(invert(-1e-13, 0.0), (-1e12, Some(1e-12)));
    assert_eq!(invert(0.01, 0.1), (10.0, None));
    assert_eq!(invert(-0.01, 0.1), (-10.0, None));
    assert_eq!(invert(-0.1, 0.1), (-10.0, None));
    assert_eq!(invert(-2.0, 0.1), (-0.5, None));
    // A deadband below 1e-12 (even 1e-13) is raised.
    assert_eq!(invert(8.0, 1e-13), (0.125, Some(1e-12)));
}

#[test]
fn scale_hypot_blend_formulas() {
    assert_eq!(scale(2.0, -3.7, 0.125), 2.0 * -3.7 + 0.125);
    assert_eq!(scale(5.0, 0.0, 1.5), 1.5);
    assert_eq!(hypot3(3.0, 4.0, 0.0), 5.0);
    assert_eq!(hypot3(1.0, 2.0, 2.0), 3.0);
    // The plain formula overflows where the library hypot would not.
    assert_eq!(hypot3(1e200, 0.0, 0.0), f64::INFINITY);
    assert_eq!(blend(10.0, 20.0, 0.25, false), 10.0 * 0.25 + 20.0 * 0.75);
    assert_eq!(blend(10.0, 20.0, -1.0, false), 20.0);
    assert_eq!(blend(10.0, 20.0, 2.0, false), 10.0);
    assert!(blend(10.0, 20.0, f64::NAN, false).is_nan());
    assert_eq!(blend(10.0, 20.0, -1.0, true), -10.0 + 20.0 * 2.0);
    assert_eq!(blend(10.0, 20.0, 2.0, true), 20.0 - 20.0);
}

#[test]
fn names_follow_halcompile() {
    let h = TestHost::new("math-names");
    h.load(&ABS, &[]).unwrap();
    h.load(&ABS_S32, &["count=2"]).unwrap();
    h.load(&ABS_S64, &["names=a64"]).unwrap();
    h.load(&DIV2, &[]).unwrap();
    h.load(&SCALE, &[]).unwrap();
    h.load(&INVERT, &[]).unwrap();
    h.load(&HYPOT, &[]).unwrap();
    h.load(&BLEND, &[]).unwrap();
    let pins = h.pins();
    for p in [
        "abs.0.in",
        "abs.0.out",
        "abs.0.sign",
        "abs.0.is-positive",
        "abs.0.is-negative",
        "abs-s32.1.is-negative",
        "a64.out",
        "div2.0.in0",
        "div2.0.in1",
        "div2.0.out",
        "scale.0.in",
        "scale.0.gain",
        "scale.0.offset",
        "scale.0.out",
        "invert.0.in",
        "invert.0.out",
        "hypot.0.in0",
        "hypot.0.in1",
        "hypot.0.in2",
        "hypot.0.out",
        "blend.0.in1",
        "blend.0.in2",
        "blend.0.select",
        "blend.0.out",
    ] {
        assert!(pins.contains(&p.to_string()), "{p} missing from {pins:?}");
    }
    assert_eq!(
        h.params(),
        ["blend.0.open", "div2.0.deadband", "invert.0.deadband"]
    );
    assert_eq!(
        h.functs(),
        [
            "a64",
            "abs-s32.0",
            "abs-s32.1",
            "abs.0",
            "blend.0",
            "div2.0",
            "hypot.0",
            "invert.0",
            "scale.0"
        ]
    );
    assert!(h.load(&SCALE, &["count=1"]).is_err(), "loaded twice");
}

#[test]
fn components_compute_in_a_thread() {
    let mut h = TestHost::new("math-run");
    for def in modules() {
        h.load(def, &[]).unwrap();
    }
    h.thread(&[
        "abs.0",
        "abs-s32.0",
        "abs-s64.0",
        "div2.0",
        "scale.0",
        "invert.0",
        "hypot.0",
        "blend.0",
    ]);
    h.expect(&[("abs.0.in", Float(-3.5))], "abs.0.out", Float(3.5));
    assert_eq!(h.get("abs.0.sign"), Bit(true));
    assert_eq!(h.get("abs.0.is-negative"), Bit(true));
    h.expect(
        &[("abs-s32.0.in", S32(i32::MIN))],
        "abs-s32.0.out",
        S32(i32::MIN),
    );
    h.expect(&[("abs-s64.0.in", S64(-9))], "abs-s64.0.out", S64(9));
    // The first call rewrites the deadband param.
    h.expect(
        &[("div2.0.in0", Float(3.0)), ("div2.0.in1", Float(4.0))],
        "div2.0.out",
        Float(0.75),
    );
    assert_eq!(h.getp("div2.0.deadband"), Float(1e-12));
    assert_eq!(h.getp("invert.0.deadband"), Float(1e-12));
    h.expect(&[("invert.0.in", Float(0.0))], "invert.0.out", Float(1e12));
    h.expect(
        &[
            ("scale.0.in", Float(2.0)),
            ("scale.0.gain", Float(3.0)),
            ("scale.0.offset", Float(1.0)),
        ],
        "scale.0.out",
        Float(7.0),
    );
    h.expect(
        &[
            ("hypot.0.in0", Float(2.0)),
            ("hypot.0.in1", Float(3.0)),
            ("hypot.0.in2", Float(6.0)),
        ],
        "hypot.0.out",
        Float(7.0),
    );
    h.expect(
        &[
            ("blend.0.in1", Float(1.0)),
            ("blend.0.in2", Float(3.0)),
            ("blend.0.select", Float(5.0)),
        ],
        "blend.0.out",
        Float(1.0),
    );
    h.setp("blend.0.open", Bit(true));
    h.expect(&[], "blend.0.out", Float(5.0 + 3.0 * -4.0));
}

#[test]
fn constant_puts_its_value_on_out() {
    let mut h = TestHost::new("math-constant");
    h.load(&CONSTANT, &["count=2"]).unwrap();
    h.thread(&["constant.0", "constant.1"]);
    h.setp("constant.1.value", Float(-2.5));
    h.run(2);
    assert_eq!(h.get("constant.0.out"), Float(0.0), "value defaults to 0.0");
    assert_eq!(h.get("constant.1.out"), Float(-2.5));
}
