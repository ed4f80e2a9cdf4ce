//! Names of event codes as LinuxCNC's hal_input turns them into pin
//! names (`KEY_A` → `key-a`, `ABS_HAT0X` → `abs-hat0x`), and the id
//! string an inputspec may match.

pub mod table;

use crate::regs::{EV_ABS, EV_KEY, EV_LED, EV_REL};

/// The table of one event type, if hal_input makes pins for it.
fn table_of(kind: u16) -> Option<(&'static [(u16, &'static str)], &'static str)> {
    match kind {
        EV_KEY => Some((table::KEYS, "KEY")),
        EV_ABS => Some((table::ABS, "ABS")),
        EV_REL => Some((table::REL, "REL")),
        EV_LED => Some((table::LEDS, "LED")),
        _ => None,
    }
}

/// The largest code of `kind` hal_input asks the device about: as
/// LinuxCNC's, the codes of the whole bytes of a bitmap that reaches its
/// table's last code (`ABS_MT_DISTANCE` 0x3b: up to 0x3f; `REL_MISC` 9:
/// up to 15, so `REL_WHEEL_HI_RES` is `rel-11`; keys up to 0x2e7).
pub fn last_code(kind: u16) -> Option<u16> {
    let (t, _) = table_of(kind)?;
    let last = t.last().map(|(c, _)| *c)?;
    Some((last / 8) * 8 + 7)
}

/// The name of a code (`BTN_TRIGGER`, `ABS_X`; `KEY_<decimal>` for a code
/// inside the range without a name); `None` past [`last_code`] or for a
/// type without pins.
pub fn code_name(kind: u16, code: u16) -> Option<String> {
    let (t, prefix) = table_of(kind)?;
    if code > last_code(kind)? {
        return None;
    }
    Some(match t.binary_search_by_key(&code, |(c, _)| *c) {
        Ok(i) => t[i].1.to_string(),
        Err(_) => format!("{prefix}_{code}"),
    })
}

/// The pin name of a code name: lower case, `_` as `-`.
pub fn hal_name(name: &str) -> String {
    name.to_ascii_lowercase().replace('_', "-")
}

/// The code a name stands for, for the simulated device's description:
/// a table name of `kind` (any case), `PREFIX_<decimal>`, or a number
/// (decimal or `0x` hex) within the type's range.
pub fn code_by_name(kind: u16, word: &str) -> Option<u16> {
    let (t, prefix) = table_of(kind)?;
    let last = last_code(kind)?;
    let upper = word.to_ascii_uppercase();
    if let Some((c, _)) = t.iter().find(|(_, n)| *n == upper) {
        return Some(*c);
    }
    let number = upper
        .strip_prefix(prefix)
        .and_then(|r| r.strip_prefix('_'))
        .unwrap_or(&upper);
    let code = match number.strip_prefix("0X") {
        Some(hex) => u16::from_str_radix(hex, 16).ok()?,
        None => number.parse::<u16>().ok()?,
    };
    (code <= last).then_some(code)
}

/// The name of an event type for messages (`EV_KEY`), or its number.
pub fn type_name(kind: u16) -> String {
    match kind {
        0x00 => "EV_SYN".into(),
        EV_KEY => "EV_KEY".into(),
        EV_REL => "EV_REL".into(),
        EV_ABS => "EV_ABS".into(),
        0x04 => "EV_MSC".into(),
        0x05 => "EV_SW".into(),
        EV_LED => "EV_LED".into(),
        0x12 => "EV_SND".into(),
        0x14 => "EV_REP".into(),
        0x15 => "EV_FF".into(),
        0x16 => "EV_PWR".into(),
        0x17 => "EV_FF_STATUS".into(),
        other => format!("type {other}"),
    }
}

/// The id string an inputspec is matched against, as LinuxCNC's:
/// `Bus=BUS_USB Vendor=046d Product=c21d Version=0111` (an unknown bus
/// as its decimal number).
pub fn id_string(id: &crate::regs::InputId) -> String {
    let bus = match table::BUSES.iter().find(|(c, _)| *c == id.bustype) {
        Some((_, n)) => (*n).to_string(),
        None => id.bustype.to_string(),
    };
    format!(
        "Bus={bus} Vendor={:04x} Product={:04x} Version={:04x}",
        id.vendor, id.product, id.version
    )
}

/// The short id string: `vendor:product` in hex (`046d:c21d`).
pub fn short_id(id: &crate::regs::InputId) -> String {
    format!("{:04x}:{:04x}", id.vendor, id.product)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regs::InputId;

    #[test]
    fn names_follow_linuxcnc() {
        assert_eq!(code_name(EV_KEY, 30).as_deref(), Some("KEY_A"));
        assert_eq!(code_name(EV_KEY, 0x120).as_deref(), Some("BTN_TRIGGER"));
        assert_eq!(code_name(EV_KEY, 0x130).as_deref(), Some("BTN_A"));
        assert_eq!(code_name(EV_KEY, 0x100).as_deref(), Some("BTN_0"));
        assert_eq!(code_name(EV_KEY, 0x110).as_deref(), Some("BTN_LEFT"));
        assert_eq!(code_name(EV_REL, 8).as_deref(), Some("REL_WHEEL"));
        assert_eq!(code_name(EV_REL, 11).as_deref(), Some("REL_11"));
        assert_eq!(code_name(EV_REL, 16), None);
        assert_eq!(code_name(EV_ABS, 0x3c).as_deref(), Some("ABS_60"));
        assert_eq!(code_name(EV_ABS, 0x40), None);
        assert_eq!(code_name(EV_LED, 15).as_deref(), Some("LED_15"));
        assert_eq!(last_code(EV_KEY), Some(0x2e7));
        assert_eq!(code_name(EV_ABS, 0x10).as_deref(), Some("ABS_HAT0X"));
        assert_eq!(code_name(EV_LED, 0).as_deref(), Some("LED_NUML"));
        assert_eq!(code_name(EV_ABS, 0x0b).as_deref(), Some("ABS_11"));
        assert_eq!(code_name(EV_KEY, 0x2e8), None);
        assert_eq!(code_name(0x05, 0), None);
        assert_eq!(hal_name("BTN_TRIGGER_HAPPY1"), "btn-trigger-happy1");
        assert_eq!(hal_name("ABS_11"), "abs-11");
    }

    #[test]
    fn names_read_back_to_codes() {
        assert_eq!(code_by_name(EV_KEY, "btn_left"), Some(0x110));
        assert_eq!(code_by_name(EV_KEY, "BTN_MOUSE"), None, "alias not kept");
        assert_eq!(code_by_name(EV_ABS, "ABS_11"), Some(11));
        assert_eq!(code_by_name(EV_REL, "0x8"), Some(8));
        assert_eq!(code_by_name(EV_REL, "11"), Some(11));
        assert_eq!(code_by_name(EV_REL, "16"), None);
        assert_eq!(code_by_name(EV_LED, "LED_CAPSL"), Some(1));
        assert_eq!(code_by_name(EV_KEY, "KEY_"), None);
    }

    #[test]
    fn id_strings_as_linuxcnc() {
        let id = InputId {
            bustype: 3,
            vendor: 0x46d,
            product: 0xc21d,
            version: 0x111,
        };
        assert_eq!(
            id_string(&id),
            "Bus=BUS_USB Vendor=046d Product=c21d Version=0111"
        );
        assert_eq!(short_id(&id), "046d:c21d");
        let odd = InputId { bustype: 99, ..id };
        assert!(id_string(&odd).starts_with("Bus=99 "));
    }
}
