//! Whether the kernel is in lockdown mode, which refuses `ioperm`,
//! `/dev/port` and the mmap of PCI resource files to everyone. An `EPERM`
//! from one of those is then not a missing permission, and the message
//! says so.

/// Where the kernel shows its lockdown state: `[none] integrity
/// confidentiality`, the active mode in brackets.
pub const LOCKDOWN_FILE: &str = "/sys/kernel/security/lockdown";

/// Whether `text` (the lockdown file's content) shows an active lockdown.
pub fn parse(text: &str) -> bool {
    text.split_whitespace()
        .find_map(|w| w.strip_prefix('[').and_then(|w| w.strip_suffix(']')))
        .is_some_and(|mode| mode != "none")
}

/// Whether this kernel is locked down (false when it cannot tell).
pub fn active() -> bool {
    std::fs::read_to_string(LOCKDOWN_FILE).is_ok_and(|t| parse(&t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_bracketed_mode() {
        assert!(!parse("[none] integrity confidentiality\n"));
        assert!(parse("none [integrity] confidentiality\n"));
        assert!(parse("none integrity [confidentiality]\n"));
        assert!(!parse(""));
        assert!(!parse("garbage"));
    }
}
