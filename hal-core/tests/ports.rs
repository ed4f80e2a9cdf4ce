//! Port pins: a byte stream from one output pin to one input pin through
//! a signal whose buffer `sets` makes, as LinuxCNC 2.9's HAL ports.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::*;
use hal_core::*;

/// A writer and a reader of one port signal `p` of `size` bytes, and
/// their component (its pins go with it).
fn linked(name: &str, size: u32) -> (Host, Component, PortOut, PortIn) {
    let host = host(name);
    let inst = host.instance().clone();
    let c = inst.new_component("ports", ComponentKind::User).unwrap();
    let w = c.port_out("ports.out").unwrap();
    let r = c.port_in("ports.in").unwrap();
    inst.newsig("p", HalType::Port).unwrap();
    inst.set_signal("p", Value::Port(size)).unwrap();
    inst.link("ports.out", "p").unwrap();
    inst.link("ports.in", "p").unwrap();
    (host, c, w, r)
}

#[test]
fn bytes_written_are_read_in_order_across_the_wrap() {
    let (_host, _c, w, r) = linked("port-order", 10);
    assert_eq!((w.buffer_size(), r.buffer_size()), (10, 10));
    // LinuxCNC's ring keeps one byte free: 10 bytes hold 9.
    assert_eq!((w.writable(), r.readable()), (9, 0));
    let mut next = 0u8;
    let mut want = 0u8;
    // Chunks of 3, 4 and 7 bytes walk the positions round the 10-byte
    // ring many times.
    for round in 0..50 {
        let n = [3usize, 4, 7][round % 3];
        let chunk: Vec<u8> = (0..n)
            .map(|_| {
                next = next.wrapping_add(1);
                next
            })
            .collect();
        assert!(w.write(&chunk), "round {round}: room for {n}");
        assert_eq!(r.readable() as usize, n);
        let mut out = vec![0u8; n];
        assert!(r.read(&mut out));
        for b in out {
            want = want.wrapping_add(1);
            assert_eq!(b, want, "round {round}");
        }
        assert_eq!(r.readable(), 0);
    }
}

#[test]
fn a_full_port_takes_nothing_and_a_short_one_gives_nothing() {
    // 9 bytes of buffer hold 8, as in LinuxCNC.
    let (_host, _c, w, r) = linked("port-full", 9);
    assert!(w.write(b"abcdef"));
    assert!(!w.write(b"ghi"), "3 bytes do not fit in the 2 left");
    assert_eq!(w.writable(), 2);
    assert!(w.write(b"gh"));
    assert_eq!((w.writable(), r.readable()), (0, 8));
    let mut nine = [0u8; 9];
    assert!(!r.read(&mut nine), "9 bytes are not there");
    assert_eq!(r.readable(), 8, "a refused read takes nothing");
    let mut two = [0u8; 2];
    assert!(r.peek(&mut two));
    assert_eq!(&two, b"ab");
    assert!(r.peek(&mut two), "a peek takes nothing");
    assert_eq!(&two, b"ab");
    assert!(r.peek_commit(2));
    assert!(!r.peek_commit(7), "only 6 are left");
    let mut rest = [0u8; 6];
    assert!(r.read(&mut rest));
    assert_eq!(&rest, b"cdefgh");
    assert!(w.write(b"xyz"));
    r.clear();
    assert_eq!((r.readable(), w.writable()), (0, 8));
}

#[test]
fn a_port_without_a_buffer_moves_nothing() {
    let host = host("port-none");
    let inst = host.instance().clone();
    let c = inst.new_component("ports", ComponentKind::User).unwrap();
    let w = c.port_out("ports.out").unwrap();
    let r = c.port_in("ports.in").unwrap();
    // Unlinked pins have no buffer.
    assert!(!w.write(b"x"));
    assert_eq!((w.writable(), r.readable(), r.buffer_size()), (0, 0, 0));
    // Nor has a signal not yet sized; `sets p 0` makes none, as in LinuxCNC.
    inst.newsig("p", HalType::Port).unwrap();
    inst.link("ports.in", "p").unwrap();
    inst.set_signal("p", Value::Port(0)).unwrap();
    assert_eq!(inst.signal_value("p").unwrap(), Value::Port(0));
    assert_eq!(r.buffer_size(), 0);
    // Sized after its reader and its writer linked, both find the buffer
    // at once: a port's buffer is no value the writer drives, so `sets`
    // takes a port signal with a writer, as LinuxCNC's does (once).
    inst.link("ports.out", "p").unwrap();
    inst.set_signal("p", Value::Port(5)).unwrap();
    assert_eq!((r.buffer_size(), w.buffer_size()), (5, 5));
    assert!(matches!(
        inst.set_signal("p", Value::Port(8)).unwrap_err(),
        HalError::PortAllocated { .. }
    ));
    assert!(w.write(b"wxyz"));
    let mut out = [0u8; 4];
    assert!(r.read(&mut out));
    assert_eq!(&out, b"wxyz");
}

