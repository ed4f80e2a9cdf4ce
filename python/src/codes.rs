//! LinuxCNC's numbers for types and directions, as its Python module shows
//! them (`hal.HAL_S32 == 3`, `hal.HAL_OUT == 32`), and the stream keys of
//! sampler and streamer channels.

use hal_core::{HalType, ParamDir, PinDir};

/// `HAL_BIT` and the other type constants, in LinuxCNC's numbering.
pub(crate) const TYPES: [(&str, i32); 7] = [
    ("HAL_BIT", 1),
    ("HAL_FLOAT", 2),
    ("HAL_S32", 3),
    ("HAL_U32", 4),
    ("HAL_PORT", 5),
    ("HAL_S64", 6),
    ("HAL_U64", 7),
];

/// `HAL_IN` and the other direction constants.
pub(crate) const DIRS: [(&str, i32); 6] = [
    ("HAL_IN", 16),
    ("HAL_OUT", 32),
    ("HAL_IO", 48),
    ("HAL_RO", 64),
    ("HAL_WO", 128),
    ("HAL_RW", 192),
];

/// Key of streamer channel 0; channel n is this plus n (LinuxCNC's).
pub(crate) const STREAMER_BASE: i32 = 0x4853_5430;
/// Key of sampler channel 0; channel n is this plus n (LinuxCNC's).
pub(crate) const SAMPLER_BASE: i32 = 0x4853_4130;

/// The HAL type of a LinuxCNC type number; `None` for numbers that are
/// no type.
pub(crate) fn hal_type(code: i64) -> Option<HalType> {
    match code {
        1 => Some(HalType::Bit),
        2 => Some(HalType::Float),
        3 => Some(HalType::S32),
        4 => Some(HalType::U32),
        5 => Some(HalType::Port),
        6 => Some(HalType::S64),
        7 => Some(HalType::U64),
        _ => None,
    }
}

/// LinuxCNC's number of a HAL type.
pub(crate) fn type_code(t: HalType) -> i32 {
    match t {
        HalType::Bit => 1,
        HalType::Float => 2,
        HalType::S32 => 3,
        HalType::U32 => 4,
        HalType::Port => 5,
        HalType::S64 => 6,
        HalType::U64 => 7,
    }
}

/// The name a type has in item reprs (`<hal pin "x" S32-OUT>`).
pub(crate) fn type_label(t: HalType) -> &'static str {
    match t {
        HalType::Bit => "BIT",
        HalType::Float => "FLOAT",
        HalType::S32 => "S32",
        HalType::U32 => "U32",
        HalType::Port => "PORT",
        HalType::S64 => "S64",
        HalType::U64 => "U64",
    }
}

/// The letter of a type in stream type strings and `element_types`.
pub(crate) fn type_letter(t: HalType) -> u8 {
    match t {
        HalType::Bit => b'b',
        HalType::Float => b'f',
        HalType::S32 => b's',
        HalType::U32 => b'u',
        // No stream carries a port; the letter only names it.
        HalType::Port => b'p',
        HalType::S64 => b'l',
        HalType::U64 => b'k',
    }
}

/// The pin direction of a LinuxCNC direction number.
pub(crate) fn pin_dir(code: i64) -> Option<PinDir> {
    match code {
        16 => Some(PinDir::In),
        32 => Some(PinDir::Out),
        48 => Some(PinDir::Io),
        _ => None,
    }
}

/// The param direction of a LinuxCNC direction number.
pub(crate) fn param_dir(code: i64) -> Option<ParamDir> {
    match code {
        64 => Some(ParamDir::Ro),
        192 => Some(ParamDir::Rw),
        _ => None,
    }
}

/// LinuxCNC's number of a pin direction.
pub(crate) fn pin_dir_code(d: PinDir) -> i32 {
    match d {
        PinDir::In => 16,
        PinDir::Out => 32,
        PinDir::Io => 48,
    }
}

/// LinuxCNC's number of a param direction.
pub(crate) fn param_dir_code(d: ParamDir) -> i32 {
    match d {
        ParamDir::Ro => 64,
        ParamDir::Rw => 192,
    }
}

/// The name a direction number has in item reprs.
pub(crate) fn dir_label(code: i32) -> &'static str {
    match code {
        16 => "IN",
        32 => "OUT",
        48 => "IO",
        64 => "RO",
        192 => "RW",
        _ => "unknown",
    }
}

/// The region holding the stream with LinuxCNC key `key`: a sampler or
/// streamer channel's FIFO for their keys, else a stream of its own.
pub(crate) fn stream_region(key: i32) -> String {
    use hal_components::infra::columns::{fifo_name, MAX_CHANNELS};
    let channel = |base: i32| {
        key.checked_sub(base)
            .filter(|n| (0..MAX_CHANNELS as i32).contains(n))
            .map(|n| n as usize)
    };
    if let Some(n) = channel(STREAMER_BASE) {
        fifo_name("streamer", n)
    } else if let Some(n) = channel(SAMPLER_BASE) {
        fifo_name("sampler", n)
    } else {
        format!("stream.{:08x}", key as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_and_direction_numbers_round_trip() {
        for t in HalType::ALL.into_iter().chain([HalType::Port]) {
            assert_eq!(hal_type(type_code(t) as i64), Some(t));
        }
        assert_eq!(hal_type(5), Some(HalType::Port), "HAL_PORT");
        assert_eq!(hal_type(0), None);
        for d in [PinDir::In, PinDir::Out, PinDir::Io] {
            assert_eq!(pin_dir(pin_dir_code(d) as i64), Some(d));
        }
        for d in [ParamDir::Ro, ParamDir::Rw] {
            assert_eq!(param_dir(param_dir_code(d) as i64), Some(d));
        }
        assert_eq!(pin_dir(64), None);
        assert_eq!(param_dir(16), None);
        // The constants agree with the conversions.
        for (name, code) in TYPES {
            let t = hal_type(code as i64).unwrap();
            assert_eq!(t == HalType::Port, name == "HAL_PORT");
        }
        for (name, code) in DIRS {
            let known = pin_dir(code as i64).is_some() || param_dir(code as i64).is_some();
            assert_eq!(known, name != "HAL_WO");
        }
    }

    #[test]
    fn stream_keys_name_sampler_and_streamer_fifos() {
        assert_eq!(stream_region(STREAMER_BASE), "streamer.0.fifo");
        assert_eq!(stream_region(STREAMER_BASE + 7), "streamer.7.fifo");
        assert_eq!(stream_region(SAMPLER_BASE + 2), "sampler.2.fifo");
        assert_eq!(stream_region(STREAMER_BASE + 8), "stream.48535438");
        assert_eq!(stream_region(-1), "stream.ffffffff");
        assert_eq!(stream_region(0x1234), "stream.00001234");
    }
}
