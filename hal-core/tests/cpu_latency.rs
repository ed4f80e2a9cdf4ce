//! A host keeps idle CPUs out of deep sleep while its threads run: from the
//! first `start` it holds a 0 µs request on /dev/cpu_dma_latency, and it
//! lets go at shutdown. Alone in its test binary, so no other host of this
//! process holds the device.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use common::*;

/// How many of this process's open files are the PM QoS device.
fn requests_held() -> usize {
    std::fs::read_dir("/proc/self/fd")
        .unwrap()
        .filter_map(|e| std::fs::read_link(e.ok()?.path()).ok())
        .filter(|target| target.as_os_str() == "/dev/cpu_dma_latency")
        .count()
}

#[test]
fn the_host_holds_the_cpu_latency_request_while_it_lives() {
    let can_request = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/cpu_dma_latency")
        .is_ok();
    let host = host("cpulat");
    let mut b = host.new_rt_component("cl").unwrap();
    b.funct("cl.f", false, |_| {}).unwrap();
    b.ready().unwrap();
    host.create_thread("t", 1_000_000, true, None).unwrap();
    host.addf("cl.f", "t", -1).unwrap();
    assert_eq!(requests_held(), 0, "nothing is held before start");
    host.start().unwrap();
    assert_eq!(requests_held(), usize::from(can_request));
    host.stop();
    // Stopped threads start again without a second request.
    host.start().unwrap();
    assert_eq!(requests_held(), usize::from(can_request));
    host.shutdown();
    assert_eq!(requests_held(), 0, "released at shutdown");
    if !can_request {
        eprintln!("/dev/cpu_dma_latency cannot be opened here; checked that nothing is held");
    }
}
