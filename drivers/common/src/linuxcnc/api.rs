//! LinuxCNC's HAL and RTAPI C functions, found at load time.
//!
//! Nothing is linked against LinuxCNC: `rtapi_app` loads `hal_lib.so`
//! with `RTLD_GLOBAL` before any module and exports `rtapi_print_msg`
//! itself, so the functions are in the process's global scope when
//! `rtapi_app_main` runs, and `dlsym(RTLD_DEFAULT, ...)` finds them. A
//! module loaded anywhere else fails with a message instead of a dynamic
//! linker error, and builds and tests link without LinuxCNC. The 64-bit
//! pin and parameter functions exist from LinuxCNC 2.10 on and are
//! optional.
//!
//! The declarations are ours, written from the ABI: `hal_pin_dir_t` and
//! `hal_param_dir_t` are C enums passed as `int`; a pin's data pointer
//! address and a parameter's data address must lie in HAL shared memory.

use std::ffi::{c_char, c_int, c_long, c_void, CStr};
use std::sync::OnceLock;

use crate::error::DriverError;

/// `hal_init(name)`: a new component; its id, or a negative errno.
pub(crate) type HalInit = unsafe extern "C" fn(*const c_char) -> c_int;
/// `hal_ready(comp_id)`, `hal_exit(comp_id)`.
pub(crate) type HalCompCall = unsafe extern "C" fn(c_int) -> c_int;
/// `hal_malloc(size)`: never freed; null when shared memory is full.
pub(crate) type HalMalloc = unsafe extern "C" fn(c_long) -> *mut c_void;
/// `hal_pin_<type>_newf(dir, data_ptr_addr, comp_id, fmt, ...)`.
pub(crate) type PinNewf =
    unsafe extern "C" fn(c_int, *mut *mut c_void, c_int, *const c_char, ...) -> c_int;
/// `hal_param_<type>_newf(dir, data_addr, comp_id, fmt, ...)`.
pub(crate) type ParamNewf =
    unsafe extern "C" fn(c_int, *mut c_void, c_int, *const c_char, ...) -> c_int;
/// A HAL function as LinuxCNC calls it: `(arg, period)`.
pub(crate) type FunctCall = unsafe extern "C" fn(*mut c_void, c_long);
/// `hal_export_funct(name, funct, arg, uses_fp, reentrant, comp_id)`.
pub(crate) type ExportFunct =
    unsafe extern "C" fn(*const c_char, FunctCall, *mut c_void, c_int, c_int, c_int) -> c_int;
/// `rtapi_print_msg(level, fmt, ...)`.
pub(crate) type PrintMsg = unsafe extern "C" fn(c_int, *const c_char, ...);

/// One pin or parameter function per HAL type, in [`hal_core::HalType`]
/// order (bit, float, s32, u32, s64, u64); the 64-bit ones may be absent.
pub(crate) struct PerType<F> {
    pub(crate) bit: F,
    pub(crate) float: F,
    pub(crate) s32: F,
    pub(crate) u32: F,
    pub(crate) s64: Option<F>,
    pub(crate) u64: Option<F>,
}

/// The functions a module calls.
pub(crate) struct Api {
    pub(crate) hal_init: HalInit,
    pub(crate) hal_ready: HalCompCall,
    pub(crate) hal_exit: HalCompCall,
    pub(crate) hal_malloc: HalMalloc,
    pub(crate) pin_newf: PerType<PinNewf>,
    pub(crate) param_newf: PerType<ParamNewf>,
    pub(crate) export_funct: ExportFunct,
    pub(crate) print_msg: PrintMsg,
}

static API: OnceLock<Api> = OnceLock::new();

/// The address of `name` in the process's global scope.
fn lookup(name: &CStr) -> Option<*mut c_void> {
    // SAFETY: dlsym with RTLD_DEFAULT and a NUL-terminated name only
    // reads the dynamic linker's tables.
    let p = unsafe { libc::dlsym(libc::RTLD_DEFAULT, name.as_ptr()) };
    (!p.is_null()).then_some(p)
}

/// Looks `name` up as a function of type `$ty` (a function pointer type
/// whose signature is LinuxCNC's for that name).
macro_rules! find {
    ($name:literal, $ty:ty) => {
        match lookup($name) {
            // SAFETY: the symbol is LinuxCNC's function of that name,
            // whose C signature the target type declares.
            Some(p) => Some(unsafe { std::mem::transmute::<*mut c_void, $ty>(p) }),
            None => None,
        }
    };
}

/// LinuxCNC's functions, found on first use; an error when this process
/// is not LinuxCNC's `rtapi_app` (or its `hal_lib` is not loaded).
pub(crate) fn api() -> Result<&'static Api, DriverError> {
    if let Some(a) = API.get() {
        return Ok(a);
    }
    let missing = |name: &str| DriverError::Unsupported {
        what: format!("LinuxCNC's {name}"),
        reason: "not found in this process: the module must be loaded by LinuxCNC's \
                 rtapi_app (halcmd loadrt), with hal_lib loaded"
            .into(),
    };
    macro_rules! need {
        ($name:literal, $ty:ty) => {
            find!($name, $ty).ok_or_else(|| missing($name.to_str().unwrap_or("?")))?
        };
    }
    let api = Api {
        hal_init: need!(c"hal_init", HalInit),
        hal_ready: need!(c"hal_ready", HalCompCall),
        hal_exit: need!(c"hal_exit", HalCompCall),
        hal_malloc: need!(c"hal_malloc", HalMalloc),
        pin_newf: PerType {
            bit: need!(c"hal_pin_bit_newf", PinNewf),
            float: need!(c"hal_pin_float_newf", PinNewf),
            s32: need!(c"hal_pin_s32_newf", PinNewf),
            u32: need!(c"hal_pin_u32_newf", PinNewf),
            s64: find!(c"hal_pin_s64_newf", PinNewf),
            u64: find!(c"hal_pin_u64_newf", PinNewf),
        },
        param_newf: PerType {
            bit: need!(c"hal_param_bit_newf", ParamNewf),
            float: need!(c"hal_param_float_newf", ParamNewf),
            s32: need!(c"hal_param_s32_newf", ParamNewf),
            u32: need!(c"hal_param_u32_newf", ParamNewf),
            s64: find!(c"hal_param_s64_newf", ParamNewf),
            u64: find!(c"hal_param_u64_newf", ParamNewf),
        },
        export_funct: need!(c"hal_export_funct", ExportFunct),
        print_msg: need!(c"rtapi_print_msg", PrintMsg),
    };
    Ok(API.get_or_init(|| api))
}

/// The functions, if [`api`] found them already (the realtime message
/// path uses this: it must not look anything up).
pub(crate) fn loaded() -> Option<&'static Api> {
    API.get()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outside_linuxcnc_the_module_says_where_it_must_run() {
        let e = api().err().expect("no LinuxCNC in a test process");
        let m = e.to_string();
        assert!(m.starts_with("LinuxCNC's hal_init: not found"), "{m}");
        assert!(m.contains("rtapi_app"), "{m}");
        assert!(loaded().is_none());
    }
}
