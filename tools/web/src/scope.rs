//! The scope: captures taken by the headless halscope's own capture
//! ([`hal_scope::scope::capture`]: its sampler at the full rate of a HAL
//! thread, its trigger with level, edge and pre-trigger), asked for with
//! halscope's words and refused with halscope's messages. The page draws
//! the record; the last one is served as halscope's CSV.
//!
//! Modes: `single` and `normal` wait for the trigger (the page asks again
//! after each record in normal mode); `auto` waits [`AUTO_WAIT`] for the
//! trigger, then takes a record at once.
//!
//! The sampler a capture of pins loads stays between records of the same
//! pins ([`Kept`]), so a page in normal mode does not load, link and
//! remove a sampler ten times a second; it is removed when another
//! source is asked for, after [`KEEP_IDLE`] without a record, on a failed
//! record and when the server stops.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use axum::extract::State;
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use hal_core::Instance;
use hal_scope::scope::args::{Args, Request, Source};
use hal_scope::scope::output::{csv as record_csv, Record};
use hal_scope::scope::Session;
use hal_scope::ScopeError;
use serde::Deserialize;

use crate::error::WebError;
use crate::record;
use crate::state::{blocking, error, Shared};

/// Most samples in a record the page asks for (its JSON and drawing stay
/// small); halscope itself takes more.
pub const MAX_SAMPLES: usize = 200_000;

/// Longest wait for a trigger: a capture holds one of the server's few
/// blocking threads.
pub const MAX_TIMEOUT: Duration = Duration::from_secs(60);

/// How long auto mode waits for the trigger before it records anyway.
pub const AUTO_WAIT: Duration = Duration::from_millis(500);

/// How long a sampler stays loaded after its last record.
pub const KEEP_IDLE: Duration = Duration::from_secs(2);

/// The capture session kept between records, and when it last recorded.
pub struct Kept {
    session: Session,
    used: Instant,
}

impl Kept {
    /// Removes the session's sampler.
    pub fn close(self) -> Result<(), ScopeError> {
        self.session.close()
    }
}

/// The kept session, if any (locked for the length of a capture).
pub type KeptSession = Mutex<Option<Kept>>;

/// A capture request, in halscope's words: `{"pins": ["a", "b"],
/// "thread": "servo-thread", "trigger": "a:rising:0.5", "samples": 1000,
/// "pre": "20%", "timeout": 10, "mode": "normal"}`, or `"channel": N`
/// for a sampler channel the HAL file made instead of pins and thread.
#[derive(Debug, Deserialize)]
pub struct ScopeRequest {
    /// Pins or signals, one per channel.
    #[serde(default)]
    pub pins: Vec<String>,
    /// The thread whose period is the sample interval.
    pub thread: Option<String>,
    /// A channel of a sampler the configuration loaded.
    pub channel: Option<usize>,
    /// `NAME:rising|falling:LEVEL`.
    pub trigger: Option<String>,
    /// Samples in the record.
    pub samples: usize,
    /// The share of the record before the trigger (`20%` or `0.2`).
    pub pre: Option<String>,
    /// Seconds to wait for the trigger (default 10).
    pub timeout: Option<f64>,
    /// `single`, `normal` or `auto`.
    #[serde(default)]
    pub mode: Mode,
}

/// The scope's trigger modes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// One record, on the trigger.
    #[default]
    Single,
    /// Records on the trigger, again and again (the page repeats).
    Normal,
    /// Records on the trigger, or without it when none comes soon.
    Auto,
}

/// A checked request: what the capture gets.
#[derive(Debug)]
pub struct Plan {
    /// halscope's request (no output files).
    pub request: Request,
    /// The mode.
    pub mode: Mode,
}

/// Checks `req` as halscope checks its command line (same messages), and
/// against the page's bounds.
pub fn plan(req: ScopeRequest) -> Result<Plan, WebError> {
    if req.samples > MAX_SAMPLES {
        return Err(WebError::ScopeSamples {
            asked: req.samples,
            max: MAX_SAMPLES,
        });
    }
    let timeout = req.timeout.unwrap_or(10.0);
    if timeout > MAX_TIMEOUT.as_secs_f64() {
        return Err(WebError::ScopeTimeout {
            asked: timeout,
            max_s: MAX_TIMEOUT.as_secs(),
        });
    }
    let args = Args {
        pins: req.pins,
        thread: req.thread,
        mult: 1,
        channel: req.channel,
        trigger: req.trigger,
        samples: req.samples,
        pre: req.pre.unwrap_or_else(|| "0%".into()),
        out: Vec::new(),
        timeout,
        instance: None,
    };
    if args.channel.is_some() && (args.thread.is_some() || !args.pins.is_empty()) {
        // halscope's command line refuses the pair too.
        return Err(WebError::ScopeSourceBoth);
    }
    let request = args.request()?;
    Ok(Plan {
        request,
        mode: req.mode,
    })
}

