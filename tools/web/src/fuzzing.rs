//! The fuzz target's body (feature `fuzzing`; fuzz/README.md): what a
//! browser or anyone else can send hal-web, through the guard and the
//! request bodies' checks.

use axum::http::{HeaderMap, HeaderName, HeaderValue};

use crate::change::{words, Change, COMMANDS};
use crate::guard::{check, Access, Policy};
use crate::machine::Action;
use crate::meters::{Meters, MAX_METERS};
use crate::scope::{plan, ScopeRequest, MAX_SAMPLES, MAX_TIMEOUT};
use crate::stream::Watch;
use crate::token::{Token, HEADER};

/// The secret of the fuzzed token policy.
const SECRET: &str = "0123456789abcdef0123456789abcdef0123456789abcdef";

/// Header lines (`name: value`) up to an empty line, then a JSON body.
/// Checks: a token policy admits only its token; no change is admitted
/// read-only or without an Origin equal to `http://` and the Host; a body
/// accepted as a change runs one of the four commands with at most
/// 64 words; a scope request accepted has a record of 2 to
/// [`MAX_SAMPLES`] samples, fewer before the trigger, and a bounded wait.
pub fn request(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let (head, body) = text.split_once("\n\n").unwrap_or((&text, ""));
    let mut headers = HeaderMap::new();
    for line in head.lines() {
        let Some((name, value)) = line.split_once(':') else {
            continue;
        };
        let (Ok(name), Ok(value)) = (
            HeaderName::from_bytes(name.trim().as_bytes()),
            HeaderValue::from_str(value.trim()),
        ) else {
            continue;
        };
        headers.append(name, value);
    }
    let token = Policy {
        token: Some(Token(SECRET.to_string())),
        read_only: false,
    };
    let open = Policy {
        token: None,
        read_only: false,
    };
    let read_only = Policy {
        token: None,
        read_only: true,
    };
    let header = |name: &str| headers.get(name).and_then(|v| v.to_str().ok());
    if check(&headers, &token, Access::Read).is_ok() {
        assert_eq!(
            headers.get(HEADER).map(|v| v.as_bytes()),
            Some(SECRET.as_bytes())
        );
    }
    for (policy, access) in [
        (&token, Access::Change),
        (&open, Access::Change),
        (&read_only, Access::Capture),
    ] {
        if check(&headers, policy, access).is_ok() {
            let host = header("host").unwrap_or_default();
            assert!(!host.is_empty());
            assert_eq!(header("origin"), Some(format!("http://{host}").as_str()));
        }
    }
    assert!(check(&headers, &read_only, Access::Change).is_err());
    if let Ok(change) = serde_json::from_str::<Change>(body) {
        if let Ok(w) = words(change) {
            assert!(COMMANDS.contains(&w[0].as_str()) && w.len() <= 65);
        }
    }
    if let Ok(watch) = serde_json::from_str::<Watch>(body) {
        if Meters::new(&watch.meters).is_ok() {
            assert!(watch.meters.len() <= MAX_METERS);
        }
    }
    let _ = serde_json::from_str::<Action>(body);
    if let Ok(req) = serde_json::from_str::<ScopeRequest>(body) {
        if let Ok(plan) = plan(req) {
            let r = &plan.request;
            assert!(r.samples >= 2 && r.samples <= MAX_SAMPLES && r.pre < r.samples);
            assert!(r.outputs.is_empty() && r.timeout <= MAX_TIMEOUT);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_pass_the_body() {
        request(b"Host: 127.0.0.1:8338\nOrigin: http://127.0.0.1:8338\n\n{\"command\":\"setp\",\"args\":[\"a\",\"1\"]}");
        request(b"Host: m:1\nX-HAL-Token: 0123456789abcdef0123456789abcdef0123456789abcdef\n\n{\"items\":[]}");
        request(b"\xff\n\n\n{");
        request(b"Host: 127.0.0.1:1\n\n{\"pins\":[\"a\"],\"thread\":\"t\",\"samples\":10,\"pre\":\"50%\",\"trigger\":\"a:rising:0\"}");
    }
}
