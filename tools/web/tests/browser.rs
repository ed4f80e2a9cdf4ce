//! hal-web's page in a real browser (Debian's headless chromium through
//! chromium-driver): a watched pin's value updates on the page, and in
//! the tree once a filter opens its group; a setp typed into the page is
//! read back with halcmd's getp, and halcmd's refusal of a bad setp shows
//! on the page word for word; a meter shows the smallest and largest value
//! seen;
//! the scope draws a capture and saves its CSV and PNG;
//! the thread view shows a thread's latency histogram;
//! on the simulated mill, the e-stop reset and machine-on buttons turn
//! the machine on, and "Home all" homes every joint; another site's page
//! posting a setp, and hal-web's own page without the token (hal-web
//! started with --token), change nothing, and the token lets it through.
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
use std::time::Duration;

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
    keep_screenshot(&browser, "main", "hal-web-pins.png");

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

    // Manual mode, then "Home all": every joint's row reads homed.
    browser.click("#machine-mode-manual");
    browser.click("#machine-home");
    let all_homed = "const rows = [...document.querySelectorAll('#machine-state tr')] \
                       .filter(r => (r.dataset.key || '').startsWith('joint ')); \
                     return rows.length > 0 && rows.every(r => r.textContent.endsWith(' homed'));";
    browser.wait_for_within(all_homed, &json!(true), Duration::from_secs(120));
}

/// A screenshot of the element `css` selects: a PNG, kept as `name` in
/// the directory `HAL_WEB_SCREENSHOTS` names (the README's pictures are
/// made so), else dropped.
fn keep_screenshot(browser: &Browser, css: &str, name: &str) {
    let png = browser.screenshot(css);
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{name} is no PNG");
    if let Some(dir) = std::env::var_os("HAL_WEB_SCREENSHOTS") {
        std::fs::write(std::path::Path::new(&dir).join(name), png).unwrap();
    }
}

const SIGGEN: &str = "\
loadrt siggen
loadrt threads name1=servo-thread period1=1000000
addf siggen.0.update servo-thread
setp siggen.0.frequency 50
net sq siggen.0.square
start
";

