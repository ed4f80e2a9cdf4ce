//! From line names to requests: each name is looked up on every chip,
//! and the lines are grouped into one bulk request per chip and
//! direction (split in requests of at most [`LINES_MAX`] lines, the
//! kernel's limit).
//!
//! A name that no chip has, or that more than one line has (on one chip
//! or on several), is a load error naming it and, for the second case,
//! every line that has it: taking the first match, as a plain directory
//! scan would, could drive a line the integrator never meant.

use crate::cfg::{Config, Direction};
use crate::chip::{ChipInfo, LineSetting};
use crate::error::GpioError;
use crate::regs::LINES_MAX;

/// One bulk request to make: lines of one chip and direction.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    /// Index of the chip in the discovery list.
    pub chip: usize,
    /// Input or output.
    pub direction: Direction,
    /// The lines, ascending by offset (request bit k = `lines[k]`).
    pub lines: Vec<LineSetting>,
    /// For each line, the index of its [`crate::cfg::LineSpec`] in the
    /// config.
    pub specs: Vec<usize>,
}

/// Where a line name was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Place {
    chip: usize,
    offset: u32,
}

/// Every line carrying `name`.
fn places(chips: &[ChipInfo], name: &str) -> Vec<Place> {
    chips
        .iter()
        .enumerate()
        .flat_map(|(c, chip)| {
            chip.line_names
                .iter()
                .enumerate()
                .filter(move |(_, n)| n.as_str() == name)
                .map(move |(o, _)| Place {
                    chip: c,
                    offset: o as u32,
                })
        })
        .collect()
}

