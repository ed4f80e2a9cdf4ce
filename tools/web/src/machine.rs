//! The machine: task's state and the panel's buttons, through task's
//! socket exactly as task-cmd sends them ([`hal_launcher::request`]), and
//! positions, homed flags and the program line from motion's pins.

use std::time::Duration;

use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use hal_core::Instance;
use hal_lang::format::get_value;
use hal_launcher::{request, TaskAnswer};
use serde::Deserialize;
use serde_json::{json, Map, Value as JsonValue};

use crate::state::{blocking, error, Shared};

/// How long a status read waits for task.
const STATUS_TIMEOUT: Duration = Duration::from_secs(2);

/// How long a button waits for task's answer (machine-on waits for the
/// e-stop chain and motion).
const ACTION_TIMEOUT: Duration = Duration::from_secs(20);

/// The panel's buttons and the task requests they send.
pub const ACTIONS: [(&str, &[&str]); 11] = [
    ("estop", &["estop"]),
    ("estop-reset", &["estop-reset"]),
    ("machine-on", &["machine-on"]),
    ("machine-off", &["machine-off"]),
    ("mode-manual", &["mode", "manual"]),
    ("mode-auto", &["mode", "auto"]),
    ("home", &["home", "all"]),
    ("run", &["run"]),
    ("pause", &["pause"]),
    ("resume", &["resume"]),
    ("abort", &["abort"]),
];

/// A button press: `{"action": "machine-on"}`.
#[derive(Debug, Deserialize)]
pub struct Action {
    /// One of [`ACTIONS`].
    pub action: String,
}

/// task's `state` answer (`key=value` lines) as a JSON object.
pub fn parse_state(text: &str) -> Map<String, JsonValue> {
    text.lines()
        .filter_map(|l| l.split_once('='))
        .map(|(k, v)| {
            (
                k.trim().to_string(),
                JsonValue::String(v.trim().to_string()),
            )
        })
        .collect()
}

/// Joint and axis positions, homed flags and the program line, from
/// motion's pins (absent on an instance without motion).
fn motion_pins(inst: &Instance) -> JsonValue {
    let mut joints = Map::new();
    let mut axes = Map::new();
    let mut line = None;
    for p in inst.pins().unwrap_or_default() {
        let value = get_value(p.value);
        if let Some(rest) = p.name.strip_prefix("joint.") {
            if let Some((n, item @ ("pos-fb" | "homed"))) = rest.split_once('.') {
                let j = joints.entry(n.to_string()).or_insert_with(|| json!({}));
                j[item] = JsonValue::String(value);
            }
        } else if let Some(l) = p.name.strip_prefix("axis.") {
            if let Some(l) = l.strip_suffix(".pos-cmd") {
                axes.insert(l.to_string(), JsonValue::String(value));
            }
        } else if p.name == "motion.program-line" {
            line = Some(value);
        }
    }
    json!({ "joints": joints, "axes": axes, "program-line": line })
}

/// Everything the machine panel shows.
pub fn status(inst: &Instance) -> JsonValue {
    let state = request(inst.name(), &["state".to_string()], STATUS_TIMEOUT);
    let motion = motion_pins(inst);
    match state {
        Ok(TaskAnswer::Done(text)) => {
            let summary = match request(inst.name(), &["status".to_string()], STATUS_TIMEOUT) {
                Ok(TaskAnswer::Done(s) | TaskAnswer::Refused(s)) => s,
                Err(e) => e.to_string(),
            };
            json!({
                "running": true,
                "state": parse_state(&text),
                "status": summary,
                "motion": motion,
            })
        }
        Ok(TaskAnswer::Refused(text)) => {
            json!({ "running": true, "error": text, "motion": motion })
        }
        Err(e) => json!({ "running": false, "error": e.to_string(), "motion": motion }),
    }
}

/// `GET /api/machine`.
pub async fn get(State(state): State<Shared>) -> Response {
    let inst = state.inst.clone();
    match blocking(move || status(&inst)).await {
        Ok(j) => Json(j).into_response(),
        Err(r) => r,
    }
}

/// `POST /api/machine`: sends the button's request to task; 200 when
/// done, 422 with task's words when refused, 502 when no machine answers.
pub async fn post(State(state): State<Shared>, Json(action): Json<Action>) -> Response {
    let Some((_, words)) = ACTIONS.iter().find(|(name, _)| *name == action.action) else {
        let names: Vec<&str> = ACTIONS.iter().map(|(n, _)| *n).collect();
        return error(
            StatusCode::BAD_REQUEST,
            format!(
                "'{}' is not a machine action (only {})",
                action.action,
                names.join(", ")
            ),
        );
    };
    let words: Vec<String> = words.iter().map(|w| w.to_string()).collect();
    let instance = state.inst.name().to_string();
    let answer = match blocking(move || request(&instance, &words, ACTION_TIMEOUT)).await {
        Ok(a) => a,
        Err(r) => return r,
    };
    match answer {
        Ok(TaskAnswer::Done(text)) => Json(json!({ "ok": true, "answer": text })).into_response(),
        Ok(TaskAnswer::Refused(text)) => (
            StatusCode::UNPROCESSABLE_ENTITY,
            Json(json!({ "ok": false, "error": text })),
        )
            .into_response(),
        Err(e) => error(StatusCode::BAD_GATEWAY, e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn state_lines_become_an_object() {
        let m = parse_state("machine=ON\nmode=MANUAL\nnoise\nprogram=IDLE\n");
        assert_eq!(m["machine"], "ON");
        assert_eq!(m["mode"], "MANUAL");
        assert_eq!(m.len(), 3);
    }
}
