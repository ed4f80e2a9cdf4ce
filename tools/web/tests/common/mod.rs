//! What hal-web's tests share: hal-web started on an instance, and a
//! small HTTP client (plain std sockets; the tests need no more).
#![allow(dead_code)]

pub mod mill;
pub mod webdriver;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running hal-web.
pub struct Web {
    pub addr: SocketAddr,
    child: Child,
}

impl Web {
    /// Starts hal-web on `instance` on a free port with `args`, and waits
    /// until it says where it listens.
    pub fn start(instance: &str, args: &[&str]) -> Web {
        let mut child = Command::new(env!("CARGO_BIN_EXE_hal-web"))
            .args(["-p", "0"])
            .args(args)
            .env("HAL_INSTANCE", instance)
            .stdout(Stdio::piped())
            .spawn()
            .expect("hal-web starts");
        let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
        let first = lines.next().expect("hal-web says where").expect("a line");
        // The rest (the token file's name) is read so hal-web never blocks.
        std::thread::spawn(move || for _ in lines {});
        let url = first
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("no address in {first:?}"));
        let addr = url
            .trim_start_matches("http://")
            .trim_end_matches('/')
            .parse()
            .unwrap();
        Web { addr, child }
    }

    /// hal-web's process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// The Host (and same Origin) the page's requests carry.
    pub fn host(&self) -> String {
        self.addr.to_string()
    }

    /// A request; (status, body).
    pub fn request(
        &self,
        method: &str,
        path: &str,
        headers: &[(&str, &str)],
        body: Option<&str>,
    ) -> (u16, String) {
        http(self.addr, method, path, headers, body)
    }

    /// A capture as the page asks for it: JSON, from the page's own
    /// origin, answered in the binary form; (status, body).
    pub fn post_binary(&self, path: &str, body: &str) -> (u16, Vec<u8>) {
        let origin = format!("http://{}", self.host());
        let headers = [
            ("Origin", origin.as_str()),
            ("Accept", "application/octet-stream"),
        ];
        http_bytes(self.addr, "POST", path, &headers, Some(body))
    }

    /// A change as the page sends it: JSON, from the page's own origin.
    pub fn post_same_origin(&self, path: &str, body: &str, token: Option<&str>) -> (u16, String) {
        let origin = format!("http://{}", self.host());
        let mut headers = vec![("Origin", origin.as_str())];
        if let Some(t) = token {
            headers.push(("X-HAL-Token", t));
        }
        self.request("POST", path, &headers, Some(body))
    }

    /// Opens the live stream of `body` (reads time out after 30 s).
    pub fn open_stream(&self, body: &str) -> BufReader<TcpStream> {
        let mut s = TcpStream::connect(self.addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        s.write_all(head("POST", "/api/stream", &self.host(), &[], Some(body)).as_bytes())
            .unwrap();
        BufReader::new(s)
    }

    /// Sends SIGTERM; whether hal-web ended within `within`.
    pub fn ends_on_sigterm(&mut self, within: Duration) -> bool {
        let pid = nix::unistd::Pid::from_raw(self.child.id() as i32);
        let _ = nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM);
        let end = Instant::now() + within;
        while Instant::now() < end {
            if let Ok(Some(_)) = self.child.try_wait() {
                return true;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        false
    }

    /// Opens the live stream of `body` and reads events until `done`
    /// accepts one's data (or 30 s pass: a failure).
    pub fn stream_until(&self, body: &str, mut done: impl FnMut(&serde_json::Value) -> bool) {
        let end = Instant::now() + Duration::from_secs(30);
        let mut reader = self.open_stream(body);
        let mut line = String::new();
        let mut seen = Vec::new();
        while Instant::now() < end {
            line.clear();
            if reader.read_line(&mut line).unwrap_or(0) == 0 {
                break;
            }
            if let Some(data) = line.trim_end().strip_prefix("data:") {
                let v: serde_json::Value = serde_json::from_str(data.trim()).unwrap();
                if done(&v) {
                    return;
                }
                seen.push(v);
            }
        }
        panic!("the stream never showed it; events: {seen:?}");
    }
}

impl Drop for Web {
    fn drop(&mut self) {
        stop(&mut self.child, Duration::from_secs(10));
    }
}

/// Ends `child` as the launcher would: SIGTERM, up to `grace` to go, then
/// SIGKILL.
pub fn stop(child: &mut Child, grace: Duration) {
    let pid = nix::unistd::Pid::from_raw(child.id() as i32);
    let _ = nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM);
    let end = Instant::now() + grace;
    while Instant::now() < end {
        if let Ok(Some(_)) = child.try_wait() {
            return;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// One HTTP/1.1 request to `addr` (Host is `addr` unless `headers` name
/// one); (status, body).
pub fn http(
    addr: SocketAddr,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: Option<&str>,
) -> (u16, String) {
    let (status, body) = http_bytes(addr, method, path, headers, body);
    (status, String::from_utf8_lossy(&body).into_owned())
}

/// As [`http`], with the body's bytes as they came.
pub fn http_bytes(
    addr: SocketAddr,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: Option<&str>,
) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    s.write_all(head(method, path, &addr.to_string(), headers, body).as_bytes())
        .unwrap();
    let (head, body) = answer(&mut s);
    let status = head.split_whitespace().nth(1).unwrap().parse().unwrap();
    (status, body)
}

/// Reads an answer's head and body: Content-Length bytes when it says
/// (a server may keep the connection open), else to the end.
fn answer(s: &mut TcpStream) -> (String, Vec<u8>) {
    let mut raw = Vec::new();
    let mut buf = [0u8; 8192];
    let split = loop {
        if let Some(at) = raw.windows(4).position(|w| w == b"\r\n\r\n") {
            break at;
        }
        let n = s.read(&mut buf).unwrap();
        assert!(n > 0, "the connection closed before the answer's head");
        raw.extend_from_slice(&buf[..n]);
    };
    let head = String::from_utf8_lossy(&raw[..split]).into_owned();
    let mut body = raw[split + 4..].to_vec();
    let lower = head.to_ascii_lowercase();
    let length = lower
        .lines()
        .find_map(|l| l.strip_prefix("content-length:"))
        .and_then(|v| v.trim().parse::<usize>().ok());
    match length {
        Some(len) => {
            while body.len() < len {
                let n = s.read(&mut buf).unwrap();
                assert!(n > 0, "the connection closed inside the body");
                body.extend_from_slice(&buf[..n]);
            }
        }
        None => {
            s.read_to_end(&mut body).unwrap();
        }
    }
    if lower.contains("transfer-encoding: chunked") {
        (head, dechunk(&body))
    } else {
        (head, body)
    }
}

fn head(
    method: &str,
    path: &str,
    host: &str,
    headers: &[(&str, &str)],
    body: Option<&str>,
) -> String {
    let mut h = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\n");
    if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("host")) {
        h.push_str(&format!("Host: {host}\r\n"));
    }
    for (k, v) in headers {
        h.push_str(&format!("{k}: {v}\r\n"));
    }
    if let Some(b) = body {
        h.push_str(&format!(
            "Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{b}",
            b.len()
        ));
    } else {
        h.push_str("\r\n");
    }
    h
}

fn dechunk(mut body: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    while let Some(eol) = body.windows(2).position(|w| w == b"\r\n") {
        let size = String::from_utf8_lossy(&body[..eol]);
        let n = usize::from_str_radix(size.trim(), 16).unwrap_or(0);
        let rest = &body[eol + 2..];
        if n == 0 || rest.len() < n {
            break;
        }
        out.extend_from_slice(&rest[..n]);
        body = rest[n..].strip_prefix(b"\r\n").unwrap_or(&rest[n..]);
    }
    out
}

/// `halcmd WORDS` on `instance` as the halcmd program runs it (its
/// command line read by halcmd's parser, then its session): (ok, stdout,
/// stderr).
pub fn halcmd(instance: &str, words: &[&str]) -> (bool, String, String) {
    let inst = hal_core::Instance::attach(instance).unwrap();
    let args: Vec<String> = words.iter().map(|s| s.to_string()).collect();
    let parsed = hal_tools::cli::parse_halcmd_args(&args).unwrap();
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let ok = {
        let mut session = hal_lang::Session::new(inst, parsed.opts, &mut out, &mut err);
        session.run_words(&parsed.command)
    };
    (
        ok,
        String::from_utf8_lossy(&out).into_owned(),
        String::from_utf8_lossy(&err).into_owned(),
    )
}
