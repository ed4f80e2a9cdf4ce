//! Tests of the module parameters, the HAL glue, and whole-module runs of
//! the host-free model.

use super::model::Stepgen;
use super::*;

fn args(words: &[&str]) -> Result<ModuleArgs> {
    ModuleArgs::parse("stepgen", PARAMS, words)
}

fn config(words: &[&str]) -> Result<Vec<ChannelConfig>> {
    parse_config(&args(words)?)
}

fn param_of(e: HalError) -> (String, String) {
    match e {
        HalError::ModuleParam { param, reason, .. } => (param, reason),
        other => panic!("not a module parameter error: {other:?}"),
    }
}

#[test]
fn channels_end_at_the_first_minus_one() {
    let c = config(&["step_type=0,2,1", "ctrl_type=p,V"]).unwrap();
    let kinds: Vec<_> = c
        .iter()
        .map(|c| (c.step_type.kind(), c.velocity_mode))
        .collect();
    assert_eq!(kinds, [(0, false), (2, true), (1, false)]);
    let c = config(&["step_type=3,-1,4"]).unwrap();
    assert_eq!(c.len(), 1);
    let c = config(&["step_type=0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0"]).unwrap();
    assert_eq!(c.len(), 16);
    // An empty item is type 0; ctrl_type beyond the channels is ignored.
    let c = config(&["step_type=,5", "ctrl_type=,pos,x"]).unwrap();
    assert_eq!(c[0].step_type.kind(), 0);
    assert!(!c[1].velocity_mode);
}

#[test]
fn bad_module_parameters_are_load_errors() {
    for (words, param, reason) in [
        (&["step_type=16"][..], "step_type", "bad stepping type 16"),
        (&["step_type=0,-2"][..], "step_type", "bad stepping type -2"),
        (&[][..], "step_type", "no channels configured"),
        (&["step_type=-1,0"][..], "step_type", "no channels"),
        (&["step_type=0", "ctrl_type=x"][..], "ctrl_type", "'x'"),
        (&["step_type=15"][..], "user_step_type", "at least one"),
        (
            &["step_type=0", "user_step_type=1,32"][..],
            "user_step_type",
            "32 uses more than 5 bits",
        ),
        (
            &["user_step_type=-5", "step_type=0"][..],
            "user_step_type",
            "-5",
        ),
    ] {
        let (p, r) = param_of(config(words).unwrap_err());
        assert_eq!(p, param, "{words:?}");
        assert!(r.contains(reason), "{words:?}: {r}");
    }
    // The table sizes are enforced by the argument parser.
    let (p, r) = param_of(args(&["step_type=0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0"]).unwrap_err());
    assert_eq!(
        (p.as_str(), r.as_str()),
        ("step_type", "can only take 16 arguments")
    );
    assert!(args(&["user_step_type=1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18"]).is_ok());
    assert!(args(&["user_step_type=1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19"]).is_err());
}

#[test]
fn user_step_type_ends_at_minus_one() {
    let c = config(&["step_type=15,15", "user_step_type=1,2,-1,64"]).unwrap();
    let t = c[1].step_type;
    assert_eq!((t.kind(), t.phases(), t.cycle_len()), (15, 2, 2));
}

/// The regression-test set-up of LinuxCNC's stepgen tests: 100 µs thread
/// running update-freq, make-pulses, capture-position; maxvel 0.15,
/// maxaccel 2, scale 32000, command 0.04, enabled.
fn regression_run(kind: &str, mut sample: impl FnMut(&Stepgen)) {
    let cfg = config(&[&format!("step_type={kind}")]).unwrap();
    let mut sg = Stepgen::new(&cfg);
    let c = &mut sg.chans[0];
    c.params.maxvel = 0.15;
    c.params.maxaccel = 2.0;
    c.params.position_scale = 32000.0;
    c.cmd = 0.04;
    c.enable = true;
    for _ in 0..3500 {
        sg.update_freq(100_000);
        sg.make_pulses(100_000);
        sg.capture_position();
        sample(&sg);
    }
}

#[test]
fn type0_steps_are_one_period_long_and_reach_the_command() {
    let mut high = 0;
    let mut last = None;
    regression_run("0", |sg| {
        let c = &sg.chans[0];
        high += usize::from(c.outputs & 1 != 0);
        assert_eq!(c.outputs & 2, 0, "never reverses");
        last = Some(*c);
    });
    assert_eq!(high, 1280);
    let c = last.unwrap();
    assert_eq!((c.counts, c.rawcounts), (1280, 1280));
    assert!((c.position_fb - 0.04).abs() < 0.5 / 32000.0);
    assert_eq!(c.params.frequency, 0.0);
    // The timing parameters were rounded to 50 µs on the first cycle
    // (update-freq ran before make-pulses) and then to 100 µs.
    assert_eq!((c.params.steplen, c.params.stepspace), (100_000, 100_000));
    assert_eq!((c.params.setup, c.params.hold), (100_000, 100_000));
}

