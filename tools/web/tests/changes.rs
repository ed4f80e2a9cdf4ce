//! Changes from the page go through halcmd's command layer: a setp is
//! read back with halcmd's getp, a refusal is halcmd's message word for
//! word, and a cross-origin or token-less request changes nothing.

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::{halcmd, Web};
use hal_core::{ComponentKind, In, Out};
use hal_host::testing::InProcessHost;

fn setp(name: &str, value: &str) -> String {
    serde_json::json!({ "command": "setp", "args": [name, value] }).to_string()
}

#[test]
fn setp_from_the_page_is_read_back_by_halcmd_and_refusals_are_halcmds() {
    let host = InProcessHost::start("web-setp");
    let inst = host.instance();
    let comp = inst.new_component("webset", ComponentKind::User).unwrap();
    let _in = comp.pin::<f64, In>("webset.in").unwrap();
    let _out = comp.pin::<f64, Out>("webset.out").unwrap();
    comp.ready().unwrap();
    let web = Web::start(&host.instance, &[]);

    let (status, body) = web.post_same_origin("/api/hal", &setp("webset.in", "3.25"), None);
    assert_eq!(status, 200, "{body}");
    let (ok, out, err) = halcmd(&host.instance, &["getp", "webset.in"]);
    assert!(ok, "{err}");
    assert_eq!(out.trim(), "3.25");

    // What halcmd says about each bad setp comes back unchanged.
    for (name, value) in [
        ("webset.nosuch", "1"),
        ("webset.out", "1"),
        ("webset.in", "fast"),
    ] {
        let (status, body) = web.post_same_origin("/api/hal", &setp(name, value), None);
        assert_eq!(status, 422, "{body}");
        let answer: serde_json::Value = serde_json::from_str(&body).unwrap();
        let (ok, _, err) = halcmd(&host.instance, &["setp", name, value]);
        assert!(!ok);
        assert!(!err.trim().is_empty());
        assert_eq!(answer["error"], err.trim_end(), "setp {name} {value}");
    }
    // Only the four changes; halcmd's other commands are not reachable.
    let load = r#"{"command":"loadusr","args":["true"]}"#;
    let (status, _) = web.post_same_origin("/api/hal", load, None);
    assert_eq!(status, 400);
}

#[test]
fn cross_origin_and_token_less_requests_change_nothing() {
    let host = InProcessHost::start("web-guard");
    let inst = host.instance();
    let comp = inst.new_component("webguard", ComponentKind::User).unwrap();
    let _in = comp.pin::<f64, In>("webguard.in").unwrap();
    comp.ready().unwrap();
    let getp = || {
        halcmd(&host.instance, &["getp", "webguard.in"])
            .1
            .trim()
            .to_string()
    };

    let web = Web::start(&host.instance, &[]);
    let body = setp("webguard.in", "7");
    let evil = [("Origin", "http://evil.example")];
    let (status, _) = web.request("POST", "/api/hal", &evil, Some(&body));
    assert_eq!(status, 403);
    // No Origin at all is no proof of the same origin either.
    let (status, _) = web.request("POST", "/api/hal", &[], Some(&body));
    assert_eq!(status, 403);
    // A page of another site whose name points at 127.0.0.1.
    let rebound = [("Host", "evil.example"), ("Origin", "http://evil.example")];
    let (status, _) = web.request("GET", "/api/show", &rebound, None);
    assert_eq!(status, 403);
    assert_eq!(getp(), "0");
    drop(web);

    let web = Web::start(&host.instance, &["--token"]);
    let token_path = hal_web::token::path(&host.instance).unwrap();
    let token = std::fs::read_to_string(&token_path).unwrap();
    let token = token.trim();
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&token_path).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o600);
    let (status, _) = web.post_same_origin("/api/hal", &body, None);
    assert_eq!(status, 401);
    let (status, _) = web.post_same_origin("/api/hal", &body, Some("0123"));
    assert_eq!(status, 401);
    let (status, _) = web.request("GET", "/api/show", &[], None);
    assert_eq!(status, 401);
    let with_token = [("X-HAL-Token", token), ("Origin", "http://evil.example")];
    let (status, _) = web.request("POST", "/api/hal", &with_token, Some(&body));
    assert_eq!(status, 403);
    assert_eq!(getp(), "0");
    let (status, answer) = web.post_same_origin("/api/hal", &body, Some(token));
    assert_eq!(status, 200, "{answer}");
    assert_eq!(getp(), "7");
    drop(web);
    assert!(!token_path.exists(), "the token file goes with hal-web");

    let web = Web::start(&host.instance, &["--read-only"]);
    let (status, _) = web.post_same_origin("/api/hal", &setp("webguard.in", "9"), None);
    assert_eq!(status, 403);
    assert_eq!(getp(), "7");
}
