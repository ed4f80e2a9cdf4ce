//! Serving a simulated Ethernet board on a UDP socket, with faults on
//! demand: requests or replies dropped, replies delayed or sent twice,
//! each at a configured rate drawn from a seeded generator, so a run
//! with the same traffic loses the same packets.
//!
//! The `hm2-eth-sim` tool runs a [`Server`] in its own process; tests
//! start one on a thread with [`spawn`] on port 0 of 127.0.0.1 and hand
//! its address to `hm2_eth`.

use std::io;
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::eth::EthBoard;

/// Rates of injected faults, each a probability per datagram (0..1).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Faults {
    /// A request datagram (one with reads) is lost before the board sees it.
    pub drop_requests: f64,
    /// A datagram of writes only is lost before the board sees it.
    pub drop_writes: f64,
    /// A reply is lost after the board executed the request.
    pub drop_replies: f64,
    /// A reply is held back by `delay`.
    pub delay_rate: f64,
    /// How long a delayed reply is held back.
    pub delay: Duration,
    /// A reply is sent twice.
    pub duplicate: f64,
    /// Seed of the generator that draws the faults.
    pub seed: u64,
}

/// What the server saw and did, counted.
#[derive(Debug, Default)]
pub struct Counts {
    /// Datagrams received.
    pub requests: AtomicU64,
    /// Replies sent (duplicates included).
    pub replies: AtomicU64,
    /// Requests dropped.
    pub dropped_requests: AtomicU64,
    /// Replies dropped.
    pub dropped_replies: AtomicU64,
    /// Replies delayed.
    pub delayed: AtomicU64,
    /// Replies duplicated.
    pub duplicated: AtomicU64,
    /// Datagrams of writes only dropped.
    pub dropped_writes: AtomicU64,
}

impl Counts {
    /// (datagrams received, replies sent, dropped requests, dropped
    /// replies, delayed, duplicated, dropped writes).
    pub fn snapshot(&self) -> [u64; 7] {
        [
            &self.requests,
            &self.replies,
            &self.dropped_requests,
            &self.dropped_replies,
            &self.delayed,
            &self.duplicated,
            &self.dropped_writes,
        ]
        .map(|c| c.load(Relaxed))
    }
}

/// A small seeded generator (xorshift64*): faults must repeat.
#[derive(Debug, Clone)]
struct Dice(u64);

