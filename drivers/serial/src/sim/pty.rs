//! [`PtyVfd`]: a simulated VFD at the far end of a pseudo-terminal pair.
//! A thread serves the master side in wall time; the component under
//! test opens the slave side (`/dev/pts/N`) as the real serial device it
//! is, through the real tty code. The drive can be unplugged (the pair
//! closes: reads and writes on the slave fail) and plugged back (a new
//! pair, and, when the simulator keeps a link such as a USB adapter's
//! `/dev/serial/by-id/...` name, the link points at it again).

use std::collections::VecDeque;
use std::os::fd::{AsFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use nix::fcntl::OFlag;
use nix::poll::{PollFd, PollFlags, PollTimeout};
use nix::pty::PtyMaster;
use nix::sys::stat::Mode;
use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};

use super::VfdSim;

/// The longest the serving thread waits for bytes before looking at the
/// clock again.
const POLL: Duration = Duration::from_millis(2);

/// One pseudo-terminal pair.
struct Pair {
    master: PtyMaster,
    /// A slave descriptor held open, so the pair lives while the
    /// component under test closes and reopens its side.
    _slave: OwnedFd,
}

struct State {
    sim: VfdSim,
    pair: Option<Pair>,
    path: String,
    link: Option<PathBuf>,
    pending: VecDeque<(Duration, Vec<u8>)>,
}

struct Inner {
    state: Mutex<State>,
    stop: AtomicBool,
    epoch: Instant,
}

/// A simulated VFD behind a pseudo-terminal.
pub struct PtyVfd {
    inner: Arc<Inner>,
    thread: Option<JoinHandle<()>>,
}

/// A new pair in raw mode. Both descriptors are close-on-exec: a
/// process started later (the component under test) must not hold the
/// master, or closing it here would not hang up the slave.
fn open_pair() -> std::io::Result<(Pair, String)> {
    let master = nix::pty::posix_openpt(OFlag::O_RDWR | OFlag::O_NOCTTY | OFlag::O_CLOEXEC)?;
    nix::pty::grantpt(&master)?;
    nix::pty::unlockpt(&master)?;
    let path = nix::pty::ptsname_r(&master)?;
    let slave = nix::fcntl::open(
        path.as_str(),
        OFlag::O_RDWR | OFlag::O_NOCTTY | OFlag::O_CLOEXEC,
        Mode::empty(),
    )?;
    let mut t = tcgetattr(&slave)?;
    cfmakeraw(&mut t);
    tcsetattr(&slave, SetArg::TCSANOW, &t)?;
    Ok((
        Pair {
            master,
            _slave: slave,
        },
        path,
    ))
}

/// Waits up to `wait` for bytes from the master side; what came.
fn read_some(master: &PtyMaster, buf: &mut [u8], wait: Duration) -> usize {
    let timeout = PollTimeout::try_from(wait).unwrap_or(PollTimeout::MAX);
    let mut fds = [PollFd::new(master.as_fd(), PollFlags::POLLIN)];
    match nix::poll::poll(&mut fds, timeout) {
        Ok(n) if n > 0 => nix::unistd::read(master, buf).unwrap_or(0),
        _ => 0,
    }
}

/// Writes all of `bytes` to the master side (the slave's input queue).
fn write_all(master: &PtyMaster, mut bytes: &[u8]) {
    while !bytes.is_empty() {
        match nix::unistd::write(master, bytes) {
            Ok(0) | Err(_) => return,
            Ok(n) => bytes = &bytes[n..],
        }
    }
}

fn place_link(link: &Path, target: &str) -> std::io::Result<()> {
    match std::fs::remove_file(link) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(e),
    }
    std::os::unix::fs::symlink(target, link)
}

impl PtyVfd {
    /// Serves `sim` on a new pseudo-terminal pair.
    pub fn start(sim: VfdSim) -> std::io::Result<PtyVfd> {
        Self::start_inner(sim, None)
    }

    /// Serves `sim` on a new pair and keeps a symbolic link `link` to its
    /// slave side, as udev keeps `/dev/serial/by-id/...` for a USB
    /// adapter. `link` must be in a directory only this user can write.
    pub fn start_linked(sim: VfdSim, link: &Path) -> std::io::Result<PtyVfd> {
        Self::start_inner(sim, Some(link.to_path_buf()))
    }

