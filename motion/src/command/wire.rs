//! How a command's fields travel in a command record: one field may be
//! the record's slot word (a joint or axis number, or a queued move's
//! motion id), every other field takes float argument words in
//! declaration order ([`WireArg`]). Fields that carry whole numbers must
//! hold a whole number in range when read back.

use super::{LineKind, ProbeType, TermCond};
use crate::kins::{Pose, NUM_AXES};
use crate::vocab::{HomeFlags, HomingConfig};

/// How a field travels in float argument words.
pub(crate) trait WireArg: Sized {
    /// How many words it takes.
    const WORDS: usize;
    /// Writes the value into `out[..Self::WORDS]`.
    fn put(&self, out: &mut [f64]);
    /// Reads the value from `a[..Self::WORDS]`; `Err(i)` if word `i` does
    /// not hold a whole number in range where one belongs.
    fn get(a: &[f64]) -> Result<Self, usize>;
}

/// Word `i` of `a` as a whole number in `lo..=hi`.
fn whole(a: &[f64], i: usize, lo: f64, hi: f64) -> Result<f64, usize> {
    let v = a[i];
    if v.fract() == 0.0 && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(i)
    }
}

const I32_MIN: f64 = i32::MIN as f64;
const I32_MAX: f64 = i32::MAX as f64;

impl WireArg for f64 {
    const WORDS: usize = 1;
    fn put(&self, out: &mut [f64]) {
        out[0] = *self;
    }
    fn get(a: &[f64]) -> Result<Self, usize> {
        Ok(a[0])
    }
}

impl WireArg for i32 {
    const WORDS: usize = 1;
    fn put(&self, out: &mut [f64]) {
        out[0] = f64::from(*self);
    }
    fn get(a: &[f64]) -> Result<Self, usize> {
        // In range and whole, so the conversion is exact.
        whole(a, 0, I32_MIN, I32_MAX).map(|v| v as i32)
    }
}

impl WireArg for bool {
    const WORDS: usize = 1;
    fn put(&self, out: &mut [f64]) {
        out[0] = f64::from(u8::from(*self));
    }
    fn get(a: &[f64]) -> Result<Self, usize> {
        whole(a, 0, 0.0, 1.0).map(|v| v != 0.0)
    }
}

impl WireArg for Pose {
    const WORDS: usize = NUM_AXES;
    fn put(&self, out: &mut [f64]) {
        out[..NUM_AXES].copy_from_slice(&self.0);
    }
    fn get(a: &[f64]) -> Result<Self, usize> {
        let mut p = Pose::ZERO;
        p.0.copy_from_slice(&a[..NUM_AXES]);
        Ok(p)
    }
}

impl WireArg for [f64; 3] {
    const WORDS: usize = 3;
    fn put(&self, out: &mut [f64]) {
        out[..3].copy_from_slice(self);
    }
    fn get(a: &[f64]) -> Result<Self, usize> {
        Ok([a[0], a[1], a[2]])
    }
}

/// The coded queueing values travel as their codes (`$max` the largest).
macro_rules! wire_by_code {
    ($($t:ty: $code:ident, $from:ident, $max:literal;)*) => {$(
        impl WireArg for $t {
            const WORDS: usize = 1;
            fn put(&self, out: &mut [f64]) {
                out[0] = self.$code() as f64;
            }
            fn get(a: &[f64]) -> Result<Self, usize> {
                let v = whole(a, 0, 0.0, $max)?;
                <$t>::$from(v as u64).ok_or(0)
            }
        }
    )*};
}

wire_by_code! {
    LineKind: code, from_code, 1.0;
    ProbeType: bits, from_bits, 3.0;
    TermCond: code, from_code, 2.0;
}

/// SET_JOINT_HOMING_PARAMS's eight words: the five values, the option
/// bits, HOME_SEQUENCE and VOLATILE_HOME.
impl WireArg for HomingConfig {
    const WORDS: usize = 8;
    fn put(&self, out: &mut [f64]) {
        out[..8].copy_from_slice(&[
            self.offset,
            self.home,
            self.final_vel,
            self.search_vel,
            self.latch_vel,
            f64::from(self.flags.bits()),
            f64::from(self.sequence),
            if self.volatile_home { 1.0 } else { 0.0 },
        ]);
    }
    fn get(a: &[f64]) -> Result<Self, usize> {
        // Whole and in range, so the conversions are exact.
        let flags = whole(a, 5, 0.0, f64::from(u32::MAX))? as u32;
        let sequence = whole(a, 6, I32_MIN, I32_MAX)? as i32;
        let volatile_home = whole(a, 7, 0.0, 1.0)? != 0.0;
        Ok(HomingConfig {
            offset: a[0],
            home: a[1],
            final_vel: a[2],
            search_vel: a[3],
            latch_vel: a[4],
            flags: HomeFlags::from_bits_retain(flags),
            sequence,
            volatile_home,
        })
    }
}

/// Writes a command's fields into a record's slot and argument words.
pub(crate) struct ArgWriter<'a> {
    /// The slot word's value, if the command has one.
    pub slot: Option<i32>,
    /// The argument words.
    args: &'a mut [f64],
    /// How many argument words are written.
    pub len: usize,
}

impl<'a> ArgWriter<'a> {
    /// Writes into `args` (zeroed by the caller).
    pub fn new(args: &'a mut [f64]) -> Self {
        ArgWriter {
            slot: None,
            args,
            len: 0,
        }
    }

    /// The next argument field.
    pub fn arg<T: WireArg>(&mut self, v: &T) {
        v.put(&mut self.args[self.len..self.len + T::WORDS]);
        self.len += T::WORDS;
    }
}

/// Reads a command's fields back from a record's slot and argument words.
pub(crate) struct ArgReader<'a> {
    /// The slot word's value.
    slot: i32,
    /// Whether the command has a slot field.
    pub takes_slot: bool,
    /// The argument words.
    args: &'a [f64],
    /// How many argument words are read.
    pub len: usize,
}

impl<'a> ArgReader<'a> {
    /// Reads from the slot word `slot` and the argument words `args`.
    pub fn new(slot: i32, args: &'a [f64]) -> Self {
        ArgReader {
            slot,
            takes_slot: false,
            args,
            len: 0,
        }
    }

    /// The slot field.
    pub fn slot(&mut self) -> i32 {
        self.takes_slot = true;
        self.slot
    }

    /// The next argument field; `Err(i)` if argument word `i` does not
    /// hold the whole number it should.
    pub fn arg<T: WireArg>(&mut self) -> Result<T, usize> {
        let at = self.len;
        self.len += T::WORDS;
        T::get(&self.args[at..at + T::WORDS]).map_err(|i| at + i)
    }
}
