//! One link (a TCP server, or a serial device) and the transactions on
//! it, run in turn by a thread of their own. A transaction waits for
//! its `MAX_UPDATE_RATE`; `SLOWDOWN` and `SERIAL_DELAY_MS` pause after
//! each. A link that fails (refused connection, closed socket, gone
//! device) is closed and tried again after a pause that doubles up to
//! [`BACKOFF_MAX`]; a failed transaction counts in its `num_errors` and
//! is said once on stderr until it works again. When the link itself
//! fails, every transaction that was due counts the failure.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::time::{Duration, Instant};

use super::config::{LinkConfig, Transaction};
use super::hal::TxPins;
use super::tcp::TcpLink;
use super::transaction::{describe_failure, execute};
use crate::error::Result;
use crate::line::{LineSettings, TtyLine};
use crate::modbus::{Master, MasterConfig, ReplyLength, Transact};

/// The first pause before a failed link is tried again.
pub const BACKOFF_MIN: Duration = Duration::from_millis(200);
/// The longest pause before a failed link is tried again.
pub const BACKOFF_MAX: Duration = Duration::from_secs(5);
/// The longest sleep between looks at the stop flag.
const WAKE: Duration = Duration::from_millis(20);

/// A serial device opened on first use and again after a failure.
pub struct SerialLink {
    path: String,
    settings: LineSettings,
    master: Option<Master<TtyLine>>,
    config: MasterConfig,
}

impl SerialLink {
    /// A link to `path` with `settings`, not opened yet.
    pub fn new(path: &str, settings: LineSettings) -> SerialLink {
        SerialLink {
            path: path.to_string(),
            settings,
            master: None,
            config: MasterConfig {
                // One request per transaction and run, as LinuxCNC's
                // mb2hal: the next run is the retry, and num_errors
                // shows every failure.
                retries: 0,
                // The link's own back-off decides when to reopen.
                reopen_interval: Duration::ZERO,
                ..MasterConfig::default()
            },
        }
    }
}

/// A link of either kind.
pub enum Link {
    /// Modbus TCP.
    Tcp(TcpLink),
    /// Modbus RTU (boxed: the master and its line are large).
    Serial(Box<SerialLink>),
}

impl Link {
    /// The link `config` describes, not connected yet.
    pub fn new(config: &LinkConfig) -> Link {
        match config {
            LinkConfig::Tcp { ip, port } => Link::Tcp(TcpLink::new(ip, *port)),
            LinkConfig::Serial { port, settings, .. } => {
                Link::Serial(Box::new(SerialLink::new(port, *settings)))
            }
        }
    }

    /// Sets the next transaction's timeouts and frame dumps.
    pub fn prepare(&mut self, tx: &Transaction) {
        let dump = tx.debug >= 3;
        match self {
            Link::Tcp(t) => t.set_timeouts(tx.response_timeout, tx.byte_timeout, dump),
            Link::Serial(s) => {
                s.config.response_timeout = tx.response_timeout;
                s.config.byte_timeout = tx.byte_timeout;
                s.config.debug = dump;
                if let Some(m) = &mut s.master {
                    *m.config_mut() = s.config;
                }
            }
        }
    }

    /// Closes the connection or device.
    pub fn close(&mut self) {
        match self {
            Link::Tcp(t) => t.close(),
            Link::Serial(s) => s.master = None,
        }
    }
}

impl Transact for Link {
    fn transact(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        reply: ReplyLength,
    ) -> Result<Vec<u8>> {
        match self {
            Link::Tcp(t) => t.transact(slave, function, data, reply),
            Link::Serial(s) => {
                let m = match &mut s.master {
                    Some(m) => m,
                    None => {
                        let line = TtyLine::open(&s.path, s.settings)?;
                        s.master.insert(Master::new(line, s.config))
                    }
                };
                m.transact(slave, function, data, reply)
            }
        }
    }

    fn is_broadcast(&self, slave: u8) -> bool {
        match self {
            Link::Tcp(t) => t.is_broadcast(slave),
            Link::Serial(_) => slave == crate::regs::modbus::BROADCAST,
        }
    }
}

