//! Module parameters as LinuxCNC's `rtapi_app` passes them.
//!
//! For `loadrt NAME key=value ...` rtapi_app looks up, in the module it
//! just loaded, `rtapi_info_address_<key>` (a pointer to the variable),
//! `rtapi_info_type_<key>` (a C string whose first letter is the type)
//! and, for arrays, `rtapi_info_size_<key>` (how many items the variable
//! holds), and stores the value before calling `rtapi_app_main`. Every
//! parameter of ours is declared as type `s`: rtapi_app then stores a
//! `strdup` of each item and checks nothing but the key and the item
//! count, and `rtapi_app_main` rebuilds the `key=value` words and parses
//! them with our host's own parser ([`hal_core::ModuleArgs::parse`]), so
//! numbers are checked and refused with the same messages in both hosts.
//!
//! An item never given stays a null pointer, so "not given" is told from
//! "given as 0" and the driver's defaults apply as in our host. After
//! reading, the strings are freed and the variables cleared: the module
//! image stays loaded between loads (`-z nodelete`), and the next load
//! must not see this one's values.
//!
//! One case is LinuxCNC's parser's own: when it refuses a `loadrt` (an
//! unknown key, too many items) after storing earlier keys of the same
//! command, `rtapi_app_main` never runs, and those earlier values stay
//! for the next `loadrt` of the module in that session, unless that one
//! gives them again.

use std::cell::UnsafeCell;
use std::ffi::{c_char, c_void, CStr};

/// A pointer in an exported symbol (`rtapi_info_address_*`,
/// `rtapi_info_type_*`): the value rtapi_app reads.
#[repr(transparent)]
pub struct SymPtr(pub *const c_void);

// SAFETY: the pointer is only read (by rtapi_app), never written.
unsafe impl Sync for SymPtr {}

impl SymPtr {
    /// A pointer to a C string literal.
    pub const fn c_str(s: &'static CStr) -> SymPtr {
        SymPtr(s.as_ptr().cast())
    }
}

/// The variable of one parameter: `N` C-string pointers (1 for a scalar)
/// that rtapi_app fills with `strdup`ed items.
#[repr(transparent)]
pub struct ArgStore<const N: usize>(UnsafeCell<[*mut c_char; N]>);

// SAFETY: rtapi_app writes the store and rtapi_app_main reads it, both
// from rtapi_app's command thread, one after the other.
unsafe impl<const N: usize> Sync for ArgStore<N> {}

impl<const N: usize> Default for ArgStore<N> {
    fn default() -> Self {
        ArgStore::new()
    }
}

impl<const N: usize> ArgStore<N> {
    /// An empty store: no item given.
    pub const fn new() -> Self {
        ArgStore(UnsafeCell::new([std::ptr::null_mut(); N]))
    }

    /// The variable's address, for `rtapi_info_address_<key>`.
    pub const fn address(&'static self) -> SymPtr {
        SymPtr(self.0.get() as *const c_void)
    }

