//! The HTTP server: routes, the guard in front of the API, and serving
//! until the instance ends or a stop is requested.

use std::net::SocketAddr;
use std::time::Duration;

use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{Method, StatusCode};
use axum::middleware::{from_fn_with_state, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use hal_core::userspace::ExitSignals;
use hal_core::Instance;

use crate::state::{blocking, error, AppState, Shared};
use crate::{change, guard, machine, page, scope, snapshot, stream, threads};

/// Largest request body accepted (a watch list of [`crate::watch::MAX_ITEMS`]).
const BODY_LIMIT: usize = 256 * 1024;

/// How often the server looks for a stop request.
const STOP_POLL: Duration = Duration::from_millis(100);

/// How often it asks whether the instance's host still runs: each ask
/// opens and locks the host's lock file and checks the runtime directory
/// (its group's lookup reads the group database), too dear for every poll.
const HOST_POLL: Duration = Duration::from_secs(1);

/// The routes of hal-web over `state`.
pub fn router(state: Shared) -> Router {
    let api = Router::new()
        .route("/show", get(show))
        .route("/stream", post(stream::post))
        .route("/hal", post(change::post))
        .route("/machine", get(machine::get).post(machine::post))
        .route("/scope", post(scope::post))
        .route("/threads", get(threads::get))
        .route("/scope.csv", get(scope::csv))
        .layer(from_fn_with_state(state.clone(), admit))
        .layer(DefaultBodyLimit::max(BODY_LIMIT));
    Router::new()
        .route("/", get(page::index))
        .route("/app.js", get(page::script))
        .route("/scope.js", get(page::scope_script))
        .route("/threads.js", get(page::threads_script))
        .route("/app.css", get(page::style))
        .nest("/api", api)
        .with_state(state)
}

/// The guard in front of every API request: the policy's checks, then a
/// place among [`crate::state::MAX_REQUESTS`].
async fn admit(State(state): State<Shared>, req: Request, next: Next) -> Response {
    let path = req.uri().path();
    let access = if req.method() != Method::POST || path.ends_with("/stream") {
        guard::Access::Read
    } else if path.ends_with("/scope") {
        guard::Access::Capture
    } else {
        guard::Access::Change
    };
    if let Err(refusal) = guard::check(req.headers(), &state.policy, access) {
        return error(refusal.status(), refusal);
    }
    let Ok(_permit) = state.requests.clone().try_acquire_owned() else {
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            "hal-web is busy with other requests; try again",
        );
    };
    next.run(req).await
}

/// `GET /api/show`.
async fn show(State(state): State<Shared>) -> Response {
    let inst = state.inst.clone();
    match blocking(move || snapshot::show(&inst)).await {
        Ok(Ok(j)) => Json(j).into_response(),
        Ok(Err(e)) => error(StatusCode::INTERNAL_SERVER_ERROR, e),
        Err(r) => r,
    }
}

/// Serves `inst` on `listener` until `exit` is requested or the
/// instance's host is gone.
pub async fn serve(
    listener: tokio::net::TcpListener,
    inst: Instance,
    policy: guard::Policy,
    exit: ExitSignals,
) -> std::io::Result<()> {
    let (stopping, stopping_rx) = tokio::sync::watch::channel(false);
    let state = AppState::new(inst.clone(), policy, stopping_rx);
    let watcher = state.clone();
    let stop = async move {
        let mut host_asked = tokio::time::Instant::now();
        loop {
            tokio::time::sleep(STOP_POLL).await;
            if let Some(idle) = scope::idle_session(&watcher.kept_scope, scope::KEEP_IDLE) {
                // Removing the sampler asks the host: not on this thread.
                tokio::task::spawn_blocking(move || idle.close());
            }
            let ask_host = host_asked.elapsed() >= HOST_POLL;
            if ask_host {
                host_asked = tokio::time::Instant::now();
            }
            if exit.requested() || (ask_host && !inst.host_alive()) {
                // Live streams see this at their next tick and end, so
                // that the graceful shutdown does not wait on them.
                let _ = stopping.send(true);
                return;
            }
        }
    };
    let served = axum::serve(listener, router(state.clone()))
        .with_graceful_shutdown(stop)
        .await;
    // The scope's sampler goes with the server (a capture still running
    // has seen `stopping` and ended).
    let kept = state
        .kept_scope
        .lock()
        .map(|mut k| k.take())
        .unwrap_or_else(|p| p.into_inner().take());
    if let Some(k) = kept {
        let _ = tokio::task::spawn_blocking(move || k.close()).await;
    }
    served
}

/// Binds `addr` (port 0: a free one) and says where it listens.
pub async fn bind(addr: SocketAddr) -> Result<tokio::net::TcpListener, crate::WebError> {
    tokio::net::TcpListener::bind(addr)
        .await
        .map_err(|source| crate::WebError::Bind {
            addr: addr.to_string(),
            source,
        })
}