#[test]
fn a_buffer_is_made_once_and_its_size_is_the_value() {
    let host = host("port-once");
    let inst = host.instance().clone();
    inst.newsig("p", HalType::Port).unwrap();
    inst.set_signal("p", Value::Port(100)).unwrap();
    assert_eq!(inst.signal_value("p").unwrap(), Value::Port(100));
    let err = inst.set_signal("p", Value::Port(200)).unwrap_err();
    assert_eq!(err.to_string(), "port is already allocated with 100 bytes.");
    assert_eq!(inst.signal_value("p").unwrap(), Value::Port(100));
    inst.newsig("q", HalType::Port).unwrap();
    let err = inst
        .set_signal("q", Value::Port(MAX_PORT_SIZE + 1))
        .unwrap_err();
    assert!(matches!(err, HalError::BadPortSize { .. }), "{err}");
    assert_eq!(inst.signal_value("q").unwrap(), Value::Port(0));
}

#[test]
fn a_port_signal_links_one_writer_and_one_reader() {
    let host = host("port-links");
    let inst = host.instance().clone();
    let c = inst.new_component("ports", ComponentKind::User).unwrap();
    let _w = c.port_out("ports.out").unwrap();
    let _w2 = c.port_out("ports.out2").unwrap();
    let _r = c.port_in("ports.in").unwrap();
    let _r2 = c.port_in("ports.in2").unwrap();
    let _f: Pin<f64, In> = c.pin("ports.float").unwrap();
    inst.newsig("p", HalType::Port).unwrap();
    inst.set_signal("p", Value::Port(16)).unwrap();
    inst.link("ports.out", "p").unwrap();
    inst.link("ports.in", "p").unwrap();
    assert!(matches!(
        inst.link("ports.in2", "p").unwrap_err(),
        HalError::PortSignalFull { .. }
    ));
    assert!(matches!(
        inst.link("ports.out2", "p").unwrap_err(),
        HalError::SignalHasWriter { .. }
    ));
    assert!(matches!(
        inst.link("ports.float", "p").unwrap_err(),
        HalError::TypeMismatch { .. }
    ));
    // Linking pins never replaces the signal's buffer.
    assert_eq!(inst.signal_value("p").unwrap(), Value::Port(16));
    // A reader that leaves takes no buffer with it: the next may join.
    inst.unlink("ports.in").unwrap();
    assert_eq!(inst.pin_value("ports.in").unwrap(), Value::Port(0));
    inst.link("ports.in2", "p").unwrap();
    assert!(matches!(
        inst.set_pin("ports.in", Value::Port(8)).unwrap_err(),
        HalError::PortPinSet { .. }
    ));
}

#[test]
fn ports_are_pins_only() {
    let host = host("port-only-pins");
    let inst = host.instance().clone();
    let c = inst.new_component("ports", ComponentKind::User).unwrap();
    assert!(matches!(
        c.pin_raw::<In>("ports.raw", HalType::Port).err().unwrap(),
        HalError::NotAPortMaker { .. }
    ));
    assert!(matches!(
        c.param_raw("ports.param", HalType::Port, ParamDir::Rw)
            .err()
            .unwrap(),
        HalError::NotAPortMaker { .. }
    ));
    assert_eq!(HalType::from_name("port"), Some(HalType::Port));
    assert!(!HalType::ALL.contains(&HalType::Port));
}

/// A writer thread and a reader thread stream 200 000 bytes through a
/// 64-byte port: every byte arrives once, in order.
#[test]
fn a_writer_and_a_reader_in_two_threads_lose_nothing() {
    let (_host, _c, w, r) = linked("port-threads", 64);
    const TOTAL: usize = 200_000;
    assert_eq!(w.buffer_size(), 64, "the port has its buffer");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    let writer = std::thread::spawn(move || {
        let mut sent = 0usize;
        while sent < TOTAL {
            assert!(
                std::time::Instant::now() < deadline,
                "writer stuck at {sent}"
            );
            let n = (sent % 13 + 1).min(TOTAL - sent);
            let chunk: Vec<u8> = (sent..sent + n).map(|i| (i % 251) as u8).collect();
            if w.write(&chunk) {
                sent += n;
            } else {
                std::thread::yield_now();
            }
        }
    });
    let mut got = 0usize;
    let mut buf = [0u8; 7];
    while got < TOTAL {
        assert!(
            std::time::Instant::now() < deadline,
            "reader stuck at {got}"
        );
        let n = (r.readable() as usize).min(buf.len());
        if n == 0 {
            std::thread::yield_now();
            continue;
        }
        assert!(r.read(&mut buf[..n]));
        for b in &buf[..n] {
            assert_eq!(*b, (got % 251) as u8, "byte {got}");
            got += 1;
        }
    }
    writer.join().unwrap();
}
