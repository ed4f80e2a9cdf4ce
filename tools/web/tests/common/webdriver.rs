//! A WebDriver session with Debian's headless chromium (chromium-driver's
//! `chromedriver`), for the browser test: just the calls it needs.

use std::net::{SocketAddr, TcpListener};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::http;

/// The programs the browser test needs, where Debian puts them.
pub const CHROMIUM: &str = "/usr/bin/chromium";
/// chromium-driver's WebDriver server.
pub const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

/// A headless chromium driven through chromedriver.
pub struct Browser {
    addr: SocketAddr,
    session: String,
    driver: Child,
}

impl Browser {
    /// Starts chromedriver on a free port and opens a headless session.
    pub fn start() -> Browser {
        Browser::start_with(None)
    }

    /// A session that saves downloads in `dir` without asking.
    pub fn downloading_to(dir: &std::path::Path) -> Browser {
        Browser::start_with(Some(dir))
    }

    fn start_with(downloads: Option<&std::path::Path>) -> Browser {
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let driver = Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let addr: SocketAddr = format!("127.0.0.1:{port}").parse().unwrap();
        let end = Instant::now() + Duration::from_secs(30);
        while std::net::TcpStream::connect(addr).is_err() {
            assert!(Instant::now() < end, "chromedriver did not listen");
            std::thread::sleep(Duration::from_millis(50));
        }
        let mut options = json!({
            "binary": CHROMIUM,
            "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
                     "--disable-dev-shm-usage", "--window-size=1280,900"],
        });
        if let Some(dir) = downloads {
            options["prefs"] = json!({
                "download.default_directory": dir.display().to_string(),
                "download.prompt_for_download": false,
            });
        }
        let caps = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": options,
        }}});
        let mut b = Browser {
            addr,
            session: String::new(),
            driver,
        };
        let v = b.call("POST", "/session", Some(caps));
        b.session = v["sessionId"].as_str().expect("a session").to_string();
        b
    }

    fn call(&self, method: &str, path: &str, body: Option<Value>) -> Value {
        let body = body.map(|b| b.to_string());
        let (status, text) = http(self.addr, method, path, &[], body.as_deref());
        let v: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
        assert_eq!(status, 200, "WebDriver {method} {path}: {text}");
        v["value"].clone()
    }

    fn session_call(&self, method: &str, path: &str, body: Option<Value>) -> Value {
        self.call(method, &format!("/session/{}{path}", self.session), body)
    }

    /// Opens `url`.
    pub fn go(&self, url: &str) {
        self.session_call("POST", "/url", Some(json!({ "url": url })));
    }

    /// Runs `script` in the page; what it returns.
    pub fn eval(&self, script: &str) -> Value {
        self.session_call(
            "POST",
            "/execute/sync",
            Some(json!({ "script": script, "args": [] })),
        )
    }

    /// The WebDriver id of the element `css` selects.
    fn element(&self, css: &str) -> String {
        let el = self.session_call(
            "POST",
            "/element",
            Some(json!({ "using": "css selector", "value": css })),
        );
        el.as_object()
            .and_then(|o| o.values().next())
            .and_then(Value::as_str)
            .expect("an element")
            .to_string()
    }

    /// Clicks the element `css` selects.
    pub fn click(&self, css: &str) {
        let id = self.element(css);
        self.session_call("POST", &format!("/element/{id}/click"), Some(json!({})));
    }

    /// Types `text` into the element `css` selects (`\u{E007}` is Enter).
    pub fn type_into(&self, css: &str, text: &str) {
        let id = self.element(css);
        self.session_call(
            "POST",
            &format!("/element/{id}/value"),
            Some(json!({ "text": text })),
        );
    }

    /// A PNG of the whole element `css` selects, as the browser draws it.
    /// An element's screenshot holds only what the viewport shows: the
    /// window is first made as tall as the page, and the element brought
    /// to the top.
    pub fn screenshot(&self, css: &str) -> Vec<u8> {
        let id = self.element(css);
        let rect = self.session_call("GET", "/window/rect", None);
        let page = self.eval("return Math.ceil(document.documentElement.scrollHeight);");
        let (width, height, page) = (
            rect["width"].as_u64().unwrap_or(1280),
            rect["height"].as_u64().unwrap_or(900),
            page.as_u64().unwrap_or(0),
        );
        if page + 200 > height {
            self.session_call(
                "POST",
                "/window/rect",
                Some(json!({ "width": width, "height": page + 200 })),
            );
        }
        self.session_call(
            "POST",
            "/execute/sync",
            Some(json!({
                "script": "document.querySelector(arguments[0]).scrollIntoView(); return true;",
                "args": [css],
            })),
        );
        let v = self.session_call("GET", &format!("/element/{id}/screenshot"), None);
        base64_decode(v.as_str().expect("a screenshot"))
    }

    /// Waits (up to 30 s) until `script` returns `want`.
    pub fn wait_for(&self, script: &str, want: &Value) {
        self.wait_for_within(script, want, Duration::from_secs(30));
    }

    /// As [`Browser::wait_for`], for up to `limit` (homing a machine
    /// takes longer than a page takes to update).
    pub fn wait_for_within(&self, script: &str, want: &Value, limit: Duration) {
        let end = Instant::now() + limit;
        loop {
            let got = self.eval(script);
            if &got == want {
                return;
            }
            assert!(Instant::now() < end, "{script} is {got}, not {want}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

/// Standard base64 (WebDriver's screenshots) to bytes.
fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| -> Option<u32> {
        match c {
            b'A'..=b'Z' => Some(u32::from(c - b'A')),
            b'a'..=b'z' => Some(u32::from(c - b'a') + 26),
            b'0'..=b'9' => Some(u32::from(c - b'0') + 52),
            b'+' => Some(62),
            b'/' => Some(63),
            _ => None,
        }
    };
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0);
    for v in text.bytes().filter_map(value) {
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    out
}

impl Drop for Browser {
    fn drop(&mut self) {
        let path = format!("/session/{}", self.session);
        if !self.session.is_empty() {
            let _ = http(self.addr, "DELETE", &path, &[], None);
        }
        super::stop(&mut self.driver, Duration::from_secs(5));
    }
}
