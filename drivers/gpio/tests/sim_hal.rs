//! `loadrt hal_gpio` on the simulated chips: every pin, parameter and
//! function, inversion, the electrical flags, reset pulses in a running
//! thread, the load errors, and a chip removed mid-run.

use std::sync::Arc;
use std::time::Duration;

mod common;

use common::*;
use hal_core::{HalType, Host, ParamDir, PinDir, Value};
use hal_driver::sim::MonotonicClock;
use hal_gpio::cfg::Direction;
use hal_gpio::chip::{ChipSet, LineSetting};
use hal_gpio::regs::flags;
use hal_gpio::sim::{SimChip, SimChips};

fn loadrt(host: &Host, args: &[&str]) -> hal_core::Result<()> {
    host.loadrt(&hal_gpio::MODULE, args)
}

fn sim(host: &Host) -> Arc<SimChips> {
    hal_driver::sim::find(host.instance().name(), hal_gpio::hal::SIM_KEY)
        .expect("simulated chips published")
}

/// Waits until the chip has been read `n` more times after this call
/// (plus one, so the n-th cycle has finished).
fn cycles(chip: &SimChip, n: u64) {
    let start = chip.gets();
    wait_for("thread cycles", || chip.gets() > start + n);
}

const EXAMPLE: &[&str] = &[
    "backend=sim",
    "inputs=GPIO5,GPIO6",
    "outputs=GPIO20,GPIO21,GPIO22",
    "invert=GPIO20",
    "reset=GPIO21,GPIO22",
];

#[test]
fn every_pin_param_and_function_as_linuxcnc_names_them() {
    let h = host("names");
    loadrt(&h, EXAMPLE).unwrap();
    let pins: Vec<_> = h
        .instance()
        .pins()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == "hal_gpio")
        .map(|p| (p.name, p.hal_type, p.dir, p.value))
        .collect();
    let b = |v| Value::Bit(v);
    assert_eq!(
        pins,
        vec![
            (
                "hal_gpio.GPIO20-out".into(),
                HalType::Bit,
                PinDir::In,
                b(false)
            ),
            (
                "hal_gpio.GPIO21-out".into(),
                HalType::Bit,
                PinDir::In,
                b(false)
            ),
            (
                "hal_gpio.GPIO22-out".into(),
                HalType::Bit,
                PinDir::In,
                b(false)
            ),
            (
                "hal_gpio.GPIO5-in".into(),
                HalType::Bit,
                PinDir::Out,
                b(false)
            ),
            (
                "hal_gpio.GPIO5-in-not".into(),
                HalType::Bit,
                PinDir::Out,
                b(true)
            ),
            (
                "hal_gpio.GPIO6-in".into(),
                HalType::Bit,
                PinDir::Out,
                b(false)
            ),
            (
                "hal_gpio.GPIO6-in-not".into(),
                HalType::Bit,
                PinDir::Out,
                b(true)
            ),
            (
                "hal_gpio.read.time".into(),
                HalType::S32,
                PinDir::Out,
                Value::S32(0)
            ),
            (
                "hal_gpio.reset.time".into(),
                HalType::S32,
                PinDir::Out,
                Value::S32(0)
            ),
            (
                "hal_gpio.write.time".into(),
                HalType::S32,
                PinDir::Out,
                Value::S32(0)
            ),
        ]
    );
    let params: Vec<_> = h
        .instance()
        .params()
        .unwrap()
        .into_iter()
        .filter(|p| p.owner == "hal_gpio" && !p.name.contains(".tmax"))
        .map(|p| (p.name, p.hal_type, p.dir, p.value))
        .collect();
    assert_eq!(
        params,
        vec![(
            "hal_gpio.reset_ns".into(),
            HalType::U32,
            ParamDir::Rw,
            Value::U32(5000)
        )]
    );
    let functs: Vec<_> = h
        .instance()
        .functs()
        .unwrap()
        .into_iter()
        .filter(|f| f.owner == "hal_gpio")
        .map(|f| (f.name, f.uses_fp))
        .collect();
    assert_eq!(
        functs,
        vec![
            ("hal_gpio.read".into(), false),
            ("hal_gpio.reset".into(), false),
            ("hal_gpio.write".into(), false),
        ]
    );
}

