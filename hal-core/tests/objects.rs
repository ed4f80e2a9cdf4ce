//! The object rules: every violation is a typed error and changes nothing.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::*;
use hal_core::*;

/// Everything visible in the instance, to compare before and after.
fn snapshot(inst: &Instance) -> String {
    format!(
        "{:?}\n{:?}\n{:?}\n{:?}\n{:?}",
        inst.components().unwrap(),
        inst.pins().unwrap(),
        inst.params().unwrap(),
        inst.signals().unwrap(),
        inst.functs().unwrap()
    )
}

fn unchanged<T: std::fmt::Debug>(inst: &Instance, f: impl FnOnce() -> Result<T>) -> HalError {
    let before = snapshot(inst);
    let err = f().expect_err("operation must fail");
    assert_eq!(
        before,
        snapshot(inst),
        "failed operation changed the instance: {err}"
    );
    err
}

#[test]
fn link_rules_are_enforced_and_failures_change_nothing() {
    let host = host("links");
    let inst = host.instance().clone();
    let c = inst.new_component("and2", ComponentKind::User).unwrap();
    let _a: Pin<bool, Out> = c.pin("and2.0.out").unwrap();
    let _b: Pin<bool, Out> = c.pin("and2.1.out").unwrap();
    let _i: Pin<bool, In> = c.pin("and2.0.in0").unwrap();
    let _f: Pin<f64, In> = c.pin("mult2.0.in0").unwrap();
    let _io: Pin<bool, Io> = c.pin("counter.0.index-enable").unwrap();
    inst.newsig("x", HalType::Bit).unwrap();
    inst.link("and2.0.out", "x").unwrap();
    inst.link("and2.0.in0", "x").unwrap();
    // Linking again to the same signal is fine.
    inst.link("and2.0.in0", "x").unwrap();

    let e = unchanged(&inst, || inst.link("and2.1.out", "x"));
    assert!(
        matches!(&e, HalError::SignalHasWriter { signal, writer, pin } if signal == "x" && writer == "and2.0.out" && pin == "and2.1.out"),
        "{e}"
    );
    let e = unchanged(&inst, || inst.link("mult2.0.in0", "x"));
    assert!(
        matches!(
            e,
            HalError::TypeMismatch {
                pin_type: HalType::Float,
                signal_type: HalType::Bit,
                ..
            }
        ),
        "{e}"
    );
    let e = unchanged(&inst, || inst.link("counter.0.index-enable", "x"));
    assert!(matches!(e, HalError::SignalHasOutputForIo { .. }), "{e}");
    inst.newsig("y", HalType::Bit).unwrap();
    let e = unchanged(&inst, || inst.link("and2.0.in0", "y"));
    assert!(
        matches!(&e, HalError::PinAlreadyLinked { signal, .. } if signal == "x"),
        "{e}"
    );
    inst.link("counter.0.index-enable", "y").unwrap();
    let e = unchanged(&inst, || inst.link("and2.1.out", "y"));
    assert!(matches!(e, HalError::SignalHasIoPins { .. }), "{e}");
    let e = unchanged(&inst, || inst.link("nope", "y"));
    assert!(matches!(e, HalError::NotFound { kind: "pin", .. }), "{e}");
    let e = unchanged(&inst, || inst.link("and2.1.out", "nope"));
    assert!(
        matches!(e, HalError::NotFound { kind: "signal", .. }),
        "{e}"
    );
}

