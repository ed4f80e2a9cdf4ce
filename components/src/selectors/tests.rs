//! Tests of mux2/4/8's select bits, mux16, mux_generic and select8.

use super::mux_generic::{self, convert, select_value, Config, Selection};
use super::*;
use crate::testing::TestHost;
use hal_core::Value::{Bit, Float, S32, U32};
use hal_core::{HalError, HalType};

const P: f64 = 0.001;

fn sel(n: u8) -> [bool; 4] {
    std::array::from_fn(|i| n >> i & 1 == 1)
}

#[test]
fn select_bits_weigh_sel0_least() {
    assert_eq!(bits_value([]), 0);
    assert_eq!(bits_value([true]), 1);
    assert_eq!(bits_value([false, true, true]), 6);
    assert_eq!(bits_value([true; 10]), 1023);
}

#[test]
fn mux16_binary_and_gray_numbers() {
    for n in 0..16u8 {
        assert_eq!(Mux16::number(sel(n), false), n as i32);
        // Gray code of n is n ^ (n >> 1); decoding it gives n back.
        assert_eq!(Mux16::number(sel(n ^ (n >> 1)), true), n as i32);
    }
}

#[test]
fn mux16_without_debounce_follows_at_once() {
    let mut m = Mux16::default();
    let i = Mux16In {
        sel: sel(5),
        ..Default::default()
    };
    let r = m.update(&i, P);
    assert_eq!(
        r,
        Mux16Out {
            selected: Some(5),
            elapsed: None,
            input: Some(5)
        }
    );
    assert_eq!(m.lastnum, 0, "lastnum only moves through the debounce path");
}

#[test]
fn mux16_suppress_no_input_keeps_everything() {
    let mut m = Mux16::default();
    let i = Mux16In {
        suppress_no_input: true,
        ..Default::default()
    };
    assert_eq!(m.update(&i, P), Mux16Out::default());
    let i = Mux16In {
        sel: sel(8),
        suppress_no_input: true,
        ..Default::default()
    };
    assert_eq!(m.update(&i, P).input, Some(8));
}

#[test]
fn mux16_debounce_counts_fperiod_then_switches() {
    let mut m = Mux16::default();
    let i = Mux16In {
        sel: sel(3),
        debounce_time: 0.0025,
        ..Default::default()
    };
    // Delay 0 -> 0.001 -> 0.002 -> 0.003: three calls wait, the fourth
    // (delay 0.003 >= 0.0025) switches.
    let mut e = 0.0;
    for _ in 0..3 {
        let r = m.update(&i, P);
        e += P;
        assert_eq!(r.elapsed, Some(e));
        assert_eq!((r.selected, r.input), (Some(3), None));
    }
    let r = m.update(&i, P);
    assert_eq!((r.elapsed, r.input), (None, Some(3)));
    assert_eq!(m.lastnum, 3);
    // Same selection again: no debounce.
    assert_eq!(m.update(&i, P).input, Some(3));
}

#[test]
fn mux16_return_to_lastnum_keeps_the_timer() {
    let mut m = Mux16::default();
    let at = |n| Mux16In {
        sel: sel(n),
        debounce_time: 0.0025,
        ..Default::default()
    };
    assert_eq!(m.update(&at(1), P).input, None); // delay 0.001
    assert_eq!(m.update(&at(1), P).input, None); // delay 0.002
                                                 // Back at lastnum (0): output follows at once, timer not cleared.
    assert_eq!(m.update(&at(0), P).input, Some(0));
    // The next change continues the old timer: 0.003 after one call.
    let r = m.update(&at(2), P);
    assert_eq!(r.input, None);
    assert!((r.elapsed.unwrap() - 0.003).abs() < 1e-15);
    assert_eq!(m.update(&at(2), P).input, Some(2));
}

#[test]
fn select8_is_one_hot_when_enabled() {
    for s in -1..9 {
        let v = select8(true, s);
        for (i, &o) in v.iter().enumerate() {
            assert_eq!(o, s == i as i32);
        }
        assert_eq!(select8(false, s), [false; 8]);
    }
}

#[test]
fn mux_generic_config_parsing() {
    let c = Config::parse("ff4").unwrap();
    assert_eq!(
        c,
        Config {
            size: 4,
            in_type: HalType::Float,
            out_type: HalType::Float
        }
    );
    let c = Config::parse("b2s").unwrap();
    assert_eq!(
        (c.size, c.in_type, c.out_type),
        (2, HalType::Bit, HalType::S32)
    );
    let c = Config::parse("8fU").unwrap();
    assert_eq!(
        (c.size, c.in_type, c.out_type),
        (8, HalType::Float, HalType::U32)
    );
    let c = Config::parse("S1u2").unwrap();
    assert_eq!(
        (c.size, c.in_type, c.out_type),
        (12, HalType::S32, HalType::U32)
    );
    assert_eq!(Config::parse("b5").unwrap().out_type, HalType::Bit);
    assert_eq!(Config::parse("f99999").unwrap().size, 1024);
    for bad in ["", "ff", "f1", "f0", "fff4", "f4x", "4", "f 4", "f-4"] {
        assert!(Config::parse(bad).is_err(), "{bad:?} accepted");
    }
}

