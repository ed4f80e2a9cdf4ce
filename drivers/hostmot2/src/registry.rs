//! The boards registered in each HAL, for `setsserial`: LinuxCNC's
//! setsserial reaches the loaded hostmot2 boards through the driver's
//! global list of them; here each board driver adds its boards to this
//! registry keyed by the HAL's name ([`LoadEnv::instance`]) and board
//! name, so tests in one process never see each other's boards.
//!
//! Entries are weak: an unloaded board is gone from the registry with
//! its last function, and a dead entry is dropped at the next
//! registration. (hal-driver's `sim::registry` is the same idea for
//! simulated boards, found by their concrete type; this one holds real
//! and simulated boards alike behind the `SserialAccess` trait, which a
//! lookup by type cannot give.)
//!
//! [`LoadEnv::instance`]: hal_driver::module::LoadEnv::instance

use std::sync::{Arc, Mutex, Weak};

use crate::modules::sserial::discovery::SserialFirmware;
use crate::pktuart::{PktUartInstance, PktUartLink};
use crate::transport::Transport;

/// What `setsserial` may do with a registered board.
pub(crate) trait SserialAccess: Send + Sync {
    /// What discovery found on the board's Smart Serial ports, if it has
    /// the module.
    fn sserial(&self) -> Option<SserialFirmware>;

    /// Runs `job` with the board's transport while none of its
    /// functions runs (it waits for the one running, if any), then puts
    /// its Smart Serial ports back to idle so they restart normally.
    /// False if the board has no Smart Serial module.
    fn setup_job(&self, job: &mut dyn FnMut(&mut dyn Transport, &SserialFirmware)) -> bool;

    /// The board's PktUARTs (for `hm2_modbus`).
    fn pktuart(&self) -> crate::pktuart::PktUartFirmware;

    /// Runs `job` with the board's transport. With `wait` unset it never
    /// waits (a realtime caller): false if one of the board's functions
    /// holds it now, and `job` did not run.
    fn transport_job(&self, wait: bool, job: &mut dyn FnMut(&mut dyn Transport)) -> bool;

    /// Carries PktUART `inst`'s traffic in the board's bursts (load
    /// time, waits for the board); the link's id.
    fn attach_pktuart(&self, inst: &PktUartInstance) -> crate::error::Result<usize>;

    /// Stops carrying link `id` (unload time, waits for the board).
    fn detach_pktuart(&self, id: usize);

    /// Runs `job` on link `id` unless one of the board's functions holds
    /// the board now (never waits: a realtime caller); false if `job`
    /// did not run.
    fn link_job(&self, id: usize, job: &mut dyn FnMut(&mut PktUartLink)) -> bool;
}

/// One registered board.
struct Entry {
    instance: String,
    name: String,
    board: Weak<dyn SserialAccess>,
}

static BOARDS: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

fn boards() -> std::sync::MutexGuard<'static, Vec<Entry>> {
    BOARDS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Registers board `name` of HAL `instance`, replacing an earlier board
/// of that name (a board reloaded while its old handle still lives).
pub(crate) fn register(instance: &str, name: &str, board: &Arc<dyn SserialAccess>) {
    let mut all = boards();
    all.retain(|e| e.board.strong_count() > 0 && !(e.instance == instance && e.name == name));
    all.push(Entry {
        instance: instance.to_string(),
        name: name.to_string(),
        board: Arc::downgrade(board),
    });
}

/// Every live board of HAL `instance`, in registration order, by name.
pub(crate) fn boards_of(instance: &str) -> Vec<(String, Arc<dyn SserialAccess>)> {
    boards()
        .iter()
        .filter(|e| e.instance == instance)
        .filter_map(|e| Some((e.name.clone(), e.board.upgrade()?)))
        .collect()
}