#[test]
fn naming_and_duplicate_rules() {
    let host = host("names");
    let inst = host.instance().clone();
    let c = inst.new_component("comp", ComponentKind::User).unwrap();
    let _p: Pin<f64, In> = c.pin("comp.in").unwrap();
    let e = unchanged(&inst, || c.pin::<f64, In>("comp.in"));
    assert!(matches!(e, HalError::Duplicate { kind: "pin", .. }), "{e}");
    let e = unchanged(&inst, || c.pin::<f64, In>("bad name"));
    assert!(matches!(e, HalError::BadName { kind: "pin", .. }), "{e}");
    let e = unchanged(&inst, || c.pin::<f64, In>(&"p".repeat(256)));
    assert!(matches!(e, HalError::NameTooLong { len: 256, .. }), "{e}");
    c.pin::<f64, In>(&"p".repeat(255)).unwrap();
    inst.newsig("s", HalType::S32).unwrap();
    let e = unchanged(&inst, || inst.newsig("s", HalType::Float));
    assert!(
        matches!(e, HalError::Duplicate { kind: "signal", .. }),
        "{e}"
    );
    let e = unchanged(&inst, || inst.newsig("a=b", HalType::Float));
    assert!(matches!(e, HalError::BadName { .. }), "{e}");
    let e = unchanged(&inst, || inst.new_component("comp", ComponentKind::User));
    assert!(
        matches!(
            e,
            HalError::Duplicate {
                kind: "component",
                ..
            }
        ),
        "{e}"
    );
    let _par = c.param::<i32, Rw>("comp.in", 0).unwrap();
    let e = unchanged(&inst, || c.param::<i32, Rw>("comp.in", 0));
    assert!(
        matches!(e, HalError::Duplicate { kind: "param", .. }),
        "{e}"
    );
    // A pin and a param may share a name: they are different kinds.
    assert!(inst.params().unwrap().iter().any(|p| p.name == "comp.in"));
}

#[test]
fn values_setp_sets_and_their_refusals() {
    let host = host("values");
    let inst = host.instance().clone();
    let c = inst.new_component("m", ComponentKind::User).unwrap();
    let input: Pin<f64, In> = c.pin_init("m.in", 2.5).unwrap();
    let out: Pin<i32, Out> = c.pin("m.out").unwrap();
    let ro: Param<u32, Ro> = c.param("m.ro", 7).unwrap();
    let rw: Param<u32, Rw> = c.param("m.rw", 1).unwrap();
    assert_eq!(inst.pin_value("m.in").unwrap(), Value::Float(2.5));
    inst.set_pin("m.in", Value::Float(-0.5)).unwrap();
    assert_eq!(input.get(), -0.5);
    let e = unchanged(&inst, || inst.set_pin("m.out", Value::S32(1)));
    assert!(matches!(e, HalError::PinIsOutput { .. }), "{e}");
    let e = unchanged(&inst, || inst.set_pin("m.in", Value::S32(1)));
    assert!(
        matches!(
            e,
            HalError::WrongType {
                expected: HalType::S32,
                actual: HalType::Float,
                ..
            }
        ),
        "{e}"
    );
    let e = unchanged(&inst, || inst.set_param("m.ro", Value::U32(1)));
    assert!(matches!(e, HalError::ParamReadOnly { .. }), "{e}");
    inst.set_param("m.rw", Value::U32(99)).unwrap();
    assert_eq!(rw.get(), 99);
    assert_eq!(ro.get(), 7);
    ro.set(8);
    assert_eq!(inst.param_value("m.ro").unwrap(), Value::U32(8));

    // The first pin on a fresh signal gives it its value.
    inst.newsig("f", HalType::Float).unwrap();
    inst.link("m.in", "f").unwrap();
    assert_eq!(inst.signal_value("f").unwrap(), Value::Float(-0.5));
    let e = unchanged(&inst, || inst.set_pin("m.in", Value::Float(1.0)));
    assert!(matches!(e, HalError::PinConnected { .. }), "{e}");
    inst.set_signal("f", Value::Float(4.0)).unwrap();
    assert_eq!(input.get(), 4.0);
    // Unlinking keeps the last value in the pin.
    inst.unlink("m.in").unwrap();
    inst.set_signal("f", Value::Float(5.0)).unwrap();
    assert_eq!(input.get(), 4.0);

    inst.newsig("i", HalType::S32).unwrap();
    out.set(-3);
    inst.link("m.out", "i").unwrap();
    assert_eq!(inst.signal_value("i").unwrap(), Value::S32(-3));
    out.set(12);
    assert_eq!(inst.signal_value("i").unwrap(), Value::S32(12));
    let e = unchanged(&inst, || inst.set_signal("i", Value::S32(1)));
    assert!(
        matches!(&e, HalError::SignalDriven { writer, .. } if writer == "m.out"),
        "{e}"
    );
    assert_eq!(inst.signal_type("i").unwrap(), HalType::S32);

    // delsig unlinks every pin; the pins keep the last value.
    inst.delsig("i").unwrap();
    assert_eq!(out.get(), 12);
    assert!(inst.pins().unwrap().iter().all(|p| p.signal.is_none()));
    let e = unchanged(&inst, || inst.delsig("i"));
    assert!(
        matches!(e, HalError::NotFound { kind: "signal", .. }),
        "{e}"
    );
}

