//! classicladder_rt in a HAL host: its pins and parameters, a project
//! handed over by the loader and run by a thread, and the loader's
//! refusals.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Value};
use hal_ladder::module::MODULE;
use hal_ladder::{handoff, user};

/// A project of our own: Q0 = I0, Q1 = not I0, %QW0 := %IW0*2 + %IF0,
/// Q2 = (%IW0 > 10), %QF0 := %IW0, and counter 0 counting I1's rising
/// edges, reset by I2, Q3 when it reaches its preset 3.
const PROJECT: &str = "\
_FILES_CLASSICLADDER
_FILE-rung_0.csv
#VER=2.0
#NEXTRUNG=1
1-0-50/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 50-0-60/0
2-0-50/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 50-0-60/1
9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 99-0-0/0 , 99-0-0/0 , 60-0-0/0
9-0-0/0 , 99-0-0/0 , 99-0-0/0 , 20-0-0/1 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 50-0-60/2
9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 99-0-0/0 , 99-0-0/0 , 60-0-0/2
0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0
_/FILE-rung_0.csv
_FILE-rung_1.csv
#VER=2.0
#NEXTRUNG=-1
1-0-50/2 , 99-0-0/0 , 12-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 0-0-0/0
0-0-0/0 , 99-0-0/0 , 99-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 50-0-60/3
1-0-50/1 , 99-0-0/0 , 99-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0
0-0-0/0 , 99-0-0/0 , 99-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0
_/FILE-rung_1.csv
_FILE-counters.csv
3
_/FILE-counters.csv
_FILE-arithmetic_expressions.csv
#VER=2.0
0000,@280/0@:=@270/0@*2+@300/0@
0001,@270/0@>10
0002,%QF0=%IW0
_/FILE-arithmetic_expressions.csv
_FILE-sections.csv
#VER=1.0
#NAME000=Main
000,0,-1,0,1,0
_/FILE-sections.csv
_/FILES_CLASSICLADDER
";

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hal-ladder-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch directory");
    d
}

fn cycles(host: &Host) -> u64 {
    host.instance().threads().expect("threads")[0].cycles
}