#[test]
fn type2_is_a_valid_quadrature_sequence_matching_counts() {
    let mut decoded = 0i32;
    let mut prev = 0b01u8; // state 0: phase-A only
    let gray = |b: u8| [0, 1, 3, 2][usize::from(b)];
    let mut n = 0;
    regression_run("2", |sg| {
        let c = &sg.chans[0];
        let now = c.outputs;
        let d = (gray(now) - gray(prev) + 4) % 4;
        match d {
            0 => {}
            1 => decoded += 1,
            3 => decoded -= 1,
            _ => panic!("quadrature skipped a state at sample {n}"),
        }
        prev = now;
        assert_eq!(decoded, c.counts, "sample {n}");
        n += 1;
    });
    assert_eq!(decoded, 1280);
}

#[test]
fn startup_period_quirk_depends_on_function_order() {
    let cfg = config(&["step_type=0"]).unwrap();
    // update-freq first in a 25 µs thread: rounded to 50 µs and kept.
    let mut sg = Stepgen::new(&cfg);
    for _ in 0..3 {
        sg.update_freq(25_000);
        sg.make_pulses(25_000);
    }
    assert_eq!(sg.chans[0].params.steplen, 50_000);
    // make-pulses first: the real period from the start.
    let mut sg = Stepgen::new(&cfg);
    for _ in 0..3 {
        sg.make_pulses(25_000);
        sg.update_freq(25_000);
    }
    assert_eq!(sg.chans[0].params.steplen, 25_000);
}

#[test]
fn update_freq_and_capture_position_share_the_scale_cache() {
    let mut sg = Stepgen::new(&config(&["step_type=0"]).unwrap());
    sg.update_freq(50_000);
    sg.capture_position();
    // capture-position corrects a zero scale and remembers the 0.0...
    sg.chans[0].params.position_scale = 0.0;
    sg.capture_position();
    assert_eq!(sg.chans[0].params.position_scale, 1.0);
    // ...so update-freq, seeing 0.0 written again, finds no change and
    // leaves it (LinuxCNC keeps one old_scale per channel).
    sg.chans[0].params.position_scale = 0.0;
    sg.update_freq(50_000);
    assert_eq!(sg.chans[0].params.position_scale, 0.0);
}

#[test]
fn velocity_mode_runs_at_the_commanded_rate() {
    let cfg = config(&["step_type=1", "ctrl_type=v"]).unwrap();
    let mut sg = Stepgen::new(&cfg);
    let c = &mut sg.chans[0];
    c.enable = true;
    c.cmd = -1000.0; // steps/s with scale 1, no limits
    let mut downs = 0;
    for _ in 0..20_000 {
        sg.make_pulses(25_000);
        sg.update_freq(25_000);
        sg.capture_position();
        downs += usize::from(sg.chans[0].outputs == 2);
        assert_ne!(sg.chans[0].outputs, 1, "never steps up");
    }
    // 0.5 s at 1000 steps/s, each down pulse one 25 µs period long.
    let c = &sg.chans[0];
    assert_eq!(c.params.frequency, -1000.0);
    assert!((499..=500).contains(&downs), "{downs}");
    assert_eq!(c.counts, -(downs as i32));
    // Disabling stops at once.
    sg.chans[0].enable = false;
    sg.update_freq(25_000);
    assert_eq!(
        (sg.chans[0].dds.addval, sg.chans[0].params.frequency),
        (0, 0.0)
    );
}

/// Runs a golden case's set-up on the model, formatting samples as
/// halsampler does. The corpus (`$HAL_GOLDEN_DIR`, else `../shared/golden`
/// beside the workspace) is found when the tests are built; without it
/// the tests calling this are ignored (`hal_no_golden`, build.rs).
fn golden_on_model(case: &str, setup: &[&str], tune: impl Fn(&mut Stepgen), period: i64) {
    let dir = std::path::Path::new(env!("HAL_GOLDEN_CORPUS")).join(case);
    let read = |name: &str| {
        std::fs::read_to_string(dir.join(name))
            .unwrap_or_else(|e| panic!("golden case {case}: {name}: {e}"))
    };
    let (input, expected) = (read("input"), read("expected"));
    let mut sg = Stepgen::new(&config(setup).unwrap());
    tune(&mut sg);
    let mut cmd = 0.0;
    let mut lines = input.lines();
    for (i, want) in expected.lines().enumerate() {
        if let Some(l) = lines.next() {
            cmd = l.trim().parse().unwrap();
        }
        sg.chans[0].cmd = cmd;
        sg.make_pulses(period);
        sg.update_freq(period);
        sg.capture_position();
        let c = &sg.chans[0];
        let got = format!(
            "{cmd:.6} {} {} {} {:.6} ",
            c.outputs & 1,
            c.outputs >> 1 & 1,
            c.counts,
            c.position_fb
        );
        assert_eq!(got, want, "{case} sample {i}");
    }
}

