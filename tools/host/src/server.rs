//! The host process: owns the instance, serves requests on its socket until
//! told to shut down or signalled, then brings everything to a safe state.

use std::io::{BufRead, BufReader, Write};
use std::os::unix::net::UnixStream;
use std::sync::atomic::{AtomicBool, Ordering::SeqCst};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{paths, Host, HostConfig, Registry};
use hal_lang::protocol::{
    decode_reply, decode_request, encode_reply, encode_request, ClientError, HostLink,
};

use crate::adopt::Adopted;
use crate::error::HostError;

/// The registry of every module this suite provides.
pub fn registry() -> Registry {
    let mut r = Registry::new();
    r.add(&hal_components::modules());
    r.add(&hal_ladder::modules());
    r.add(&[&hal_parport::MODULE, &hal_parport::speaker::MODULE]);
    r.add(&hostmot2::hal::modules());
    r.add(&motion::tp_home::modules());
    r.add(&[&hal_gpio::MODULE]);
    r.add(&hal_i2c::modules());
    r.add(&[&hal_motenc::MODULE]);
    r.add(&[&hal_stg::MODULE]);
    r.add(&[&hal_ppmc::MODULE]);
    r.add(&[&hal_canservo::MODULE]);
    r.add(&[&hal_ethercat::MODULE]);
    r.add(&motion::modules());
    r
}

/// Runs a host for `config` until a `shutdown` request or a signal.
/// `ready` is called once the socket accepts connections. Each connection
/// is served by a thread of its own (a halcmd started by `loadusr` talks to
/// the host while its parent's connection is open); requests are executed
/// one at a time.
pub fn serve(config: HostConfig, ready: impl FnOnce()) -> Result<(), HostError> {
    let signals = ExitSignals::install()?;
    let instance = config.instance.clone();
    let host = Host::create(config)?;
    // LinuxCNC's own processes take the first component ids; reproduce its
    // numbering so `show` output matches (the first loadrt gets id 6).
    host.instance().advance_component_ids(4)?;
    let registry = registry();
    let sock = paths::socket(&instance)?;
    // We hold the instance lock, so a socket file here is stale.
    let listener = paths::bind_socket(&sock).map_err(|source| HostError::Bind { source })?;
    listener
        .set_nonblocking(true)
        .map_err(|source| HostError::Socket { source })?;
    ready();
    let stop = AtomicBool::new(false);
    let exec_lock = Mutex::new(());
    let held_open = Mutex::new(Vec::new());
    let adopted = Adopted::new();
    let result = std::thread::scope(|scope| loop {
        if signals.requested() || stop.load(SeqCst) {
            stop.store(true, SeqCst);
            break Ok(());
        }
        match listener.accept() {
            Ok((stream, _)) => {
                let ctx = Ctx {
                    host: &host,
                    registry: &registry,
                    stop: &stop,
                    exec_lock: &exec_lock,
                    signals: &signals,
                    held_open: &held_open,
                    adopted: &adopted,
                };
                scope.spawn(move || ctx.handle(stream));
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => {
                stop.store(true, SeqCst);
                break Err(HostError::Socket { source: e });
            }
        }
    });
    drop(listener);
    let _ = std::fs::remove_file(&sock);
    // Programs loadusr started go first, as `unload all` does in LinuxCNC.
    for note in adopted.stop_all(ADOPTED_GRACE) {
        eprintln!("HAL: {note}");
    }
    host.shutdown();
    // Dropping the host releases the instance lock last of all.
    drop(host);
    // Whoever asked for the shutdown sees its connection close only now,
    // when segment, socket and lock are gone: `realtime stop` waits for
    // that, so a `realtime start` right after it finds the instance free.
    drop(held_open);
    result
}

/// What a connection thread needs.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    host: &'a Host,
    registry: &'a Registry,
    stop: &'a AtomicBool,
    exec_lock: &'a Mutex<()>,
    signals: &'a ExitSignals,
    /// Connections that asked for the shutdown, closed once it is done.
    held_open: &'a Mutex<Vec<UnixStream>>,
    /// Programs `loadusr` started, stopped at shutdown.
    adopted: &'a Adopted,
}

