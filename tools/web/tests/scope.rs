//! The scope served by hal-web against the headless halscope's capture:
//! the same request on the same siggen gives the same record (trigger
//! position, sample values, CSV); the page's binary form of a record
//! holds the record the CSV is of; auto mode records without a trigger
//! that never comes; refusals are halscope's; read-only and other
//! origins take no capture of pins; a page asking record after record
//! keeps one sampler, checks it is still wired, and removes it when idle.

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use clap::Parser as _;
use common::Web;
use hal_host::testing::InProcessHost;
use hal_scope::scope::args::Args;
use hal_scope::scope::output::{csv, Record};
use serde_json::Value;

const SIGGEN: &str = "\
loadrt siggen
loadrt threads name1=servo-thread period1=1000000
addf siggen.0.update servo-thread
setp siggen.0.frequency 50
net sq siggen.0.square
start
";

const PINS: &str = "sq,siggen.0.sawtooth,siggen.0.clock";

fn siggen_host(tag: &str) -> InProcessHost {
    let host = InProcessHost::start(tag);
    let (ok, _, err) = host.run("setup.hal", SIGGEN, false);
    assert!(ok, "{err}");
    host
}

/// The headless halscope's record for its command line `words`.
fn headless(host: &InProcessHost, words: &[&str]) -> Result<Record, hal_scope::scope::ScopeError> {
    let mut argv = vec!["halscope"];
    argv.extend(words);
    argv.extend(["--out", "unused.csv"]);
    let mut req = Args::try_parse_from(argv).unwrap().request()?;
    req.outputs.clear();
    hal_scope::scope::capture(&host.instance(), &req, &|| false)
}