/// Runs the (started) thread for `n` more cycles.
fn wait(host: &Host, n: u64) {
    let target = cycles(host) + n;
    let end = Instant::now() + Duration::from_secs(10);
    while cycles(host) < target {
        assert!(Instant::now() < end, "the thread does not run");
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[test]
fn pins_params_and_a_program_running_in_a_thread() {
    let host = Host::create(HostConfig::for_tests("ladder")).unwrap();
    host.loadrt(
        &MODULE,
        &[
            "numPhysInputs=4",
            "numPhysOutputs=4",
            "numS32in=1",
            "numS32out=1",
        ],
    )
    .unwrap();
    let inst = host.instance();
    let pins: Vec<String> = inst.pins().unwrap().into_iter().map(|p| p.name).collect();
    for want in [
        "classicladder.0.in-03",
        "classicladder.0.out-03",
        "classicladder.0.s32in-00",
        "classicladder.0.s32out-00",
        "classicladder.0.floatin-09",
        "classicladder.0.floatout-09",
        "classicladder.0.hide_gui",
    ] {
        assert!(pins.iter().any(|p| p == want), "{want} in {pins:?}");
    }
    assert!(!pins.iter().any(|p| p == "classicladder.0.in-04"));
    assert_eq!(
        inst.param_value("classicladder.ladder-state").unwrap(),
        Value::S32(0)
    );
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    host.addf("classicladder.0.refresh", "servo", -1).unwrap();
    let dir = scratch("run");
    let file = dir.join("p.clp");
    std::fs::write(&file, PROJECT).unwrap();
    let notes = user::load(inst, "test", &file).unwrap();
    assert!(notes.is_empty(), "{notes:?}");
    host.start().unwrap();
    // The module decodes a new program about 2048 words a period: the
    // default sizes' 11 000 take 6 periods.
    let end = Instant::now() + Duration::from_secs(10);
    while inst.param_value("classicladder.ladder-state").unwrap() != Value::S32(2) {
        assert!(Instant::now() < end, "the program is never taken");
        std::thread::sleep(Duration::from_millis(1));
    }
    let taken_at = cycles(&host);
    assert!(taken_at >= 6, "taken in {taken_at} periods: not spread");
    // Loaded again while the thread runs: the module answers.
    user::load(inst, "test", &file).unwrap();
    let region = inst.region(handoff::REGION).unwrap();
    let seq = handoff::sequence(region.words());
    assert_eq!(
        handoff::status(region.words()),
        handoff::Status::Running(seq)
    );
    let get = |p: &str| inst.pin_value(p).unwrap();
    assert_eq!(get("classicladder.0.out-00"), Value::Bit(false));
    assert_eq!(get("classicladder.0.out-01"), Value::Bit(true));
    inst.set_pin("classicladder.0.in-00", Value::Bit(true))
        .unwrap();
    inst.set_pin("classicladder.0.s32in-00", Value::S32(21))
        .unwrap();
    inst.set_pin("classicladder.0.floatin-00", Value::Float(-2.7))
        .unwrap();
    wait(&host, 3);
    assert_eq!(get("classicladder.0.out-00"), Value::Bit(true));
    assert_eq!(get("classicladder.0.out-01"), Value::Bit(false));
    assert_eq!(
        get("classicladder.0.s32out-00"),
        Value::S32(40),
        "21*2 + trunc(-2.7)"
    );
    assert_eq!(get("classicladder.0.out-02"), Value::Bit(true), "21 > 10");
    assert_eq!(get("classicladder.0.floatout-00"), Value::Float(21.0));
    // The counter: three rising edges of I1 reach the preset.
    for _ in 0..3 {
        assert_eq!(get("classicladder.0.out-03"), Value::Bit(false));
        inst.set_pin("classicladder.0.in-01", Value::Bit(true))
            .unwrap();
        wait(&host, 2);
        inst.set_pin("classicladder.0.in-01", Value::Bit(false))
            .unwrap();
        wait(&host, 2);
    }
    assert_eq!(get("classicladder.0.out-03"), Value::Bit(true), "3 counted");
    inst.set_pin("classicladder.0.in-02", Value::Bit(true))
        .unwrap();
    wait(&host, 2);
    assert_eq!(get("classicladder.0.out-03"), Value::Bit(false), "reset");
    host.stop();
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn the_loader_refuses_with_line_and_reason() {
    let host = Host::create(HostConfig::for_tests("ladder")).unwrap();
    let inst = host.instance();
    let dir = scratch("refuse");
    let file = dir.join("p.clp");
    std::fs::write(&file, PROJECT).unwrap();
    let e = user::load(inst, "test", &file).unwrap_err().to_string();
    assert!(e.contains("classicladder_rt is not loaded"), "{e}");
    host.loadrt(&MODULE, &["numPhysInputs=2"]).unwrap();
    let e = user::load(inst, "test", &file).unwrap_err().to_string();
    assert!(
        e.contains("line 15") && e.contains("%I2") && e.contains("numPhysInputs"),
        "{e}"
    );
    let bad = PROJECT
        .replace("1-0-50/2 , 99", "1-0-50/1 , 99")
        .replace("0001,@270/0@>10", "0001,@270/0@+10");
    std::fs::write(&file, bad).unwrap();
    let e = user::load(inst, "test", &file).unwrap_err().to_string();
    assert!(
        e.contains("line 26 (expression 1") && e.contains("no comparison"),
        "{e}"
    );
    let e = user::load(inst, "test", &dir.join("missing.clp"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.clp"), "{e}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn sizes_follow_the_parameters() {
    let host = Host::create(HostConfig::for_tests("ladder")).unwrap();
    let e = host
        .loadrt(&MODULE, &["numRungs=20000"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("numRungs"), "{e}");
    let e = host
        .loadrt(&MODULE, &["period=1000000"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("period"), "{e}");
    host.loadrt(&MODULE, &["numPhysInputs=0", "numFloatIn=2"])
        .unwrap();
    let pins: Vec<String> = host
        .instance()
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .collect();
    let count = |prefix: &str| pins.iter().filter(|p| p.starts_with(prefix)).count();
    assert_eq!(count("classicladder.0.in-"), 15, "0 keeps the default");
    assert_eq!(count("classicladder.0.floatin-"), 2);
    assert_eq!(count("classicladder.0.s32out-"), 10);
}
