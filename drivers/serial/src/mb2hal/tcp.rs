//! Modbus TCP: the MBAP header (transaction id, protocol 0, length,
//! unit) before each PDU, over a `TcpStream` with a connect timeout, a
//! reply timeout for a reply's first byte and a byte timeout within it.
//!
//! [`MbapClient`] does the framing on any [`Wire`] (the socket, or
//! scripted bytes in tests and the fuzz target); [`TcpLink`] owns the
//! connection: it connects on first use and drops the connection when
//! the stream can no longer be trusted (closed, cut reply, a header
//! that cannot be right), to connect again later. A late reply to an
//! earlier request that timed out is recognised by its transaction id
//! and skipped.

use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

use crate::error::{ExceptionCode, Result, SerialError};
use crate::modbus::{hex, ReplyLength, Transact};
use crate::regs::modbus::EXCEPTION_FLAG;

/// Bytes of the MBAP header: transaction id, protocol id, length, unit.
pub const HEADER_LEN: usize = 7;
/// The longest PDU (function code and data).
pub const MAX_PDU: usize = 253;
/// How many late replies one transaction skips before giving up.
const MAX_STALE: usize = 8;

/// The bytes a client reads and writes (a socket; scripted in tests).
pub trait Wire {
    /// Writes all of `bytes`.
    fn send(&mut self, bytes: &[u8]) -> io::Result<()>;
    /// Reads what is there within `timeout` (at most `buf.len()`); 0 bytes
    /// means the peer closed; a timeout is `TimedOut` or `WouldBlock`.
    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize>;
}

impl Wire for TcpStream {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.write_all(bytes)
    }

    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        self.set_read_timeout(Some(timeout.max(Duration::from_millis(1))))?;
        self.read(buf)
    }
}

/// A request ADU: header (length counts unit, function and data), unit,
/// function, data.
pub fn request(tid: u16, unit: u8, function: u8, data: &[u8]) -> Vec<u8> {
    let mut adu = Vec::with_capacity(HEADER_LEN + 1 + data.len());
    adu.extend_from_slice(&tid.to_be_bytes());
    adu.extend_from_slice(&[0, 0]);
    adu.extend_from_slice(&((data.len() + 2) as u16).to_be_bytes());
    adu.push(unit);
    adu.push(function);
    adu.extend_from_slice(data);
    adu
}

/// A reply's header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// The transaction id.
    pub tid: u16,
    /// How many bytes follow the unit: the PDU's length.
    pub pdu_len: usize,
    /// The unit identifier.
    pub unit: u8,
}

/// Checks a reply header: protocol 0, a length that holds at least a
/// function code and at most a whole PDU.
pub fn parse_header(address: &str, h: &[u8; HEADER_LEN]) -> Result<Header> {
    let bad = |what: String| SerialError::BadHeader {
        address: address.to_string(),
        what,
    };
    let protocol = u16::from_be_bytes([h[2], h[3]]);
    if protocol != 0 {
        return Err(bad(format!("protocol identifier {protocol} (Modbus is 0)")));
    }
    let length = usize::from(u16::from_be_bytes([h[4], h[5]]));
    if !(2..=MAX_PDU + 1).contains(&length) {
        return Err(bad(format!(
            "length {length} (a reply holds 2 to {} bytes after it)",
            MAX_PDU + 1
        )));
    }
    Ok(Header {
        tid: u16::from_be_bytes([h[0], h[1]]),
        pdu_len: length - 1,
        unit: h[6],
    })
}

/// Checks a reply PDU to `function` from `unit`: the function, or an
/// exception; returns the data after the function code.
pub fn check_pdu(unit: u8, function: u8, header: &Header, pdu: &[u8]) -> Result<Vec<u8>> {
    if header.unit != unit {
        return Err(SerialError::WrongSlave {
            expected: unit,
            found: header.unit,
        });
    }
    let Some((&f, data)) = pdu.split_first() else {
        return Err(SerialError::BadReply {
            slave: unit,
            function,
            what: "empty reply".into(),
        });
    };
    if f == function | EXCEPTION_FLAG {
        return match data {
            [code] => Err(SerialError::Exception {
                slave: unit,
                function,
                code: ExceptionCode(*code),
            }),
            _ => Err(SerialError::BadReply {
                slave: unit,
                function,
                what: format!("exception reply with {} code bytes", data.len()),
            }),
        };
    }
    if f != function {
        return Err(SerialError::WrongFunction {
            slave: unit,
            expected: function,
            found: f,
        });
    }
    Ok(data.to_vec())
}