/// Waits (up to 10 s) until hal-web has removed its idle sampler.
/// Waits until hal-web's idle sampler is gone, with the signals it made
/// (it unloads the sampler first, then deletes them: a test looking at
/// the signals the moment the sampler goes may catch them on the way).
fn wait_sampler_removed(host: &InProcessHost) {
    let inst = host.instance();
    let until = std::time::Instant::now() + std::time::Duration::from_secs(10);
    let made_signals = || {
        inst.signals()
            .unwrap()
            .iter()
            .any(|s| s.name.starts_with("halscope-"))
    };
    while inst.component("sampler").unwrap().is_some() || made_signals() {
        assert!(
            std::time::Instant::now() < until,
            "hal-web's idle sampler was not removed"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

fn capture(web: &Web, body: &str) -> (u16, Value) {
    let (status, answer) = web.post_same_origin("/api/scope", body, None);
    (status, serde_json::from_str(&answer).unwrap())
}

fn column(v: &Value, c: usize) -> Vec<f64> {
    v["columns"][c]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// `got` equals `want` except at samples next to an edge of either (a
/// value that differs from a neighbour's).
fn assert_same_but_edge_jitter(what: &str, got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    let at_edge = |v: &[f64], i: usize| {
        (i > 0 && v[i - 1] != v[i]) || v.get(i + 1).is_some_and(|n| *n != v[i])
    };
    for i in 0..got.len() {
        assert!(
            got[i] == want[i] || at_edge(got, i) || at_edge(want, i),
            "{what} differs at sample {i}:\n got  {got:?}\n want {want:?}"
        );
    }
    let differing = got.iter().zip(want).filter(|(a, b)| a != b).count();
    assert!(
        differing <= 2,
        "{what}: {differing} samples differ:\n got  {got:?}\n want {want:?}"
    );
}

/// CSV lines without their first field (the sampler's sample number,
/// which differs between two captures).
fn without_tags(text: &str) -> Vec<String> {
    text.lines()
        .map(|l| l.split_once(',').unwrap().1.to_string())
        .collect()
}

#[test]
fn a_capture_served_by_hal_web_equals_the_headless_capture() {
    let host = siggen_host("web-scope");
    let web = Web::start(&host.instance, &[]);
    let (status, answer) = web.request("GET", "/api/scope.csv", &[], None);
    assert_eq!(status, 404, "{answer}");
    let body = serde_json::json!({
        "pins": PINS.split(',').collect::<Vec<_>>(), "thread": "servo-thread",
        "trigger": "sq:rising:0.5", "samples": 100, "pre": "20%", "mode": "single",
    })
    .to_string();
    let (status, got) = capture(&web, &body);
    assert_eq!(status, 200, "{got}");
    // The sampler stays for the next record a while, then goes.
    wait_sampler_removed(&host);
    let want = headless(
        &host,
        &[
            "--pins",
            PINS,
            "--thread",
            "servo-thread",
            "--trigger",
            "sq:rising:0.5",
            "--samples",
            "100",
            "--pre",
            "20%",
        ],
    )
    .unwrap();
    assert_eq!(want.trigger_index, 20);
    assert_eq!(got["trigger_index"], 20);
    assert_eq!(got["triggered"], true);
    assert_eq!(got["period_ns"], want.period_ns);
    assert_eq!(got["names"], serde_json::json!(want.names));
    assert_eq!(got["types"], serde_json::json!(["float", "float", "bit"]));
    let want_col = |c: usize| -> Vec<f64> {
        want.rows
            .iter()
            .map(|r| hal_scope::scope::capture::numeric(want.types[c], r[c + 1]))
            .collect()
    };
    // The square and the clock sample for sample, but for an edge one
    // sample early or late: siggen's phase step (50 Hz at 1 ms) is not
    // exact in binary, so when the phase lands a rounding error away from
    // a switching point, two records taken at different times may put
    // that edge on neighbouring samples. The sawtooth to the rounding of
    // siggen's phase.
    assert_same_but_edge_jitter("square", &column(&got, 0), &want_col(0));
    assert_same_but_edge_jitter("clock", &column(&got, 2), &want_col(2));
    for (a, b) in column(&got, 1).iter().zip(want_col(1)) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    assert!(column(&got, 0)[19] < 0.5 && column(&got, 0)[20] >= 0.5);
    // The CSV served is halscope's CSV of the same samples.
    let (status, text) = web.request("GET", "/api/scope.csv", &[], None);
    assert_eq!(status, 200, "{text}");
    assert_eq!(without_tags(&text), without_tags(&csv(&want)));
    let first_tag = first_tag(&text);
    assert_eq!(got["first_sample"], first_tag);
    // Nothing of the capture stays behind.
    let inst = host.instance();
    assert!(inst.component("sampler").unwrap().is_none());
    assert!(inst
        .pin("siggen.0.sawtooth")
        .unwrap()
        .unwrap()
        .signal
        .is_none());
}

/// The binary form of a record (tools/web/src/record.rs): its header
/// and its columns.
fn decode(bytes: &[u8]) -> (Value, Vec<Vec<f64>>) {
    let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
    let head: Value = serde_json::from_slice(&bytes[4..4 + len]).unwrap();
    let n = head["samples"].as_u64().unwrap() as usize;
    let body = &bytes[(4 + len).next_multiple_of(8)..];
    assert_eq!(body.len(), 8 * n * head["names"].as_array().unwrap().len());
    let columns = body
        .chunks(8 * n)
        .map(|c| {
            c.chunks(8)
                .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
                .collect()
        })
        .collect();
    (head, columns)
}

#[test]
fn the_page_gets_the_record_in_binary_and_the_same_record_as_csv() {
    let host = siggen_host("web-scope-binary");
    let web = Web::start(&host.instance, &[]);
    let body = serde_json::json!({
        "pins": PINS.split(',').collect::<Vec<_>>(), "thread": "servo-thread",
        "trigger": "sq:rising:0.5", "samples": 60, "pre": "25%", "mode": "normal",
    })
    .to_string();
    let (status, bytes) = web.post_binary("/api/scope", &body);
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&bytes));
    let (head, columns) = decode(&bytes);
    assert_eq!(head["samples"], 60);
    assert_eq!(head["trigger_index"], 15);
    assert_eq!(head["triggered"], true);
    assert_eq!(head["types"], serde_json::json!(["float", "float", "bit"]));
    assert!(columns[0][14] < 0.5 && columns[0][15] >= 0.5);
    // The CSV served is of the same record: sample for sample, to the
    // CSV's six decimals.
    let (status, text) = web.request("GET", "/api/scope.csv", &[], None);
    assert_eq!(status, 200, "{text}");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').skip(2).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 60);
    for (i, row) in rows.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            assert!((columns[c][i] - v).abs() < 1e-6, "sample {i}, column {c}");
        }
    }
    let first_tag = first_tag(&text);
    assert_eq!(head["first_sample"], first_tag);
    // A refusal is JSON, whatever the request accepts.
    let (status, bytes) = web.post_binary(
        "/api/scope",
        r#"{"pins":["sq"],"thread":"servo-thread","samples":1}"#,
    );
    assert_eq!(status, 400);
    let refusal: Value = serde_json::from_slice(&bytes).unwrap();
    assert!(refusal["error"].is_string(), "{refusal}");
}