#[test]
fn mux_generic_select_bits() {
    for (size, bits) in [
        (2, 1),
        (3, 1),
        (4, 2),
        (5, 2),
        (6, 0),
        (7, 0),
        (8, 3),
        (9, 3),
        (10, 0),
        (12, 0),
        (16, 4),
        (17, 4),
        (1024, 10),
    ] {
        let c = Config {
            size,
            in_type: HalType::Bit,
            out_type: HalType::Bit,
        };
        assert_eq!(c.select_bits(), bits, "size {size}");
    }
}

#[test]
fn mux_generic_conversions() {
    use HalType as T;
    assert_eq!(convert(Bit(true), T::Float), Float(1.0));
    assert_eq!(convert(Bit(true), T::S32), S32(1));
    assert_eq!(convert(Bit(false), T::U32), U32(0));
    assert_eq!(convert(Float(1e-11), T::Bit), Bit(false));
    assert_eq!(convert(Float(2e-7), T::Bit), Bit(false));
    assert_eq!(convert(Float(-3e-7), T::Bit), Bit(true));
    assert_eq!(convert(Float(5000000000.001), T::S32), S32(i32::MAX));
    assert_eq!(convert(Float(-5e9), T::S32), S32(i32::MIN));
    assert_eq!(convert(Float(-2.9), T::S32), S32(-2));
    assert_eq!(convert(Float(f64::NAN), T::S32), S32(i32::MIN));
    assert_eq!(convert(Float(5000000000.001), T::U32), U32(u32::MAX));
    assert_eq!(convert(Float(-0.5), T::U32), U32(0));
    assert_eq!(convert(Float(3e9 + 0.7), T::U32), U32(3_000_000_000));
    assert_eq!(convert(Float(f64::NAN), T::U32), U32(0));
    assert_eq!(convert(S32(-999), T::U32), U32(0));
    assert_eq!(convert(S32(-999), T::Bit), Bit(true));
    assert_eq!(convert(S32(-999), T::Float), Float(-999.0));
    assert_eq!(convert(U32(u32::MAX), T::S32), S32(i32::MAX));
    assert_eq!(convert(U32(u32::MAX), T::Float), Float(4294967295.0));
    assert_eq!(convert(U32(0), T::Bit), Bit(false));
}

#[test]
fn mux_generic_select_value_adds_bits_and_int() {
    assert_eq!(select_value([true, false, true], 0), 5);
    assert_eq!(select_value([true], 2), 3);
    assert_eq!(select_value([true], u32::MAX), 0);
}

#[test]
fn mux_generic_debounce_lags_by_debounce_over_period() {
    let mut s = Selection::default();
    // 1 ms period, 4000 us debounce: four calls count 1000..4000, the
    // fifth switches.
    for e in [1000, 2000, 3000, 4000] {
        assert_eq!(s.update(1, false, 4000, 1_000_000, 2), None);
        assert_eq!(s.elapsed, e);
        assert_eq!(s.selected, 0);
    }
    assert_eq!(s.update(1, false, 4000, 1_000_000, 2), Some(1));
    assert_eq!(
        s,
        Selection {
            selected: 1,
            elapsed: 0
        }
    );
    // Unchanged selection: immediate.
    assert_eq!(s.update(1, false, 4000, 1_000_000, 2), Some(1));
}

#[test]
fn mux_generic_clamps_and_suppresses() {
    let mut s = Selection::default();
    assert_eq!(s.update(7, false, 0, 1_000_000, 4), Some(3));
    assert_eq!(s.selected, 7, "selected keeps the unclamped value");
    assert_eq!(s.update(0x8000_0000, false, 0, 1_000_000, 4), Some(3));
    assert_eq!(s.update(u32::MAX, false, 0, 1_000_000, 4), Some(3));
    assert_eq!(s.update(0, true, 0, 1_000_000, 4), None);
    assert_eq!(s.selected, u32::MAX);
    assert_eq!(s.update(0, false, 0, 1_000_000, 4), Some(0));
}

#[test]
fn mux_generic_elapsed_wraps() {
    let mut s = Selection {
        selected: 0,
        elapsed: u32::MAX - 10,
    };
    // debounce-us at the maximum: elapsed wraps rather than saturating.
    assert_eq!(s.update(1, false, u32::MAX, 1_000_000, 2), None);
    assert_eq!(s.elapsed, 989);
}

