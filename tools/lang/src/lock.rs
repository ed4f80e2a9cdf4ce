//! halcmd's `lock`, `unlock` and `status`: the lock level each word sets,
//! and the status report, in LinuxCNC's words.

use hal_core::lock_bits::*;
use hal_core::{HalStatistics, Instance};

use crate::error::{LangError, Result};

/// The lock level after `lock WORD` (`set` true) or `unlock WORD` from
/// `current`. As LinuxCNC: `lock` and `lock all` lock everything, `lock
/// none` nothing, `lock tune` loading and configuration only; `unlock`,
/// `unlock all` and `unlock none` unlock everything, `unlock tune` the
/// tune bits. Here also `load`, `config`, `params` and `run` lock or
/// unlock their one bit, leaving the others as they are.
pub fn next_level(current: u8, set: bool, word: Option<&str>) -> Result<u8> {
    let bit = |w: &str| match w {
        "load" => Some(LOAD),
        "config" => Some(CONFIG),
        "params" => Some(PARAMS),
        "run" => Some(RUN),
        "tune" => Some(TUNE),
        _ => None,
    };
    let word = word.unwrap_or("all");
    let level = match (set, word) {
        (true, "all") => ALL,
        (true, "none") | (false, "all") | (false, "none") => NONE,
        (true, "tune") => TUNE,
        (true, w) => current | bit(w).ok_or_else(|| unknown(set, w))?,
        (false, w) => current & !bit(w).ok_or_else(|| unknown(set, w))?,
    };
    Ok(level)
}

fn unknown(set: bool, word: &str) -> LangError {
    let (command, action) = if set {
        ("lock", "Locking")
    } else {
        ("unlock", "Unlocking")
    };
    LangError::LockWord {
        action,
        command,
        word: word.to_string(),
    }
}

/// `status lock`: the lock value and what each set bit locks.
pub fn lock_status(level: u8) -> String {
    let mut s = format!("HAL locking status:\n  current lock value {level} ({level:02x})\n");
    if level == NONE {
        s.push_str("  HAL_LOCK_NONE - nothing is locked\n");
    }
    for (bit, text) in [
        (
            LOAD,
            "  HAL_LOCK_LOAD    - loading of new components is locked\n",
        ),
        (CONFIG, "  HAL_LOCK_CONFIG  - link and addf is locked\n"),
        (PARAMS, "  HAL_LOCK_PARAMS  - setting params is locked\n"),
        (RUN, "  HAL_LOCK_RUN     - running/stopping HAL is locked\n"),
    ] {
        if level & bit != 0 {
            s.push_str(text);
        }
    }
    s
}

/// `status mem`: segment use and live/recycled object counts.
pub fn mem_status(st: &HalStatistics) -> String {
    let row = |label: &str, (a, r): (usize, usize)| format!("  active/recycled {label} {a}/{r}\n");
    [
        "HAL memory status\n".to_string(),
        format!("  used/total shared memory:   {}/{}\n", st.used, st.total),
        row("components:", st.comps),
        row("pins:      ", st.pins),
        row("parameters:", st.params),
        row("aliases:   ", st.aliases),
        row("signals:   ", st.signals),
        row("functions: ", st.functs),
        row("threads:   ", st.threads),
    ]
    .concat()
}

/// `status [lock|mem|all]`.
pub fn status(inst: &Instance, what: Option<&str>) -> Result<String> {
    let mem = || -> Result<String> { Ok(mem_status(&inst.statistics()?)) };
    match what.unwrap_or("all") {
        "all" => Ok(lock_status(inst.lock_level()) + &mem()?),
        "lock" => Ok(lock_status(inst.lock_level())),
        "mem" => mem(),
        other => Err(LangError::UnknownKind {
            command: "status",
            kind: other.to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_set_and_clear_bits_as_linuxcnc() {
        assert_eq!(next_level(0, true, None).unwrap(), ALL);
        assert_eq!(next_level(0, true, Some("tune")).unwrap(), TUNE);
        assert_eq!(next_level(ALL, true, Some("none")).unwrap(), NONE);
        assert_eq!(
            next_level(LOAD, true, Some("params")).unwrap(),
            LOAD | PARAMS
        );
        assert_eq!(next_level(ALL, false, Some("tune")).unwrap(), ALL & !TUNE);
        assert_eq!(next_level(TUNE | RUN, false, Some("run")).unwrap(), TUNE);
        assert_eq!(next_level(ALL, false, None).unwrap(), NONE);
        assert!(next_level(0, true, Some("bogus"))
            .unwrap_err()
            .to_string()
            .starts_with("Locking failed: unknown lock type 'bogus'"));
    }

    #[test]
    fn lock_status_reads_as_linuxcnc() {
        assert_eq!(
            lock_status(0),
            "HAL locking status:\n  current lock value 0 (00)\n  HAL_LOCK_NONE - nothing is locked\n"
        );
        assert_eq!(
            lock_status(255),
            "HAL locking status:\n  current lock value 255 (ff)\n\
             \x20 HAL_LOCK_LOAD    - loading of new components is locked\n\
             \x20 HAL_LOCK_CONFIG  - link and addf is locked\n\
             \x20 HAL_LOCK_PARAMS  - setting params is locked\n\
             \x20 HAL_LOCK_RUN     - running/stopping HAL is locked\n"
        );
    }
}
