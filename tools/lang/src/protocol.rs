//! The host's control protocol over its Unix socket.
//!
//! A request is one line: words separated by the unit separator (0x1F). A
//! reply is one line: `ok`, or `err`, 0x1F, and a message. Words and
//! messages never contain newlines or 0x1F (requests with them are refused
//! before sending; messages have them replaced by spaces).

use std::io::{BufRead, BufReader, Write};
use std::os::unix::net::UnixStream;
use std::path::PathBuf;
use std::time::Duration;

use hal_core::paths;

const SEP: char = '\u{1f}';

/// Errors talking to the host.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// No host answers on the instance's socket.
    #[error("realtime not running for instance '{instance}'")]
    NotRunning {
        /// The instance name.
        instance: String,
    },
    /// The connection failed or broke mid-request.
    #[error("talking to the HAL host at {path}: {source}")]
    Io {
        /// The host's socket.
        path: PathBuf,
        /// The error from the socket.
        #[source]
        source: std::io::Error,
    },
    /// A word would break the line protocol; refused before sending.
    #[error("argument contains a newline or control separator: {arg:?}")]
    BadArgument {
        /// The offending word.
        arg: String,
    },
    /// The runtime directory or the socket's permissions refused us.
    #[error(transparent)]
    Hal(hal_core::HalError),
    /// The host answered `err` with this message.
    #[error("{0}")]
    Refused(String),
    /// The host did not exit in time after `shutdown`.
    #[error("the host of instance '{instance}' did not exit within {limit_s} s")]
    StillRunning {
        /// The instance.
        instance: String,
        /// How long it was given, in seconds.
        limit_s: f64,
        /// The host's process id, as the socket's peer credentials gave
        /// it when we connected (None if the kernel did not say).
        pid: Option<i32>,
    },
    /// The host's answer is not a reply of this protocol.
    #[error("malformed reply from the HAL host: {line:?}")]
    Malformed {
        /// The line received.
        line: String,
    },
}

/// Encodes a request line (without the newline).
pub fn encode_request(words: &[String]) -> Result<String, ClientError> {
    if let Some(bad) = words.iter().find(|w| w.contains(['\n', SEP])) {
        return Err(ClientError::BadArgument { arg: bad.clone() });
    }
    Ok(words.join(&SEP.to_string()))
}

/// Decodes a request line into words.
pub fn decode_request(line: &str) -> Vec<String> {
    line.split(SEP).map(str::to_string).collect()
}

/// Encodes a reply line (without the newline): `ok`, or the error's
/// message.
pub fn encode_reply<E: std::fmt::Display>(result: &Result<(), E>) -> String {
    match result {
        Ok(()) => "ok".to_string(),
        Err(m) => format!("err{SEP}{}", m.to_string().replace(['\n', SEP], " ")),
    }
}

/// Decodes a reply line: the host's refusal is [`ClientError::Refused`]
/// with its message, a line that is no reply [`ClientError::Malformed`].
pub fn decode_reply(line: &str) -> Result<(), ClientError> {
    let line = line.trim_end_matches('\n');
    if line == "ok" {
        Ok(())
    } else if let Some(m) = line.strip_prefix(&format!("err{SEP}")) {
        Err(ClientError::Refused(m.to_string()))
    } else {
        Err(ClientError::Malformed {
            line: line.to_string(),
        })
    }
}

/// Where a halcmd session sends the requests only the host can carry out
/// (`loadrt`, `addf`, `start`, ...): the host's socket ([`Client`]), or
/// a host in the same process (`hal_host::InProcess`).
pub trait HostLink {
    /// Sends one request and waits for its reply.
    fn call(&mut self, words: &[String]) -> Result<(), ClientError>;
}

impl HostLink for Client {
    fn call(&mut self, words: &[String]) -> Result<(), ClientError> {
        Client::call(self, words)
    }
}

/// A connection to an instance's host.
pub struct Client {
    reader: BufReader<UnixStream>,
    writer: UnixStream,
    path: PathBuf,
}