#[test]
fn without_reset_lines_there_is_no_reset_ns_and_no_reset() {
    let h = host("noreset");
    loadrt(&h, &["backend=sim", "outputs=A"]).unwrap();
    assert!(h.instance().param("hal_gpio.reset_ns").unwrap().is_none());
    let functs: Vec<_> = h
        .instance()
        .functs()
        .unwrap()
        .into_iter()
        .map(|f| f.name)
        .collect();
    assert!(functs.contains(&"hal_gpio.write".to_string()));
    assert!(!functs.contains(&"hal_gpio.reset".to_string()));
}

#[test]
fn inputs_outputs_and_inversion_in_a_running_thread() {
    let h = host("io");
    loadrt(&h, EXAMPLE).unwrap();
    let s = sim(&h);
    let chip = s.chips()[0].clone();
    // Requested: the inverted output sits high (inactive) at once.
    assert_eq!(s.level("GPIO20"), Some(true));
    assert_eq!(s.level("GPIO21"), Some(false));
    run(&h, 1_000_000, &["hal_gpio.read", "hal_gpio.write"]);
    s.set_outside("GPIO5", true);
    cycles(&chip, 2);
    assert!(bit(&h, "hal_gpio.GPIO5-in") && !bit(&h, "hal_gpio.GPIO5-in-not"));
    assert!(!bit(&h, "hal_gpio.GPIO6-in") && bit(&h, "hal_gpio.GPIO6-in-not"));
    s.set_outside("GPIO5", false);
    s.set_outside("GPIO6", true);
    cycles(&chip, 2);
    assert!(!bit(&h, "hal_gpio.GPIO5-in") && bit(&h, "hal_gpio.GPIO5-in-not"));
    assert!(bit(&h, "hal_gpio.GPIO6-in") && !bit(&h, "hal_gpio.GPIO6-in-not"));

    set(&h, "hal_gpio.GPIO20-out", true);
    set(&h, "hal_gpio.GPIO22-out", true);
    cycles(&chip, 2);
    assert_eq!(s.level("GPIO20"), Some(false), "inverted: TRUE is low");
    assert_eq!(s.level("GPIO22"), Some(true));
    assert_eq!(s.level("GPIO21"), Some(false));
    // Nothing changes: no more writes.
    let writes = chip.sets();
    cycles(&chip, 3);
    assert_eq!(chip.sets(), writes, "write only on change");
    h.stop();
    // Unload: every output to its inactive level, then the lines are
    // released (and float back to their outside level, 0 here).
    chip.clear_events();
    h.unloadrt("hal_gpio").unwrap();
    let ev = |n: &str| -> Vec<bool> {
        chip.events_of(chip.offset(n).unwrap())
            .iter()
            .map(|e| e.level)
            .collect()
    };
    assert_eq!(
        ev("GPIO20"),
        [true, false],
        "inactive (high), then released"
    );
    assert_eq!(
        ev("GPIO22"),
        [false],
        "inactive (low); release changes nothing"
    );
    assert_eq!(chip.line_flags(0), None, "lines released");
}

#[test]
fn electrical_flags_reach_the_chip() {
    let h = host("flags");
    loadrt(
        &h,
        &[
            "backend=sim",
            "inputs=I1,I2,I3",
            "outputs=O1,O2,O3",
            "pullup=I1",
            "pulldown=I2,O3",
            "biasdisable=I3",
            "opendrain=O1",
            "opensource=O2",
            "invert=O2",
        ],
    )
    .unwrap();
    let s = sim(&h);
    let f = |n: &str| {
        let (c, o) = s.line(n).unwrap();
        c.line_flags(o).unwrap()
    };
    let used = flags::USED;
    assert_eq!(f("I1"), used | flags::INPUT | flags::BIAS_PULL_UP);
    assert_eq!(f("I2"), used | flags::INPUT | flags::BIAS_PULL_DOWN);
    assert_eq!(f("I3"), used | flags::INPUT | flags::BIAS_DISABLED);
    assert_eq!(f("O1"), used | flags::OUTPUT | flags::OPEN_DRAIN);
    assert_eq!(
        f("O2"),
        used | flags::OUTPUT | flags::OPEN_SOURCE | flags::ACTIVE_LOW
    );
    assert_eq!(f("O3"), used | flags::OUTPUT | flags::BIAS_PULL_DOWN);
    let (c, o) = s.line("O1").unwrap();
    assert_eq!(c.consumer(o), "hal_gpio");
}