/// The chips, for "searched ..." messages.
fn chip_list(chips: &[ChipInfo]) -> String {
    if chips.is_empty() {
        return "no chips".into();
    }
    chips
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The request groups for `cfg` on `chips`, chips in discovery order,
/// inputs before outputs on each chip.
pub fn resolve(cfg: &Config, chips: &[ChipInfo]) -> Result<Vec<Group>, GpioError> {
    let mut found: Vec<(usize, Place)> = Vec::with_capacity(cfg.lines.len());
    for (s, spec) in cfg.lines.iter().enumerate() {
        let param = match spec.direction {
            Direction::Input => "inputs",
            Direction::Output => "outputs",
        };
        let index = spec.item;
        let at = places(chips, &spec.name);
        match at.as_slice() {
            [] => {
                return Err(GpioError::LineNotFound {
                    param,
                    item: index,
                    name: spec.name.clone(),
                    searched: chip_list(chips),
                })
            }
            [one] => found.push((s, *one)),
            many => {
                return Err(GpioError::LineAmbiguous {
                    param,
                    item: index,
                    name: spec.name.clone(),
                    places: many
                        .iter()
                        .map(|p| format!("{} line {}", chips[p.chip], p.offset))
                        .collect::<Vec<_>>()
                        .join(" and "),
                })
            }
        }
    }
    let mut groups = Vec::new();
    for chip in 0..chips.len() {
        for direction in [Direction::Input, Direction::Output] {
            let mut lines: Vec<(u32, usize)> = found
                .iter()
                .filter(|(s, p)| p.chip == chip && cfg.lines[*s].direction == direction)
                .map(|(s, p)| (p.offset, *s))
                .collect();
            lines.sort_unstable();
            for chunk in lines.chunks(LINES_MAX) {
                groups.push(Group {
                    chip,
                    direction,
                    lines: chunk
                        .iter()
                        .map(|&(offset, s)| {
                            let spec = &cfg.lines[s];
                            LineSetting {
                                offset,
                                direction,
                                active_low: spec.invert,
                                drive: spec.drive,
                                bias: spec.bias,
                            }
                        })
                        .collect(),
                    specs: chunk.iter().map(|&(_, s)| s).collect(),
                });
            }
        }
    }
    Ok(groups)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cfg::{Bias, Drive, LineSpec};

    fn chip(name: &str, lines: &[&str]) -> ChipInfo {
        ChipInfo {
            path: format!("/dev/{name}"),
            name: name.into(),
            label: format!("{name}-label"),
            line_names: lines.iter().map(|s| s.to_string()).collect(),
        }
    }

    fn spec(name: &str, direction: Direction) -> LineSpec {
        LineSpec {
            name: name.into(),
            item: 0,
            direction,
            invert: false,
            reset: false,
            drive: Drive::PushPull,
            bias: Bias::AsIs,
        }
    }

    #[test]
    fn groups_per_chip_and_direction_in_offset_order() {
        let chips = [
            chip("gpiochip0", &["", "A", "B", "C", "D"]),
            chip("gpiochip1", &["E", "F"]),
        ];
        let mut d = spec("D", Direction::Output);
        d.invert = true;
        let cfg = Config {
            lines: vec![
                spec("C", Direction::Input),
                spec("F", Direction::Input),
                spec("A", Direction::Input),
                d,
                spec("B", Direction::Output),
                spec("E", Direction::Output),
            ],
        };
        let g = resolve(&cfg, &chips).unwrap();
        let summary: Vec<_> = g
            .iter()
            .map(|g| {
                (
                    g.chip,
                    g.direction,
                    g.lines.iter().map(|l| l.offset).collect::<Vec<_>>(),
                    g.specs.clone(),
                )
            })
            .collect();
        assert_eq!(
            summary,
            vec![
                (0, Direction::Input, vec![1, 3], vec![2, 0]),
                (0, Direction::Output, vec![2, 4], vec![4, 3]),
                (1, Direction::Input, vec![1], vec![1]),
                (1, Direction::Output, vec![0], vec![5]),
            ]
        );
        assert!(g[1].lines[1].active_low && !g[1].lines[0].active_low);
    }

    #[test]
    fn unknown_and_ambiguous_names_are_load_errors_naming_them() {
        let chips = [
            chip("gpiochip0", &["A", "DUP", "TWICE", "TWICE"]),
            chip("gpiochip1", &["DUP"]),
        ];
        let cfg = Config {
            lines: vec![
                spec("A", Direction::Input),
                LineSpec {
                    item: 1,
                    ..spec("NOPE", Direction::Input)
                },
            ],
        };
        let e = resolve(&cfg, &chips).unwrap_err().to_string();
        assert!(
            e.contains("parameter 'inputs': item 1 \"NOPE\": no GPIO line has this name (searched gpiochip0 [gpiochip0-label], gpiochip1 [gpiochip1-label])"),
            "{e}"
        );
        let cfg = Config {
            lines: vec![spec("DUP", Direction::Output)],
        };
        let e = resolve(&cfg, &chips).unwrap_err().to_string();
        assert!(
            e.contains("parameter 'outputs': item 0 \"DUP\": the name is on more than one line (gpiochip0 [gpiochip0-label] line 1 and gpiochip1 [gpiochip1-label] line 0)"),
            "{e}"
        );
        let cfg = Config {
            lines: vec![spec("TWICE", Direction::Input)],
        };
        let e = resolve(&cfg, &chips).unwrap_err().to_string();
        assert!(
            e.contains("line 2 and gpiochip0 [gpiochip0-label] line 3"),
            "{e}"
        );
        let e = resolve(&cfg, &[]).unwrap_err().to_string();
        assert!(e.contains("searched no chips"), "{e}");
    }

    #[test]
    fn more_than_64_lines_on_a_chip_take_two_requests() {
        let names: Vec<String> = (0..70).map(|i| format!("L{i}")).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let chips = [chip("gpiochip0", &refs)];
        let cfg = Config {
            lines: names.iter().map(|n| spec(n, Direction::Input)).collect(),
        };
        let g = resolve(&cfg, &chips).unwrap();
        assert_eq!(g.len(), 2);
        assert_eq!((g[0].lines.len(), g[1].lines.len()), (64, 6));
        assert_eq!(g[1].lines[0].offset, 64);
    }
}
