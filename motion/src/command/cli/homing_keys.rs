//! A joint's homing configuration as `KEY=VALUE` words with the
//! `[JOINT_n]` INI keys (`HOME_SEQUENCE=1 HOME_USE_INDEX=YES`), each key
//! described once in [`KEYS`].

use super::CliError;
use crate::vocab::{HomeFlags, HomingConfig};

/// What a key sets.
#[derive(Clone, Copy)]
enum Key {
    Offset,
    Home,
    SearchVel,
    LatchVel,
    FinalVel,
    Sequence,
    VolatileHome,
    /// A YES/NO option bit.
    Flag(HomeFlags),
    /// HOME_ABSOLUTE_ENCODER: 0 none, 1 absolute, 2 absolute without the
    /// final move.
    AbsoluteEncoder,
}

/// Every key, in the order they are written back.
const KEYS: [(&str, Key); 13] = [
    ("HOME_OFFSET", Key::Offset),
    ("HOME", Key::Home),
    ("HOME_SEARCH_VEL", Key::SearchVel),
    ("HOME_LATCH_VEL", Key::LatchVel),
    ("HOME_FINAL_VEL", Key::FinalVel),
    ("HOME_SEQUENCE", Key::Sequence),
    ("VOLATILE_HOME", Key::VolatileHome),
    ("HOME_USE_INDEX", Key::Flag(HomeFlags::USE_INDEX)),
    (
        "HOME_INDEX_NO_ENCODER_RESET",
        Key::Flag(HomeFlags::INDEX_NO_ENCODER_RESET),
    ),
    ("HOME_IGNORE_LIMITS", Key::Flag(HomeFlags::IGNORE_LIMITS)),
    ("HOME_IS_SHARED", Key::Flag(HomeFlags::IS_SHARED)),
    ("LOCKING_INDEXER", Key::Flag(HomeFlags::UNLOCK_FIRST)),
    ("HOME_ABSOLUTE_ENCODER", Key::AbsoluteEncoder),
];

/// The option bits HOME_ABSOLUTE_ENCODER 0, 1 and 2 set.
const ABSOLUTE: [HomeFlags; 3] = [
    HomeFlags::empty(),
    HomeFlags::ABSOLUTE_ENCODER.union(HomeFlags::NO_REHOME),
    HomeFlags::ABSOLUTE_ENCODER
        .union(HomeFlags::NO_REHOME)
        .union(HomeFlags::NO_FINAL_MOVE),
];

/// Every bit HOME_ABSOLUTE_ENCODER sets.
const ABSOLUTE_BITS: HomeFlags = ABSOLUTE[2];

/// The configuration of `words`, starting from the INI defaults.
pub(super) fn read(words: &[String]) -> Result<HomingConfig, CliError> {
    let mut config = HomingConfig {
        final_vel: -1.0,
        sequence: 999,
        ..HomingConfig::default()
    };
    for word in words {
        let (key, v) = word
            .split_once('=')
            .ok_or_else(|| CliError::NotKeyValue { word: word.clone() })?;
        let key = key.to_ascii_uppercase();
        let Some(&(_, what)) = KEYS.iter().find(|(k, _)| *k == key) else {
            return Err(CliError::UnknownHomingKey { key });
        };
        set(&mut config, what, &key, v)?;
    }
    Ok(config)
}

/// Sets key `key` (which sets `what`) to `v`.
fn set(config: &mut HomingConfig, what: Key, key: &str, v: &str) -> Result<(), CliError> {
    let num = || {
        v.parse::<f64>().map_err(|_| CliError::NotNumber {
            what: key.to_string(),
            text: v.to_string(),
        })
    };
    match what {
        Key::Offset => config.offset = num()?,
        Key::Home => config.home = num()?,
        Key::SearchVel => config.search_vel = num()?,
        Key::LatchVel => config.latch_vel = num()?,
        Key::FinalVel => config.final_vel = num()?,
        Key::Sequence => {
            config.sequence = v.parse().map_err(|_| CliError::NotInteger {
                what: "HOME_SEQUENCE",
                text: v.to_string(),
            })?
        }
        Key::VolatileHome => config.volatile_home = yes_no(key, v)?,
        Key::Flag(bit) => config.flags.set(bit, yes_no(key, v)?),
        Key::AbsoluteEncoder => {
            let level = ["0", "1", "2"]
                .iter()
                .position(|l| *l == v)
                .ok_or_else(|| CliError::NotAbsoluteEncoder {
                    text: v.to_string(),
                })?;
            config.flags.remove(ABSOLUTE_BITS);
            config.flags.insert(ABSOLUTE[level]);
        }
    }
    Ok(())
}

/// An INI-style yes/no value.
fn yes_no(key: &str, v: &str) -> Result<bool, CliError> {
    match v.to_ascii_uppercase().as_str() {
        "YES" | "TRUE" | "1" => Ok(true),
        "NO" | "FALSE" | "0" => Ok(false),
        _ => Err(CliError::NotYesNo {
            key: key.to_string(),
            text: v.to_string(),
        }),
    }
}

/// Every key of `config` as a word; `None` if the keys cannot say its
/// option bits.
pub(super) fn write(config: &HomingConfig) -> Option<Vec<String>> {
    let flags = config.flags;
    let level = ABSOLUTE
        .iter()
        .position(|&a| flags.intersection(ABSOLUTE_BITS) == a)?;
    if !flags.difference(HomeFlags::all()).is_empty() {
        return None;
    }
    let yes = |on: bool| if on { "YES" } else { "NO" };
    let words = KEYS.iter().map(|&(key, what)| {
        let v = match what {
            Key::Offset => config.offset.to_string(),
            Key::Home => config.home.to_string(),
            Key::SearchVel => config.search_vel.to_string(),
            Key::LatchVel => config.latch_vel.to_string(),
            Key::FinalVel => config.final_vel.to_string(),
            Key::Sequence => config.sequence.to_string(),
            Key::VolatileHome => yes(config.volatile_home).to_string(),
            Key::Flag(bit) => yes(flags.contains(bit)).to_string(),
            Key::AbsoluteEncoder => level.to_string(),
        };
        format!("{key}={v}")
    });
    Some(words.collect())
}
