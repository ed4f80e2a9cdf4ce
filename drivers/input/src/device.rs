//! What hal_input needs of an input device, whether a kernel event node
//! ([`crate::evdev`]) or a simulated one ([`crate::sim`]), and of the
//! set of devices an inputspec is looked up in.

use std::os::fd::BorrowedFd;
use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::regs::{AbsInfo, Event, InputId};

/// Who a device says it is.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Identity {
    /// Its event node (`/dev/input/event3`).
    pub path: PathBuf,
    /// Its name (`EVIOCGNAME`).
    pub name: String,
    /// Where it is connected (`EVIOCGPHYS`), if it says.
    pub phys: Option<String>,
    /// Bus, vendor, product and version (`EVIOCGID`).
    pub id: InputId,
}

/// An open input device.
pub trait InputDevice: Send {
    /// Who it is.
    fn identity(&self) -> &Identity;

    /// The codes of event type `kind` it has, up to `max`, in order.
    fn codes(&mut self, kind: u16, max: u16) -> Result<Vec<u16>>;

    /// An absolute axis's range and current value.
    fn absinfo(&mut self, code: u16) -> Result<AbsInfo>;

    /// The keys and buttons held down now.
    fn keys_held(&mut self) -> Result<Vec<u16>>;

    /// Takes the device for this process alone (`EVIOCGRAB`): its events
    /// no longer reach the console or the desktop.
    fn grab(&mut self) -> Result<()>;

    /// Appends the events that have arrived to `out`, without waiting.
    /// A device that went away is [`crate::InputError::Gone`].
    fn read_available(&mut self, out: &mut Vec<Event>) -> Result<()>;

    /// Sends one event to the device (an LED's state).
    fn write(&mut self, event: Event) -> Result<()>;

    /// The file to wait on for events, if the device has one.
    fn fd(&self) -> Option<BorrowedFd<'_>>;
}

/// The devices an inputspec is looked up in.
pub trait Catalogue {
    /// What the catalogue is, for messages (`/dev/input`).
    fn describe(&self) -> String;

    /// Whether `path` names a device node that exists.
    fn exists(&self, path: &Path) -> bool;

    /// Every event node, in LinuxCNC's order (`event2` before `event10`).
    fn nodes(&self) -> Vec<PathBuf>;

    /// Opens a node for reading and writing.
    fn open(&self, path: &Path) -> Result<Box<dyn InputDevice>>;
}

/// Orders paths as people count: digit runs by value
/// (`/dev/input/event2` before `/dev/input/event10`).
pub fn human_order(a: &Path, b: &Path) -> std::cmp::Ordering {
    fn pieces(s: &str) -> Vec<(bool, &str)> {
        let mut out = Vec::new();
        let mut start = 0;
        let bytes = s.as_bytes();
        for i in 1..=bytes.len() {
            let boundary =
                i == bytes.len() || bytes[i].is_ascii_digit() != bytes[start].is_ascii_digit();
            if boundary {
                out.push((bytes[start].is_ascii_digit(), &s[start..i]));
                start = i;
            }
        }
        out
    }
    let (a, b) = (a.to_string_lossy(), b.to_string_lossy());
    let (pa, pb) = (pieces(&a), pieces(&b));
    for (x, y) in pa.iter().zip(pb.iter()) {
        let ord = match (x, y) {
            ((true, n), (true, m)) => {
                let (n, m) = (n.trim_start_matches('0'), m.trim_start_matches('0'));
                n.len().cmp(&m.len()).then_with(|| n.cmp(m))
            }
            ((_, s), (_, t)) => s.cmp(t),
        };
        if ord.is_ne() {
            return ord;
        }
    }
    pa.len().cmp(&pb.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn event_nodes_sort_by_number() {
        let mut v: Vec<PathBuf> = ["event10", "event2", "event1", "event02x"]
            .iter()
            .map(|n| Path::new("/dev/input").join(n))
            .collect();
        v.sort_by(|a, b| human_order(a, b));
        let names: Vec<String> = v
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["event1", "event2", "event02x", "event10"]);
    }
}
