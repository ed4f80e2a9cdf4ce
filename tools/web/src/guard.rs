//! Who may ask what: the token, the Host a loopback server answers to,
//! same-origin changes and read-only mode. Checked before any handler
//! runs; nothing here logs a header.

use axum::http::{header, HeaderMap, StatusCode};

use crate::token::{Token, HEADER};

/// The rules a server enforces.
#[derive(Debug, Clone)]
pub struct Policy {
    /// The token every API request must carry, if one is in force.
    pub token: Option<Token>,
    /// Changes are refused.
    pub read_only: bool,
}

/// Why a request is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    /// No token, or the wrong one.
    #[error("this request needs the access token in the X-HAL-Token header")]
    Token,
    /// A loopback server asked under another host name (DNS rebinding).
    #[error("hal-web answers on this address only as localhost, 127.0.0.1 or [::1]")]
    Host,
    /// A change from another origin, or without an Origin header.
    #[error("changes are accepted only from hal-web's own page (same origin)")]
    CrossOrigin,
    /// A change while read-only.
    #[error("hal-web runs read-only (--read-only): nothing is changed")]
    ReadOnly,
}

impl Refusal {
    /// The HTTP status that goes with it.
    pub fn status(self) -> StatusCode {
        match self {
            Refusal::Token => StatusCode::UNAUTHORIZED,
            _ => StatusCode::FORBIDDEN,
        }
    }
}

/// What a request may do, which decides what it needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Reads (the tree, live values, the machine's state): the token.
    Read,
    /// A scope capture: the token and the same origin (it adds a sampler
    /// for the capture's time), allowed read-only; the capture itself
    /// refuses read-only what would change the HAL.
    Capture,
    /// Changes the HAL or the machine: the token, the same origin, and
    /// not read-only.
    Change,
}

/// Checks a request's headers for `access`.
pub fn check(headers: &HeaderMap, policy: &Policy, access: Access) -> Result<(), Refusal> {
    let host = text(headers, header::HOST.as_str()).unwrap_or_default();
    match &policy.token {
        Some(token) => {
            let offered = headers
                .get(HEADER)
                .map(|v| v.as_bytes())
                .unwrap_or_default();
            if !token.matches(offered) {
                return Err(Refusal::Token);
            }
        }
        // Without a token only the loopback is served; a page of another
        // site whose name was made to point at 127.0.0.1 comes with its
        // own name as Host and is refused.
        None if !is_loopback_host(host) => return Err(Refusal::Host),
        None => {}
    }
    if access == Access::Read {
        return Ok(());
    }
    if access == Access::Change && policy.read_only {
        return Err(Refusal::ReadOnly);
    }
    let same_origin = text(headers, header::ORIGIN.as_str())
        .is_some_and(|origin| origin.strip_prefix("http://") == Some(host) && !host.is_empty());
    let fetch_site_ok = text(headers, "sec-fetch-site").is_none_or(|s| s == "same-origin");
    if same_origin && fetch_site_ok {
        Ok(())
    } else {
        Err(Refusal::CrossOrigin)
    }
}

fn text<'h>(headers: &'h HeaderMap, name: &str) -> Option<&'h str> {
    headers.get(name).and_then(|v| v.to_str().ok())
}

/// Whether a Host header names the loopback: `localhost`, `127.x.y.z` or
/// `[::1]`, with or without a port.
fn is_loopback_host(host: &str) -> bool {
    let name = if let Some(rest) = host.strip_prefix('[') {
        match rest.split_once(']') {
            Some((inside, port)) if port.is_empty() || is_port(port) => inside,
            _ => return false,
        }
    } else {
        match host.rsplit_once(':') {
            Some((name, port)) if is_port(port) => name,
            Some(_) => return false,
            None => host,
        }
    };
    name.eq_ignore_ascii_case("localhost")
        || name
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback())
}

fn is_port(s: &str) -> bool {
    s.strip_prefix(':').unwrap_or(s).parse::<u16>().is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        let mut h = HeaderMap::new();
        for (k, v) in pairs {
            h.insert(*k, HeaderValue::from_str(v).unwrap());
        }
        h
    }

    fn open() -> Policy {
        Policy {
            token: None,
            read_only: false,
        }
    }

    #[test]
    fn loopback_host_names_are_told_apart() {
        for ok in [
            "localhost",
            "localhost:8338",
            "127.0.0.1:1",
            "[::1]:80",
            "[::1]",
        ] {
            assert!(is_loopback_host(ok), "{ok}");
        }
        for bad in ["evil.example:8338", "", "127.0.0.1:x", "[::1]x", "10.0.0.1"] {
            assert!(!is_loopback_host(bad), "{bad}");
        }
    }

    #[test]
    fn changes_need_the_same_origin() {
        let p = open();
        let host = ("host", "127.0.0.1:9");
        assert_eq!(check(&headers(&[host]), &p, Access::Read), Ok(()));
        assert_eq!(
            check(&headers(&[host]), &p, Access::Change),
            Err(Refusal::CrossOrigin)
        );
        let other = ("origin", "http://evil.example");
        assert_eq!(
            check(&headers(&[host, other]), &p, Access::Change),
            Err(Refusal::CrossOrigin)
        );
        let same = ("origin", "http://127.0.0.1:9");
        assert_eq!(check(&headers(&[host, same]), &p, Access::Change), Ok(()));
        let cross_site = ("sec-fetch-site", "cross-site");
        assert_eq!(
            check(&headers(&[host, same, cross_site]), &p, Access::Change),
            Err(Refusal::CrossOrigin)
        );
        let ro = Policy {
            read_only: true,
            ..open()
        };
        assert_eq!(
            check(&headers(&[host, same]), &ro, Access::Change),
            Err(Refusal::ReadOnly)
        );
        assert_eq!(check(&headers(&[host, same]), &ro, Access::Capture), Ok(()));
        assert_eq!(
            check(&headers(&[host, other]), &ro, Access::Capture),
            Err(Refusal::CrossOrigin)
        );
        let rebound = ("host", "evil.example:9");
        assert_eq!(
            check(&headers(&[rebound]), &p, Access::Read),
            Err(Refusal::Host)
        );
    }

    #[test]
    fn a_token_in_force_is_required() {
        let token = Token::generate().unwrap();
        let p = Policy {
            token: Some(token.clone()),
            read_only: false,
        };
        let host = ("host", "machine:8338");
        assert_eq!(
            check(&headers(&[host]), &p, Access::Read),
            Err(Refusal::Token)
        );
        let wrong = ("x-hal-token", "00");
        assert_eq!(
            check(&headers(&[host, wrong]), &p, Access::Read),
            Err(Refusal::Token)
        );
        let right = ("x-hal-token", token.secret());
        assert_eq!(check(&headers(&[host, right]), &p, Access::Read), Ok(()));
        let same = ("origin", "http://machine:8338");
        assert_eq!(
            check(&headers(&[host, right, same]), &p, Access::Change),
            Ok(())
        );
    }
}