    fn start_inner(sim: VfdSim, link: Option<PathBuf>) -> std::io::Result<PtyVfd> {
        let (pair, path) = open_pair()?;
        if let Some(l) = &link {
            place_link(l, &path)?;
        }
        let inner = Arc::new(Inner {
            state: Mutex::new(State {
                sim,
                pair: Some(pair),
                path,
                link,
                pending: VecDeque::new(),
            }),
            stop: AtomicBool::new(false),
            epoch: Instant::now(),
        });
        let serving = inner.clone();
        let thread = std::thread::Builder::new()
            .name("vfd-sim".into())
            .spawn(move || serve(&serving))?;
        Ok(PtyVfd {
            inner,
            thread: Some(thread),
        })
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.inner.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The device the component opens: the link if there is one, else
    /// the pty slave.
    pub fn device(&self) -> String {
        let st = self.lock();
        match &st.link {
            Some(l) => l.to_string_lossy().into_owned(),
            None => st.path.clone(),
        }
    }

    /// The pty slave of the present pair.
    pub fn pty_path(&self) -> String {
        self.lock().path.clone()
    }

    /// Works on the simulated drive (set faults, read the model).
    pub fn with<R>(&self, f: impl FnOnce(&mut VfdSim) -> R) -> R {
        f(&mut self.lock().sim)
    }

    /// Unplugs the drive: the pair closes (the component's reads and
    /// writes fail) and the link disappears.
    pub fn unplug(&self) {
        let mut st = self.lock();
        st.pair = None;
        st.pending.clear();
        st.sim.set_unplugged(true);
        if let Some(l) = &st.link {
            let _ = std::fs::remove_file(l);
        }
    }

    /// Plugs it back on a new pair; the link follows. Returns the new
    /// pty slave.
    pub fn replug(&self) -> std::io::Result<String> {
        let (pair, path) = open_pair()?;
        let mut st = self.lock();
        if let Some(l) = &st.link {
            place_link(l, &path)?;
        }
        st.pair = Some(pair);
        st.path = path.clone();
        st.sim.set_unplugged(false);
        Ok(path)
    }
}

impl Drop for PtyVfd {
    fn drop(&mut self) {
        self.inner.stop.store(true, Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        let st = self.lock();
        if let Some(l) = &st.link {
            let _ = std::fs::remove_file(l);
        }
    }
}

/// The serving thread: bytes from the master side into the simulator,
/// replies back when due, the model advanced by wall time.
fn serve(inner: &Inner) {
    let mut buf = [0u8; 512];
    while !inner.stop.load(Relaxed) {
        let pause = {
            let mut st = inner.state.lock().unwrap_or_else(|p| p.into_inner());
            serve_once(inner.epoch, &mut st, &mut buf)
        };
        match pause {
            Some(d) => std::thread::sleep(d),
            None => std::thread::yield_now(),
        }
    }
}

/// One round of the serving thread, under the lock; returns how long to
/// sleep outside it (None: just let others have the lock).
fn serve_once(epoch: Instant, st: &mut State, buf: &mut [u8]) -> Option<Duration> {
    let now = epoch.elapsed();
    let Some(pair) = st.pair.as_ref() else {
        st.sim.advance_to(now.as_nanos() as u64);
        return Some(POLL);
    };
    let wait = st
        .pending
        .front()
        .map_or(POLL, |(due, _)| due.saturating_sub(now).min(POLL));
    let got = read_some(&pair.master, buf, wait);
    let now = epoch.elapsed();
    let now_ns = now.as_nanos() as u64;
    st.sim.feed(&buf[..got], now_ns);
    if let Some(reply) = st.sim.poll(now_ns) {
        st.pending.push_back((now + reply.delay, reply.bytes));
    }
    while st.pending.front().is_some_and(|(due, _)| *due <= now) {
        if let Some((_, bytes)) = st.pending.pop_front() {
            if let Some(pair) = &st.pair {
                write_all(&pair.master, &bytes);
            }
        }
    }
    None
}