    /// Appends `key=value` to `out` if rtapi_app stored anything (array
    /// items joined by `,`, as they were given), then frees the strings
    /// and clears the store.
    pub fn take(&self, key: &str, out: &mut Vec<String>) {
        // SAFETY: see the Sync impl: nothing else touches the store while
        // rtapi_app_main runs.
        let items = unsafe { &mut *self.0.get() };
        let given: Vec<String> = items
            .iter()
            .take_while(|p| !p.is_null())
            // SAFETY: a non-null item is a NUL-terminated strdup.
            .map(|&p| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
            .collect();
        if !given.is_empty() {
            out.push(format!("{key}={}", given.join(",")));
        }
        for p in items.iter_mut() {
            if !p.is_null() {
                // SAFETY: rtapi_app made it with strdup (malloc) and
                // nothing else holds it.
                unsafe { libc::free(p.cast()) };
                *p = std::ptr::null_mut();
            }
        }
    }
}

/// The module's parameter symbols and `rtapi_app_main`/`rtapi_app_exit`
/// for `<module>.so`, from the driver type and its parameter table macro:
///
/// ```text
/// hal_driver::linuxcnc_module!(hal_parport::HalParport, hal_parport::hal_parport_params);
/// ```
///
/// Put it in the lib.rs of a `cdylib` crate linked with `-z nodelete`
/// (its build script: `cargo:rustc-cdylib-link-arg=-Wl,-z,nodelete`).
#[macro_export]
macro_rules! linuxcnc_module {
    ($driver:ty, $($table:ident)::+) => {
        $($table)::+!($crate::__linuxcnc_params);

        /// LinuxCNC's entry: loads the module (`halcmd loadrt`).
        #[no_mangle]
        pub extern "C" fn rtapi_app_main() -> ::core::ffi::c_int {
            $crate::linuxcnc::app_main::<$driver>(__linuxcnc_params::take_all())
        }

        /// LinuxCNC's exit: unloads the module (`halcmd unload`).
        #[no_mangle]
        pub extern "C" fn rtapi_app_exit() {
            $crate::linuxcnc::app_exit::<$driver>()
        }
    };
}

/// The `rtapi_info_*` symbols of a parameter table (what
/// [`linuxcnc_module!`] hands the driver's table macro).
#[doc(hidden)]
#[macro_export]
macro_rules! __linuxcnc_params {
    ($($name:ident : $kind:ident $(($n:expr))? = $help:literal),* $(,)?) => {
        #[allow(non_snake_case, non_upper_case_globals, missing_docs)]
        mod __linuxcnc_params {
            $(
                pub mod $name {
                    use $crate::linuxcnc::{ArgStore, SymPtr};
                    const LEN: usize = 1 $(- 1 + $n)?;
                    pub static STORE: ArgStore<LEN> = ArgStore::new();
                    #[export_name = ::core::concat!("rtapi_info_address_", ::core::stringify!($name))]
                    pub static ADDRESS: SymPtr = STORE.address();
                    #[export_name = ::core::concat!("rtapi_info_type_", ::core::stringify!($name))]
                    pub static TYPE: SymPtr = SymPtr::c_str(c"s");
                    #[export_name = ::core::concat!("rtapi_info_description_", ::core::stringify!($name))]
                    pub static DESCRIPTION: SymPtr = SymPtr::c_str(
                        match ::core::ffi::CStr::from_bytes_with_nul(::core::concat!($help, "\0").as_bytes()) {
                            Ok(s) => s,
                            Err(_) => c"",
                        },
                    );
                    $(
                        #[export_name = ::core::concat!("rtapi_info_size_", ::core::stringify!($name))]
                        pub static SIZE: ::core::ffi::c_int = $n as ::core::ffi::c_int;
                    )?
                }
            )*

            /// Every parameter rtapi_app stored, as `key=value` words;
            /// the stores are cleared.
            pub fn take_all() -> ::std::vec::Vec<::std::string::String> {
                let mut out = ::std::vec::Vec::new();
                $( $name::STORE.take(::core::stringify!($name), &mut out); )*
                out
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_items_become_words_and_the_store_empties() {
        static SCALAR: ArgStore<1> = ArgStore::new();
        static ARRAY: ArgStore<4> = ArgStore::new();
        let dup = |s: &CStr| {
            // SAFETY: strdup of a NUL-terminated string, as rtapi_app does.
            unsafe { libc::strdup(s.as_ptr()) }
        };
        // SAFETY: the test plays rtapi_app, the only writer.
        unsafe {
            (*SCALAR.0.get())[0] = dup(c"0 sim");
            (*ARRAY.0.get())[0] = dup(c"1");
            (*ARRAY.0.get())[1] = dup(c"");
            (*ARRAY.0.get())[2] = dup(c"3");
        }
        let mut out = Vec::new();
        SCALAR.take("cfg", &mut out);
        ARRAY.take("ids", &mut out);
        assert_eq!(out, vec!["cfg=0 sim".to_string(), "ids=1,,3".to_string()]);
        out.clear();
        SCALAR.take("cfg", &mut out);
        ARRAY.take("ids", &mut out);
        assert!(out.is_empty(), "a second load sees nothing of the first");
        assert!(!SCALAR.address().0.is_null());
    }
}