#[test]
fn mux_generic_pins_and_functions() {
    let h = TestHost::new("muxgen-names");
    h.load(&mux_generic::MODULE, &["config=\"ff4,bs2,su8,u6b\""])
        .unwrap();
    let pins = h.pins();
    let want = |n: &str| assert!(pins.contains(&n.to_string()), "{n} missing: {pins:?}");
    for n in [
        "mux-gen.00.sel-bit-00",
        "mux-gen.00.sel-bit-01",
        "mux-gen.00.sel-int",
        "mux-gen.00.in-float-03",
        "mux-gen.00.out-float",
        "mux-gen.00.suppress-no-input",
        "mux-gen.00.debounce-us",
        "mux-gen.01.in-bit-01",
        "mux-gen.01.out-s32",
        "mux-gen.02.sel-bit-02",
        "mux-gen.02.in-s32-07",
        "mux-gen.02.out-u32",
        "mux-gen.03.in-u32-05",
        "mux-gen.03.out-bit",
    ] {
        want(n);
    }
    assert!(!pins.iter().any(|p| p.starts_with("mux-gen.03.sel-bit")));
    assert!(!pins.contains(&"mux-gen.01.sel-bit-01".to_string()));
    assert_eq!(pins.len(), 10 + 7 + 15 + 10);
    assert_eq!(
        h.functs(),
        ["mux-gen.00", "mux-gen.01", "mux-gen.02", "mux-gen.03"]
    );
    assert_eq!(h.params().len(), 8);
    let info = h.host.instance().params().unwrap();
    let sel = info
        .iter()
        .find(|p| p.name == "mux-gen.00.selected")
        .unwrap();
    assert_eq!(sel.hal_type, HalType::U32);
    assert_eq!(sel.dir, hal_core::ParamDir::Ro);
}

#[test]
fn mux_generic_bad_config_fails_the_load() {
    let h = TestHost::new("muxgen-bad");
    for args in [
        &[][..],
        &["config=ff4,f1"][..],
        &["config=ff4,"][..],
        &["config=fx4"][..],
        &["config=fff4"][..],
    ] {
        let e = h.load(&mux_generic::MODULE, args).unwrap_err();
        assert!(
            matches!(&e, HalError::ModuleParam { param, .. } if param == "config"),
            "{args:?}: {e}"
        );
        assert!(h.pins().is_empty(), "{args:?} left pins");
    }
    let many = format!("config={}", vec!["bb2"; 101].join(","));
    assert!(h.load(&mux_generic::MODULE, &[&many]).is_err());
    let hundred = format!("config={}", vec!["bb2"; 100].join(","));
    h.load(&mux_generic::MODULE, &[&hundred]).unwrap();
    assert_eq!(h.functs().last().unwrap(), "mux-gen.99");
}

#[test]
fn mux_generic_runs() {
    let mut h = TestHost::new("muxgen-run");
    h.load(&mux_generic::MODULE, &["config=fs4,u3f"]).unwrap();
    h.thread(&["mux-gen.00", "mux-gen.01"]);
    h.set("mux-gen.00.in-float-02", Float(-7.9));
    h.set("mux-gen.00.in-float-03", Float(1e10));
    h.expect(
        &[("mux-gen.00.sel-bit-01", Bit(true))],
        "mux-gen.00.out-s32",
        S32(-7),
    );
    assert_eq!(h.getp("mux-gen.00.selected"), U32(2));
    h.expect(
        &[("mux-gen.00.sel-int", U32(1))],
        "mux-gen.00.out-s32",
        S32(i32::MAX),
    );
    h.set("mux-gen.01.in-u32-02", U32(u32::MAX));
    h.expect(
        &[("mux-gen.01.sel-int", U32(9))],
        "mux-gen.01.out-float",
        Float(4294967295.0),
    );
    assert_eq!(h.getp("mux-gen.01.selected"), U32(9));
}

#[test]
fn mux16_and_select8_glue() {
    let mut h = TestHost::new("mux16-run");
    h.load(&MUX16, &[]).unwrap();
    h.load(&SELECT8, &[]).unwrap();
    let pins = h.pins();
    assert!(pins.contains(&"mux16.0.in15".to_string()));
    assert!(pins.contains(&"mux16.0.out-s".to_string()));
    assert!(pins.contains(&"select8.0.out7".to_string()));
    assert_eq!(h.params(), ["mux16.0.elapsed", "mux16.0.selected"]);
    assert_eq!(h.get("select8.0.enable"), Bit(true));
    h.thread(&["mux16.0", "select8.0"]);
    h.set("mux16.0.in11", Float(-2.75));
    h.expect(
        &[
            ("mux16.0.sel0", Bit(true)),
            ("mux16.0.sel1", Bit(true)),
            ("mux16.0.sel3", Bit(true)),
        ],
        "mux16.0.out-f",
        Float(-2.75),
    );
    assert_eq!(h.get("mux16.0.out-s"), S32(-2));
    assert_eq!(h.getp("mux16.0.selected"), S32(11));
    // Gray 0b1011 decodes to 13.
    h.set("mux16.0.in13", Float(3e10));
    h.expect(
        &[("mux16.0.use-graycode", Bit(true))],
        "mux16.0.out-f",
        Float(3e10),
    );
    assert_eq!(h.get("mux16.0.out-s"), S32(i32::MIN));
    h.expect(&[("select8.0.sel", S32(6))], "select8.0.out6", Bit(true));
    h.expect(
        &[("select8.0.enable", Bit(false))],
        "select8.0.out6",
        Bit(false),
    );
}
