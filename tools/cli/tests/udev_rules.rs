//! The udev rules parse: every line is a list of KEY op "value" pairs with
//! keys udev knows, match keys before assignments, and quoted values; and
//! `udevadm verify` accepts the file where the installed udev has it.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::path::Path;

const MATCH_KEYS: &[&str] = &[
    "KERNEL",
    "SUBSYSTEM",
    "ATTR",
    "ACTION",
    "DRIVER",
    "ENV",
    "TAG",
];
const ASSIGN_KEYS: &[&str] = &["GROUP", "MODE", "OWNER", "RUN", "TAG", "SYMLINK"];

/// Checks one rule line; returns the problem if any. The error is a
/// description for the failing test's message, nothing a caller matches
/// on, so a string is clearer here than an error type.
fn check_line(line: &str) -> Result<(), String> {
    let mut rest = line.trim();
    let mut seen_assign = false;
    let mut pairs = 0;
    while !rest.is_empty() {
        // KEY or KEY{attr}
        let key_end = rest
            .find(|c: char| !(c.is_ascii_uppercase() || c == '_'))
            .ok_or("line ends inside a key")?;
        let key = &rest[..key_end];
        rest = &rest[key_end..];
        if let Some(r) = rest.strip_prefix('{') {
            let close = r.find('}').ok_or("unclosed {attribute}")?;
            if close == 0 {
                return Err(format!("{key}{{}} has an empty attribute"));
            }
            rest = &r[close + 1..];
        }
        let op = ["==", "!=", "+=", "-=", ":=", "="]
            .into_iter()
            .find(|op| rest.starts_with(op))
            .ok_or_else(|| format!("no operator after {key}"))?;
        rest = &rest[op.len()..];
        let is_match = op == "==" || op == "!=";
        let known = if is_match { MATCH_KEYS } else { ASSIGN_KEYS };
        if !known.contains(&key) {
            return Err(format!("unexpected key {key} with {op}"));
        }
        if is_match && seen_assign {
            return Err(format!("match {key} after an assignment"));
        }
        seen_assign |= !is_match;
        let value = rest
            .strip_prefix('"')
            .ok_or_else(|| format!("value of {key} is not quoted"))?;
        let close = value
            .find('"')
            .ok_or_else(|| format!("value of {key} is not closed"))?;
        if key == "MODE"
            && !(value[..close].len() == 4
                && value[..close].chars().all(|c| ('0'..='7').contains(&c)))
        {
            return Err(format!(
                "MODE {:?} is not four octal digits",
                &value[..close]
            ));
        }
        rest = value[close + 1..].trim_start();
        pairs += 1;
        if let Some(r) = rest.strip_prefix(',') {
            rest = r.trim_start();
            if rest.is_empty() {
                return Err("trailing comma".into());
            }
        } else if !rest.is_empty() {
            return Err(format!("missing comma before {rest:?}"));
        }
    }
    if !seen_assign || pairs < 2 {
        return Err("a rule needs at least one match and one assignment".into());
    }
    Ok(())
}

#[test]
fn the_rules_parse() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../udev");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("rules") {
            continue;
        }
        files += 1;
        let text = std::fs::read_to_string(&path).unwrap();
        let mut rules = 0;
        for (i, line) in text.lines().enumerate() {
            if line.trim().is_empty() || line.trim_start().starts_with('#') {
                continue;
            }
            check_line(line).unwrap_or_else(|e| panic!("{}:{}: {e}", path.display(), i + 1));
            rules += 1;
        }
        assert!(rules >= 5, "{} has only {rules} rules", path.display());
        // The real parser, where the installed udev has `verify`.
        if let Ok(out) = std::process::Command::new("udevadm")
            .arg("verify")
            .arg(&path)
            .output()
        {
            let err = String::from_utf8_lossy(&out.stderr);
            if out.status.success() {
                continue;
            }
            if err.contains("Unknown command")
                || err.contains("unknown command")
                || err.contains("invalid option")
            {
                eprintln!("udevadm has no verify here; checked with our own parser only");
            } else {
                panic!("udevadm verify {}: {err}", path.display());
            }
        }
    }
    assert!(files >= 1);
}

#[test]
fn the_checker_rejects_broken_rules() {
    for bad in [
        r#"KERNEL=="x", GROUP="hal", MODE="660""#,
        r#"KERNEL=="x" GROUP="hal""#,
        r#"KERNEL=="x", GROUP="hal"#,
        r#"GROUP="hal", KERNEL=="x""#,
        r#"KERNAL=="x", GROUP="hal""#,
        r#"KERNEL=="x","#,
        r#"ATTR{}=="1", GROUP="hal""#,
    ] {
        assert!(check_line(bad).is_err(), "accepted: {bad}");
    }
    check_line(r#"SUBSYSTEM=="pci", ATTR{vendor}=="0x2718", RUN+="/bin/sh -c 'x'""#).unwrap();
}