impl Client {
    /// Connects to the host of `instance`.
    pub fn connect(instance: &str) -> Result<Client, ClientError> {
        // An instance out of reach says why: its segment names the group.
        let not_running = || match paths::segment_access(instance) {
            Err(e) => ClientError::Hal(e),
            Ok(()) => ClientError::NotRunning {
                instance: instance.to_string(),
            },
        };
        let path = match paths::socket(instance) {
            Ok(p) => p,
            Err(hal_core::HalError::NoRuntimeDir { .. }) => return Err(not_running()),
            Err(e) => return Err(ClientError::Hal(e)),
        };
        let stream = UnixStream::connect(&path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound | std::io::ErrorKind::ConnectionRefused => not_running(),
            std::io::ErrorKind::PermissionDenied => {
                ClientError::Hal(paths::denied("connecting to", &path))
            }
            _ => ClientError::Io {
                path: path.clone(),
                source: e,
            },
        })?;
        let io = |source| ClientError::Io {
            path: path.clone(),
            source,
        };
        let writer = stream.try_clone().map_err(io)?;
        Ok(Client {
            reader: BufReader::new(stream),
            writer,
            path,
        })
    }

    /// The process at the other end of the socket (the host), from the
    /// kernel's peer credentials.
    pub fn peer_pid(&self) -> Option<i32> {
        use nix::sys::socket::{getsockopt, sockopt::PeerCredentials};
        getsockopt(&self.writer, PeerCredentials)
            .ok()
            .map(|c| c.pid())
            .filter(|&p| p > 0)
    }

    /// Sends one request and waits up to `limit` for its reply: a host
    /// that stopped answering is an error, never a wait without end.
    pub fn call_within(&mut self, words: &[String], limit: Duration) -> Result<(), ClientError> {
        let _ = self.reader.get_ref().set_read_timeout(Some(limit));
        let r = self.call(words);
        let _ = self.reader.get_ref().set_read_timeout(None);
        r
    }

    /// Sends one request and waits for its reply.
    pub fn call(&mut self, words: &[String]) -> Result<(), ClientError> {
        let line = encode_request(words)?;
        let io = |source| ClientError::Io {
            path: self.path.clone(),
            source,
        };
        self.writer
            .write_all(format!("{line}\n").as_bytes())
            .map_err(io)?;
        let mut reply = String::new();
        let n = self
            .reader
            .read_line(&mut reply)
            .map_err(|source| ClientError::Io {
                path: self.path.clone(),
                source,
            })?;
        if n == 0 {
            return Err(ClientError::Io {
                path: self.path.clone(),
                source: std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    "the host closed the connection",
                ),
            });
        }
        decode_reply(&reply)
    }

    /// Waits up to `limit` for the host to close this connection (after a
    /// `shutdown` it does so once it has released everything). Returns
    /// false if the limit passed first.
    pub fn wait_closed(&mut self, limit: Duration) -> bool {
        let end = std::time::Instant::now() + limit;
        let mut scratch = Vec::new();
        loop {
            let left = end.saturating_duration_since(std::time::Instant::now());
            if left.is_zero() {
                return false;
            }
            let _ = self.reader.get_ref().set_read_timeout(Some(left));
            scratch.clear();
            match self.reader.read_until(b'\n', &mut scratch) {
                Ok(0) => return true,
                Ok(_) => {}
                Err(e)
                    if e.kind() == std::io::ErrorKind::WouldBlock
                        || e.kind() == std::io::ErrorKind::TimedOut
                        || e.kind() == std::io::ErrorKind::Interrupted => {}
                // A reset connection is a closed one.
                Err(_) => return true,
            }
        }
    }

    /// Waits up to `timeout` for the host of `instance` to accept requests.
    pub fn wait_for(instance: &str, timeout: Duration) -> Result<Client, ClientError> {
        let end = std::time::Instant::now() + timeout;
        loop {
            match Client::connect(instance) {
                Ok(mut c) => {
                    if c.call(&["ping".to_string()]).is_ok() {
                        return Ok(c);
                    }
                }
                Err(ClientError::NotRunning { .. }) => {}
                Err(e) => return Err(e),
            }
            if std::time::Instant::now() >= end {
                return Err(ClientError::NotRunning {
                    instance: instance.to_string(),
                });
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_and_replies_round_trip() {
        let words = vec!["loadrt".to_string(), "threads".into(), "name1=a b".into()];
        assert_eq!(decode_request(&encode_request(&words).unwrap()), words);
        assert!(encode_request(&["a\nb".to_string()]).is_err());
        assert!(decode_reply(&encode_reply::<String>(&Ok(()))).is_ok());
        assert!(matches!(
            decode_reply(&encode_reply(&Err("bad\nthing"))),
            Err(ClientError::Refused(m)) if m == "bad thing"
        ));
        assert!(decode_reply("garbage").is_err());
    }
}
