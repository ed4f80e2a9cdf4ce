use hal_core::{ComponentKind, HalType, Host, HostConfig, Instance, Out, Pin, ValueKind};

use super::layout::{record, w, Fault, Settings, State, Status, TriggerSetting, REGION};
use super::sample::Sampler;
use super::MODULE;

/// A host with scope_rt loaded (`args`) and a user component whose
/// pins `src.x` (float) and `src.b` (bit) the tests drive.
fn setup(tag: &str, args: &[&str]) -> (Host, Pin<f64, Out>, Pin<bool, Out>) {
    let host = Host::create(HostConfig::for_tests(tag)).unwrap();
    host.loadrt(&MODULE, args).unwrap();
    let comp = host
        .instance()
        .new_component("src", ComponentKind::User)
        .unwrap();
    let x = comp.pin::<f64, Out>("src.x").unwrap();
    let b = comp.pin::<bool, Out>("src.b").unwrap();
    comp.ready().unwrap();
    std::mem::forget(comp);
    (host, x, b)
}

fn word(inst: &Instance, pin: &str) -> (u64, HalType) {
    let (off, _, t) = inst.value_word(ValueKind::Pin, pin).unwrap().unwrap();
    (off, t)
}

fn snapshot(inst: &Instance) -> Vec<u64> {
    let r = inst.region(REGION).unwrap();
    r.words()
        .iter()
        .map(|v| v.load(std::sync::atomic::Ordering::Relaxed))
        .collect()
}

fn set_state(inst: &Instance, s: State) {
    let r = inst.region(REGION).unwrap();
    r.words()[w::STATE].store(s as u64, std::sync::atomic::Ordering::Relaxed);
}

#[test]
fn the_module_has_linuxcnc_names_and_checks_num_samples() {
    let host = Host::create(HostConfig::for_tests("scope-rt-names")).unwrap();
    for bad in ["num_samples=0", "num_samples=-5", "num_samples=99999999999"] {
        let e = host.loadrt(&MODULE, &[bad]).unwrap_err().to_string();
        assert!(e.contains("num_samples"), "{bad}: {e}");
    }
    assert!(host.loadrt(&MODULE, &["num_samples=x"]).is_err());
    host.loadrt::<&str>(&MODULE, &[]).unwrap();
    let inst = host.instance();
    let functs: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
    assert_eq!(functs, ["scope.sample"]);
    let st = Status::parse(&snapshot(inst)).unwrap();
    assert_eq!((st.state, st.buf_len), (State::Idle, 16000));
}

#[test]
fn a_rising_trigger_with_pre_trigger_samples() {
    let (host, x, b) = setup("scope-rt-rise", &["num_samples=40"]);
    let inst = host.instance();
    let settings = Settings {
        channels: vec![word(inst, "src.x"), word(inst, "src.b")],
        rec_len: 10,
        pre_trig: 3,
        mult: 1,
        trigger: Some(TriggerSetting {
            channel: 0,
            level: 4.5,
            rising: true,
        }),
    };
    let region = inst.region(REGION).unwrap();
    settings.write(region.words()).unwrap();
    set_state(inst, State::Arm);
    let mut s = Sampler::new(region);
    s.run(1000); // takes the settings
                 // A ramp 0..9 repeating: the first rise through 4.5 is at k = 5.
    for k in 0..40u64 {
        x.set((k % 10) as f64);
        b.set(k % 2 == 1);
        s.run(1000);
    }
    let words = snapshot(inst);
    let st = Status::parse(&words).unwrap();
    assert_eq!(st.state, State::Done);
    assert_eq!((st.samples, st.trig_pos), (10, 3));
    assert_eq!(st.types, [HalType::Float, HalType::Bit]);
    let rows = record(&words, &st).unwrap();
    let xs: Vec<f64> = rows.iter().map(|r| f64::from_bits(r[0])).collect();
    assert_eq!(xs, [2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 0.0, 1.0]);
    let bs: Vec<u64> = rows.iter().map(|r| r[1]).collect();
    assert_eq!(bs, [0, 1, 0, 1, 0, 1, 0, 1, 0, 1]);
    assert_eq!(st.period_ns, 1000);
}

