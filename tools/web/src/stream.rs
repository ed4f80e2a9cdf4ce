//! The live stream: what one page watches, read 1 to 20 times a second
//! and sent as server-sent events, only the values that changed after the
//! first, and the page's meters ([`crate::meters`]) with their smallest
//! and largest values. Streams are bounded in number
//! ([`crate::state::MAX_STREAMS`]), items ([`MAX_ITEMS`]) and meters
//! ([`crate::meters::MAX_METERS`]); each tick's reads run off the
//! runtime's thread.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::State;
use axum::http::StatusCode;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::Json;
use futures_util::stream::{self, Stream};
use serde::Deserialize;
use serde_json::json;
use tokio::sync::OwnedSemaphorePermit;

use crate::meters::{Meters, Reading};
use crate::state::{error, Shared, MAX_STREAMS};
use crate::watch::{Item, Watched, MAX_ITEMS};

/// The rate unless the page asks for another.
const DEFAULT_HZ: u32 = 10;
/// The fastest rate served.
pub const MAX_HZ: u32 = 20;

/// A stream request: `{"items": [{"kind": "pin", "name": "..."}], "hz": 20,
/// "meters": [{"kind": "sig", "name": "..."}]}`.
#[derive(Debug, Deserialize)]
pub struct Watch {
    /// What to read.
    pub items: Vec<Item>,
    /// What to show as meters (value, min and max since the stream began).
    #[serde(default)]
    pub meters: Vec<Item>,
    /// Reads per second (1 to 20).
    pub hz: Option<u32>,
}

/// One stream's state between ticks.
struct Ticker {
    state: Shared,
    /// The watch list, between its reads (taken while a read runs).
    watched: Option<Watched>,
    /// The meters, between their reads (taken while a read runs).
    meters: Option<Meters>,
    last_meters: Vec<Reading>,
    /// The event's text, kept between ticks for its room.
    text: Vec<u8>,
    interval: tokio::time::Interval,
    first: bool,
    /// Held while the stream lives: its place among [`MAX_STREAMS`].
    _permit: OwnedSemaphorePermit,
}

/// `POST /api/stream`.
pub async fn post(State(state): State<Shared>, Json(watch): Json<Watch>) -> Response {
    if watch.items.len() > MAX_ITEMS {
        return error(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("a page may watch at most {MAX_ITEMS} items"),
        );
    }
    let meters = match Meters::new(&watch.meters) {
        Ok(m) => m,
        Err(msg) => return error(StatusCode::BAD_REQUEST, msg),
    };
    let Ok(permit) = state.streams.clone().try_acquire_owned() else {
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            format!("hal-web serves at most {MAX_STREAMS} live pages at once"),
        );
    };
    let hz = watch.hz.unwrap_or(DEFAULT_HZ).clamp(1, MAX_HZ);
    let mut interval = tokio::time::interval(Duration::from_millis(1000 / u64::from(hz)));
    interval.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let ticker = Ticker {
        state,
        watched: Some(Watched::new(watch.items)),
        meters: Some(meters),
        last_meters: Vec::new(),
        text: Vec::new(),
        interval,
        first: true,
        _permit: permit,
    };
    Sse::new(events(ticker))
        .keep_alive(KeepAlive::default())
        .into_response()
}

/// The events of one stream: `{"values": {"INDEX": "VALUE" or null},
/// "meters": {"INDEX": {"value", "min", "max"}}}`, every item and meter
/// at first, then those that changed; a tick with no change sends
/// nothing.
fn events(ticker: Ticker) -> impl Stream<Item = Result<Event, Infallible>> {
    stream::unfold(ticker, |mut t| async move {
        loop {
            t.interval.tick().await;
            if *t.state.stopping.borrow() {
                return None;
            }
            let inst = t.state.inst.clone();
            let mut watched = t.watched.take()?;
            let mut meters = t.meters.take()?;
            let mut text = std::mem::take(&mut t.text);
            let (watched, meters, readings, mut text, values) =
                tokio::task::spawn_blocking(move || {
                    text.clear();
                    text.extend_from_slice(b"{\"values\":{");
                    let values = watched.changes(&inst, &mut text);
                    text.push(b'}');
                    let readings = meters.read(&inst).to_vec();
                    (watched, meters, readings, text, values)
                })
                .await
                .ok()?;
            t.watched = Some(watched);
            t.meters = Some(meters);
            let changed_meters = changes(t.first, &t.last_meters, &readings);
            t.first = false;
            t.last_meters = readings;
            if values == 0 && changed_meters.is_empty() {
                t.text = text;
                continue;
            }
            if !changed_meters.is_empty() {
                text.extend_from_slice(b",\"meters\":");
                // Writing to a Vec cannot fail.
                let _ = serde_json::to_writer(&mut text, &changed_meters);
            }
            text.push(b'}');
            // Plain ASCII and serde_json's text: always UTF-8.
            let event = match std::str::from_utf8(&text) {
                Ok(s) => Event::default().data(s),
                Err(_) => return None,
            };
            t.text = text;
            return Some((Ok(event), t));
        }
    })
}

/// The entries of `now` that differ from `last` (all of them when
/// `first`), by index.
fn changes<T: PartialEq + serde::Serialize>(
    first: bool,
    last: &[T],
    now: &[T],
) -> serde_json::Map<String, serde_json::Value> {
    let mut changed = serde_json::Map::new();
    for (i, v) in now.iter().enumerate() {
        if first || last.get(i) != Some(v) {
            changed.insert(i.to_string(), json!(v));
        }
    }
    changed
}
