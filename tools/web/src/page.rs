//! The page itself: plain HTML, CSS and JavaScript built into the binary
//! (app.js: the tree, watch list, meters, changes and machine panel;
//! scope.js: the scope;
//! threads.js: thread timing and latency histograms).
//! They hold no data, so they are served without the token (a browser's
//! first request cannot carry it); every `/api` request needs it.

use axum::http::header;
use axum::response::{IntoResponse, Response};

const INDEX: &str = include_str!("../assets/index.html");
const SCRIPT: &str = include_str!("../assets/app.js");
const SCOPE_SCRIPT: &str = include_str!("../assets/scope.js");
const THREADS_SCRIPT: &str = include_str!("../assets/threads.js");
const STYLE: &str = include_str!("../assets/app.css");

/// The headers every page file gets: no framing by another site, no
/// caching, no referrer, scripts and requests only from this origin.
fn with_headers(content_type: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-store"),
            (header::X_FRAME_OPTIONS, "DENY"),
            (header::REFERRER_POLICY, "no-referrer"),
            (
                header::CONTENT_SECURITY_POLICY,
                "default-src 'self'; frame-ancestors 'none'; form-action 'none'",
            ),
        ],
        body,
    )
        .into_response()
}

/// `GET /`.
pub async fn index() -> Response {
    with_headers("text/html; charset=utf-8", INDEX)
}

/// `GET /app.js`.
pub async fn script() -> Response {
    with_headers("text/javascript; charset=utf-8", SCRIPT)
}

/// `GET /scope.js`.
pub async fn scope_script() -> Response {
    with_headers("text/javascript; charset=utf-8", SCOPE_SCRIPT)
}

/// `GET /threads.js`.
pub async fn threads_script() -> Response {
    with_headers("text/javascript; charset=utf-8", THREADS_SCRIPT)
}

/// `GET /app.css`.
pub async fn style() -> Response {
    with_headers("text/css; charset=utf-8", STYLE)
}
