//! The private HAL instance a latency test runs on: a host of its own
//! (`hal-host`, so the threads get whatever realtime rights the host
//! binary has), the `threads` module with the base and servo threads,
//! started at once.

use std::process::Child;
use std::time::Duration;

use hal_core::Instance;
use hal_lang::host_process::{start_host_own_group, stop_host};
use hal_lang::protocol::Client;

use super::args::Config;
use super::stats::ThreadStats;
use crate::error::ScopeError as LatencyError;

/// The base thread's name.
pub const BASE_THREAD: &str = "base-thread";
/// The servo thread's name.
pub const SERVO_THREAD: &str = "servo-thread";

/// A running private instance.
pub struct Session {
    instance: String,
    host: Option<Child>,
    inst: Instance,
    threads: Vec<String>,
}

impl Session {
    /// Starts a host on instance `instance` (which must be free) with the
    /// threads `cfg` asks for, and starts them.
    pub fn start(instance: &str, cfg: &Config) -> Result<Session, LatencyError> {
        let host = start_host_own_group(instance).map_err(LatencyError::Host)?;
        let inst = match Instance::attach(instance) {
            Ok(i) => i,
            Err(source) => {
                let _ = stop_host(instance, Duration::from_secs(10));
                return Err(LatencyError::Instance {
                    instance: instance.to_string(),
                    source,
                });
            }
        };
        let mut s = Session {
            instance: instance.to_string(),
            host: Some(host),
            inst,
            threads: Vec::new(),
        };
        let mut load = vec!["loadrt".to_string(), "threads".to_string()];
        let mut n = 0;
        let mut add = |name: &str, period: i64| {
            n += 1;
            load.push(format!("name{n}={name}"));
            load.push(format!("period{n}={period}"));
            s.threads.push(name.to_string());
        };
        if let Some(base) = cfg.base_ns {
            add(BASE_THREAD, base);
        }
        add(SERVO_THREAD, cfg.servo_ns);
        s.call(&load)?;
        s.call(&["start".to_string()])?;
        Ok(s)
    }

    fn call(&self, words: &[String]) -> Result<(), LatencyError> {
        Client::connect(&self.instance)
            .and_then(|mut c| c.call(words))
            .map_err(|source| LatencyError::HostRequest {
                command: words.join(" "),
                source,
            })
    }

    /// The instance's name.
    pub fn instance(&self) -> &str {
        &self.instance
    }

    /// The process id of the host.
    pub fn host_pid(&self) -> Option<u32> {
        self.host.as_ref().map(Child::id)
    }

    /// The names of the HAL threads, fastest first.
    pub fn thread_names(&self) -> &[String] {
        &self.threads
    }

    /// Whether the host still runs.
    pub fn host_alive(&self) -> bool {
        self.inst.host_alive()
    }

    /// The threads' figures now, fastest first.
    pub fn snapshot(&self) -> Result<Vec<ThreadStats>, LatencyError> {
        let infos = self
            .inst
            .threads()
            .map_err(|source| LatencyError::Instance {
                instance: self.instance.clone(),
                source,
            })?;
        Ok(self
            .threads
            .iter()
            .filter_map(|name| infos.iter().find(|t| &t.name == name))
            .map(ThreadStats::from_info)
            .collect())
    }

    /// Stops the threads (their figures stay as they are).
    pub fn stop_threads(&self) -> Result<(), LatencyError> {
        self.call(&["stop".to_string()])
    }

    /// Shuts the host down and waits for it.
    pub fn finish(mut self) -> Result<(), LatencyError> {
        self.shutdown()
    }

    fn shutdown(&mut self) -> Result<(), LatencyError> {
        let Some(mut child) = self.host.take() else {
            return Ok(());
        };
        let r = stop_host(&self.instance, Duration::from_secs(10));
        if r.is_err() {
            let _ = child.kill();
        }
        let _ = child.wait();
        r.map_err(LatencyError::HostStop)
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        let _ = self.shutdown();
    }
}
