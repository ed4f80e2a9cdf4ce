//! What tests of this crate and of the crates above it use (feature
//! `testing`): a host served in the test's own process.

use std::time::Duration;

/// A host served on a background thread of this process, for tests that
/// drive a [`hal_lang::Session`] directly.
pub struct InProcessHost {
    /// The instance's name.
    pub instance: String,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl InProcessHost {
    /// Starts a host on an instance of its own (`tag` names it) and waits
    /// until it serves; panics if it does not (a test's failure).
    pub fn start(tag: &str) -> InProcessHost {
        let mut cfg = hal_core::HostConfig::for_tests(tag);
        cfg.shm_size = 8 << 20;
        let name = cfg.instance.clone();
        let (tx, rx) = std::sync::mpsc::channel();
        let thread = std::thread::spawn(move || {
            crate::serve(cfg, move || {
                let _ = tx.send(());
            })
            .expect("host serves");
        });
        rx.recv_timeout(Duration::from_secs(20))
            .expect("host ready");
        InProcessHost {
            instance: name,
            thread: Some(thread),
        }
    }

    /// The instance, attached.
    pub fn instance(&self) -> hal_core::Instance {
        hal_core::Instance::attach(&self.instance).expect("attach")
    }

    /// Runs `text` as file `name`; returns (ok, stdout, stderr).
    pub fn run(&self, name: &str, text: &str, keep_going: bool) -> (bool, String, String) {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let opts = hal_lang::Options {
            keep_going,
            ..Default::default()
        };
        let ok = {
            let mut s = hal_lang::Session::new(self.instance(), opts, &mut out, &mut err);
            s.run_text(Some(name), text)
        };
        (
            ok,
            String::from_utf8_lossy(&out).into_owned(),
            String::from_utf8_lossy(&err).into_owned(),
        )
    }
}

impl Drop for InProcessHost {
    fn drop(&mut self) {
        let _ = hal_lang::host_process::stop_host(&self.instance, Duration::from_secs(10));
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
