//! carousel's module parameters: `pockets=`, `encoding=`, `dir=`,
//! `num_sense=` and `parity=`, one entry per instance. The number of
//! instances is the number of leading non-zero `pockets` entries (one when
//! none is given), and an entry left out takes the value the previous
//! instance used (the first instance: 8 pockets, gray code, both
//! directions, 4 sense pins, even parity).

use hal_core::module::{ModuleArgs, ParamDecl, ParamKind};
use hal_core::{HalError, Result};

/// Most carousels one load may create.
pub const MAX_CHAN: usize = 8;
/// Most sense pins an instance may have.
pub const MAX_SENSE: usize = 32;

/// How the carousel reports its position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// Gray code on the sense pins (`gray`).
    Gray,
    /// Plain binary (`binary`).
    Binary,
    /// Binary-coded decimal, four pins per digit (`bcd`).
    Bcd,
    /// One sensor per pocket (`single`).
    Single,
    /// An index sensor (`sense-0`) and a pocket sensor (`sense-1`)
    /// (`index`).
    Index,
    /// As index, with pockets on both edges of the pocket sensor (`edge`).
    Edge,
    /// Encoder or stepgen counts (`counts`).
    Counts,
}

impl Encoding {
    /// The encoding a `encoding=` entry names.
    pub fn parse(s: &str) -> Option<Encoding> {
        Some(match s {
            "gray" => Encoding::Gray,
            "binary" => Encoding::Binary,
            "bcd" => Encoding::Bcd,
            "single" => Encoding::Single,
            "index" => Encoding::Index,
            "edge" => Encoding::Edge,
            "counts" => Encoding::Counts,
            _ => return None,
        })
    }

    /// Whether the carousel must find its home before it knows where it
    /// is.
    pub fn needs_homing(self) -> bool {
        matches!(self, Encoding::Index | Encoding::Edge | Encoding::Counts)
    }
}

/// One instance's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Number of pockets (at least 1).
    pub pockets: i32,
    /// Position encoding.
    pub encoding: Encoding,
    /// TRUE when the carousel may turn both ways (`dir=2`).
    pub bidirectional: bool,
    /// Number of `sense-N` pins.
    pub sense: usize,
    /// Parity the encoder's parity bit makes: 0 even, 1 odd.
    pub parity: i32,
}

/// carousel's module parameters (and `personality=`, which halcompile
/// declares but carousel overrides with the number of sense pins).
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "pockets",
        kind: ParamKind::IntArray(MAX_CHAN),
        help: "number of pockets in each carousel",
    },
    ParamDecl {
        name: "encoding",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "position feedback type: gray, binary, bcd, single, index, edge or counts",
    },
    ParamDecl {
        name: "dir",
        kind: ParamKind::IntArray(MAX_CHAN),
        help: "1 for unidirectional, 2 for bidirectional",
    },
    ParamDecl {
        name: "num_sense",
        kind: ParamKind::IntArray(MAX_CHAN),
        help: "number of sense pins to create",
    },
    ParamDecl {
        name: "parity",
        kind: ParamKind::IntArray(MAX_CHAN),
        help: "0 for even parity, 1 for odd",
    },
    crate::halcomp::PERSONALITY,
];

/// Entry `i` of an int array whose first element defaults to -1 and the
/// rest to 0 (LinuxCNC's initialisers).
fn entry(given: &[i64], i: usize) -> i64 {
    given.get(i).copied().unwrap_or(if i == 0 { -1 } else { 0 })
}

