//! hal-web on a running instance: started with `loadusr -W`, it becomes
//! ready and ends with `unloadusr`; a pin's new value reaches the live
//! stream; meters keep their smallest and largest values; the tree lists signals with their writer and readers.

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::io::BufRead;
use std::time::{Duration, Instant};

use common::Web;
use hal_core::{ComponentKind, Out};
use hal_host::testing::InProcessHost;

#[test]
fn loadusr_w_waits_until_hal_web_serves() {
    let host = InProcessHost::start("web-loadusr");
    let (ok, _, err) = host.run("t.hal", "loadusr -W hal-web -p 0\n", false);
    assert!(ok, "{err}");
    let inst = host.instance();
    let comp = inst
        .component("hal-web")
        .unwrap()
        .expect("hal-web registered");
    assert!(comp.ready);
    let (ok, _, err) = host.run("t.hal", "unloadusr hal-web\n", false);
    assert!(ok, "{err}");
    let end = Instant::now() + Duration::from_secs(20);
    while inst.component("hal-web").unwrap().is_some() {
        assert!(Instant::now() < end, "hal-web did not end");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_pin_value_updates_in_the_stream() {
    let host = InProcessHost::start("web-stream");
    let inst = host.instance();
    let comp = inst.new_component("webtest", ComponentKind::User).unwrap();
    let pin = comp.pin::<f64, Out>("webtest.out").unwrap();
    comp.ready().unwrap();
    pin.set(1.5);
    let web = Web::start(&host.instance, &[]);
    let body =
        r#"{"items":[{"kind":"pin","name":"webtest.out"},{"kind":"pin","name":"nosuch"}],"hz":20}"#;
    let mut step = 0;
    web.stream_until(body, |event| {
        let values = &event["values"];
        if step == 0 {
            // The first event has every item; one that does not exist is null.
            assert_eq!(values["0"], "1.5", "{event}");
            assert!(values["1"].is_null(), "{event}");
            pin.set(-2.25);
            step = 1;
            return false;
        }
        values["0"] == "-2.25"
    });
}

#[test]
fn meters_keep_the_smallest_and_largest_value_seen() {
    let host = InProcessHost::start("web-meter");
    let inst = host.instance();
    let comp = inst.new_component("webmeter", ComponentKind::User).unwrap();
    let pin = comp.pin::<f64, Out>("webmeter.out").unwrap();
    comp.ready().unwrap();
    pin.set(1.5);
    let web = Web::start(&host.instance, &[]);
    let (status, answer) = web.request(
        "POST",
        "/api/stream",
        &[],
        Some(r#"{"items":[],"meters":[{"kind":"thread","name":"x"}]}"#),
    );
    assert_eq!(status, 400, "{answer}");
    assert!(answer.contains("not a 'thread'"), "{answer}");
    let body = r#"{"items":[],"meters":[{"kind":"pin","name":"webmeter.out"},{"kind":"sig","name":"nosuch"}],"hz":20}"#;
    // Each value is set once the meter has shown the one before.
    let steps = [(-2.0, "-2"), (3.25, "3.25"), (0.5, "0.5")];
    let mut step = 0;
    web.stream_until(body, |event| {
        let m = &event["meters"]["0"];
        if step == 0 {
            assert_eq!(m["value"], "1.5", "{event}");
            assert_eq!(
                (m["min"].as_f64(), m["max"].as_f64()),
                (Some(1.5), Some(1.5))
            );
            let gone = &event["meters"]["1"];
            assert!(gone["value"].is_null() && gone["min"].is_null(), "{event}");
        } else if m["value"] != steps[step - 1].1 {
            return false;
        }
        if step == steps.len() {
            assert_eq!(
                (m["min"].as_f64(), m["max"].as_f64()),
                (Some(-2.0), Some(3.25))
            );
            return true;
        }
        pin.set(steps[step].0);
        step += 1;
        false
    });
}

#[test]
fn a_long_watch_list_updates_too() {
    let host = InProcessHost::start("web-many");
    let inst = host.instance();
    let comp = inst.new_component("webmany", ComponentKind::User).unwrap();
    let pins: Vec<_> = (0..40)
        .map(|i| comp.pin::<i32, Out>(&format!("webmany.{i}")).unwrap())
        .collect();
    comp.ready().unwrap();
    let web = Web::start(&host.instance, &[]);
    let mut items: Vec<_> = (0..40)
        .map(|i| serde_json::json!({"kind": "pin", "name": format!("webmany.{i}")}))
        .collect();
    // The same item twice, and a signal that does not exist.
    items.push(serde_json::json!({"kind": "pin", "name": "webmany.39"}));
    items.push(serde_json::json!({"kind": "sig", "name": "nosuch"}));
    let body = serde_json::json!({ "items": items, "hz": 20 }).to_string();
    let mut first = true;
    web.stream_until(&body, |event| {
        let values = &event["values"];
        if first {
            assert_eq!(values["0"], "0", "{event}");
            assert_eq!(values["40"], "0", "{event}");
            assert!(values["41"].is_null(), "{event}");
            pins[39].set(-7);
            first = false;
            return false;
        }
        values["39"] == "-7" && values["40"] == "-7"
    });
}

#[test]
fn live_streams_are_bounded_and_end_with_hal_web() {
    let host = InProcessHost::start("web-bound");
    let mut web = Web::start(&host.instance, &[]);
    let body = r#"{"items":[{"kind":"thread","name":"nosuch"}],"hz":20}"#;
    // Each stream answers with its head and a first event.
    let mut open = Vec::new();
    for _ in 0..8 {
        let mut reader = web.open_stream(body);
        let mut line = String::new();
        while !line.starts_with("data:") {
            line.clear();
            assert!(reader.read_line(&mut line).unwrap() > 0, "a stream ended");
        }
        open.push(reader);
    }
    let (status, answer) = web.request("POST", "/api/stream", &[], Some(body));
    assert_eq!(status, 503, "{answer}");
    assert!(answer.contains("at most 8 live pages"), "{answer}");
    // Open streams do not keep hal-web from ending.
    assert!(web.ends_on_sigterm(Duration::from_secs(5)));
}

#[test]
fn the_tree_shows_signals_with_writer_and_readers() {
    let host = InProcessHost::start("web-tree");
    let inst = host.instance();
    let comp = inst.new_component("webtree", ComponentKind::User).unwrap();
    let _out = comp.pin::<f64, Out>("webtree.out").unwrap();
    let _in = comp.pin::<f64, hal_core::In>("webtree.in").unwrap();
    comp.ready().unwrap();
    let (ok, _, err) = host.run("t.hal", "net speed webtree.out => webtree.in\n", false);
    assert!(ok, "{err}");
    let web = Web::start(&host.instance, &[]);
    let (status, body) = web.request("GET", "/api/show", &[], None);
    assert_eq!(status, 200, "{body}");
    let show: serde_json::Value = serde_json::from_str(&body).unwrap();
    let sig = show["signals"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["name"] == "speed")
        .expect("the signal is listed");
    assert_eq!(sig["writer"], "webtree.out");
    assert_eq!(sig["readers"], serde_json::json!(["webtree.in"]));
    let pin = show["pins"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "webtree.in")
        .expect("the pin is listed");
    assert_eq!(pin["signal"], "speed");
    assert_eq!(pin["dir"], "IN");
    // The page itself comes from the binary.
    let (status, page) = web.request("GET", "/", &[], None);
    assert_eq!(status, 200);
    assert!(page.contains("<script src=\"app.js\""), "{page}");
}