#[test]
fn auto_mode_records_without_a_trigger_and_refusals_are_halscopes() {
    let host = siggen_host("web-scope-auto");
    let web = Web::start(&host.instance, &[]);
    let never = r#"{"pins":["sq"],"thread":"servo-thread","trigger":"sq:rising:5",
                    "samples":30,"pre":"50%","mode":"auto","timeout":5}"#;
    let (status, got) = capture(&web, never);
    assert_eq!(status, 200, "{got}");
    assert_eq!(got["triggered"], false);
    assert_eq!(got["trigger_index"], 0);
    assert_eq!(column(&got, 0).len(), 30);

    // A capture that fails says what halscope says.
    let (status, got) = capture(&web, r#"{"pins":["sq"],"thread":"fast","samples":10}"#);
    assert_eq!(status, 422, "{got}");
    let says = headless(
        &host,
        &["--pins", "sq", "--thread", "fast", "--samples", "10"],
    )
    .unwrap_err()
    .to_string();
    assert_eq!(got["error"], says);
    let (status, got) = capture(
        &web,
        r#"{"pins":["sq"],"thread":"servo-thread","samples":1}"#,
    );
    assert_eq!(status, 400, "{got}");
    let says = headless(
        &host,
        &["--pins", "sq", "--thread", "servo-thread", "--samples", "1"],
    )
    .unwrap_err()
    .to_string();
    assert_eq!(got["error"], says);

    // From another origin: refused before anything is loaded.
    let body = r#"{"pins":["sq"],"thread":"servo-thread","samples":10}"#;
    let (status, answer) = web.request(
        "POST",
        "/api/scope",
        &[("Origin", "http://evil.example")],
        Some(body),
    );
    assert_eq!(status, 403, "{answer}");
    assert!(answer.contains("same origin"), "{answer}");

    // Read-only: pins would need a sampler of hal-web's own. (One hal-web
    // serves an instance at a time.)
    drop(web);
    let ro = Web::start(&host.instance, &["--read-only"]);
    let (status, got) = capture(&ro, body);
    assert_eq!(status, 403, "{got}");
    assert!(
        got["error"].as_str().unwrap().contains("read-only"),
        "{got}"
    );
    assert!(host.instance().component("sampler").unwrap().is_none());
}

#[test]
fn record_after_record_keeps_one_sampler_while_it_is_wired_as_made() {
    let host = siggen_host("web-scope-kept");
    let web = Web::start(&host.instance, &[]);
    let inst = host.instance();
    let normal = r#"{"pins":["sq","siggen.0.sawtooth"],"thread":"servo-thread",
                     "trigger":"sq:rising:0.5","samples":20,"mode":"normal"}"#;
    let sampler_id = || inst.component("sampler").unwrap().map(|c| c.id);
    let (status, got) = capture(&web, normal);
    assert_eq!(status, 200, "{got}");
    let first = sampler_id().expect("the sampler is kept after a record");
    for _ in 0..3 {
        let (status, got) = capture(&web, normal);
        assert_eq!(status, 200, "{got}");
        assert_eq!(got["trigger_index"], 0);
        assert_eq!(sampler_id(), Some(first), "the same sampler records again");
    }

    // Another source: the old sampler goes, a new one comes.
    let other = r#"{"pins":["siggen.0.clock"],"thread":"servo-thread","samples":10}"#;
    let (status, got) = capture(&web, other);
    assert_eq!(status, 200, "{got}");
    assert_eq!(got["names"], serde_json::json!(["siggen.0.clock"]));
    let second = sampler_id().unwrap();
    assert_ne!(second, first);

    // Someone rewires the kept sampler: the next record says so and the
    // sampler goes; the one after starts afresh.
    inst.unlink("sampler.0.pin.0").unwrap();
    let (status, got) = capture(&web, other);
    assert_eq!(status, 422, "{got}");
    let said = got["error"].as_str().unwrap();
    assert!(said.contains("changed since the last record"), "{said}");
    assert!(said.contains("sampler.0.pin.0"), "{said}");
    assert_eq!(sampler_id(), None);
    let (status, got) = capture(&web, other);
    assert_eq!(status, 200, "{got}");

    // Idle: removed with the signals it made.
    wait_sampler_removed(&host);
    let signals = inst.signals().unwrap();
    assert!(
        signals.iter().all(|s| !s.name.starts_with("halscope-")),
        "{:?}",
        signals.iter().map(|s| &s.name).collect::<Vec<_>>()
    );
    assert!(inst
        .pin("siggen.0.clock")
        .unwrap()
        .unwrap()
        .signal
        .is_none());
}

/// The sample tag of the first data row of a served CSV.
fn first_tag(csv: &str) -> u64 {
    csv.lines()
        .nth(1)
        .and_then(|row| row.split(',').next())
        .and_then(|tag| tag.parse().ok())
        .unwrap_or_else(|| panic!("no first sample tag in:\n{csv}"))
}
