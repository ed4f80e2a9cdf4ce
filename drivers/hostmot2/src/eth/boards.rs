//! The Ethernet board table (hostmot2-more.md 1.5): which board a
//! space-7 name is, its HAL name, connectors and FPGA part, matched as
//! hm2_eth matches them (in this order; `7I92` shadows `7I92T`).

use crate::llio::Llio;

/// How a table entry matches the space-7 name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Match {
    /// The name starts with the entry's text.
    Prefix,
    /// The name is the entry's text.
    Exact,
}

/// One kind of Ethernet board.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EthKind {
    /// The space-7 name or its start (`7I96S`, `7I76E-16`).
    pub name: &'static str,
    /// How it matches.
    pub matching: Match,
    /// The board type in HAL names (`7i96s` in `hm2_7i96s.0`).
    pub board: &'static str,
    /// Connector names, in I/O order.
    pub connectors: &'static [&'static str],
    /// Pins per connector.
    pub pins: u32,
    /// The FPGA part hm2_eth reports.
    pub fpga_part: &'static str,
}

const fn kind(
    name: &'static str,
    matching: Match,
    board: &'static str,
    connectors: &'static [&'static str],
    pins: u32,
    fpga_part: &'static str,
) -> EthKind {
    EthKind {
        name,
        matching,
        board,
        connectors,
        pins,
        fpga_part,
    }
}

use Match::{Exact, Prefix};

/// Every Ethernet board hm2_eth knows, in its matching order.
pub const BOARDS: &[EthKind] = &[
    kind(
        "7I80DB-16",
        Prefix,
        "7i80",
        &["J2", "J3", "J4", "J5"],
        17,
        "XC6SLX16",
    ),
    kind(
        "7I80DB-25",
        Prefix,
        "7i80",
        &["J2", "J3", "J4", "J5"],
        17,
        "XC6SLX25",
    ),
    kind(
        "7I80HD-16",
        Prefix,
        "7i80",
        &["P1", "P2", "P3"],
        24,
        "XC6SLX16",
    ),
    kind(
        "7I80HD-25",
        Prefix,
        "7i80",
        &["P1", "P2", "P3"],
        24,
        "XC6SLX25",
    ),
    kind(
        "7I80HDT",
        Prefix,
        "7i80",
        &["P1", "P2", "P3"],
        24,
        "T20F256",
    ),
    kind(
        "7I76E-16",
        Prefix,
        "7i76e",
        &["P1", "P2", "P3"],
        17,
        "XC6SLX16",
    ),
    kind("7I76EU", Exact, "7i76e", &["P1", "P2", "P3"], 17, "T20F256"),
    kind("7I92", Prefix, "7i92", &["P2", "P1"], 17, "XC6SLX9"),
    kind("7I93", Prefix, "7i93", &["P2", "P1"], 24, "XC6SLX9"),
    kind("7I94", Exact, "7i94", &["P2", "J1,J4"], 21, "XC6SLX9"),
    kind("7I94T", Exact, "7i94", &["P2", "J1,J4"], 21, "T20F256"),
    kind("7I95", Exact, "7i95", &["P1", "TB1"], 29, "XC6SLX9"),
    kind("7I95T", Exact, "7i95", &["P1", "TB1"], 29, "T20F256"),
    kind("7I96", Exact, "7i96", &["P1", "TB1", "TB2"], 17, "XC6SLX9"),
    kind(
        "7I96S",
        Exact,
        "7i96s",
        &["P1", "TB1", "TB2"],
        17,
        "T20F256",
    ),
    kind("7I97", Exact, "7i97", &["P1", "TB1", "TB2"], 17, "XC6SLX9"),
    kind("7I97T", Exact, "7i97", &["P1", "TB1", "TB2"], 17, "T20F256"),
    kind("7I98", Prefix, "7i98", &["P1", "P2", "P3"], 17, "XC6SLX9"),
    kind("MC04", Prefix, "mc04", &["P1", "P2"], 30, "XC6SLX9"),
    kind("8CSS", Prefix, "8css", &["P1", "P2"], 30, "XC6SLX9"),
];

/// LEDs hm2_eth gives every board.
pub const LEDS: u32 = 4;

/// The space-7 name as text: up to the first NUL, non-printables as `?`.
pub fn name_text(raw: &[u8]) -> String {
    raw.iter()
        .take_while(|&&b| b != 0)
        .map(|&b| if b.is_ascii_graphic() { b as char } else { '?' })
        .collect()
}

/// The table entry for a space-7 name.
pub fn lookup(name: &str) -> Option<&'static EthKind> {
    BOARDS.iter().find(|k| match k.matching {
        Prefix => name.starts_with(k.name),
        Exact => name == k.name,
    })
}

impl EthKind {
    /// The llio of board number `n` of this type.
    pub fn llio(&self, n: usize) -> Llio {
        Llio {
            name: format!("hm2_{}.{n}", self.board),
            connectors: self.connectors.iter().map(|c| c.to_string()).collect(),
            pins_per_connector: self.pins,
            num_leds: LEDS,
            fpga_part: self.fpga_part.to_string(),
        }
    }
}

/// The llio of a board the table does not know, from its IDROM: named
/// after the first four characters of its space-7 name, connectors `??`
/// (LinuxCNC: "port names will be wrong"), part `??`, no LEDs.
pub fn unknown_llio(name: &str, n: usize, connectors: u32, pins: u32) -> Llio {
    let short: String = name
        .chars()
        .take(4)
        .map(|c| c.to_ascii_lowercase())
        .filter(|c| c.is_ascii_alphanumeric())
        .collect();
    let short = if short.is_empty() {
        "eth".into()
    } else {
        short
    };
    Llio {
        name: format!("hm2_{short}.{n}"),
        connectors: vec!["??".to_string(); connectors as usize],
        pins_per_connector: pins,
        num_leds: 0,
        fpga_part: "??".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_as_hm2_eth_matches_them() {
        assert_eq!(lookup("7I96S").unwrap().board, "7i96s");
        assert_eq!(lookup("7I96").unwrap().board, "7i96");
        assert_eq!(lookup("7I76E-16").unwrap().board, "7i76e");
        assert!(lookup("7I76E").is_none(), "the 16 is part of the match");
        assert_eq!(
            lookup("7I92T").unwrap().fpga_part,
            "XC6SLX9",
            "shadowed by 7I92"
        );
        assert_eq!(lookup("7I80DB-25").unwrap().connectors.len(), 4);
        assert!(lookup("7I96SX").is_none());
        assert_eq!(lookup("7I96S").unwrap().llio(1).name, "hm2_7i96s.1");
        assert_eq!(name_text(b"7I96S\0\0\0\x01"), "7I96S");
        assert_eq!(name_text(b"7I\x0196"), "7I?96");
        let u = unknown_llio("litehm2", 0, 3, 24);
        assert_eq!(u.name, "hm2_lite.0");
        assert!(u.validate().is_ok());
    }
}