#[test]
#[cfg_attr(
    hal_no_golden,
    ignore = "no golden corpus when built (../shared/golden beside the checkout, or HAL_GOLDEN_DIR)"
)]
fn model_matches_golden_type0_position() {
    golden_on_model(
        "stepgen-type0-pos",
        &["step_type=0"],
        |sg| {
            sg.chans[0].enable = true;
            let p = &mut sg.chans[0].params;
            p.position_scale = 1000.0;
            p.maxvel = 1.5;
            p.maxaccel = 200.0;
            p.steplen = 50_000;
            p.stepspace = 50_000;
            p.setup = 100_000;
            p.hold = 75_000;
        },
        50_000,
    );
}

#[test]
#[cfg_attr(
    hal_no_golden,
    ignore = "no golden corpus when built (../shared/golden beside the checkout, or HAL_GOLDEN_DIR)"
)]
fn model_matches_golden_type2_velocity() {
    golden_on_model(
        "stepgen-type2-vel",
        &["step_type=2", "ctrl_type=v"],
        |sg| {
            sg.chans[0].enable = true;
            let p = &mut sg.chans[0].params;
            p.position_scale = 2000.0;
            p.maxvel = 5.0;
            p.maxaccel = 400.0;
            p.steplen = 25_000;
            p.hold = 50_000;
        },
        25_000,
    );
}

#[test]
fn bench_entry_point_runs_many_channels() {
    let cfg = config(&["step_type=0,1,2,3,4,5,6,7,8,9,10,11,12,13,14"]).unwrap();
    let mut sg = Stepgen::new(&cfg);
    for c in &mut sg.chans {
        c.enable = true;
        c.dds.target_addval = 1 << 26; // a quarter step per call
    }
    let mut steps = 0;
    for _ in 0..8 {
        steps += sg.make_pulses(1000);
    }
    // Every channel steps at calls 2 and 6.
    assert_eq!(steps, 2 * sg.chans.len());
    assert!(sg.chans.iter().all(|c| c.rawcounts == 2));
}

mod hal {
    use super::*;
    use crate::testing::host;
    use hal_core::Value;

    fn load(h: &Host, words: &[&str]) -> Result<()> {
        h.loadrt(&MODULE, words)
    }

    #[test]
    fn items_depend_on_type_and_mode() {
        let h = host();
        load(
            &h,
            &[
                "step_type=0,1,2,15",
                "ctrl_type=p,p,v",
                "user_step_type=1,4",
            ],
        )
        .unwrap();
        let inst = h.instance();
        let pin = |n: &str| inst.pin_value(n).is_ok();
        let par = |n: &str| inst.param_value(n).ok();
        assert!(pin("stepgen.0.step") && pin("stepgen.0.dir") && pin("stepgen.0.position-cmd"));
        assert!(pin("stepgen.1.up") && pin("stepgen.1.down"));
        assert!(pin("stepgen.2.phase-A") && pin("stepgen.2.phase-B") && !pin("stepgen.2.phase-C"));
        assert!(pin("stepgen.2.velocity-cmd") && !pin("stepgen.2.position-cmd"));
        assert!(pin("stepgen.3.phase-C") && !pin("stepgen.3.phase-D"));
        assert_eq!(par("stepgen.0.dirsetup"), Some(Value::U32(1)));
        assert_eq!(par("stepgen.0.dirhold"), Some(Value::U32(1)));
        assert_eq!(par("stepgen.0.stepspace"), Some(Value::U32(1)));
        assert_eq!(par("stepgen.1.stepspace"), Some(Value::U32(1)));
        assert_eq!(par("stepgen.1.dirdelay"), Some(Value::U32(1)));
        assert_eq!(par("stepgen.1.dirsetup"), None);
        assert_eq!(par("stepgen.2.stepspace"), None);
        assert_eq!(par("stepgen.3.position-scale"), Some(Value::Float(1.0)));
        assert!(matches!(
            inst.set_param("stepgen.0.rawcounts", Value::S32(1)),
            Err(HalError::ParamReadOnly { .. })
        ));
        assert!(inst.set_param("stepgen.0.steplen", Value::U32(7)).is_ok());
        assert_eq!(h.loaded_components(), ["stepgen"]);
    }

    #[test]
    fn failed_load_leaves_nothing() {
        let h = host();
        assert!(load(&h, &["step_type=0,99"]).is_err());
        assert!(load(&h, &["step_type=0", "ctrl_type=p,q"]).is_ok());
        let h = host();
        assert!(load(&h, &["step_type=0,1", "ctrl_type=p,q"]).is_err());
        assert!(h.loaded_components().is_empty());
        assert!(h.instance().pin_value("stepgen.0.step").is_err());
    }
}