#[test]
fn falling_edge_multiplier_and_ring_wrap() {
    let (host, x, _b) = setup("scope-rt-fall", &["num_samples=12"]);
    let inst = host.instance();
    let settings = Settings {
        channels: vec![word(inst, "src.x")],
        rec_len: 12,
        pre_trig: 5,
        mult: 2,
        trigger: Some(TriggerSetting {
            channel: 0,
            level: 0.0,
            rising: false,
        }),
    };
    let region = inst.region(REGION).unwrap();
    settings.write(region.words()).unwrap();
    set_state(inst, State::Arm);
    let mut s = Sampler::new(region);
    s.run(1000);
    // Call c sees x = c; sampled every second call: 1, 3, 5, ...; the
    // value goes negative (falls through 0) at call 41.
    for c in 0..200i64 {
        x.set(if c < 40 { c as f64 } else { -(c as f64) });
        s.run(1000);
    }
    let words = snapshot(inst);
    let st = Status::parse(&words).unwrap();
    assert_eq!((st.state, st.trig_pos, st.samples), (State::Done, 5, 12));
    let xs: Vec<f64> = record(&words, &st)
        .unwrap()
        .iter()
        .map(|r| f64::from_bits(r[0]))
        .collect();
    assert_eq!(
        xs,
        [31.0, 33.0, 35.0, 37.0, 39.0, -41.0, -43.0, -45.0, -47.0, -49.0, -51.0, -53.0]
    );
}

#[test]
fn no_trigger_records_at_once_and_reset_stops() {
    let (host, x, _b) = setup("scope-rt-free", &["num_samples=8"]);
    let inst = host.instance();
    let settings = Settings {
        channels: vec![word(inst, "src.x")],
        rec_len: 4,
        pre_trig: 0,
        mult: 1,
        trigger: None,
    };
    let region = inst.region(REGION).unwrap();
    settings.write(region.words()).unwrap();
    set_state(inst, State::Arm);
    let mut s = Sampler::new(region);
    s.run(1000);
    for k in 0..2 {
        x.set(k as f64 + 10.0);
        s.run(1000);
    }
    set_state(inst, State::Reset);
    s.run(1000);
    let st = Status::parse(&snapshot(inst)).unwrap();
    assert_eq!(st.state, State::Idle);
    set_state(inst, State::Arm);
    s.run(1000);
    for k in 0..6 {
        x.set(k as f64 + 20.0);
        s.run(1000);
    }
    let words = snapshot(inst);
    let st = Status::parse(&words).unwrap();
    assert_eq!((st.state, st.trig_pos), (State::Done, 0));
    let xs: Vec<f64> = record(&words, &st)
        .unwrap()
        .iter()
        .map(|r| f64::from_bits(r[0]))
        .collect();
    assert_eq!(xs, [20.0, 21.0, 22.0, 23.0]);
}

#[test]
fn bad_settings_and_garbage_stop_with_a_fault() {
    use std::sync::atomic::Ordering::Relaxed;
    let (host, _x, _b) = setup("scope-rt-fault", &["num_samples=8"]);
    let inst = host.instance();
    let region = inst.region(REGION).unwrap();
    let words = region.words();
    let mut s = Sampler::new(region.clone());
    let cases: &[(usize, u64, Fault)] = &[
        (w::CHANNELS, 17, Fault::Channels),
        (w::REC_LEN, 9, Fault::RecLen),
        (w::PRE_TRIG, 4, Fault::PreTrig),
        (w::TRIG_CHAN, 2, Fault::TrigChan),
        (w::CHAN_TYPE, 99, Fault::Type),
        (w::MULT, 0, Fault::Mult),
    ];
    for (i, v, want) in cases {
        for (j, good) in [
            (w::CHANNELS, 1),
            (w::REC_LEN, 4),
            (w::PRE_TRIG, 1),
            (w::TRIG_CHAN, 1),
            (w::CHAN_TYPE, 2),
            (w::MULT, 1),
            (w::CHAN_WORD, u64::MAX),
        ] {
            words[j].store(good, Relaxed);
        }
        words[*i].store(*v, Relaxed);
        words[w::STATE].store(State::Arm as u64, Relaxed);
        s.run(1000);
        let st = Status::parse(&snapshot(inst)).unwrap();
        assert_eq!(
            (st.state, st.fault),
            (State::Fault, *want),
            "word {i} = {v}"
        );
    }
    // A state that is none, and a cell offset that is no cell: no panic,
    // no read outside the cells.
    words[w::MULT].store(1, Relaxed);
    words[w::STATE].store(12345, Relaxed);
    s.run(1000);
    assert_eq!(Status::parse(&snapshot(inst)).unwrap().fault, Fault::State);
    words[w::TRIG_CHAN].store(0, Relaxed);
    words[w::STATE].store(State::Arm as u64, Relaxed);
    for _ in 0..10 {
        s.run(1000);
    }
    assert_eq!(Status::parse(&snapshot(inst)).unwrap().state, State::Done);
}

