//! The shared word table of our modules in LinuxCNC
//! ([`module::words`](crate::module::words) says why and how): the C
//! functions every module image exports (made by `linuxcnc_module!`),
//! and the table a load uses, which calls the first image's.

use std::ffi::{c_char, c_int, CStr, CString};
use std::sync::OnceLock;

use super::api::lookup;
use crate::module::words::{self, ForeignTable};

/// The HAL name our host's table files LinuxCNC's words under.
const HAL: &str = "linuxcnc";

type CPublish = unsafe extern "C" fn(*const c_char, u64) -> u64;
type CRead = unsafe extern "C" fn(*const c_char, *mut u64) -> c_int;
type CWithdraw = unsafe extern "C" fn(u64);

/// The first image's functions.
struct Shared {
    publish: CPublish,
    read: CRead,
    withdraw: CWithdraw,
}

static SHARED: OnceLock<Option<Shared>> = OnceLock::new();

/// The functions in the process's global scope (the first image's), or
/// none (this image's own table then serves, seen by this module only).
fn shared() -> Option<&'static Shared> {
    SHARED
        .get_or_init(|| {
            let publish = lookup(c"hal_suite_word_publish")?;
            let read = lookup(c"hal_suite_word_read")?;
            let withdraw = lookup(c"hal_suite_word_withdraw")?;
            // SAFETY: the symbols are the functions below, exported by
            // one of our module images with these signatures.
            Some(unsafe {
                Shared {
                    publish: std::mem::transmute::<*mut std::ffi::c_void, CPublish>(publish),
                    read: std::mem::transmute::<*mut std::ffi::c_void, CRead>(read),
                    withdraw: std::mem::transmute::<*mut std::ffi::c_void, CWithdraw>(withdraw),
                }
            })
        })
        .as_ref()
}

fn publish(key: &str, word: u64) -> u64 {
    match (shared(), CString::new(key)) {
        // SAFETY: a NUL-terminated key, to the exported function.
        (Some(s), Ok(k)) => unsafe { (s.publish)(k.as_ptr(), word) },
        _ => words::publish_local(HAL, key, word),
    }
}

fn read(key: &str) -> Option<u64> {
    match (shared(), CString::new(key)) {
        (Some(s), Ok(k)) => {
            let mut word = 0u64;
            // SAFETY: a NUL-terminated key and a valid out pointer.
            let found = unsafe { (s.read)(k.as_ptr(), &mut word) };
            (found != 0).then_some(word)
        }
        _ => words::read_local(HAL, key),
    }
}

fn withdraw(id: u64) {
    match shared() {
        // SAFETY: an id the same function table handed out.
        Some(s) => unsafe { (s.withdraw)(id) },
        None => words::withdraw_local(id),
    }
}

/// The table a load in LinuxCNC uses.
pub(crate) fn table() -> ForeignTable {
    ForeignTable {
        publish,
        read,
        withdraw,
    }
}

/// The key behind a C pointer, if it is one.
///
/// # Safety
/// `key` is null or NUL-terminated.
unsafe fn key_of<'a>(key: *const c_char) -> Option<&'a str> {
    if key.is_null() {
        return None;
    }
    // SAFETY: the caller's promise.
    unsafe { CStr::from_ptr(key) }.to_str().ok()
}

/// `hal_suite_word_publish` of this image.
///
/// # Safety
/// `key` is null or NUL-terminated.
pub unsafe fn c_publish(key: *const c_char, word: u64) -> u64 {
    // SAFETY: the caller's promise.
    match unsafe { key_of(key) } {
        Some(k) => words::publish_local(HAL, k, word),
        None => 0,
    }
}

/// `hal_suite_word_read` of this image: 1 and the word in `out`, or 0.
///
/// # Safety
/// `key` is null or NUL-terminated; `out` is null or valid for a write.
pub unsafe fn c_read(key: *const c_char, out: *mut u64) -> c_int {
    // SAFETY: the caller's promise.
    let key = unsafe { key_of(key) };
    match (key.and_then(|k| words::read_local(HAL, k)), out.is_null()) {
        (Some(w), false) => {
            // SAFETY: the caller's promise.
            unsafe { out.write(w) };
            1
        }
        _ => 0,
    }
}

/// `hal_suite_word_withdraw` of this image.
pub fn c_withdraw(id: u64) {
    words::withdraw_local(id)
}
