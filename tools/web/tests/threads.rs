//! Thread timing and the latency histogram served by hal-web are the
//! figures latency-test reads: once the threads stop, the served figures
//! equal latency-test's of the same threads.

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::time::{Duration, Instant};

use common::Web;
use hal_core::latency_bucket_floor_us;
use hal_host::testing::InProcessHost;
use hal_scope::latency::stats::{verdict, ThreadStats};

#[test]
fn threads_and_latency_histograms_are_latency_tests_figures() {
    let host = InProcessHost::start("web-threads");
    let setup = "loadrt threads name1=fast period1=200000 name2=slow period2=1000000\nstart\n";
    let (ok, _, err) = host.run("setup.hal", setup, false);
    assert!(ok, "{err}");
    let inst = host.instance();
    let end = Instant::now() + Duration::from_secs(30);
    while inst.threads().unwrap().iter().any(|t| t.cycles < 50) {
        assert!(Instant::now() < end, "the threads did not run");
        std::thread::sleep(Duration::from_millis(20));
    }
    let (ok, _, err) = host.run("stop.hal", "stop\n", false);
    assert!(ok, "{err}");
    // A thread waking as `stop` came may still count that cycle.
    let mut want = Vec::new();
    loop {
        std::thread::sleep(Duration::from_millis(20));
        let now: Vec<ThreadStats> = inst
            .threads()
            .unwrap()
            .iter()
            .map(ThreadStats::from_info)
            .collect();
        if now == want {
            break;
        }
        want = now;
    }
    let web = Web::start(&host.instance, &[]);
    let (status, body) = web.request("GET", "/api/threads", &[], None);
    assert_eq!(status, 200, "{body}");
    let got: serde_json::Value = serde_json::from_str(&body).unwrap();
    let threads = got["threads"].as_array().unwrap();
    assert_eq!(threads.len(), 2);
    for t in &want {
        let g = threads
            .iter()
            .find(|g| g["name"] == t.name.as_str())
            .unwrap();
        assert_eq!(g["period"], t.period_ns);
        assert_eq!(g["cycles"], t.cycles);
        assert_eq!(g["overruns"], t.overruns);
        assert_eq!(g["histogram"], serde_json::json!(t.histogram));
        assert_eq!(g["latency"]["min"], serde_json::json!(t.min_ns));
        assert_eq!(g["latency"]["max"], serde_json::json!(t.max_ns));
        assert_eq!(
            g["latency"]["p99"],
            serde_json::json!(t.percentile_ns(0.99))
        );
        assert_eq!(g["running"], false);
        assert_eq!(t.samples(), t.histogram.iter().sum::<u64>());
    }
    let floors = got["bucket_floor_us"].as_array().unwrap();
    assert_eq!(floors.len(), want[0].histogram.len());
    assert_eq!(floors[20], latency_bucket_floor_us(20));
    let (_, max) = verdict(&want).unwrap();
    assert_eq!(got["verdict"]["max"], max);
}
