//! The udev rules (udev/60-hal-suite.rules) give the `hal` group every
//! hm2_pci board: for each entry of the driver's board table, a rule
//! matching its vendor, device and subsystem IDs changes the group and
//! mode of the BAR file the driver maps and of `enable`.

use hostmot2::pci::BOARDS;

/// udev's glob: literal characters, `*`, `?` and `[...]` classes with
/// ranges.
fn glob(pattern: &str, text: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pattern.chars().collect(), text.chars().collect());
    fn go(p: &[char], t: &[char]) -> bool {
        match p.first() {
            None => t.is_empty(),
            Some('*') => (0..=t.len()).any(|k| go(&p[1..], &t[k..])),
            Some('?') => !t.is_empty() && go(&p[1..], &t[1..]),
            Some('[') => {
                let Some(end) = p.iter().position(|&c| c == ']') else {
                    return false;
                };
                let class = &p[1..end];
                let Some(&c) = t.first() else { return false };
                let mut hit = false;
                let mut i = 0;
                while i < class.len() {
                    if i + 2 < class.len() && class[i + 1] == '-' {
                        hit |= class[i] <= c && c <= class[i + 2];
                        i += 3;
                    } else {
                        hit |= class[i] == c;
                        i += 1;
                    }
                }
                hit && go(&p[end + 1..], &t[1..])
            }
            Some(&c) => t.first() == Some(&c) && go(&p[1..], &t[1..]),
        }
    }
    go(&p, &t)
}

/// The value of `KEY=="value"` (or `KEY{attr}=="value"`) in a rule line.
fn matcher<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let at = line.find(&format!("{key}==\""))? + key.len() + 3;
    line[at..].split('"').next()
}

#[test]
fn every_hm2_pci_board_is_given_to_the_hal_group() {
    let rules_path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../udev/60-hal-suite.rules");
    let rules = std::fs::read_to_string(rules_path).unwrap();
    let lines: Vec<&str> = rules
        .lines()
        .filter(|l| l.contains("SUBSYSTEM==\"pci\""))
        .collect();
    for b in BOARDS {
        let id = |v: u16| format!("0x{v:04x}");
        let ids = b.ids;
        let covered = lines.iter().any(|l| {
            let ok = |key: &str, v: Option<u16>| match (matcher(l, key), v) {
                (Some(p), Some(v)) => glob(p, &id(v)),
                (None, _) => true,
                (Some(_), None) => false,
            };
            ok("ATTR{vendor}", Some(ids.vendor))
                && ok("ATTR{device}", Some(ids.device))
                && ok("ATTR{subsystem_vendor}", ids.subvendor)
                && ok("ATTR{subsystem_device}", ids.subdevice)
                && l.contains("chgrp hal")
                && l.contains(&format!("/sys%p/resource{}", b.bar))
                && l.contains("/sys%p/enable")
                && l.contains("chmod 0660")
        });
        assert!(
            covered,
            "no udev rule gives the hal group {} ({})",
            ids, b.board
        );
    }
    assert!(glob("0x3[34][0-9a-f][0-9a-f]", "0x3472"));
    assert!(!glob("0x3[34][0-9a-f][0-9a-f]", "0x3133"));
    assert!(glob("0x342[789]", "0x3428"));
}
