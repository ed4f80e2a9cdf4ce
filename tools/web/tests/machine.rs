//! The machine panel on the simulated mill (configs/sim/mill run by the
//! suite's `linuxcnc`): the state reads as task's, machine-on and home go
//! through task as task-cmd sends them, a refusal is task's message, and
//! a button pressed from another origin does nothing; the launcher starts
//! hal-web when the INI's `[HAL]HALWEB` asks for it.
//! (`linuxcnc` comes from cargo's output directory: see [`Mill`].)

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::time::{Duration, Instant};

use common::mill::Mill;
use common::Web;
use hal_launcher::TaskAnswer;

fn machine(web: &Web) -> serde_json::Value {
    let (status, body) = web.request("GET", "/api/machine", &[], None);
    assert_eq!(status, 200, "{body}");
    serde_json::from_str(&body).unwrap()
}

fn press(web: &Web, action: &str) -> (u16, serde_json::Value) {
    let body = serde_json::json!({ "action": action }).to_string();
    let (status, answer) = web.post_same_origin("/api/machine", &body, None);
    (status, serde_json::from_str(&answer).unwrap())
}

/// Waits (up to `secs`) until `done` accepts the panel's state.
fn wait_for(web: &Web, secs: u64, what: &str, done: impl Fn(&serde_json::Value) -> bool) {
    let end = Instant::now() + Duration::from_secs(secs);
    loop {
        let m = machine(web);
        if done(&m) {
            return;
        }
        assert!(Instant::now() < end, "never {what}: {m}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn machine_on_and_home_go_through_task() {
    let mill = Mill::start();
    let web = Web::start(&mill.instance, &[]);
    let m = machine(&web);
    assert_eq!(m["running"], true, "{m}");
    assert_eq!(m["state"]["machine"], "ESTOP", "{m}");

    // In e-stop, task refuses machine-on; the page gets task's words.
    let (status, answer) = press(&web, "machine-on");
    assert_eq!(status, 422, "{answer}");
    let Some(TaskAnswer::Refused(why)) = mill.task("machine-on") else {
        panic!("task accepted machine-on in e-stop");
    };
    assert_eq!(answer["error"], why);

    // A button pressed from another origin does nothing.
    let evil = [("Origin", "http://evil.example")];
    let body = r#"{"action":"estop-reset"}"#;
    let (status, _) = web.request("POST", "/api/machine", &evil, Some(body));
    assert_eq!(status, 403);
    assert_eq!(machine(&web)["state"]["machine"], "ESTOP");

    let (status, answer) = press(&web, "estop-reset");
    assert_eq!(status, 200, "{answer}");
    let (status, answer) = press(&web, "machine-on");
    assert_eq!(status, 200, "{answer}");
    wait_for(&web, 10, "on", |m| m["state"]["machine"] == "ON");

    let (status, answer) = press(&web, "mode-manual");
    assert_eq!(status, 200, "{answer}");
    let (status, answer) = press(&web, "home");
    assert_eq!(status, 200, "{answer}");
    wait_for(&web, 120, "homed", |m| {
        let joints = m["motion"]["joints"].as_object();
        joints.is_some_and(|j| !j.is_empty() && j.values().all(|j| j["homed"] == "TRUE"))
    });
}

#[test]
fn the_launcher_starts_hal_web_when_the_ini_asks() {
    // A free port for hal-web, which the INI names.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let mill = Mill::start_with(&format!("HALWEB = hal-web --read-only -p {port}"));
    let inst = hal_core::Instance::attach(&mill.instance).unwrap();
    // The launcher waited for it (loadusr -Wn) before task answered.
    let comp = inst.component("hal-web").unwrap().expect("hal-web runs");
    assert!(comp.ready);
    let addr: std::net::SocketAddr = format!("127.0.0.1:{port}").parse().unwrap();
    let (status, body) = common::http(addr, "GET", "/api/show", &[], None);
    assert_eq!(status, 200, "{body}");
    let show: serde_json::Value = serde_json::from_str(&body).unwrap();
    assert_eq!(show["instance"], mill.instance.as_str());
    // With the INI's options: read-only.
    let origin = format!("http://{addr}");
    let (status, body) = common::http(
        addr,
        "POST",
        "/api/hal",
        &[("Origin", &origin)],
        Some(r#"{"command":"setp","args":["motion.enable","0"]}"#),
    );
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("read-only"), "{body}");
}