#[test]
fn signal_shows_its_pins_and_counts() {
    let host = host("sigshow");
    let inst = host.instance().clone();
    let c = inst.new_component("c", ComponentKind::User).unwrap();
    let _o: Pin<u64, Out> = c.pin("c.out").unwrap();
    let _a: Pin<u64, In> = c.pin("c.a").unwrap();
    let _b: Pin<u64, In> = c.pin("c.b").unwrap();
    inst.newsig("s", HalType::U64).unwrap();
    for p in ["c.out", "c.a", "c.b"] {
        inst.link(p, "s").unwrap();
    }
    let s = &inst.signals().unwrap()[0];
    assert_eq!((s.writers, s.readers, s.bidirs), (1, 2, 0));
    assert_eq!(
        s.pins,
        vec![
            ("c.a".into(), PinDir::In),
            ("c.b".into(), PinDir::In),
            ("c.out".into(), PinDir::Out)
        ]
    );
    inst.delsig_all().unwrap();
    assert!(inst.signals().unwrap().is_empty());
}

#[test]
fn dropping_a_component_removes_everything_it_owns() {
    let host = host("drop");
    let inst = host.instance().clone();
    let empty = snapshot(&inst);
    {
        let c = inst.new_component("gone", ComponentKind::User).unwrap();
        let _p: Pin<bool, Out> = c.pin("gone.out").unwrap();
        let _q: Param<f64, Rw> = c.param("gone.gain", 1.0).unwrap();
        let _r = c.region("gone.mem", 100).unwrap();
        inst.newsig("keep", HalType::Bit).unwrap();
        inst.link("gone.out", "keep").unwrap();
        // A later pin fails: the caller drops the half-built component.
        assert!(c.pin::<bool, Out>("gone.out").is_err());
    }
    inst.delsig("keep").unwrap();
    assert_eq!(snapshot(&inst), empty);
    assert!(inst.regions().unwrap().is_empty());
}

#[test]
fn aliases_rename_and_restore() {
    let host = host("alias");
    let inst = host.instance().clone();
    let c = inst.new_component("c", ComponentKind::User).unwrap();
    let p: Pin<i32, In> = c.pin("c.zzz").unwrap();
    let _q: Pin<i32, In> = c.pin("c.aaa").unwrap();
    inst.alias(AliasKind::Pin, "c.zzz", "c.bbb").unwrap();
    let names: Vec<_> = inst
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| (p.name, p.orig_name))
        .collect();
    assert_eq!(
        names,
        vec![
            ("c.aaa".into(), None),
            ("c.bbb".into(), Some("c.zzz".into()))
        ]
    );
    // Found by either name.
    inst.set_pin("c.zzz", Value::S32(5)).unwrap();
    inst.set_pin("c.bbb", Value::S32(6)).unwrap();
    assert_eq!(p.get(), 6);
    let e = unchanged(&inst, || inst.alias(AliasKind::Pin, "c.bbb", "c.aaa"));
    assert!(matches!(e, HalError::Duplicate { .. }), "{e}");
    inst.unalias(AliasKind::Pin, "c.bbb").unwrap();
    assert!(inst
        .pins()
        .unwrap()
        .iter()
        .any(|p| p.name == "c.zzz" && p.orig_name.is_none()));
    let e = unchanged(&inst, || inst.unalias(AliasKind::Pin, "c.zzz"));
    assert!(matches!(e, HalError::NotFound { kind: "alias", .. }), "{e}");
}

