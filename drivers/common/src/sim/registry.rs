//! Simulated boards that `loadrt` made, so tests and tools in the same
//! process can reach them (set shaft positions, read what the board
//! drives). Keyed by HAL instance name and a driver-chosen key (e.g.
//! `parport.0`, `hm2_5i25.0`), so several instances in one process stay
//! apart. Entries are weak: a board disappears when its driver unloads.

use std::any::Any;
use std::sync::{Arc, Mutex, Weak};

type Entry = (String, String, Weak<dyn Any + Send + Sync>);

static BOARDS: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

fn boards() -> std::sync::MutexGuard<'static, Vec<Entry>> {
    BOARDS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Records `board` as `key` of `instance`, replacing an earlier board
/// under that key. Call it after the component is ready, so a failed
/// `loadrt` never publishes anything.
pub fn publish<T: Any + Send + Sync>(instance: &str, key: &str, board: &Arc<T>) {
    let board: Arc<dyn Any + Send + Sync> = board.clone();
    publish_any(instance, key, &board);
}

/// [`publish`] for a board whose type is erased already (what the
/// driver layer's exporter holds); [`find`] still finds it by its type.
pub fn publish_any(instance: &str, key: &str, board: &Arc<dyn Any + Send + Sync>) {
    let weak = Arc::downgrade(board);
    let mut b = boards();
    b.retain(|(i, k, w)| w.strong_count() > 0 && !(i == instance && k == key));
    b.push((instance.to_string(), key.to_string(), weak));
}

/// The board published as `key` of `instance`, while its driver is loaded
/// and if it is a `T`.
pub fn find<T: Any + Send + Sync>(instance: &str, key: &str) -> Option<Arc<T>> {
    let b = boards();
    b.iter()
        .find(|(i, k, _)| i == instance && k == key)
        .and_then(|(_, _, w)| w.upgrade())
        .and_then(|a| a.downcast::<T>().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boards_are_found_by_instance_and_key_while_alive() {
        let a = Arc::new(5u32);
        publish("reg-i1", "drv.0", &a);
        publish("reg-i2", "drv.0", &Arc::new(6u32));
        assert_eq!(find::<u32>("reg-i1", "drv.0").as_deref(), Some(&5));
        assert!(find::<u32>("reg-i2", "drv.0").is_none(), "dropped");
        assert!(find::<u64>("reg-i1", "drv.0").is_none(), "other type");
        assert!(find::<u32>("reg-i1", "drv.1").is_none());
        let b = Arc::new(7u32);
        publish("reg-i1", "drv.0", &b);
        assert_eq!(find::<u32>("reg-i1", "drv.0").as_deref(), Some(&7));
        drop((a, b));
        assert!(find::<u32>("reg-i1", "drv.0").is_none());
    }
}