/// Takes one record as `plan` asks, in the kept session when it records
/// the same source; whether the trigger came. The session is kept for the
/// next record unless the record failed for another reason than a
/// trigger that did not come.
pub fn take(
    inst: &Instance,
    plan: &Plan,
    kept: &mut Option<Kept>,
    interrupted: &dyn Fn() -> bool,
) -> Result<(Record, bool), ScopeError> {
    let source = &plan.request.source;
    let mut session = match kept.take() {
        Some(k) if k.session.serves(source) => k.session,
        other => {
            // Only one sampler of our own can be loaded at a time.
            if let Some(k) = other {
                k.session.close()?;
            }
            Session::open(inst, source)?
        }
    };
    let taken = record_in(&mut session, inst, plan, interrupted);
    match &taken {
        Ok(_) | Err(ScopeError::Timeout(_)) => {
            *kept = Some(Kept {
                session,
                used: Instant::now(),
            })
        }
        Err(_) => {
            // The record's error is the one to report.
            let _ = session.close();
        }
    }
    taken
}

/// One record of `session` in `plan`'s mode.
fn record_in(
    session: &mut Session,
    inst: &Instance,
    plan: &Plan,
    interrupted: &dyn Fn() -> bool,
) -> Result<(Record, bool), ScopeError> {
    let req = &plan.request;
    if plan.mode != Mode::Auto || req.trigger.is_none() {
        let record = session.record(inst, req, interrupted)?;
        return Ok((record, req.trigger.is_some()));
    }
    let waiting = Request {
        timeout: req.timeout.min(AUTO_WAIT),
        ..req.clone()
    };
    match session.record(inst, &waiting, interrupted) {
        Ok(record) => Ok((record, true)),
        Err(ScopeError::Timeout(_)) => {
            let at_once = Request {
                trigger: None,
                pre: 0,
                ..req.clone()
            };
            Ok((session.record(inst, &at_once, interrupted)?, false))
        }
        Err(e) => Err(e),
    }
}

/// Takes the kept session out when it has not recorded for `idle`, or
/// at once with `Duration::ZERO`; `None` while a capture holds it.
pub fn idle_session(kept: &KeptSession, idle: Duration) -> Option<Session> {
    let mut guard = kept.try_lock().ok()?;
    if guard.as_ref()?.used.elapsed() < idle {
        return None;
    }
    guard.take().map(|k| k.session)
}

/// The last record taken, for the CSV.
pub type LastRecord = Mutex<Option<Arc<Record>>>;

/// `POST /api/scope`: takes a record; 200 with it (JSON, or the binary
/// form of [`record`] when the request accepts
/// `application/octet-stream`), 400 for a request halscope refuses, 422
/// when the capture fails (halscope's message), 503 while another
/// capture runs. Refusals are JSON either way.
pub async fn post(
    State(state): State<Shared>,
    headers: HeaderMap,
    Json(req): Json<ScopeRequest>,
) -> Response {
    let binary = wants_binary(&headers);
    let plan = match plan(req) {
        Ok(p) => p,
        Err(msg) => return error(StatusCode::BAD_REQUEST, msg),
    };
    if state.policy.read_only && matches!(plan.request.source, Source::Own { .. }) {
        return error(
            StatusCode::FORBIDDEN,
            "hal-web runs read-only (--read-only): a capture of pins would add a sampler; \
             capture through a channel of a sampler the HAL file loaded",
        );
    }
    let Ok(_permit) = state.capturing.clone().try_acquire_owned() else {
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            "another capture is running; try again when it ends",
        );
    };
    let worker = state.clone();
    let taken = blocking(move || {
        let stopping = || *worker.stopping.borrow();
        match worker.kept_scope.lock() {
            Ok(mut kept) => take(&worker.inst, &plan, &mut kept, &stopping),
            Err(poisoned) => {
                // A capture that panicked left the session in an unknown
                // state: drop it (removing its sampler) and start afresh.
                let mut kept = poisoned.into_inner();
                *kept = None;
                take(&worker.inst, &plan, &mut kept, &stopping)
            }
        }
    })
    .await;
    match taken {
        Ok(Ok((taken, triggered))) => {
            let answer = if binary {
                (
                    [
                        (header::CONTENT_TYPE, record::BINARY_TYPE),
                        (header::CACHE_CONTROL, "no-store"),
                    ],
                    record::binary(&taken, triggered),
                )
                    .into_response()
            } else {
                Json(record::json(&taken, triggered)).into_response()
            };
            if let Ok(mut last) = state.last_record.lock() {
                *last = Some(Arc::new(taken));
            }
            answer
        }
        Ok(Err(e)) => error(StatusCode::UNPROCESSABLE_ENTITY, e),
        Err(r) => r,
    }
}