#[test]
fn ring_and_seqlock_round_trip() {
    let host = host("ring");
    let inst = host.instance().clone();
    let c = inst.new_component("s", ComponentKind::User).unwrap();
    let mut w = RingWriter::create(&c, "s.fifo", 4, 3).unwrap();
    let mut r = RingReader::open(&inst, "s.fifo").unwrap();
    assert_eq!(w.capacity(), 3);
    for i in 0..3u64 {
        assert!(w.push(&[i, i + 1, i + 2]));
    }
    assert!(!w.push(&[9, 9, 9]), "a depth-4 ring holds 3");
    assert_eq!(r.len(), 3);
    let mut out = [0u64; 3];
    for i in 0..3u64 {
        assert!(r.pop(&mut out));
        assert_eq!(out, [i, i + 1, i + 2]);
    }
    assert!(!r.pop(&mut out));
    // Wrap around many times.
    for i in 0..1000u64 {
        assert!(w.push(&[i]));
        assert!(r.pop(&mut out));
        assert_eq!(out, [i, 0, 0]);
    }
    assert!(RingWriter::create(&c, "s.bad", 1, 1).is_err());

    let mut sw = SeqLockWriter::create(&c, "s.status", 4).unwrap();
    let sr = SeqLockReader::open(&inst, "s.status").unwrap();
    sw.write(&[1, 2, 3, 4]);
    let mut snap = [0u64; 4];
    assert!(sr.read(&mut snap));
    assert_eq!(snap, [1, 2, 3, 4]);
}

#[test]
fn seqlock_readers_never_see_a_mixed_snapshot() {
    let host = host("seqlock");
    let inst = host.instance().clone();
    let c = inst.new_component("s", ComponentKind::User).unwrap();
    let mut sw = SeqLockWriter::create(&c, "s.status", 8).unwrap();
    let sr = SeqLockReader::open(&inst, "s.status").unwrap();
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let s2 = stop.clone();
    let writer = std::thread::spawn(move || {
        let mut i = 0u64;
        while !s2.load(std::sync::atomic::Ordering::Relaxed) {
            sw.write(&[i; 8]);
            i += 1;
            // A writer that never pauses can starve a reader for good
            // (every attempt overlaps a write, each read gives up after
            // its retries): leave gaps, as a periodic writer does.
            for _ in 0..200 {
                std::hint::spin_loop();
            }
        }
    });
    let mut snap = [0u64; 8];
    let mut consistent = 0;
    for _ in 0..50_000 {
        if sr.read(&mut snap) {
            assert!(snap.iter().all(|&v| v == snap[0]), "torn snapshot {snap:?}");
            consistent += 1;
        }
    }
    assert!(consistent > 0, "no read got a snapshot");
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    writer.join().unwrap();
}

#[test]
fn process_model_errors() {
    let name = unique_instance("absent");
    assert!(matches!(
        Instance::attach(&name),
        Err(HalError::NotRunning { .. })
    ));
    let host = Host::create(HostConfig::new(&name)).unwrap();
    assert!(matches!(
        Host::create(HostConfig::new(&name)),
        Err(HalError::AlreadyRunning { .. })
    ));
    let other = Instance::attach(&name).unwrap();
    other.newsig("from-other", HalType::Bit).unwrap();
    assert_eq!(host.instance().signals().unwrap()[0].name, "from-other");
    drop(host);
    assert!(
        !hal_core::paths::segment(&name).exists(),
        "host removes its segment"
    );
    assert!(matches!(
        Instance::attach(&name),
        Err(HalError::NotRunning { .. })
    ));
    assert!(matches!(
        Instance::attach("../etc"),
        Err(HalError::BadName { .. })
    ));
}

#[test]
fn a_full_segment_is_an_error_not_a_crash() {
    let mut cfg = HostConfig::new(&unique_instance("full"));
    cfg.shm_size = 2 << 20;
    let host = Host::create(cfg).unwrap();
    let inst = host.instance();
    let c = inst.new_component("c", ComponentKind::User).unwrap();
    let mut made = 0;
    let err = loop {
        match c.pin::<f64, In>(&format!("c.p{made}")) {
            Ok(p) => {
                std::mem::forget(p);
                made += 1;
            }
            Err(e) => break e,
        }
    };
    assert!(matches!(err, HalError::OutOfMemory { .. }), "{err}");
    assert!(made > 100);
    // Still fully usable.
    assert_eq!(inst.pins().unwrap().len(), made);
}

#[test]
fn thousands_of_pins_and_signals_fit() {
    let host = host("many");
    let inst = host.instance();
    let c = inst.new_component("big", ComponentKind::User).unwrap();
    let mut pins = Vec::new();
    for i in 0..3000 {
        pins.push(c.pin::<f64, Out>(&format!("big.{i:04}.out")).unwrap());
        inst.newsig(&format!("s{i:04}"), HalType::Float).unwrap();
    }
    inst.link("big.2999.out", "s2999").unwrap();
    pins[2999].set(1.5);
    assert_eq!(inst.signal_value("s2999").unwrap(), Value::Float(1.5));
    assert_eq!(inst.pins().unwrap().len(), 3000);
}