#[test]
fn reset_gives_one_pulse_of_reset_ns_per_period() {
    let h = host("reset");
    loadrt(
        &h,
        &[
            "backend=sim",
            "outputs=STEP,DIR",
            "reset=STEP",
            "invert=DIR",
        ],
    )
    .unwrap();
    let s = sim(&h);
    let chip = s.chips()[0].clone();
    // reset_ns above a quarter period is clamped and written back.
    h.instance()
        .set_param("hal_gpio.reset_ns", Value::U32(900_000))
        .unwrap();
    set(&h, "hal_gpio.STEP-out", true);
    set(&h, "hal_gpio.DIR-out", true);
    run(
        &h,
        2_000_000,
        &["hal_gpio.read", "hal_gpio.write", "hal_gpio.reset"],
    );
    wait_for("reset_ns clamp", || {
        h.instance().param_value("hal_gpio.reset_ns").unwrap() == Value::U32(500_000)
    });
    h.instance()
        .set_param("hal_gpio.reset_ns", Value::U32(20_000))
        .unwrap();
    let step = chip.offset("STEP").unwrap();
    wait_for("pulses", || {
        chip.events_of(step)
            .windows(2)
            .filter(|w| w[0].level && !w[1].level && w[1].time_ns - w[0].time_ns < 100_000)
            .count()
            >= 5
    });
    h.stop();
    let ev = chip.events_of(step);
    // Rise, fall, rise, fall ...: one pulse per period.
    assert!(ev.windows(2).all(|w| w[0].level != w[1].level), "{ev:?}");
    let widths: Vec<u64> = ev
        .windows(2)
        .filter(|w| w[0].level)
        .map(|w| w[1].time_ns - w[0].time_ns)
        .collect();
    // The pulses after reset_ns was set to 20 us (a pulse can come out
    // longer when the thread is preempted, never shorter).
    let short: Vec<u64> = widths.into_iter().filter(|&w| w < 100_000).collect();
    for width in &short {
        assert!(*width >= 20_000, "pulse of {width} ns, reset_ns 20000");
    }
    // DIR is not a reset line: high (inverted, inactive) when requested,
    // low (TRUE) at the first write, and there it stayed.
    let dir = chip.offset("DIR").unwrap();
    let levels: Vec<bool> = chip.events_of(dir).iter().map(|e| e.level).collect();
    assert_eq!(levels, [true, false]);
}

#[test]
fn simloop_wires_outputs_to_inputs() {
    let h = host("loop");
    loadrt(&h, &["backend=simloop", "inputs=I0,I1", "outputs=O0,O1"]).unwrap();
    let chip = sim(&h).chips()[0].clone();
    run(&h, 1_000_000, &["hal_gpio.write", "hal_gpio.read"]);
    set(&h, "hal_gpio.O1-out", true);
    cycles(&chip, 2);
    assert!(!bit(&h, "hal_gpio.I0-in") && bit(&h, "hal_gpio.I1-in"));
}