impl Ctx<'_> {
    fn handle(self, stream: UnixStream) {
        let _ = stream.set_nonblocking(false);
        let _ = stream.set_read_timeout(Some(Duration::from_millis(100)));
        let Ok(mut writer) = stream.try_clone() else {
            return;
        };
        let mut reader = BufReader::new(stream);
        let mut line = Vec::new();
        loop {
            if self.stop.load(SeqCst) || self.signals.requested() {
                return;
            }
            // A timeout may interrupt a line; what was read stays in
            // `line` and the next read continues it.
            match reader.read_until(b'\n', &mut line) {
                Ok(0) => return,
                Ok(_) if line.ends_with(b"\n") => {}
                Ok(_) => continue,
                Err(e)
                    if e.kind() == std::io::ErrorKind::WouldBlock
                        || e.kind() == std::io::ErrorKind::TimedOut =>
                {
                    continue
                }
                Err(_) => return,
            }
            let text = String::from_utf8_lossy(&line)
                .trim_end_matches('\n')
                .to_string();
            line.clear();
            let words = decode_request(&text);
            let result = if words[0] == "adopt" {
                // `adopt PID NAME`: needs the peer, not the HAL.
                let arg = |i: usize| words.get(i).map_or("", String::as_str);
                self.adopted
                    .adopt(arg(1), arg(2), peer_pid(&writer))
                    .map(|()| Next::Continue)
            } else {
                let _serial = self.exec_lock.lock().unwrap_or_else(|e| e.into_inner());
                execute(self.host, self.registry, &words)
            };
            let (result, shutdown) = match result {
                Ok(Next::Shutdown) => (Ok(()), true),
                Ok(Next::Continue) => (Ok(()), false),
                Err(e) => (Err(e), false),
            };
            let reply = encode_reply(&result);
            let _ = writer.write_all(format!("{reply}\n").as_bytes());
            if shutdown {
                let mut held = self.held_open.lock().unwrap_or_else(|e| e.into_inner());
                held.push(writer);
                held.push(reader.into_inner());
                self.stop.store(true, SeqCst);
                return;
            }
        }
    }
}

/// How long programs `loadusr` started get to end after SIGTERM.
const ADOPTED_GRACE: Duration = Duration::from_secs(5);

/// The PID of the process at the other end of a connection.
fn peer_pid(stream: &UnixStream) -> Option<i32> {
    nix::sys::socket::getsockopt(stream, nix::sys::socket::sockopt::PeerCredentials)
        .ok()
        .map(|c| c.pid())
}

/// A host of this process as a halcmd session's link to its host: each
/// request runs as the socket's connection threads run it, without the
/// socket and its two thread wake-ups per request. The fuzz targets drive
/// their host this way, with drivers in simulated form only.
pub struct InProcess {
    host: Arc<Host>,
    registry: Registry,
}

impl InProcess {
    /// A link to `host`, offering the modules of `registry` to `loadrt`.
    pub fn new(host: Arc<Host>, registry: Registry) -> InProcess {
        InProcess { host, registry }
    }
}

impl HostLink for InProcess {
    /// Encodes and decodes the request and its reply as the socket does,
    /// so a request behaves the same either way.
    fn call(&mut self, words: &[String]) -> Result<(), ClientError> {
        let words = decode_request(&encode_request(words)?);
        let result = execute(&self.host, &self.registry, &words).map(|_| ());
        decode_reply(&encode_reply(&result))
    }
}

/// What a request asked the host to do next.
enum Next {
    Continue,
    Shutdown,
}

fn execute(host: &Host, registry: &Registry, words: &[String]) -> Result<Next, HostError> {
    let arg = |i: usize| words.get(i).map(String::as_str).unwrap_or("");
    let r = match arg(0) {
        "ping" => Ok(()),
        "shutdown" => return Ok(Next::Shutdown),
        "loadrt" => match registry.find(arg(1)) {
            Some(def) => Ok(host.loadrt(def, &words[2..])?),
            None => Err(HostError::UnknownModule {
                name: arg(1).to_string(),
            }),
        },
        "unloadrt" => Ok(host.unloadrt(arg(1))?),
        "unload" => Ok(host.unload(arg(1))?),
        "addf" => {
            let pos = match words.get(3) {
                None => -1,
                Some(p) => p
                    .parse::<i32>()
                    .map_err(|_| HostError::BadPosition { text: p.clone() })?,
            };
            Ok(host.addf(arg(1), arg(2), pos)?)
        }
        "initf" => Ok(host.initf(arg(1), arg(2))?),
        "delf" => Ok(host.delf(arg(1), words.get(2).map(String::as_str))?),
        "setthread" => crate::setthread::apply(host, &words[1..]),
        "start" => Ok(host.start()?),
        "stop" => host
            .instance()
            .check_unlocked(hal_core::lock_bits::RUN, "stop_threads")
            .map(|()| host.stop())
            .map_err(HostError::from),
        other => Err(HostError::UnknownRequest {
            word: other.to_string(),
        }),
    };
    r.map(|()| Next::Continue)
}
