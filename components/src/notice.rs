//! Messages that a realtime function wants on stderr.
//!
//! LinuxCNC components print a few diagnostics from inside their realtime
//! functions (div2's "divisor too close to zero"). A function body here may
//! not make system calls, so it only counts the message as posted (one
//! atomic add); a helper thread outside realtime writes it to stderr a few
//! milliseconds later. When the owning function is dropped (unload, host
//! exit) anything still pending is written at once, so no message is lost.
//!
//! Each [`Notice`] has a fixed table of texts; posts of one text are
//! written in order, but two different texts posted within one polling
//! interval may come out in table order rather than posting order.

use std::borrow::Cow;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex, Once, Weak};
use std::time::Duration;

/// How often the helper thread looks for posted messages.
const POLL: Duration = Duration::from_millis(10);

/// The posted counts of one notice, shared with the helper thread.
struct Board {
    texts: Vec<Cow<'static, str>>,
    posted: Vec<AtomicU32>,
    /// How many posts of each text have been written (helper side only).
    written: Mutex<Vec<u32>>,
}

impl Board {
    /// Writes every post not written yet.
    fn flush(&self) {
        use std::io::Write;
        let mut written = self.written.lock().unwrap_or_else(|e| e.into_inner());
        let stderr = std::io::stderr();
        let mut err = stderr.lock();
        for (i, text) in self.texts.iter().enumerate() {
            let posted = self.posted[i].load(Ordering::Acquire);
            while written[i] != posted {
                let _ = err.write_all(text.as_bytes());
                written[i] = written[i].wrapping_add(1);
            }
        }
        let _ = err.flush();
    }
}

/// Every live notice, polled by the helper thread.
static BOARDS: Mutex<Vec<Weak<Board>>> = Mutex::new(Vec::new());
static HELPER: Once = Once::new();

fn start_helper() {
    HELPER.call_once(|| {
        let spawned = std::thread::Builder::new()
            .name("hal-notice".into())
            .spawn(|| loop {
                std::thread::sleep(POLL);
                let boards: Vec<Arc<Board>> = {
                    let mut all = BOARDS.lock().unwrap_or_else(|e| e.into_inner());
                    all.retain(|w| w.strong_count() > 0);
                    all.iter().filter_map(Weak::upgrade).collect()
                };
                for b in boards {
                    b.flush();
                }
            });
        // Without the helper, messages still come out when the notice is
        // dropped.
        drop(spawned);
    });
}

/// A set of stderr messages one realtime function may post.
pub struct Notice {
    board: Arc<Board>,
}

impl Notice {
    /// A notice able to post any of `texts` (by index). Call outside
    /// realtime (it allocates and may start the helper thread).
    pub fn new(texts: &'static [&'static str]) -> Notice {
        Notice::with_texts(texts.iter().map(|&t| Cow::Borrowed(t)).collect())
    }

    /// A notice whose texts are made at load time (from module
    /// parameters, say). Call outside realtime, as [`Notice::new`].
    pub fn with_texts(texts: Vec<Cow<'static, str>>) -> Notice {
        let n = texts.len();
        let board = Arc::new(Board {
            texts,
            posted: (0..n).map(|_| AtomicU32::new(0)).collect(),
            written: Mutex::new(vec![0; n]),
        });
        BOARDS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(Arc::downgrade(&board));
        start_helper();
        Notice { board }
    }

    /// Posts text `i` for writing; realtime-safe (one atomic add).
    #[inline]
    pub fn post(&self, i: usize) {
        if let Some(c) = self.board.posted.get(i) {
            c.fetch_add(1, Ordering::Release);
        }
    }
}

impl Drop for Notice {
    fn drop(&mut self) {
        self.board.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How many times text `i` of `n` has been posted (0 outside the
    /// table).
    fn posted(n: &Notice, i: usize) -> u32 {
        n.board
            .posted
            .get(i)
            .map_or(0, |c| c.load(Ordering::Acquire))
    }

    #[test]
    fn posts_are_counted_and_flushed_once() {
        static TEXTS: &[&str] = &["", ""];
        let n = Notice::new(TEXTS);
        n.post(0);
        n.post(0);
        n.post(1);
        n.post(7); // out of the table: ignored
        assert_eq!((posted(&n, 0), posted(&n, 1), posted(&n, 7)), (2, 1, 0));
        n.board.flush();
        assert_eq!(*n.board.written.lock().unwrap(), vec![2, 1]);
        n.board.flush();
        assert_eq!(*n.board.written.lock().unwrap(), vec![2, 1]);
    }
}