/// Whether the request's `Accept` names the binary record.
fn wants_binary(headers: &HeaderMap) -> bool {
    headers
        .get_all(header::ACCEPT)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(','))
        .any(|t| {
            t.split(';')
                .next()
                .is_some_and(|m| m.trim().eq_ignore_ascii_case(record::BINARY_TYPE))
        })
}

/// `GET /api/scope.csv`: the last record as halscope writes its CSV.
pub async fn csv(State(state): State<Shared>) -> Response {
    let last = state.last_record.lock().ok().and_then(|l| l.clone());
    let Some(record) = last else {
        return error(StatusCode::NOT_FOUND, "no capture has been taken yet");
    };
    (
        [
            (header::CONTENT_TYPE, "text/csv; charset=utf-8"),
            (
                header::CONTENT_DISPOSITION,
                "attachment; filename=\"halscope.csv\"",
            ),
            (header::CACHE_CONTROL, "no-store"),
        ],
        record_csv(&record),
    )
        .into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(json: &str) -> Result<Plan, WebError> {
        plan(serde_json::from_str(json).unwrap())
    }

    #[test]
    fn the_binary_record_is_for_who_accepts_it() {
        let accept = |v: &str| {
            let mut h = HeaderMap::new();
            h.insert(header::ACCEPT, v.parse().unwrap());
            wants_binary(&h)
        };
        assert!(accept("application/octet-stream"));
        assert!(accept("application/json, Application/Octet-Stream;q=0.9"));
        assert!(!accept("application/json"));
        assert!(!accept("*/*"));
        assert!(!wants_binary(&HeaderMap::new()));
    }

    #[test]
    fn requests_read_as_halscope_words() {
        let p = req(
            r#"{"pins":["a","b"],"thread":"servo-thread","trigger":"a:falling:-1",
                        "samples":100,"pre":"20%","mode":"auto"}"#,
        )
        .unwrap();
        assert_eq!(p.request.pre, 20);
        assert_eq!(p.mode, Mode::Auto);
        assert!(p.request.outputs.is_empty());
        let p = req(r#"{"channel":2,"samples":10}"#).unwrap();
        assert_eq!(p.request.source, Source::Channel(2));
    }

    #[test]
    fn refusals_are_halscopes() {
        use clap::Parser as _;
        let e = |j: &str| req(j).unwrap_err().to_string();
        let halscope = |words: &[&str]| {
            let mut v = vec!["halscope"];
            v.extend(words);
            v.extend(["--out", "x.csv"]);
            Args::try_parse_from(v)
                .unwrap()
                .request()
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            e(r#"{"pins":["a"],"thread":"t","samples":1}"#),
            halscope(&["--pins", "a", "--thread", "t", "--samples", "1"])
        );
        assert_eq!(
            e(r#"{"pins":["a"],"thread":"t","samples":10,"trigger":"a:up:1"}"#),
            halscope(&["--pins", "a", "--thread", "t", "--trigger", "a:up:1"])
        );
        // Pins without a thread parse (scope_rt, when loaded, knows its
        // thread); neither pins nor a channel is refused alike.
        assert!(req(r#"{"pins":["a"],"samples":10}"#).is_ok());
        assert_eq!(e(r#"{"samples":10}"#), halscope(&[]));
        assert!(e(r#"{"pins":["a"],"thread":"t","samples":200001}"#).contains("at most"));
        assert!(e(r#"{"pins":["a"],"thread":"t","samples":9,"timeout":61}"#).contains("60 s"));
        assert!(e(r#"{"pins":["a"],"channel":1,"samples":9}"#).contains("channel"));
    }
}
