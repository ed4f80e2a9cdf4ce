//! What every handler shares, and how handlers answer.

use std::sync::Arc;

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use hal_core::Instance;
use serde_json::json;
use tokio::sync::Semaphore;

use crate::guard::Policy;

/// Most live streams at once (each reads its items 10 to 20 times a second).
pub const MAX_STREAMS: usize = 8;

/// Most API requests in progress at once (beyond: 503).
pub const MAX_REQUESTS: usize = 16;

/// The server's shared state.
pub struct AppState {
    /// The instance served.
    pub inst: Instance,
    /// Who may ask what.
    pub policy: Policy,
    /// Permits for live streams.
    pub streams: Arc<Semaphore>,
    /// Permits for API requests in progress.
    pub requests: Arc<Semaphore>,
    /// Becomes true when the server stops: live streams end.
    pub stopping: tokio::sync::watch::Receiver<bool>,
    /// The one permit for a scope capture.
    pub capturing: Arc<Semaphore>,
    /// The last scope record, for its CSV.
    pub last_record: crate::scope::LastRecord,
    /// The scope's sampler, kept between records of the same pins.
    pub kept_scope: crate::scope::KeptSession,
}

/// A shared handle on the state.
pub type Shared = Arc<AppState>;

impl AppState {
    /// The state for serving `inst` under `policy`.
    pub fn new(
        inst: Instance,
        policy: Policy,
        stopping: tokio::sync::watch::Receiver<bool>,
    ) -> Shared {
        Arc::new(AppState {
            stopping,
            inst,
            policy,
            streams: Arc::new(Semaphore::new(MAX_STREAMS)),
            requests: Arc::new(Semaphore::new(MAX_REQUESTS)),
            capturing: Arc::new(Semaphore::new(1)),
            last_record: std::sync::Mutex::new(None),
            kept_scope: std::sync::Mutex::new(None),
        })
    }
}

/// A JSON error answer: `{"error": msg}` with `status`.
pub fn error(status: StatusCode, msg: impl std::fmt::Display) -> Response {
    (status, Json(json!({ "error": msg.to_string() }))).into_response()
}

/// Runs blocking work (HAL reads, halcmd, task requests) off the
/// runtime's thread; a panic there becomes a 500.
pub async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<T, Response> {
    tokio::task::spawn_blocking(f).await.map_err(|e| {
        error(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the request's work failed: {e}"),
        )
    })
}