impl Dice {
    fn new(seed: u64) -> Dice {
        Dice(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// True with probability `p`.
    fn chance(&mut self, p: f64) -> bool {
        if p <= 0.0 {
            return false;
        }
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        ((x >> 11) as f64 / (1u64 << 53) as f64) < p
    }
}

/// The shared state of a served board.
pub struct Shared {
    board: Mutex<EthBoard>,
    faults: Mutex<(Faults, Dice)>,
    /// What happened so far.
    pub counts: Counts,
}

impl Shared {
    /// Runs `f` on the board (the server waits meanwhile).
    pub fn with<R>(&self, f: impl FnOnce(&mut EthBoard) -> R) -> R {
        f(&mut lock(&self.board))
    }

    /// Changes the fault rates (the generator restarts from their seed).
    pub fn set_faults(&self, faults: Faults) {
        *lock(&self.faults) = (faults, Dice::new(faults.seed));
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A board answering on a socket.
pub struct Server {
    socket: UdpSocket,
    shared: Arc<Shared>,
}

impl Server {
    /// Serves `board` on `socket` with `faults`.
    pub fn new(socket: UdpSocket, board: EthBoard, faults: Faults) -> Server {
        Server {
            socket,
            shared: Arc::new(Shared {
                board: Mutex::new(board),
                faults: Mutex::new((faults, Dice::new(faults.seed))),
                counts: Counts::default(),
            }),
        }
    }

    /// Where it listens.
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.socket.local_addr()
    }

    /// The board and counters, shared with the serving loop.
    pub fn shared(&self) -> Arc<Shared> {
        self.shared.clone()
    }

    /// Answers datagrams until `stop` is set.
    pub fn run(&self, stop: &AtomicBool) -> io::Result<()> {
        let mut buf = vec![0u8; 65536];
        let mut reply = Vec::with_capacity(2048);
        let mut held: Vec<(Instant, Vec<u8>, SocketAddr)> = Vec::new();
        while !stop.load(Relaxed) {
            let now = Instant::now();
            let mut k = 0;
            while k < held.len() {
                if held[k].0 <= now {
                    let (_, bytes, to) = held.swap_remove(k);
                    self.send(&bytes, to);
                } else {
                    k += 1;
                }
            }
            let wait = held
                .iter()
                .map(|h| h.0.saturating_duration_since(now))
                .min()
                .unwrap_or(Duration::from_millis(20))
                .clamp(Duration::from_micros(50), Duration::from_millis(20));
            self.socket.set_read_timeout(Some(wait))?;
            let (n, from) = match self.socket.recv_from(&mut buf) {
                Ok(x) => x,
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock
                            | io::ErrorKind::TimedOut
                            | io::ErrorKind::Interrupted
                            | io::ErrorKind::ConnectionRefused
                    ) =>
                {
                    continue
                }
                Err(e) => return Err(e),
            };
            let c = &self.shared.counts;
            c.requests.fetch_add(1, Relaxed);
            let has_reads = crate::lbp16::parse(&buf[..n])
                .any(|p| p.is_ok_and(|p| !p.cmd.write && p.cmd.count > 0));
            let (drop_request, drop_reply, delay, twice, delay_for) = {
                let mut f = lock(&self.shared.faults);
                let (rates, dice) = &mut *f;
                let lose = if has_reads {
                    rates.drop_requests
                } else {
                    rates.drop_writes
                };
                (
                    dice.chance(lose),
                    dice.chance(rates.drop_replies),
                    dice.chance(rates.delay_rate),
                    dice.chance(rates.duplicate),
                    rates.delay,
                )
            };
            if drop_request {
                if has_reads {
                    c.dropped_requests.fetch_add(1, Relaxed);
                } else {
                    c.dropped_writes.fetch_add(1, Relaxed);
                }
                continue;
            }
            let answered = self.shared.with(|b| b.handle(&buf[..n], &mut reply));
            if !answered {
                continue;
            }
            if drop_reply {
                c.dropped_replies.fetch_add(1, Relaxed);
                continue;
            }
            let copies = if twice {
                c.duplicated.fetch_add(1, Relaxed);
                2
            } else {
                1
            };
            if delay {
                c.delayed.fetch_add(1, Relaxed);
                for _ in 0..copies {
                    held.push((Instant::now() + delay_for, reply.clone(), from));
                }
            } else {
                for _ in 0..copies {
                    self.send(&reply, from);
                }
            }
        }
        Ok(())
    }

    fn send(&self, bytes: &[u8], to: SocketAddr) {
        // Counted first: whoever receives it may look at the count.
        self.shared.counts.replies.fetch_add(1, Relaxed);
        if self.socket.send_to(bytes, to).is_err() {
            self.shared.counts.replies.fetch_sub(1, Relaxed);
        }
    }
}

/// A server running on a thread of this process; stopped when dropped.
pub struct Running {
    addr: SocketAddr,
    shared: Arc<Shared>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<io::Result<()>>>,
}

impl Running {
    /// Where the board listens (`127.0.0.1:<port>`).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The board, its fault rates and counters.
    pub fn shared(&self) -> &Arc<Shared> {
        &self.shared
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Serves `board` on 127.0.0.1 at a port the system picks, on a thread.
pub fn spawn(board: EthBoard, faults: Faults) -> io::Result<Running> {
    spawn_on(board, faults, SocketAddr::from(([127, 0, 0, 1], 0)))
}

/// Serves `board` at `addr` (a loopback address of its own at LBP16's
/// port 27181, for a tool that knows no other port), on a thread.
pub fn spawn_on(board: EthBoard, faults: Faults, addr: SocketAddr) -> io::Result<Running> {
    let socket = UdpSocket::bind(addr)?;
    let server = Server::new(socket, board, faults);
    let addr = server.local_addr()?;
    let shared = server.shared();
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let thread = std::thread::Builder::new()
        .name(format!("hm2-eth-sim {addr}"))
        .spawn(move || server.run(&flag))?;
    Ok(Running {
        addr,
        shared,
        stop,
        thread: Some(thread),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dice_repeat_and_keep_their_rate() {
        let mut a = Dice::new(7);
        let mut b = Dice::new(7);
        let xs: Vec<bool> = (0..1000).map(|_| a.chance(0.1)).collect();
        let ys: Vec<bool> = (0..1000).map(|_| b.chance(0.1)).collect();
        assert_eq!(xs, ys);
        let hits = xs.iter().filter(|x| **x).count();
        assert!((60..140).contains(&hits), "{hits}");
        assert!(!Dice::new(1).chance(0.0));
        assert!(Dice::new(1).chance(1.0));
    }
}