/// The MBAP framing on a [`Wire`].
pub struct MbapClient<W: Wire> {
    wire: W,
    address: String,
    next_tid: u16,
    /// Wait for a reply's first byte.
    pub response_timeout: Duration,
    /// Wait between bytes of one reply.
    pub byte_timeout: Duration,
    /// Print every ADU in hex on stderr.
    pub debug: bool,
}

impl<W: Wire> MbapClient<W> {
    /// A client on `wire`, `address` naming the server in messages.
    pub fn new(wire: W, address: &str) -> MbapClient<W> {
        MbapClient {
            wire,
            address: address.to_string(),
            next_tid: 1,
            response_timeout: Duration::from_millis(500),
            byte_timeout: Duration::from_millis(500),
            debug: false,
        }
    }

    /// The wire (tests).
    pub fn wire(&self) -> &W {
        &self.wire
    }

    fn net(&self, op: &'static str, source: io::Error) -> SerialError {
        SerialError::Net {
            address: self.address.clone(),
            op,
            source,
        }
    }

    /// Fills `buf`: the first read waits up to `first`, later ones up to
    /// the byte timeout. Ok(false) when nothing came at all.
    fn fill(&mut self, buf: &mut [u8], first: Duration, unit: u8, function: u8) -> Result<bool> {
        let mut got = 0;
        while got < buf.len() {
            let wait = if got == 0 { first } else { self.byte_timeout };
            match self.wire.receive(&mut buf[got..], wait) {
                Ok(0) => {
                    let eof = io::Error::new(
                        io::ErrorKind::UnexpectedEof,
                        "the server closed the connection",
                    );
                    return Err(self.net("read", eof));
                }
                Ok(n) => got += n,
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                    ) =>
                {
                    if got == 0 {
                        return Ok(false);
                    }
                    return Err(SerialError::Truncated {
                        slave: unit,
                        function,
                        got,
                        expected: buf.len(),
                    });
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.net("read", e)),
            }
        }
        Ok(true)
    }

    /// One request and its reply's data.
    pub fn transact(&mut self, unit: u8, function: u8, data: &[u8]) -> Result<Vec<u8>> {
        if data.len() + 1 > MAX_PDU {
            return Err(SerialError::BadRequest(format!(
                "a request of {} bytes does not fit a PDU",
                data.len() + 1
            )));
        }
        let tid = self.next_tid;
        self.next_tid = self.next_tid.wrapping_add(1);
        let adu = request(tid, unit, function, data);
        if self.debug {
            eprintln!("{} > {}", self.address, hex(&adu));
        }
        if let Err(e) = self.wire.send(&adu) {
            return Err(self.net("write", e));
        }
        let deadline = Instant::now() + self.response_timeout;
        for _ in 0..=MAX_STALE {
            let left = deadline.saturating_duration_since(Instant::now());
            let mut h = [0u8; HEADER_LEN];
            if !self.fill(&mut h, left, unit, function)? {
                return Err(SerialError::Timeout {
                    slave: unit,
                    function,
                    waited_ms: self.response_timeout.as_millis() as u64,
                });
            }
            let header = parse_header(&self.address, &h)?;
            let mut pdu = vec![0u8; header.pdu_len];
            if !self.fill(&mut pdu, self.byte_timeout, unit, function)? {
                return Err(SerialError::Truncated {
                    slave: unit,
                    function,
                    got: HEADER_LEN,
                    expected: HEADER_LEN + header.pdu_len,
                });
            }
            if self.debug {
                eprintln!("{} < {}{}", self.address, hex(&h), hex(&pdu));
            }
            if header.tid == tid {
                return check_pdu(unit, function, &header, &pdu);
            }
            // A late reply to an earlier request: skip it.
        }
        Err(SerialError::BadReply {
            slave: unit,
            function,
            what: format!("no reply with transaction id {tid} among {MAX_STALE} others"),
        })
    }
}

/// A Modbus TCP connection to one server, made on first use and again
/// after a failure.
pub struct TcpLink {
    host: String,
    port: u16,
    address: String,
    client: Option<MbapClient<TcpStream>>,
    next_tid: u16,
    response_timeout: Duration,
    byte_timeout: Duration,
    debug: bool,
}