/// The configuration of every instance the arguments ask for.
pub fn configs(args: &ModuleArgs) -> Result<Vec<Config>> {
    let bad = |param: &str, reason: String| HalError::ModuleParam {
        module: "carousel".into(),
        param: param.into(),
        reason,
    };
    let pockets = args.int_array("pockets");
    let count = (0..MAX_CHAN)
        .take_while(|&i| entry(pockets, i) != 0)
        .count()
        .max(1);
    let mut cur = Config {
        pockets: 8,
        encoding: Encoding::Gray,
        bidirectional: true,
        sense: 4,
        parity: 0,
    };
    let mut out = Vec::with_capacity(count);
    for i in 0..count {
        match entry(pockets, i) {
            p if p > 0 => cur.pockets = p as i32,
            -1 if i == 0 && pockets.is_empty() => {}
            0 => {}
            p => return Err(bad("pockets", format!("{p}: must be positive"))),
        }
        match args.str_array("encoding").get(i).map(String::as_str) {
            None | Some("") => {}
            Some(e) => {
                cur.encoding = Encoding::parse(e).ok_or_else(|| {
                    bad(
                        "encoding",
                        format!("'{e}': expected gray, binary, bcd, single, index, edge or counts"),
                    )
                })?;
            }
        }
        let dir = entry(args.int_array("dir"), i);
        if dir > 0 {
            cur.bidirectional = dir > 1;
        }
        match entry(args.int_array("parity"), i) {
            -1 => {}
            p @ (0 | 1) => cur.parity = p as i32,
            p => return Err(bad("parity", format!("{p}: expected 0 (even) or 1 (odd)"))),
        }
        let num_sense = entry(args.int_array("num_sense"), i);
        if cur.encoding == Encoding::Index {
            cur.sense = 2;
        } else if num_sense > 0 {
            cur.sense = num_sense.min(MAX_SENSE as i64 + 1) as usize;
        }
        let mut inst = cur;
        if inst.encoding == Encoding::Single && inst.sense < inst.pockets as usize {
            inst.sense = inst.pockets as usize;
        }
        if inst.sense > MAX_SENSE {
            return Err(bad(
                "num_sense",
                format!(
                    "carousel {i} needs {} sense pins, at most {MAX_SENSE} allowed",
                    inst.sense
                ),
            ));
        }
        out.push(inst);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(a: &[&str]) -> Result<Vec<Config>> {
        configs(&ModuleArgs::parse("carousel", PARAMS, a)?)
    }

    #[test]
    fn defaults_make_one_gray_carousel() {
        assert_eq!(
            parse(&[]).unwrap(),
            [Config {
                pockets: 8,
                encoding: Encoding::Gray,
                bidirectional: true,
                sense: 4,
                parity: 0
            }]
        );
        assert_eq!(parse(&["pockets=0"]).unwrap().len(), 1);
    }

    #[test]
    fn entries_cascade_from_the_previous_instance() {
        let c = parse(&[
            "pockets=10,12,6",
            "encoding=binary,,index",
            "dir=1",
            "num_sense=5",
            "parity=1",
        ])
        .unwrap();
        assert_eq!(c.len(), 3);
        assert_eq!((c[0].pockets, c[1].pockets, c[2].pockets), (10, 12, 6));
        assert_eq!(c[1].encoding, Encoding::Binary, "empty entry keeps binary");
        assert_eq!(c[2].encoding, Encoding::Index);
        assert!(c.iter().all(|c| !c.bidirectional));
        assert_eq!((c[0].sense, c[1].sense, c[2].sense), (5, 5, 2));
        // LinuxCNC's parity entries after the first default to 0, not -1.
        assert_eq!((c[0].parity, c[1].parity), (1, 0));
    }

    #[test]
    fn single_sensors_cover_every_pocket_and_index_sticks() {
        let c = parse(&["pockets=12,3", "encoding=single,gray"]).unwrap();
        assert_eq!((c[0].sense, c[1].sense), (12, 4));
        let c = parse(&["pockets=6,6", "encoding=index,gray"]).unwrap();
        assert_eq!(c[1].sense, 2, "index mode's 2 sense pins carry over");
    }

    #[test]
    fn bad_entries_fail() {
        for bad in [
            &["encoding=grey"][..],
            &["pockets=-3"],
            &["parity=2"],
            &["num_sense=33"],
            &["pockets=40", "encoding=single"],
            &["pockets=1,2,3,4,5,6,7,8,9"],
        ] {
            assert!(parse(bad).is_err(), "{bad:?}");
        }
    }
}
