//! Pins and parameters in LinuxCNC's HAL shared memory.
//!
//! A LinuxCNC pin is a pointer cell (allocated by us with `hal_malloc`)
//! that LinuxCNC keeps pointing at the pin's value: its own dummy signal,
//! or the signal it is linked to (`net` rewrites the cell). A parameter
//! is a value cell of ours that LinuxCNC reads and writes in place. The
//! values have C's layout: `hal_bit_t` one byte (0 or 1), `hal_float_t`
//! a `double` aligned to 8, `hal_s32_t`/`hal_u32_t` four bytes, and from
//! LinuxCNC 2.10 on `hal_s64_t`/`hal_u64_t` eight.
//!
//! Accesses are relaxed atomic loads and stores of the value's width
//! (plain moves on x86): another thread of `rtapi_app` or a `halcmd` in
//! another process may write the same memory at any time. A `get` is two
//! loads (the pointer cell, then the value), as in LinuxCNC's own
//! components; the match on the value type is resolved at compile time.

use std::ffi::c_void;
use std::marker::PhantomData;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicI32, AtomicPtr, AtomicU32, AtomicU64, AtomicU8, Ordering::Relaxed};

use hal_core::{Direction, HalHost, HalType, HostParam, HostPin, ParamAccess, PinValue, Writable};

/// LinuxCNC's HAL, as seen from a module `rtapi_app` loaded: the host
/// type of a driver's pins there.
#[derive(Debug, Clone, Copy, Default)]
pub struct LinuxCnc;

impl HalHost for LinuxCnc {
    type Pin<T: PinValue, D: Direction> = LcncPin<T, D>;
    type Param<T: PinValue, A: ParamAccess> = LcncParam<T, A>;
}

/// Reads a value of type `T` at `p`.
///
/// # Safety
/// `p` points to a live, suitably aligned value of `T`'s HAL type.
#[inline(always)]
unsafe fn load<T: PinValue>(p: *const c_void) -> T {
    // SAFETY: the caller's contract (all arms); atomics of the value's
    // width have its size and alignment.
    unsafe {
        match T::HAL_TYPE {
            HalType::Bit => T::from_bits(((*p.cast::<AtomicU8>()).load(Relaxed) != 0) as u64),
            HalType::S32 => T::from_bits((*p.cast::<AtomicI32>()).load(Relaxed) as i64 as u64),
            HalType::U32 => T::from_bits((*p.cast::<AtomicU32>()).load(Relaxed) as u64),
            HalType::Float | HalType::S64 | HalType::U64 => {
                T::from_bits((*p.cast::<AtomicU64>()).load(Relaxed))
            }
            // No value type is a port: nothing to read.
            HalType::Port => T::from_bits(0),
        }
    }
}

/// Writes `v` at `p`.
///
/// # Safety
/// As for [`load`].
#[inline(always)]
unsafe fn store<T: PinValue>(p: *const c_void, v: T) {
    let bits = v.to_bits();
    // SAFETY: as in `load` (all arms).
    unsafe {
        match T::HAL_TYPE {
            HalType::Bit => (*p.cast::<AtomicU8>()).store((bits != 0) as u8, Relaxed),
            HalType::S32 => (*p.cast::<AtomicI32>()).store(bits as i32, Relaxed),
            HalType::U32 => (*p.cast::<AtomicU32>()).store(bits as u32, Relaxed),
            HalType::Float | HalType::S64 | HalType::U64 => {
                (*p.cast::<AtomicU64>()).store(bits, Relaxed)
            }
            // No value type is a port: nothing to write.
            HalType::Port => {}
        }
    }
}

/// A LinuxCNC pin of value type `T` and direction `D`.
pub struct LcncPin<T: PinValue, D: Direction> {
    /// The pin's pointer cell in HAL shared memory.
    cell: NonNull<AtomicPtr<c_void>>,
    _marker: PhantomData<fn() -> (T, D)>,
}

// SAFETY: the handle only makes atomic accesses to HAL shared memory,
// which stays mapped for the life of the process.
unsafe impl<T: PinValue, D: Direction> Send for LcncPin<T, D> {}
// SAFETY: as above.
unsafe impl<T: PinValue, D: Direction> Sync for LcncPin<T, D> {}

impl<T: PinValue, D: Direction> LcncPin<T, D> {
    /// A handle on the pin whose pointer cell is `cell`.
    ///
    /// # Safety
    /// `cell` is a pin's data pointer address that LinuxCNC keeps
    /// pointing at a live value of `T`'s HAL type in shared memory.
    pub(crate) unsafe fn new(cell: NonNull<c_void>) -> Self {
        LcncPin {
            cell: cell.cast(),
            _marker: PhantomData,
        }
    }

