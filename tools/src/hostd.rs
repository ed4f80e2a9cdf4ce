//! The host process: owns the instance, serves requests on its socket until
//! told to shut down or signalled, then brings everything to a safe state.

use std::io::{BufRead, BufReader, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{paths, Host, HostConfig, Registry};

use crate::protocol::{decode_request, encode_reply};

/// The registry of every module this suite provides.
pub fn registry() -> Registry {
    let mut r = Registry::new();
    r.add(&hal_components::modules());
    r
}

/// What a request asked the serve loop to do next.
enum Next {
    Continue,
    Shutdown,
}

/// Runs a host for `config` until a `shutdown` request or a signal.
/// `ready` is called once the socket accepts connections.
pub fn serve(config: HostConfig, ready: impl FnOnce()) -> Result<(), String> {
    let signals = ExitSignals::install().map_err(|e| e.to_string())?;
    let instance = config.instance.clone();
    let host = Host::create(config).map_err(|e| e.to_string())?;
    // LinuxCNC's own processes take the first component ids; reproduce its
    // numbering so `show` output matches (the first loadrt gets id 6).
    host.instance()
        .advance_component_ids(4)
        .map_err(|e| e.to_string())?;
    let registry = registry();
    let sock = paths::socket(&instance);
    // We hold the instance lock, so a socket file here is stale.
    let _ = std::fs::remove_file(&sock);
    let listener = UnixListener::bind(&sock)
        .map_err(|e| format!("binding the control socket {}: {e}", sock.display()))?;
    listener
        .set_nonblocking(true)
        .map_err(|e| format!("control socket: {e}"))?;
    ready();
    let result = loop {
        if signals.requested() {
            break Ok(());
        }
        match listener.accept() {
            Ok((stream, _)) => match handle(&host, &registry, stream, &signals) {
                Next::Continue => {}
                Next::Shutdown => break Ok(()),
            },
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => break Err(format!("control socket: {e}")),
        }
    };
    drop(listener);
    let _ = std::fs::remove_file(&sock);
    host.shutdown();
    result
}

fn handle(host: &Host, registry: &Registry, stream: UnixStream, signals: &ExitSignals) -> Next {
    let _ = stream.set_nonblocking(false);
    let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
    let Ok(mut writer) = stream.try_clone() else {
        return Next::Continue;
    };
    let mut reader = BufReader::new(stream);
    let mut line = String::new();
    loop {
        line.clear();
        match reader.read_line(&mut line) {
            Ok(0) => return Next::Continue,
            Ok(_) => {}
            Err(e)
                if e.kind() == std::io::ErrorKind::WouldBlock
                    || e.kind() == std::io::ErrorKind::TimedOut =>
            {
                if signals.requested() {
                    return Next::Shutdown;
                }
                continue;
            }
            Err(_) => return Next::Continue,
        }
        let words = decode_request(line.trim_end_matches('\n'));
        let (result, next) = execute(host, registry, &words);
        let reply = encode_reply(&result);
        if writer.write_all(format!("{reply}\n").as_bytes()).is_err() {
            return next;
        }
        if let Next::Shutdown = next {
            return next;
        }
    }
}

fn execute(host: &Host, registry: &Registry, words: &[String]) -> (Result<(), String>, Next) {
    let arg = |i: usize| words.get(i).map(String::as_str).unwrap_or("");
    let r = match arg(0) {
        "ping" | "setexact" => Ok(()),
        "shutdown" => return (Ok(()), Next::Shutdown),
        "loadrt" => match registry.find(arg(1)) {
            Some(def) => host.loadrt(def, &words[2..]).map_err(|e| e.to_string()),
            None => Err(format!("module '{}' not found", arg(1))),
        },
        "unloadrt" => host.unloadrt(arg(1)).map_err(|e| e.to_string()),
        "unload" => host.unload(arg(1)).map_err(|e| e.to_string()),
        "addf" => {
            let pos = match words.get(3) {
                None => Ok(-1),
                Some(p) => p.parse::<i32>().map_err(|_| format!("bad position '{p}'")),
            };
            pos.and_then(|p| host.addf(arg(1), arg(2), p).map_err(|e| e.to_string()))
        }
        "initf" => host.initf(arg(1), arg(2)).map_err(|e| e.to_string()),
        "delf" => host
            .delf(arg(1), words.get(2).map(String::as_str))
            .map_err(|e| e.to_string()),
        "start" => host.start().map_err(|e| e.to_string()),
        "stop" => {
            host.stop();
            Ok(())
        }
        other => Err(format!("unknown host request '{other}'")),
    };
    (r, Next::Continue)
}
