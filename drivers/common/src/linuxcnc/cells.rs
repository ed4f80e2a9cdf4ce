//! Cells in LinuxCNC's HAL shared memory, reused across loads.
//!
//! LinuxCNC wants a pin's data pointer address and a parameter's value in
//! its shared memory, which only `hal_malloc` hands out and nothing ever
//! frees. A module that called `hal_malloc` on every load would use more
//! shared memory each time it is loaded and unloaded. So every cell a
//! module uses is 8 bytes (a pointer, or any HAL value), taken from a
//! pool that `hal_malloc` fills a chunk at a time, and given back to the
//! pool once the component that used it is gone (`hal_exit` returned).
//! The module image stays loaded between loads (`-z nodelete`), and with
//! it the pool: after the first load, loading again takes no new shared
//! memory.

use std::ffi::{c_long, c_void};
use std::ptr::NonNull;
use std::sync::Mutex;

use super::api::Api;

/// Cells one `hal_malloc` call provides.
const CHUNK: usize = 64;
const CELL: usize = 8;

/// A free cell's address (a plain number, so the pool is `Send`).
type Addr = usize;

static FREE: Mutex<Vec<Addr>> = Mutex::new(Vec::new());

fn free_list() -> std::sync::MutexGuard<'static, Vec<Addr>> {
    FREE.lock().unwrap_or_else(|e| e.into_inner())
}

/// An 8-byte, 8-aligned cell in HAL shared memory, zeroed; `None` when
/// shared memory is full.
pub(crate) fn take(api: &Api) -> Option<NonNull<c_void>> {
    let mut free = free_list();
    if free.is_empty() {
        refill(api, &mut free)?;
    }
    let addr = free.pop()?;
    let cell = NonNull::new(addr as *mut c_void)?;
    // SAFETY: the address is an 8-aligned cell of a hal_malloc block that
    // no live component uses (it is on the free list).
    unsafe { cell.cast::<u64>().as_ptr().write(0) };
    Some(cell)
}

/// Returns cells whose component LinuxCNC has removed (`hal_exit`), or
/// that were never handed to LinuxCNC.
pub(crate) fn give_back(cells: impl IntoIterator<Item = NonNull<c_void>>) {
    free_list().extend(cells.into_iter().map(|c| c.as_ptr() as Addr));
}

/// Adds one `hal_malloc` block's cells to the free list.
fn refill(api: &Api, free: &mut Vec<Addr>) -> Option<()> {
    // One spare cell, so the block holds CHUNK aligned cells whatever
    // alignment hal_malloc gives.
    let bytes = (CHUNK + 1) * CELL;
    // SAFETY: hal_malloc takes a size and returns shared memory or null.
    let block = unsafe { (api.hal_malloc)(bytes as c_long) };
    if block.is_null() {
        return None;
    }
    let first = (block as Addr).next_multiple_of(CELL);
    free.extend((0..CHUNK).rev().map(|i| first + i * CELL));
    Some(())
}