    #[inline(always)]
    fn value(&self) -> *const c_void {
        // SAFETY: `new`'s contract: the cell lives in shared memory.
        unsafe { self.cell.as_ref() }.load(Relaxed)
    }
}

impl<T: PinValue, D: Direction> Clone for LcncPin<T, D> {
    fn clone(&self) -> Self {
        LcncPin {
            cell: self.cell,
            _marker: PhantomData,
        }
    }
}

impl<T: PinValue, D: Direction> HostPin<T, D> for LcncPin<T, D> {
    #[inline(always)]
    fn get(&self) -> T {
        // SAFETY: LinuxCNC keeps the cell pointing at a value of the
        // pin's type (`new`'s contract).
        unsafe { load(self.value()) }
    }

    #[inline(always)]
    fn set(&self, v: T)
    where
        D: Writable,
    {
        // SAFETY: as in `get`.
        unsafe { store(self.value(), v) }
    }

    #[inline(always)]
    fn overwrite(&self, v: T) {
        // SAFETY: as in `get`.
        unsafe { store(self.value(), v) }
    }
}

/// A LinuxCNC parameter of value type `T` and access `A`.
pub struct LcncParam<T: PinValue, A: ParamAccess> {
    /// The value cell in HAL shared memory.
    cell: NonNull<c_void>,
    _marker: PhantomData<fn() -> (T, A)>,
}

// SAFETY: as for LcncPin.
unsafe impl<T: PinValue, A: ParamAccess> Send for LcncParam<T, A> {}
// SAFETY: as above.
unsafe impl<T: PinValue, A: ParamAccess> Sync for LcncParam<T, A> {}

impl<T: PinValue, A: ParamAccess> LcncParam<T, A> {
    /// A handle on the parameter whose value lives at `cell`.
    ///
    /// # Safety
    /// `cell` is an 8-byte, 8-aligned cell in HAL shared memory that
    /// stays allocated while the handle is used.
    pub(crate) unsafe fn new(cell: NonNull<c_void>) -> Self {
        LcncParam {
            cell,
            _marker: PhantomData,
        }
    }
}

impl<T: PinValue, A: ParamAccess> Clone for LcncParam<T, A> {
    fn clone(&self) -> Self {
        LcncParam {
            cell: self.cell,
            _marker: PhantomData,
        }
    }
}

impl<T: PinValue, A: ParamAccess> HostParam<T, A> for LcncParam<T, A> {
    #[inline(always)]
    fn get(&self) -> T {
        // SAFETY: `new`'s contract.
        unsafe { load(self.cell.as_ptr()) }
    }

    #[inline(always)]
    fn set(&self, v: T) {
        // SAFETY: `new`'s contract.
        unsafe { store(self.cell.as_ptr(), v) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::{In, Out, Rw};

    /// Values keep C's layout: a bit is one byte, s32 four, float eight.
    #[test]
    fn handles_read_and_write_c_layout_through_the_pointer_cell() {
        let value: *mut u64 = Box::into_raw(Box::new([0u64; 2])).cast();
        let other: *mut u64 = Box::into_raw(Box::new(7u64));
        let cell: *mut *mut c_void = Box::into_raw(Box::new(value.cast::<c_void>()));
        let cell_nn = NonNull::new(cell.cast::<c_void>()).expect("boxed");
        // SAFETY: (the whole test) the cell points at `value` (16 aligned
        // bytes) or `other`, all alive until freed at the end.
        unsafe {
            let bit: LcncPin<bool, Out> = LcncPin::new(cell_nn);
            let s32: LcncPin<i32, Out> = LcncPin::new(cell_nn);
            let float: LcncPin<f64, In> = LcncPin::new(cell_nn);
            bit.set(true);
            assert_eq!(*value, 1, "a bit is one byte, 1");
            s32.set(-2);
            assert_eq!(*value as u32, 0xFFFF_FFFE);
            assert_eq!(s32.get(), -2);
            float.overwrite(1.5);
            assert_eq!(*value, 1.5f64.to_bits());
            assert_eq!(float.get(), 1.5);
            // `net` relinks: the cell now points elsewhere.
            *cell = other.cast();
            assert_eq!(s32.get(), 7);
            let p: LcncParam<u32, Rw> =
                LcncParam::new(NonNull::new(value.add(1).cast()).expect("in box"));
            p.set(42);
            assert_eq!(p.get(), 42);
            assert_eq!(*value.add(1), 42);
            drop(Box::from_raw(cell));
            drop(Box::from_raw(other));
            drop(Box::from_raw(value.cast::<[u64; 2]>()));
        }
    }
}
