//! Thread timing and the wake-up latency histogram, live: each thread's
//! own counters read from the segment as latency-test reads them
//! ([`hal_scope::latency::stats`]), with its percentiles and LinuxCNC's
//! verdict on the largest latency.

use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use hal_core::{latency_bucket_floor_us, Instance, ThreadInfo};
use hal_scope::latency::report::period_text;
use hal_scope::latency::stats::{verdict, ThreadStats};
use serde_json::{json, Value as JsonValue};

use crate::state::{blocking, error, Shared};

/// One thread: timing, latency figures and histogram counts.
fn thread(info: &ThreadInfo) -> JsonValue {
    let s = ThreadStats::from_info(info);
    json!({
        "name": s.name,
        "period": s.period_ns,
        "period_text": period_text(s.period_ns),
        "running": info.running,
        "time": info.time_ns,
        "tmax": info.tmax_ns,
        "cycles": s.cycles,
        "overruns": s.overruns,
        "latency": {
            "min": s.min_ns,
            "p50": s.percentile_ns(0.5),
            "p99": s.percentile_ns(0.99),
            "p999": s.percentile_ns(0.999),
            "max": s.max_ns,
        },
        "histogram": s.histogram,
    })
}

/// Every thread's figures, the lower edge (µs) of each histogram bucket,
/// and the verdict.
pub fn threads(inst: &Instance) -> hal_core::Result<JsonValue> {
    let infos = inst.threads()?;
    let stats: Vec<ThreadStats> = infos.iter().map(ThreadStats::from_info).collect();
    let buckets = stats.iter().map(|t| t.histogram.len()).max().unwrap_or(0);
    let floors: Vec<u64> = (0..buckets).map(latency_bucket_floor_us).collect();
    let verdict = verdict(&stats)
        .map(|(v, max)| json!({ "max": max, "short": v.short(), "sentence": v.sentence() }));
    Ok(json!({
        "threads": infos.iter().map(thread).collect::<Vec<_>>(),
        "bucket_floor_us": floors,
        "verdict": verdict,
    }))
}

/// `GET /api/threads`.
pub async fn get(State(state): State<Shared>) -> Response {
    let inst = state.inst.clone();
    match blocking(move || threads(&inst)).await {
        Ok(Ok(j)) => Json(j).into_response(),
        Ok(Err(e)) => error(StatusCode::INTERNAL_SERVER_ERROR, e),
        Err(r) => r,
    }
}