/// One transaction with its pins and schedule.
struct Scheduled {
    tx: Transaction,
    pins: TxPins,
    next: Instant,
    /// The failure last said, so that a repeated one is said once.
    said: Option<String>,
}

/// A link and its transactions, as one thread runs them.
pub struct LinkRunner {
    link: Link,
    name: String,
    txs: Vec<Scheduled>,
    slowdown: Duration,
    delay: Duration,
    backoff: Duration,
    down_until: Option<Instant>,
}

impl LinkRunner {
    /// The runner of the link `config` with `txs` (each with its pins);
    /// `slowdown` is `[MB2HAL_INIT] SLOWDOWN`.
    pub fn new(config: &LinkConfig, txs: Vec<(Transaction, TxPins)>, slowdown: Duration) -> Self {
        let now = Instant::now();
        let delay = match config {
            LinkConfig::Serial { delay, .. } => *delay,
            LinkConfig::Tcp { .. } => Duration::ZERO,
        };
        LinkRunner {
            link: Link::new(config),
            name: config.describe(),
            txs: txs
                .into_iter()
                .map(|(tx, pins)| Scheduled {
                    tx,
                    pins,
                    next: now,
                    said: None,
                })
                .collect(),
            slowdown,
            delay,
            backoff: BACKOFF_MIN,
            down_until: None,
        }
    }

    /// Runs the transactions until `stop` is set.
    pub fn run(&mut self, stop: &AtomicBool) {
        while !stop.load(Relaxed) {
            if !self.round(stop) {
                let now = Instant::now();
                let next = self.txs.iter().map(|t| t.next).min().unwrap_or(now);
                let until = self.down_until.map_or(next, |d| d.max(next));
                pause(until.saturating_duration_since(now).min(WAKE), stop);
            }
        }
    }

    /// One pass over the transactions that are due; whether any ran.
    pub fn round(&mut self, stop: &AtomicBool) -> bool {
        let mut ran = false;
        for i in 0..self.txs.len() {
            if stop.load(Relaxed) {
                break;
            }
            let now = Instant::now();
            if let Some(until) = self.down_until {
                if now < until {
                    break;
                }
                self.down_until = None;
            }
            if now < self.txs[i].next {
                continue;
            }
            ran = true;
            let s = &mut self.txs[i];
            s.next = now + s.tx.period();
            self.link.prepare(&s.tx);
            match execute(&mut self.link, &s.tx, &s.pins) {
                Ok(()) => {
                    s.pins.num_errors.set(0);
                    self.backoff = BACKOFF_MIN;
                    if s.said.take().is_some() && s.tx.debug >= 1 {
                        eprintln!("mb2hal: [{}] works again", s.tx.section);
                    }
                    if s.tx.debug >= 2 {
                        eprintln!("mb2hal: [{}] {} OK", s.tx.section, s.tx.code.name());
                    }
                }
                Err(e) => {
                    let n = s.pins.num_errors.get().saturating_add(1);
                    s.pins.num_errors.set(n);
                    let msg = describe_failure(&s.tx, &self.name, &e);
                    if s.tx.debug >= 1 && s.said.as_deref() != Some(msg.as_str()) {
                        eprintln!("mb2hal: {msg}");
                    }
                    s.said = Some(msg);
                    if e.is_line_failure() {
                        // The others that were due cannot run either:
                        // they fail with it.
                        for (j, o) in self.txs.iter_mut().enumerate() {
                            if j != i && o.next <= now {
                                let n = o.pins.num_errors.get().saturating_add(1);
                                o.pins.num_errors.set(n);
                                o.next = now + o.tx.period();
                            }
                        }
                        self.link.close();
                        self.down_until = Some(Instant::now() + self.backoff);
                        self.backoff = (self.backoff * 2).min(BACKOFF_MAX);
                        break;
                    }
                }
            }
            pause(self.slowdown + self.delay, stop);
        }
        ran
    }
}

/// Sleeps `d`, waking early when `stop` is set.
fn pause(d: Duration, stop: &AtomicBool) {
    let until = Instant::now() + d;
    loop {
        let now = Instant::now();
        if now >= until || stop.load(Relaxed) {
            return;
        }
        std::thread::sleep((until - now).min(WAKE));
    }
}
