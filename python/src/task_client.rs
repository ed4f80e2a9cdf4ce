//! The native half of the Python `linuxcnc` module: one request to the
//! launcher's task socket, and an INI file read as the launcher reads it.
//! The pure-Python package `linuxcnc` (in `python/linuxcnc/`) builds
//! LinuxCNC's `stat`, `command`, `error_channel` and `ini` on these.

use std::io::{ErrorKind, Read, Write};
use std::os::unix::net::UnixStream;
use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;

/// Separates the request's words, and the answer's tag from its text.
const UNIT: char = '\u{1f}';
/// Stands for a newline inside the answer's text.
const LINE: char = '\u{1e}';
/// The longest answer read (a stat snapshot is a few kB).
const MAX_ANSWER: u64 = 4 << 20;

/// Sends `words` to task on the instance `HAL_INSTANCE` names and waits
/// at most `timeout` seconds for the answer: `(True, text)` when done,
/// `(False, why)` when refused. OSError when no machine runs or the
/// answer does not come.
#[pyfunction]
#[pyo3(name = "_task_request", signature = (words, timeout = 10.0))]
pub fn task_request(py: Python<'_>, words: Vec<String>, timeout: f64) -> PyResult<(bool, String)> {
    if !(timeout.is_finite() && timeout > 0.0) {
        return Err(PyValueError::new_err(format!(
            "timeout must be a positive number of seconds, not {timeout}"
        )));
    }
    let instance = hal_core::instance_from_env();
    let line = hal_lang::protocol::encode_request(&words)
        .map_err(|e| PyValueError::new_err(format!("task request {words:?}: {e}")))?;
    py.detach(|| exchange(&instance, &line, Duration::from_secs_f64(timeout)))
        .map_err(|e| PyOSError::new_err(chain(&e)))
}

/// Why a request to task got no answer.
#[derive(Debug, thiserror::Error)]
pub enum TaskClientError {
    /// The instance's runtime directory gave no socket path.
    #[error("the task socket of HAL instance '{instance}'")]
    SocketPath {
        instance: String,
        #[source]
        source: hal_core::HalError,
    },
    /// Nothing listens at the socket: no machine runs on the instance.
    #[error("no machine runs on HAL instance '{instance}' (no task at {}): start it with linuxcnc MACHINE.ini", path.display())]
    NoMachine { instance: String, path: PathBuf },
    /// Connecting, writing or reading failed.
    #[error("{step} task at {}", path.display())]
    Io {
        step: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The answer was not `ok` or `err`, a unit separator and a text.
    #[error("malformed answer from task: {answer:?}")]
    Malformed { answer: String },
}

/// The error and its causes in one line, for a Python exception.
fn chain(e: &TaskClientError) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        text.push_str(": ");
        text.push_str(&c.to_string());
        cause = c.source();
    }
    text
}

fn exchange(
    instance: &str,
    line: &str,
    timeout: Duration,
) -> Result<(bool, String), TaskClientError> {
    let path: PathBuf =
        hal_core::paths::runtime_file(instance, "-task.sock").map_err(|source| {
            TaskClientError::SocketPath {
                instance: instance.to_string(),
                source,
            }
        })?;
    let io = |step: &'static str| {
        let path = path.clone();
        move |source| TaskClientError::Io { step, path, source }
    };
    let mut s = UnixStream::connect(&path).map_err(|e| match e.kind() {
        ErrorKind::NotFound | ErrorKind::ConnectionRefused => TaskClientError::NoMachine {
            instance: instance.to_string(),
            path: path.clone(),
        },
        _ => io("connecting to")(e),
    })?;
    s.set_write_timeout(Some(timeout))
        .map_err(io("talking to"))?;
    s.set_read_timeout(Some(timeout))
        .map_err(io("talking to"))?;
    s.write_all(format!("{line}\n").as_bytes())
        .map_err(io("writing to"))?;
    let mut answer = Vec::new();
    s.take(MAX_ANSWER)
        .read_to_end(&mut answer)
        .map_err(io("reading from"))?;
    let answer = String::from_utf8_lossy(&answer);
    let answer = answer.trim_end_matches('\n');
    let malformed = || TaskClientError::Malformed {
        answer: answer.to_string(),
    };
    let (tag, text) = answer.split_once(UNIT).ok_or_else(malformed)?;
    let text = text.replace(LINE, "\n");
    match tag {
        "ok" => Ok((true, text)),
        "err" => Ok((false, text)),
        _ => Err(malformed()),
    }
}

/// The entries of the INI file at `path`, `(section, key, value)` in file
/// order, read as the launcher reads it (`#INCLUDE`, continuation lines).
/// OSError naming the file and the problem when it cannot be read.
#[pyfunction]
#[pyo3(name = "_ini_entries")]
pub fn ini_entries(path: PathBuf) -> PyResult<Vec<(String, String, String)>> {
    let ini = hal_lang::ini::Ini::load(&path).map_err(|e| PyOSError::new_err(e.to_string()))?;
    Ok(ini
        .entries()
        .iter()
        .map(|e| (e.section.clone(), e.key.clone(), e.value.clone()))
        .collect())
}
