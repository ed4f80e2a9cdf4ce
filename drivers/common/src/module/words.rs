//! Words one module leaves for the modules loaded after it into the same
//! HAL: hostmot2's debug switches for hm2_pci, hm2_eth and hm2_test,
//! which also refuse to load without it.
//!
//! A word is a `u64` under a key, visible while the module that
//! published it holds its [`PublishedWord`]. In our host every module is
//! code of the host's process, so one table per process serves, keyed by
//! the HAL instance. In LinuxCNC each module is an image of its own with
//! its own copy of this crate; there the table of the first of our
//! modules `rtapi_app` loaded serves them all: every module image
//! exports the three functions of [`ForeignTable`] (`linuxcnc_module!`
//! makes them), and a load finds them in the process's global scope,
//! where the first image's come first. Images are never unmapped (they
//! are linked `-z nodelete`), so that table outlives every module.

use std::sync::Mutex;

/// One published word.
struct Entry {
    instance: String,
    key: String,
    word: u64,
    id: u64,
}

/// This image's table, and the next id it hands out.
static TABLE: Mutex<(Vec<Entry>, u64)> = Mutex::new((Vec::new(), 1));

fn table() -> std::sync::MutexGuard<'static, (Vec<Entry>, u64)> {
    TABLE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Publishes `word` under `key` in HAL `instance` in this image's table,
/// replacing an earlier word of that key; returns the id that withdraws it.
pub fn publish_local(instance: &str, key: &str, word: u64) -> u64 {
    let mut t = table();
    let id = t.1;
    t.1 += 1;
    t.0.retain(|e| !(e.instance == instance && e.key == key));
    t.0.push(Entry {
        instance: instance.to_string(),
        key: key.to_string(),
        word,
        id,
    });
    id
}

/// The word under `key` in HAL `instance` in this image's table.
pub fn read_local(instance: &str, key: &str) -> Option<u64> {
    table()
        .0
        .iter()
        .find(|e| e.instance == instance && e.key == key)
        .map(|e| e.word)
}

/// Withdraws the word published with `id` (a word replaced since stays).
pub fn withdraw_local(id: u64) {
    table().0.retain(|e| e.id != id);
}

/// The three C functions through which LinuxCNC modules share one table
/// (see the module docs); keys are NUL-terminated, the HAL is LinuxCNC's.
#[derive(Clone, Copy, Debug)]
pub struct ForeignTable {
    /// `publish(key, word) -> id`.
    pub publish: fn(&str, u64) -> u64,
    /// `read(key) -> word`.
    pub read: fn(&str) -> Option<u64>,
    /// `withdraw(id)`.
    pub withdraw: fn(u64),
}

/// Where a load's words go.
#[derive(Clone, Debug)]
pub(crate) enum Words {
    /// This image's table, under our host's instance name.
    Local(String),
    /// A table shared by foreign-host module images.
    Foreign(ForeignTable),
}

impl Words {
    pub(crate) fn publish(&self, key: &str, word: u64) -> PublishedWord {
        match self {
            Words::Local(instance) => PublishedWord {
                id: publish_local(instance, key, word),
                withdraw: withdraw_local,
            },
            Words::Foreign(t) => PublishedWord {
                id: (t.publish)(key, word),
                withdraw: t.withdraw,
            },
        }
    }

    pub(crate) fn read(&self, key: &str) -> Option<u64> {
        match self {
            Words::Local(instance) => read_local(instance, key),
            Words::Foreign(t) => (t.read)(key),
        }
    }
}

/// A word published by [`LoadEnv::publish_word`](super::LoadEnv::publish_word);
/// dropping it withdraws the word. Keep it with the module's component
/// ([`Exporter::keep`](super::Exporter::keep)).
pub struct PublishedWord {
    id: u64,
    withdraw: fn(u64),
}

impl std::fmt::Debug for PublishedWord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PublishedWord")
            .field("id", &self.id)
            .finish()
    }
}

impl Drop for PublishedWord {
    fn drop(&mut self) {
        (self.withdraw)(self.id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_per_instance_and_go_with_their_holder() {
        let a = Words::Local("words-a".into());
        let b = Words::Local("words-b".into());
        assert_eq!(a.read("core"), None);
        let held = a.publish("core", 7);
        assert_eq!(a.read("core"), Some(7));
        assert_eq!(b.read("core"), None);
        let newer = a.publish("core", 9);
        assert_eq!(a.read("core"), Some(9));
        drop(held);
        assert_eq!(
            a.read("core"),
            Some(9),
            "a replaced word's holder withdraws nothing"
        );
        drop(newer);
        assert_eq!(a.read("core"), None);
    }
}
