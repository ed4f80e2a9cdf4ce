//! The TCP side: bounded line reading, one thread per connection, a
//! bound on connections, and the end of the server on `shutdown`.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use super::parse::MAX_LINE;
use super::session::{After, Machine, Session, Settings};

/// What one read of [`LineReader::next_line`] found.
#[derive(Debug, PartialEq, Eq)]
pub enum Line {
    /// A request line, its end removed.
    Text(String),
    /// A line longer than [`MAX_LINE`] bytes (skipped up to its end).
    TooLong,
    /// A line that is not UTF-8.
    NotText,
    /// The peer closed the connection.
    End,
}

/// Splits a byte stream at any run of `\r` and `\n`, holding at most
/// [`MAX_LINE`] bytes of a line.
#[derive(Debug)]
pub struct LineReader<R> {
    inner: R,
    buf: Vec<u8>,
    start: usize,
    line: Vec<u8>,
    overflow: bool,
}

impl<R: Read> LineReader<R> {
    /// Reads lines from `inner`.
    pub fn new(inner: R) -> LineReader<R> {
        LineReader {
            inner,
            buf: Vec::new(),
            start: 0,
            line: Vec::new(),
            overflow: false,
        }
    }

    /// The next line; read errors count as the end.
    pub fn next_line(&mut self) -> Line {
        loop {
            while self.start < self.buf.len() {
                let b = self.buf[self.start];
                self.start += 1;
                if b == b'\r' || b == b'\n' {
                    if self.overflow {
                        self.overflow = false;
                        self.line.clear();
                        return Line::TooLong;
                    }
                    if self.line.is_empty() {
                        continue;
                    }
                    let bytes = std::mem::take(&mut self.line);
                    return String::from_utf8(bytes).map_or(Line::NotText, Line::Text);
                }
                if self.line.len() < MAX_LINE {
                    self.line.push(b);
                } else {
                    self.overflow = true;
                }
            }
            self.buf.resize(4096, 0);
            self.start = 0;
            match self.inner.read(&mut self.buf) {
                Ok(0) | Err(_) => {
                    self.buf.clear();
                    if self.overflow {
                        self.overflow = false;
                        self.line.clear();
                        return Line::TooLong;
                    }
                    if self.line.is_empty() {
                        return Line::End;
                    }
                    // The last line may come without its end.
                    let bytes = std::mem::take(&mut self.line);
                    return String::from_utf8(bytes).map_or(Line::NotText, Line::Text);
                }
                Ok(n) => self.buf.truncate(n),
            }
        }
    }
}

/// Serves one connection until it ends; whether it asked for shutdown.
pub fn serve_connection(stream: TcpStream, cfg: &Settings, machine: &mut dyn Machine) -> bool {
    let Ok(mut out) = stream.try_clone() else {
        return false;
    };
    let mut lines = LineReader::new(stream);
    let mut session = Session::new(cfg);
    let mut replies = Vec::new();
    loop {
        replies.clear();
        let after = match lines.next_line() {
            Line::End => return false,
            Line::TooLong => {
                replies.push(format!("error: line longer than {MAX_LINE} bytes"));
                After::Continue
            }
            Line::NotText => {
                replies.push("error: the line is not UTF-8 text".to_string());
                After::Continue
            }
            Line::Text(t) => session.handle(&t, machine, &mut replies),
        };
        for r in &replies {
            if out.write_all(format!("{r}\r\n").as_bytes()).is_err() {
                return false;
            }
        }
        match after {
            After::Continue => {}
            After::Close => return false,
            After::Shutdown => return true,
        }
    }
}

/// Accepts connections on `listener` (at most `max_sessions` at once;
/// negative: no bound), each served on its own thread with a machine
/// from `machine`; returns when a session asks for shutdown.
pub fn run<M, F>(listener: TcpListener, cfg: Settings, max_sessions: i64, machine: F)
where
    M: Machine,
    F: Fn() -> M + Send + Sync + 'static,
{
    let cfg = Arc::new(cfg);
    let machine = Arc::new(machine);
    let open = Arc::new(AtomicUsize::new(0));
    let (done_tx, done_rx) = std::sync::mpsc::channel::<()>();
    let limit = usize::try_from(max_sessions).ok();
    // The accept loop never ends by itself; a shutdown ends the server
    // (and the process with it, which leaves this thread behind).
    std::thread::spawn(move || {
        for conn in listener.incoming() {
            let Ok(mut stream) = conn else { continue };
            if limit.is_some_and(|l| open.load(Ordering::SeqCst) >= l) {
                let _ = stream.write_all(b"error: too many sessions\r\n");
                continue;
            }
            open.fetch_add(1, Ordering::SeqCst);
            let (cfg, machine, open, done) = (
                Arc::clone(&cfg),
                Arc::clone(&machine),
                Arc::clone(&open),
                done_tx.clone(),
            );
            std::thread::spawn(move || {
                let mut m = machine();
                let shutdown = serve_connection(stream, &cfg, &mut m);
                open.fetch_sub(1, Ordering::SeqCst);
                if shutdown {
                    let _ = done.send(());
                }
            });
        }
    });
    let _ = done_rx.recv();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_split_at_any_run_of_line_ends_and_are_bounded() {
        let mut long = vec![b'x'; MAX_LINE + 10];
        long.extend_from_slice(b"\nafter\r\n\r\nlast");
        let mut r = LineReader::new(&b"one\r\ntwo\n\n\rthree\r"[..]);
        assert_eq!(r.next_line(), Line::Text("one".into()));
        assert_eq!(r.next_line(), Line::Text("two".into()));
        assert_eq!(r.next_line(), Line::Text("three".into()));
        assert_eq!(r.next_line(), Line::End);
        let mut r = LineReader::new(&long[..]);
        assert_eq!(r.next_line(), Line::TooLong);
        assert_eq!(r.next_line(), Line::Text("after".into()));
        assert_eq!(r.next_line(), Line::Text("last".into()));
        assert_eq!(r.next_line(), Line::End);
        let mut r = LineReader::new(&b"\xff\xfe\n"[..]);
        assert_eq!(r.next_line(), Line::NotText);
    }
}
