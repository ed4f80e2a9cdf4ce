//! Task's `stat` snapshot (`NAME=KIND:VALUE` lines), read for `get`.

use std::collections::HashMap;

/// One snapshot: each name with its value text.
#[derive(Debug, Default, Clone)]
pub struct Snapshot(HashMap<String, String>);

impl Snapshot {
    /// Reads task's answer; lines that are not `NAME=KIND:VALUE` are
    /// passed over.
    pub fn parse(text: &str) -> Snapshot {
        Snapshot(
            text.lines()
                .filter_map(|l| {
                    let (name, rest) = l.split_once('=')?;
                    let (_, value) = rest.split_once(':')?;
                    Some((name.to_string(), value.to_string()))
                })
                .collect(),
        )
    }

    /// The value text of `name`.
    pub fn text(&self, name: &str) -> Option<&str> {
        self.0.get(name).map(String::as_str)
    }

    /// `name` as an integer.
    pub fn int(&self, name: &str) -> Option<i64> {
        self.text(name)?.trim().parse().ok()
    }

    /// `name` as a number.
    pub fn num(&self, name: &str) -> Option<f64> {
        self.text(name)?.trim().parse().ok()
    }

    /// `name` as a list of numbers.
    pub fn nums(&self, name: &str) -> Vec<f64> {
        self.text(name)
            .map(|t| {
                t.split_whitespace()
                    .filter_map(|w| w.parse().ok())
                    .collect()
            })
            .unwrap_or_default()
    }

    /// `name` is a true flag.
    pub fn flag(&self, name: &str) -> bool {
        self.int(name).is_some_and(|v| v != 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_read_by_kind() {
        let s = Snapshot::parse("task_state=i:4\nposition=F:1 2.5 -3\nfile=s:\nbad line\n");
        assert_eq!(s.int("task_state"), Some(4));
        assert_eq!(s.nums("position"), [1.0, 2.5, -3.0]);
        assert_eq!(s.text("file"), Some(""));
        assert!(s.text("bad line").is_none());
        assert!(!s.flag("missing"));
    }
}
