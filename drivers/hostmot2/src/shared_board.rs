//! A registered board shared by its cycle functions, the safe state and
//! the modules that use its Smart Serial ports or PktUARTs (`setsserial`,
//! `hm2_modbus`, through the [`registry`](crate::registry)).

use std::sync::{Arc, Mutex, TryLockError};

use hal_core::HalHost;
use hal_driver::fault::SafeState;
use hal_driver::pci::EnableGuard;

use crate::board::Board;
use crate::transport::Transport;

/// A registered board shared by its functions and the safe state. The
/// functions of one instance never run at the same time (the host
/// serialises threads), so the lock is never contended: a function takes
/// it with `try_lock`, which never waits, and would skip its cycle rather
/// than block if it ever were.
pub struct SharedBoard<H: HalHost> {
    board: Mutex<Board<H>>,
    /// What must live as long as the board (a PCI device's enable).
    _keep: Option<EnableGuard>,
}

impl<H: HalHost> SharedBoard<H> {
    /// Shares `board`, keeping `keep` alive with it.
    pub fn new(board: Board<H>, keep: Option<EnableGuard>) -> SharedBoard<H> {
        SharedBoard {
            board: Mutex::new(board),
            _keep: keep,
        }
    }

    /// Runs `f` on the board unless another function holds it.
    #[inline]
    pub fn with<R>(&self, f: impl FnOnce(&mut Board<H>) -> R) -> Option<R> {
        match self.board.try_lock() {
            Ok(mut b) => Some(f(&mut b)),
            Err(TryLockError::Poisoned(p)) => Some(f(&mut p.into_inner())),
            Err(TryLockError::WouldBlock) => None,
        }
    }
}

impl<H: HalHost> crate::registry::SserialAccess for SharedBoard<H>
where
    Board<H>: Send,
{
    fn sserial(&self) -> Option<crate::modules::sserial::discovery::SserialFirmware> {
        let b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.firmware().sserial.clone()
    }

    fn setup_job(
        &self,
        job: &mut dyn FnMut(
            &mut dyn Transport,
            &crate::modules::sserial::discovery::SserialFirmware,
        ),
    ) -> bool {
        let mut b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.sserial_setup(job)
    }

    fn pktuart(&self) -> crate::pktuart::PktUartFirmware {
        let b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.firmware().pktuart.clone()
    }

    fn transport_job(&self, wait: bool, job: &mut dyn FnMut(&mut dyn Transport)) -> bool {
        if wait {
            let mut b = self.board.lock().unwrap_or_else(|e| e.into_inner());
            job(b.transport_mut());
            return true;
        }
        self.with(|b| job(b.transport_mut())).is_some()
    }

    fn attach_pktuart(&self, inst: &crate::pktuart::PktUartInstance) -> crate::Result<usize> {
        let mut b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.attach_pktuart(inst)
    }

    fn detach_pktuart(&self, id: usize) {
        let mut b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.detach_pktuart(id);
    }

    fn link_job(&self, id: usize, job: &mut dyn FnMut(&mut crate::pktuart::PktUartLink)) -> bool {
        self.with(|b| b.pktuart_link(id).map(job).is_some())
            .unwrap_or(false)
    }
}

/// Makes `board` known to the modules that use a loaded board's Smart
/// Serial ports or PktUARTs (`setsserial`, `hm2_modbus`) in HAL
/// `instance`, under the board's name: what the board drivers do for
/// their boards, for a program (or test) that registers a board itself.
/// The entry lasts as long as `board`.
pub fn publish_board<H: HalHost + 'static>(instance: &str, board: &Arc<SharedBoard<H>>)
where
    Board<H>: Send,
{
    let name = board
        .board
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .name()
        .to_string();
    let access: Arc<dyn crate::registry::SserialAccess> = board.clone();
    crate::registry::register(instance, &name, &access);
}

impl<H: HalHost> SafeState for SharedBoard<H> {
    fn go_safe(&self) {
        let mut b = self.board.lock().unwrap_or_else(|e| e.into_inner());
        b.go_safe();
    }
}
