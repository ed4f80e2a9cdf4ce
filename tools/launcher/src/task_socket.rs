//! The socket `task-cmd` talks to: one request per connection, a line of
//! words separated by the unit separator (0x1F); the answer is one line,
//! `ok` or `err`, 0x1F, and a text whose newlines travel as 0x1E. The
//! launcher polls it from its task loop; nothing here blocks.

use std::io::{ErrorKind, Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::PathBuf;

use hal_lang::protocol::decode_request;

use crate::error::LaunchError;

const UNIT: char = '\u{1f}';
const LINE: char = '\u{1e}';

/// Where the launcher of `instance` listens.
pub fn socket_path(instance: &str) -> std::io::Result<PathBuf> {
    hal_core::paths::runtime_file(instance, "-task.sock").map_err(std::io::Error::other)
}

/// A connection waiting for its answer.
pub type ConnId = u64;

struct Conn {
    id: ConnId,
    stream: UnixStream,
    buf: Vec<u8>,
    asked: bool,
}

/// The listening socket and its open connections.
pub struct TaskServer {
    listener: UnixListener,
    path: PathBuf,
    conns: Vec<Conn>,
    next_id: ConnId,
}

impl TaskServer {
    /// Listens for `instance` (a stale socket file is replaced: the HAL
    /// host's lock, held by our host, says no other launcher runs).
    pub fn bind(instance: &str) -> std::io::Result<TaskServer> {
        let path = socket_path(instance)?;
        let listener = hal_core::paths::bind_socket(&path).map_err(std::io::Error::other)?;
        listener.set_nonblocking(true)?;
        Ok(TaskServer {
            listener,
            path,
            conns: Vec::new(),
            next_id: 1,
        })
    }

    /// Accepts connections and returns the requests that arrived.
    pub fn poll(&mut self) -> Vec<(ConnId, Vec<String>)> {
        while let Ok((stream, _)) = self.listener.accept() {
            if stream.set_nonblocking(true).is_ok() {
                self.conns.push(Conn {
                    id: self.next_id,
                    stream,
                    buf: Vec::new(),
                    asked: false,
                });
                self.next_id += 1;
            }
        }
        let mut out = Vec::new();
        let mut gone = Vec::new();
        for c in self.conns.iter_mut().filter(|c| !c.asked) {
            let mut chunk = [0u8; 4096];
            loop {
                match c.stream.read(&mut chunk) {
                    Ok(0) => {
                        gone.push(c.id);
                        break;
                    }
                    Ok(n) => c.buf.extend_from_slice(&chunk[..n]),
                    Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                    Err(_) => {
                        gone.push(c.id);
                        break;
                    }
                }
                if c.buf.len() > 64 * 1024 {
                    gone.push(c.id);
                    break;
                }
            }
            if let Some(end) = c.buf.iter().position(|&b| b == b'\n') {
                let line = String::from_utf8_lossy(&c.buf[..end]).into_owned();
                c.asked = true;
                out.push((c.id, decode_request(&line)));
            }
        }
        self.conns.retain(|c| !gone.contains(&c.id));
        out
    }

    /// Answers a request and closes its connection.
    pub fn reply(&mut self, id: ConnId, result: Result<String, LaunchError>) {
        let Some(i) = self.conns.iter().position(|c| c.id == id) else {
            return;
        };
        let mut c = self.conns.swap_remove(i);
        let (tag, text) = match result {
            Ok(t) => ("ok", t),
            Err(e) => ("err", e.to_string()),
        };
        let text = text.trim_end().replace('\n', &LINE.to_string());
        let _ = c.stream.set_nonblocking(false);
        let _ = c
            .stream
            .set_write_timeout(Some(std::time::Duration::from_secs(1)));
        let _ = c
            .stream
            .write_all(format!("{tag}{UNIT}{text}\n").as_bytes());
    }
}

impl Drop for TaskServer {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Why `task-cmd` could not get an answer.
#[derive(Debug, thiserror::Error)]
pub enum TaskClientError {
    /// No launcher listens for the instance.
    #[error(
        "no machine is running for instance '{instance}' (start it with: linuxcnc MACHINE.ini)"
    )]
    NotRunning {
        /// The HAL instance name.
        instance: String,
    },
    /// The connection failed or the answer did not come in time.
    #[error("talking to the launcher: {0}")]
    Io(#[from] std::io::Error),
    /// The answer is not in the protocol.
    #[error("malformed answer from the launcher: {0:?}")]
    Malformed(String),
}

/// The launcher's answer to a request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TaskAnswer {
    /// Done; what it says about it.
    Done(String),
    /// Refused; why, in the launcher's words.
    Refused(String),
}

/// Sends one request and returns the launcher's answer.
pub fn request(
    instance: &str,
    words: &[String],
    timeout: std::time::Duration,
) -> Result<TaskAnswer, TaskClientError> {
    let path = socket_path(instance)?;
    let mut s = UnixStream::connect(&path).map_err(|e| match e.kind() {
        ErrorKind::NotFound | ErrorKind::ConnectionRefused => TaskClientError::NotRunning {
            instance: instance.to_string(),
        },
        _ => TaskClientError::Io(e),
    })?;
    let line = hal_lang::protocol::encode_request(words)
        .map_err(|e| TaskClientError::Malformed(e.to_string()))?;
    s.write_all(format!("{line}\n").as_bytes())?;
    s.set_read_timeout(Some(timeout))?;
    let mut answer = String::new();
    s.read_to_string(&mut answer)?;
    let answer = answer.trim_end_matches('\n');
    let (tag, text) = answer
        .split_once(UNIT)
        .ok_or_else(|| TaskClientError::Malformed(answer.to_string()))?;
    let text = text.replace(LINE, "\n");
    match tag {
        "ok" => Ok(TaskAnswer::Done(text)),
        "err" => Ok(TaskAnswer::Refused(text)),
        _ => Err(TaskClientError::Malformed(answer.to_string())),
    }
}