#[test]
fn settings_are_checked_before_they_are_written() {
    let words: Vec<std::sync::atomic::AtomicU64> = (0..80)
        .map(|_| std::sync::atomic::AtomicU64::new(0))
        .collect();
    super::layout::init(&words, 16);
    let ok = Settings {
        channels: vec![(0, HalType::Float); 2],
        rec_len: 8,
        pre_trig: 0,
        mult: 1,
        trigger: None,
    };
    ok.write(&words).unwrap();
    let e = |s: Settings| s.write(&words).unwrap_err().to_string();
    assert!(e(Settings {
        rec_len: 9,
        ..ok.clone()
    })
    .contains("give 2 to 8"));
    assert!(e(Settings {
        channels: vec![],
        ..ok.clone()
    })
    .contains("channels"));
    assert!(e(Settings {
        pre_trig: 8,
        ..ok.clone()
    })
    .contains("pre-trigger"));
    assert!(e(Settings {
        mult: 0,
        ..ok.clone()
    })
    .contains("multiplier"));
    let t = TriggerSetting {
        channel: 2,
        level: 0.0,
        rising: true,
    };
    assert!(e(Settings {
        trigger: Some(t),
        ..ok.clone()
    })
    .contains("trigger channel"));
}

#[test]
fn the_reader_refuses_garbage_with_what_and_where() {
    let words: Vec<std::sync::atomic::AtomicU64> = (0..80)
        .map(|_| std::sync::atomic::AtomicU64::new(0))
        .collect();
    super::layout::init(&words, 16);
    let good: Vec<u64> = words
        .iter()
        .map(|v| v.load(std::sync::atomic::Ordering::Relaxed))
        .collect();
    assert!(Status::parse(&good).is_ok());
    let with = |i: usize, v: u64| {
        let mut g = good.clone();
        g[i] = v;
        Status::parse(&g).unwrap_err().to_string()
    };
    assert!(with(w::MAGIC, 7).contains("magic"));
    assert!(with(w::VERSION, 2).contains("version"));
    assert!(with(w::BUF_LEN, 17).contains("buffer length"));
    assert!(with(w::STATE, 8).contains("state"));
    assert!(Status::parse(&good[..3])
        .unwrap_err()
        .to_string()
        .contains("past the end"));
    // A Done region whose record lies outside the ring.
    let mut done = good.clone();
    done[w::STATE] = State::Done as u64;
    done[w::CHANNELS] = 2;
    done[w::CHAN_TYPE] = 2;
    done[w::CHAN_TYPE + 1] = 1;
    done[w::SAMPLES] = 8;
    done[w::START] = 7;
    done[w::TRIG_POS] = 7;
    let st = Status::parse(&done).unwrap();
    assert_eq!(record(&done, &st).unwrap().len(), 8);
    done[w::START] = 8;
    assert!(Status::parse(&done)
        .unwrap_err()
        .to_string()
        .contains("record start"));
    done[w::START] = 0;
    done[w::SAMPLES] = 9;
    assert!(Status::parse(&done)
        .unwrap_err()
        .to_string()
        .contains("sample count"));
}
