//! hal-web's page in a real browser (Debian's headless chromium through
//! chromium-driver): a watched pin's value updates on the page, and in
//! the tree once a filter opens its group; a setp typed into the page is
//! read back with halcmd's getp, and halcmd's refusal of a bad setp shows
//! on the page word for word; a meter shows the smallest and largest value
//! seen;
//! on the simulated mill, the e-stop reset and machine-on buttons turn
//! the machine on.
//!
//! Ignored where chromium is absent; scripts/test-all runs it (with
//! --include-ignored) when /usr/bin/chromium and /usr/bin/chromedriver
//! are there, and scripts/install-deps installs them.

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::mill::Mill;
use common::webdriver::Browser;
use common::{halcmd, Web};
use hal_core::{ComponentKind, In, Out};
use hal_host::testing::InProcessHost;
use hal_launcher::TaskAnswer;
use serde_json::json;

fn value_of(name: &str) -> String {
    format!(
        "const c = document.querySelector('#watch tr[data-name=\"{name}\"] td.value'); \
         return c ? c.textContent : null;"
    )
}

#[test]
#[ignore = "needs Debian's chromium and chromium-driver (scripts/install-deps installs them; \
            scripts/test-all runs this test with --include-ignored when they are there)"]
fn the_page_shows_live_values_and_sets_through_halcmd() {
    let host = InProcessHost::start("web-browser");
    let inst = host.instance();
    let comp = inst.new_component("webpage", ComponentKind::User).unwrap();
    let out = comp.pin::<f64, Out>("webpage.out").unwrap();
    let _in = comp.pin::<f64, In>("webpage.in").unwrap();
    comp.ready().unwrap();
    out.set(1.5);
    let web = Web::start(&host.instance, &[]);
    let browser = Browser::start();
    let url = format!("http://{}/", web.host());
    browser.go(&url);
    // The watch list lives in the browser's localStorage, per instance.
    let watch =
        json!([{"kind": "pin", "name": "webpage.out"}, {"kind": "pin", "name": "webpage.in"}]);
    browser.eval(&format!(
        "localStorage.setItem('hal-web.watch.{0}', '{1}'); \
         localStorage.setItem('hal-web.meters.{0}', '[{{\"kind\":\"pin\",\"name\":\"webpage.out\"}}]'); \
         return true;",
        host.instance, watch
    ));
    browser.go(&url);
    browser.wait_for(&value_of("webpage.out"), &json!("1.5"));
    out.set(-4.75);
    browser.wait_for(&value_of("webpage.out"), &json!("-4.75"));

    // A filter opens the tree's groups; their rows update live too.
    browser.type_into("#filter", "webpage");
    let in_tree =
        "const c = document.querySelector('#tree tr[data-name=\"webpage.out\"] td.value'); \
                   return c ? c.textContent : null;";
    browser.wait_for(in_tree, &json!("-4.75"));
    out.set(8.5);
    browser.wait_for(in_tree, &json!("8.5"));
    browser.wait_for(&value_of("webpage.out"), &json!("8.5"));
    let meter = |cell: &str| {
        format!(
            "const c = document.querySelector('#meters tr[data-name=\"webpage.out\"] td.{cell}'); \
             return c ? c.textContent : null;"
        )
    };
    browser.wait_for(&meter("value"), &json!("8.5"));
    browser.wait_for(&meter("min"), &json!("-4.75"));
    browser.wait_for(&meter("max"), &json!("8.5"));

    let field = "#watch tr[data-name=\"webpage.in\"] input.set";
    browser.type_into(field, "3.25\u{E007}");
    browser.wait_for(&value_of("webpage.in"), &json!("3.25"));
    let (ok, got, err) = halcmd(&host.instance, &["getp", "webpage.in"]);
    assert!(ok, "{err}");
    assert_eq!(got.trim(), "3.25");

    browser.eval(&format!(
        "document.querySelector('{}').value = ''; return true;",
        field.replace('\'', "\\'")
    ));
    browser.type_into(field, "fast\u{E007}");
    let (ok, _, refusal) = halcmd(&host.instance, &["setp", "webpage.in", "fast"]);
    assert!(!ok);
    browser.wait_for(
        "return document.getElementById('message').textContent;",
        &json!(refusal.trim_end()),
    );
}

#[test]
#[ignore = "needs Debian's chromium and chromium-driver (scripts/install-deps installs them; \
            scripts/test-all runs this test with --include-ignored when they are there)"]
fn the_machine_buttons_turn_the_mill_on() {
    let mill = Mill::start();
    let web = Web::start(&mill.instance, &[]);
    let browser = Browser::start();
    browser.go(&format!("http://{}/", web.host()));
    let machine = "const r = document.querySelector('#machine-state tr[data-key=\"machine\"] td:last-child'); \
                   return r ? r.textContent : null;";
    browser.wait_for(machine, &json!("ESTOP"));
    browser.click("#machine-estop-reset");
    browser.wait_for(machine, &json!("OFF"));
    browser.click("#machine-machine-on");
    browser.wait_for(machine, &json!("ON"));
    assert!(matches!(mill.task("state"), Some(TaskAnswer::Done(s)) if s.contains("machine=ON")));
}