#[test]
fn bad_parameters_are_refused_and_leave_nothing_loaded() {
    let h = host("params");
    for (args, want) in [
        (
            &["backend=bogus", "inputs=A"][..],
            "hal_gpio: parameter 'backend': 'bogus' is not one of cdev|sim|simloop",
        ),
        (
            &["backend=sim", "inputs=A", "invert=A"][..],
            "hal_gpio: parameter 'invert': item 0 \"A\": invert= applies to outputs only",
        ),
        (&["backend=sim"][..], "no lines given"),
        (&["backend=sim", "colour=red"][..], "unknown parameter"),
    ] {
        let e = loadrt(&h, args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert!(h.loaded_components().is_empty(), "{args:?}");
    }
}

fn chips_with(names: &[(&str, &[&str])]) -> Arc<SimChips> {
    Arc::new(SimChips::new(
        names
            .iter()
            .map(|(n, lines)| {
                Arc::new(SimChip::new(
                    n,
                    &format!("{n}-label"),
                    lines,
                    Arc::new(MonotonicClock),
                ))
            })
            .collect(),
    ))
}

fn load_on(h: &Host, chips: &SimChips, args: &[&str]) -> hal_core::Result<()> {
    let decls = hal_gpio::MODULE.params;
    let args = hal_core::ModuleArgs::parse("hal_gpio", decls, args)?;
    let cfg = hal_gpio::cfg::parse("hal_gpio", &args).map_err(|e| e.into_hal("hal_gpio"))?;
    hal_gpio::load_on(h, &cfg, chips, Arc::new(MonotonicClock), None)
}

#[test]
fn names_found_nowhere_or_twice_are_load_errors_naming_them() {
    let h = host("names-err");
    let chips = chips_with(&[
        ("gpiochip0", &["", "GPIO5", "DUP", "GPIO7"]),
        ("gpiochip1", &["DUP", "EXP1"]),
    ]);
    let e = load_on(&h, &chips, &["inputs=GPIO5,GPIO99"])
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "hal_gpio: parameter 'inputs': item 1 \"GPIO99\": no GPIO line has this name \
         (searched gpiochip0 [gpiochip0-label], gpiochip1 [gpiochip1-label]); names are \
         case-sensitive and as `gpioinfo` prints them"
    );
    // The output list is checked as well as the input list.
    let e = load_on(&h, &chips, &["inputs=GPIO5", "outputs=EXP1,gpio7"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("parameter 'outputs': item 1 \"gpio7\": no GPIO line"),
        "{e}"
    );
    let e = load_on(&h, &chips, &["outputs=DUP"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("\"DUP\": the name is on more than one line (gpiochip0 [gpiochip0-label] line 2 and gpiochip1 [gpiochip1-label] line 0)"),
        "{e}"
    );
    assert!(h.loaded_components().is_empty());
    // Nothing was requested by the failed loads.
    for c in chips.chips() {
        for o in 0..c.info().line_names.len() as u32 {
            assert_eq!(c.line_flags(o), None);
        }
    }
    // Lines of two chips: one request per chip and direction.
    load_on(&h, &chips, &["inputs=GPIO5,EXP1", "outputs=GPIO7"]).unwrap();
    assert!(chips.chips()[0].line_flags(1).is_some());
    assert!(chips.chips()[1].line_flags(1).is_some());
}

#[test]
fn a_busy_line_names_its_holder_and_releases_the_others() {
    let h = host("busy");
    let chips = chips_with(&[("gpiochip0", &["A", "B"]), ("gpiochip1", &["C"])]);
    let theirs = chips.chips()[1]
        .request(
            &[LineSetting {
                offset: 0,
                direction: Direction::Input,
                active_low: false,
                drive: Default::default(),
                bias: Default::default(),
            }],
            "spi0",
        )
        .unwrap();
    let e = load_on(&h, &chips, &["inputs=A,C"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("requesting C on gpiochip1 [gpiochip1-label]"),
        "{e}"
    );
    assert!(e.contains("in use by \"spi0\""), "{e}");
    assert_eq!(chips.chips()[0].line_flags(0), None, "A released again");
    drop(theirs);
    load_on(&h, &chips, &["inputs=A,C"]).unwrap();
    assert_eq!(ChipSet::chips(&*chips).unwrap().len(), 2);
}

#[test]
fn a_chip_that_goes_away_sets_outputs_inactive_and_says_why_once() {
    let h = host("gone");
    let chips = chips_with(&[("gpiochip0", &["IN", "OUT"]), ("gpiochip1", &["OUT2"])]);
    load_on(&h, &chips, &["inputs=IN", "outputs=OUT,OUT2"]).unwrap();
    set(&h, "hal_gpio.OUT-out", true);
    set(&h, "hal_gpio.OUT2-out", true);
    let c0 = chips.chips()[0].clone();
    let c1 = chips.chips()[1].clone();
    run(&h, 1_000_000, &["hal_gpio.read", "hal_gpio.write"]);
    cycles(&c0, 2);
    assert!(c0.level(1) && c1.level(0));
    c0.remove();
    wait_for("fault message", || {
        h.flush_rt_log();
        h.rt_log()
            .history()
            .iter()
            .any(|(_, m)| m.contains("hal_gpio: reading GPIO lines failed"))
    });
    // The other chip's output went inactive and stays there.
    wait_for("safe output", || !c1.level(0));
    let sets = c1.sets();
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(c1.sets(), sets, "outputs left alone after the fault");
    h.flush_rt_log();
    let said = h
        .rt_log()
        .history()
        .iter()
        .filter(|(_, m)| m.contains("hal_gpio:"))
        .count();
    assert_eq!(said, 1, "said once");
    assert!(h.fault().is_none(), "no panic, the thread runs on");
}