#[test]
fn stale_segment_of_a_dead_host_is_reclaimed() {
    if let Some((role, inst)) = child_role() {
        if role == "dying-host" {
            let host = Host::create(HostConfig::new(&inst)).unwrap();
            host.instance().newsig("old", HalType::Bit).unwrap();
            std::mem::forget(host);
            // SAFETY: _exit ends the process at once; nothing after it runs,
            // which is the point: die without cleaning up.
            unsafe { libc::_exit(0) };
        }
        return;
    }
    let name = unique_instance("stale");
    let mut child = spawn_child(
        "stale_segment_of_a_dead_host_is_reclaimed",
        "dying-host",
        &name,
    );
    child.wait().unwrap();
    assert!(
        hal_core::paths::segment(&name).exists(),
        "dead host left its segment"
    );
    assert!(matches!(
        Instance::attach(&name),
        Err(HalError::NotRunning { .. })
    ));
    let host = Host::create(HostConfig::new(&name)).unwrap();
    assert!(host.notes().iter().any(|n| n.contains("reclaimed")));
    assert!(host.instance().signals().unwrap().is_empty());
}

#[test]
fn raw_params_and_writable_raw_inputs_follow_their_run_time_type() {
    let host = host("raw");
    let inst = host.instance().clone();
    let c = inst.new_component("py", ComponentKind::User).unwrap();
    let gain = c.param_raw("py.gain", HalType::S32, ParamDir::Rw).unwrap();
    let ro = c.param_raw("py.count", HalType::U64, ParamDir::Ro).unwrap();
    assert_eq!(gain.value(), Value::S32(0));
    gain.set_bits(Value::S32(-7).to_bits());
    assert_eq!(inst.param_value("py.gain").unwrap(), Value::S32(-7));
    inst.set_param("py.gain", Value::S32(9)).unwrap();
    assert_eq!(gain.value(), Value::S32(9));
    assert_eq!(gain.hal_type(), HalType::S32);
    // The owner writes a read-only param; setp may not.
    ro.set_bits(u64::MAX);
    assert_eq!(inst.param_value("py.count").unwrap(), Value::U64(u64::MAX));
    assert!(matches!(
        inst.set_param("py.count", Value::U64(1)),
        Err(HalError::ParamReadOnly { .. })
    ));
    let input: RawPin<In> = c.pin_raw("py.in", HalType::Float).unwrap();
    input.overwrite_bits(1.5f64.to_bits());
    assert_eq!(inst.pin_value("py.in").unwrap(), Value::Float(1.5));
    // Linked, the write goes to the signal.
    inst.newsig("s", HalType::Float).unwrap();
    inst.link("py.in", "s").unwrap();
    input.overwrite_bits(2.5f64.to_bits());
    assert_eq!(inst.signal_value("s").unwrap(), Value::Float(2.5));
}

#[test]
fn a_typed_ring_tells_an_attaching_process_its_columns() {
    let host = host("typed-ring");
    let inst = host.instance().clone();
    let c = inst.new_component("s", ComponentKind::User).unwrap();
    let all = HalType::ALL;
    let w = RingWriter::create_typed(&c, "s.stream", 10, &all).unwrap();
    assert_eq!((w.width(), w.depth(), w.capacity()), (7, 10, 9));
    let r = RingReader::open(&inst, "s.stream").unwrap();
    assert_eq!(r.column_types().as_deref(), Some(&all[..]));
    let many = vec![HalType::U64; MAX_TYPED_COLUMNS];
    let w = RingWriter::create_typed(&c, "s.wide", 2, &many).unwrap();
    assert_eq!(w.column_types(), Some(many));
    // An untyped ring says so; bad column counts are refused.
    let u = RingWriter::create(&c, "s.plain", 4, 3).unwrap();
    assert_eq!(u.column_types(), None);
    assert!(RingWriter::create_typed(&c, "s.none", 4, &[]).is_err());
    let too_many = vec![HalType::Bit; MAX_TYPED_COLUMNS + 1];
    assert!(RingWriter::create_typed(&c, "s.over", 4, &too_many).is_err());
    assert!(inst.region("s.none").is_err() && inst.region("s.over").is_err());
}