/// Waits (up to 30 s) for `path` to exist with the whole download in it.
fn downloaded(path: &std::path::Path) -> Vec<u8> {
    let end = std::time::Instant::now() + std::time::Duration::from_secs(30);
    let partial = path.with_extension("crdownload");
    loop {
        if path.exists() && !partial.exists() {
            return std::fs::read(path).unwrap();
        }
        assert!(
            std::time::Instant::now() < end,
            "{} was not downloaded",
            path.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

#[test]
#[ignore = "needs Debian's chromium and chromium-driver (scripts/install-deps installs them; \
            scripts/test-all runs this test with --include-ignored when they are there)"]
fn the_scope_draws_a_capture_and_saves_csv_and_png() {
    let host = InProcessHost::start("web-browser-scope");
    let (ok, _, err) = host.run("setup.hal", SIGGEN, false);
    assert!(ok, "{err}");
    let web = Web::start(&host.instance, &[]);
    let downloads = std::env::temp_dir().join(format!("hal-web-downloads-{}", host.instance));
    let _ = std::fs::remove_dir_all(&downloads);
    std::fs::create_dir_all(&downloads).unwrap();
    let browser = Browser::downloading_to(&downloads);
    browser.go(&format!("http://{}/", web.host()));
    browser.wait_for(
        "return document.querySelectorAll('#scope-thread option').length;",
        &json!(1),
    );
    // The thread view shows the servo thread and its latency histogram.
    browser.wait_for(
        "return document.querySelector('#threads tr[data-name=\"servo-thread\"]') !== null \
         && Number(document.getElementById('latency').dataset.bars || 0) > 0;",
        &json!(true),
    );
    browser.type_into("#scope-pins", "sq,siggen.0.sine");
    // 5 ms a division at 1 ms a sample: 50 samples, 10 before the trigger.
    browser.eval(
        "document.getElementById('scope-timebase').value = '5'; \
         document.getElementById('scope-trigger').value = 'sq'; \
         document.getElementById('scope-level').value = '0.5'; return true;",
    );
    browser.click("#scope-run");
    browser.wait_for(
        "return document.getElementById('scope').dataset.samples || null;",
        &json!("50"),
    );
    browser.wait_for(
        "return document.getElementById('scope-state').textContent;",
        &json!("triggered"),
    );
    assert_eq!(
        browser.eval("return document.getElementById('scope').dataset.drawn;"),
        json!("100")
    );
    // Something other than the white background and the grid was drawn.
    let colored = browser.eval(
        "const c = document.getElementById('scope'); \
         const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
         let n = 0; for (let i = 0; i < d.length; i += 4) \
           if (d[i] > 150 && d[i + 1] < 80 && d[i + 2] < 80) n++; \
         return n > 100;",
    );
    assert_eq!(colored, json!(true));
    keep_screenshot(&browser, "#scope-pane", "hal-web-scope.png");

    browser.click("#scope-csv");
    let csv = String::from_utf8(downloaded(&downloads.join("halscope.csv"))).unwrap();
    let (status, served) = web.request("GET", "/api/scope.csv", &[], None);
    assert_eq!(status, 200);
    assert_eq!(csv, served);
    assert!(
        csv.starts_with("sample,time_ms,sq,siggen.0.sine\n"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 51);
    let trigger_row: Vec<&str> = csv.lines().nth(11).unwrap().split(',').collect();
    assert_eq!(trigger_row[1], "0.000000", "{csv}");

    browser.click("#scope-png");
    let png = downloaded(&downloads.join("halscope.png"));
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    let _ = std::fs::remove_dir_all(&downloads);
}

/// Serves `html` to every request on a port of its own: a page of
/// another origin than hal-web's. Returns its address.
fn serve_other_origin(html: String) -> std::net::SocketAddr {
    use std::io::{Read, Write};
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    std::thread::spawn(move || {
        for mut conn in listener.incoming().flatten() {
            let mut request = [0u8; 4096];
            let _ = conn.read(&mut request);
            let answer = format!(
                "HTTP/1.1 200 OK\r\nContent-Type: text/html\r\nContent-Length: {}\r\n\
                 Connection: close\r\n\r\n{html}",
                html.len()
            );
            let _ = conn.write_all(answer.as_bytes());
        }
    });
    addr
}

#[test]
#[ignore = "needs Debian's chromium and chromium-driver (scripts/install-deps installs them; \
            scripts/test-all runs this test with --include-ignored when they are there)"]
fn another_sites_page_and_a_page_without_the_token_change_nothing() {
    let host = InProcessHost::start("web-browser-guard");
    let inst = host.instance();
    let comp = inst.new_component("webguard", ComponentKind::User).unwrap();
    let _in = comp.pin::<f64, In>("webguard.in").unwrap();
    comp.ready().unwrap();
    let getp = || {
        let (ok, got, err) = halcmd(&host.instance, &["getp", "webguard.in"]);
        assert!(ok, "{err}");
        got.trim().to_string()
    };
    let web = Web::start(&host.instance, &["--token"]);
    let token_path = hal_web::token::path(&host.instance).unwrap();
    let token = std::fs::read_to_string(&token_path).unwrap();
    let token = token.trim().to_string();
    let setp =
        |value: &str| json!({ "command": "setp", "args": ["webguard.in", value] }).to_string();

    // Another site's page posts a setp to hal-web as a "simple" request
    // (no preflight), even with the token it could not know: refused.
    let evil = format!(
        "<html><body><script>\
         fetch('http://{}/api/hal', {{method: 'POST', mode: 'no-cors', \
         headers: {{'Content-Type': 'text/plain'}}, body: '{}'}})\
         .then(() => {{ document.title = 'sent'; }}, () => {{ document.title = 'failed'; }});\
         </script></body></html>",
        web.host(),
        setp("7")
    );
    let evil_addr = serve_other_origin(evil);
    let browser = Browser::start();
    browser.go(&format!("http://{evil_addr}/"));
    browser.wait_for("return document.title;", &json!("sent"));
    assert_eq!(getp(), "0", "another origin's request changed the HAL");

    // hal-web's own page without the token: the same setp is refused and
    // the page asks for the token; with it, the setp goes through.
    browser.go(&format!("http://{}/", web.host()));
    let post = |with_token: bool| {
        let header = if with_token {
            format!("'X-HAL-Token': '{token}', ")
        } else {
            String::new()
        };
        format!(
            "const r = await fetch('/api/hal', {{method: 'POST', \
             headers: {{{header}'Content-Type': 'application/json'}}, body: '{}'}}); \
             return r.status;",
            setp("3.5")
        )
    };
    let status = browser.eval(&format!("return (async () => {{ {} }})();", post(false)));
    assert_eq!(status, json!(401));
    assert_eq!(getp(), "0", "a request without the token changed the HAL");
    browser.wait_for(
        "return !document.getElementById('token-form').hidden;",
        &json!(true),
    );
    let status = browser.eval(&format!("return (async () => {{ {} }})();", post(true)));
    assert_eq!(status, json!(200));
    assert_eq!(getp(), "3.5");
}
