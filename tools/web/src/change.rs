//! Changes to the HAL from the page: setp, sets, net and unlinkp, run by
//! halcmd's own command layer, so that the locks, types and writers are
//! checked as halcmd checks them and a refusal reads as halcmd's.

use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use hal_core::Instance;
use serde::Deserialize;
use serde_json::json;

use crate::state::{blocking, error, Shared};

/// The halcmd commands the page may run.
pub const COMMANDS: [&str; 4] = ["setp", "sets", "net", "unlinkp"];

/// Most words after the command (net with many pins).
const MAX_ARGS: usize = 64;

/// Longest word accepted.
const MAX_WORD: usize = 1024;

/// A change request: `{"command": "setp", "args": ["name", "1"]}`.
#[derive(Debug, Deserialize)]
pub struct Change {
    /// One of [`COMMANDS`].
    pub command: String,
    /// Its words, as halcmd takes them.
    pub args: Vec<String>,
}

/// What halcmd said about one command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// Whether it succeeded.
    pub ok: bool,
    /// Its standard output.
    pub output: String,
    /// Its messages (halcmd's refusal, word for word).
    pub messages: String,
}

/// Runs `words` as one halcmd command on `inst`.
pub fn run_halcmd(inst: &Instance, words: &[String]) -> Outcome {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let ok = {
        let mut session = hal_lang::Session::new(
            inst.clone(),
            hal_lang::Options::default(),
            &mut out,
            &mut err,
        );
        session.run_words(words)
    };
    Outcome {
        ok,
        output: String::from_utf8_lossy(&out).into_owned(),
        messages: String::from_utf8_lossy(&err).into_owned(),
    }
}

/// Checks a change request's shape; the words to run.
pub(crate) fn words(change: Change) -> Result<Vec<String>, String> {
    if !COMMANDS.contains(&change.command.as_str()) {
        return Err(format!(
            "'{}' is not a change the page may make (only {})",
            change.command,
            COMMANDS.join(", ")
        ));
    }
    if change.args.len() > MAX_ARGS {
        return Err(format!("more than {MAX_ARGS} words"));
    }
    if change.args.iter().any(|a| a.len() > MAX_WORD) {
        return Err(format!("a word longer than {MAX_WORD} bytes"));
    }
    let mut words = vec![change.command];
    words.extend(change.args);
    Ok(words)
}

/// `POST /api/hal`: runs the command; 200 when done, 422 with halcmd's
/// message when refused.
pub async fn post(State(state): State<Shared>, Json(change): Json<Change>) -> Response {
    let words = match words(change) {
        Ok(w) => w,
        Err(msg) => return error(StatusCode::BAD_REQUEST, msg),
    };
    let inst = state.inst.clone();
    let outcome = match blocking(move || run_halcmd(&inst, &words)).await {
        Ok(o) => o,
        Err(r) => return r,
    };
    let status = if outcome.ok {
        StatusCode::OK
    } else {
        StatusCode::UNPROCESSABLE_ENTITY
    };
    let body = json!({
        "ok": outcome.ok,
        "output": outcome.output,
        "error": outcome.messages.trim_end(),
    });
    (status, Json(body)).into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_four_changes_pass() {
        let c = |cmd: &str, args: &[&str]| Change {
            command: cmd.into(),
            args: args.iter().map(|s| s.to_string()).collect(),
        };
        assert_eq!(words(c("setp", &["a", "1"])).unwrap(), ["setp", "a", "1"]);
        assert!(words(c("loadusr", &["rm"]))
            .unwrap_err()
            .contains("'loadusr' is not a change"));
        assert!(words(c("net", &["x"; 65])).is_err());
        let long = "x".repeat(MAX_WORD + 1);
        assert!(words(c("sets", &[&long, "1"])).is_err());
    }
}