impl TcpLink {
    /// A link to `host:port`, not connected yet.
    pub fn new(host: &str, port: u16) -> TcpLink {
        TcpLink {
            host: host.to_string(),
            port,
            address: format!("{host}:{port}"),
            client: None,
            next_tid: 1,
            response_timeout: Duration::from_millis(500),
            byte_timeout: Duration::from_millis(500),
            debug: false,
        }
    }

    /// `host:port`.
    pub fn address(&self) -> &str {
        &self.address
    }

    /// The timeouts of the next transactions (each transaction has its
    /// own), and whether to print every ADU.
    pub fn set_timeouts(&mut self, response: Duration, byte: Duration, debug: bool) {
        self.response_timeout = response;
        self.byte_timeout = byte;
        self.debug = debug;
        if let Some(c) = &mut self.client {
            c.response_timeout = response;
            c.byte_timeout = byte;
            c.debug = debug;
        }
    }

    /// Whether a connection is open.
    pub fn is_connected(&self) -> bool {
        self.client.is_some()
    }

    /// Drops the connection.
    pub fn close(&mut self) {
        if let Some(c) = self.client.take() {
            self.next_tid = c.next_tid;
        }
    }

    /// Connects, waiting at most the response timeout (at least a
    /// second) for each address the host name resolves to.
    pub fn connect(&mut self) -> Result<()> {
        let fail = |source: io::Error| SerialError::Connect {
            address: self.address.clone(),
            source,
        };
        let addrs = (self.host.as_str(), self.port)
            .to_socket_addrs()
            .map_err(fail)?;
        let wait = self.response_timeout.max(Duration::from_secs(1));
        let mut last = io::Error::new(io::ErrorKind::NotFound, "the name has no address");
        for a in addrs {
            match TcpStream::connect_timeout(&a, wait) {
                Ok(s) => {
                    let _ = s.set_nodelay(true);
                    let mut c = MbapClient::new(s, &self.address);
                    c.next_tid = self.next_tid;
                    c.response_timeout = self.response_timeout;
                    c.byte_timeout = self.byte_timeout;
                    c.debug = self.debug;
                    self.client = Some(c);
                    return Ok(());
                }
                Err(e) => last = e,
            }
        }
        Err(fail(last))
    }
}

impl Transact for TcpLink {
    fn transact(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        _reply: ReplyLength,
    ) -> Result<Vec<u8>> {
        if self.client.is_none() {
            self.connect()?;
        }
        let Some(c) = self.client.as_mut() else {
            return Err(SerialError::Connect {
                address: self.address.clone(),
                source: io::Error::new(io::ErrorKind::NotConnected, "not connected"),
            });
        };
        let r = c.transact(slave, function, data);
        if let Err(e) = &r {
            if e.is_line_failure() || matches!(e, SerialError::Truncated { .. }) {
                self.close();
            }
        }
        r
    }

    fn is_broadcast(&self, _slave: u8) -> bool {
        false
    }
}

/// A wire that plays back fixed chunks and records what was sent (tests
/// and the fuzz target): each read returns at most one chunk's rest;
/// with nothing left it times out.
#[cfg(any(test, feature = "testing"))]
pub struct ScriptWire {
    chunks: std::collections::VecDeque<Vec<u8>>,
    /// Everything sent.
    pub sent: Vec<u8>,
}

#[cfg(any(test, feature = "testing"))]
impl ScriptWire {
    /// A wire answering `chunks`, in order.
    pub fn new(chunks: impl IntoIterator<Item = Vec<u8>>) -> ScriptWire {
        ScriptWire {
            chunks: chunks.into_iter().collect(),
            sent: Vec::new(),
        }
    }
}

#[cfg(any(test, feature = "testing"))]
impl Wire for ScriptWire {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.sent.extend_from_slice(bytes);
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], _timeout: Duration) -> io::Result<usize> {
        let Some(chunk) = self.chunks.front_mut() else {
            return Err(io::ErrorKind::TimedOut.into());
        };
        let n = chunk.len().min(buf.len());
        buf[..n].copy_from_slice(&chunk[..n]);
        chunk.drain(..n);
        if chunk.is_empty() {
            self.chunks.pop_front();
        }
        Ok(n)
    }
}

#[cfg(any(test, feature = "testing"))]
impl Transact for MbapClient<ScriptWire> {
    fn transact(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        _reply: ReplyLength,
    ) -> Result<Vec<u8>> {
        MbapClient::transact(self, slave, function, data)
    }

    fn is_broadcast(&self, _slave: u8) -> bool {
        false
    }
}

#[cfg(test)]
#[path = "tcp_tests.rs"]
mod tests;
