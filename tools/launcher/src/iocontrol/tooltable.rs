//! LinuxCNC's tool table file (`[EMCIO]TOOL_TABLE`): one tool per line,
//! words `T<tool> P<pocket>` and optionally `D<diameter>`, the offsets
//! `X Y Z A B C U V W`, `I<front angle> J<back angle> Q<orientation>`,
//! then `;` and a comment. Lines that are empty or only a comment are
//! skipped; a line that cannot be read is skipped with a message naming
//! the file and line, as is a tool or (random changer) pocket given twice.
//!
//! Where a tool sits: on a non-random changer the tools take the slots
//! 1, 2, 3... in file order (their `P` is only reported on
//! `tool-prep-pocket`); on a random changer the slot is the pocket number
//! and slot 0 is the spindle. Slot 0 is always the spindle.

use std::fmt::Write as _;
use std::path::Path;

/// Slots a table holds, the spindle included (LinuxCNC's
/// `CANON_POCKETS_MAX`).
pub const POCKETS_MAX: usize = 1000;

/// One tool.
#[derive(Debug, Clone, PartialEq)]
pub struct Tool {
    /// The tool number (`T`).
    pub number: i32,
    /// The pocket (`P`).
    pub pocket: i32,
    /// Offsets X Y Z A B C U V W.
    pub offset: [f64; 9],
    /// `D`.
    pub diameter: f64,
    /// `I`.
    pub front_angle: f64,
    /// `J`.
    pub back_angle: f64,
    /// `Q`.
    pub orientation: i32,
    /// The text after `;`.
    pub comment: String,
}

impl Tool {
    /// A tool with only its number and pocket.
    pub fn new(number: i32, pocket: i32) -> Tool {
        Tool {
            number,
            pocket,
            offset: [0.0; 9],
            diameter: 0.0,
            front_angle: 0.0,
            back_angle: 0.0,
            orientation: 0,
            comment: String::new(),
        }
    }
}

/// A line that was skipped, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableProblem {
    /// The file as named.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// Why it was skipped.
    pub reason: String,
}

impl std::fmt::Display for TableProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.reason)
    }
}

/// A tool table: slot 0 is the spindle.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolTable {
    /// Slots; `None` is empty. Only as long as the highest slot used (at
    /// most [`POCKETS_MAX`]).
    pub slots: Vec<Option<Tool>>,
    /// Whether slots are pockets (random changer).
    pub random: bool,
    /// Lines that were skipped.
    pub problems: Vec<TableProblem>,
}

const AXES: &[u8; 9] = b"XYZABCUVW";

/// Parses one line. `Ok(None)` for a line without a tool.
pub fn parse_line(line: &str) -> Result<Option<Tool>, String> {
    let (data, comment) = match line.split_once(';') {
        Some((d, c)) => (d, c.trim_end_matches(['\r', '\n']).to_string()),
        None => (line, String::new()),
    };
    if data.trim().is_empty() {
        return Ok(None);
    }
    let mut number = None;
    let mut pocket = None;
    let mut tool = Tool::new(0, 0);
    tool.comment = comment;
    for word in data.split_whitespace() {
        let mut chars = word.chars();
        let letter = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or(' ');
        let rest = chars.as_str();
        let int = || {
            rest.parse::<i32>()
                .map_err(|_| format!("'{word}': {letter} needs a whole number"))
        };
        let real = || {
            rest.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{word}': {letter} needs a number"))
        };
        match letter {
            'T' => number = Some(int()?),
            'P' => pocket = Some(int()?),
            'D' => tool.diameter = real()?,
            'I' => tool.front_angle = real()?,
            'J' => tool.back_angle = real()?,
            'Q' => tool.orientation = int()?,
            c if AXES.contains(&(c as u8)) && c.is_ascii() => {
                let i = AXES.iter().position(|&a| a == c as u8).unwrap_or(0);
                tool.offset[i] = real()?;
            }
            _ => return Err(format!("unknown word '{word}'")),
        }
    }
    tool.number = number.ok_or("no T word (tool number)")?;
    tool.pocket = pocket.ok_or("no P word (pocket)")?;
    if tool.number < 0 {
        return Err(format!("tool number {} is negative", tool.number));
    }
    Ok(Some(tool))
}

impl ToolTable {
    /// An empty table.
    pub fn empty(random: bool) -> ToolTable {
        ToolTable {
            slots: vec![None],
            random,
            problems: Vec::new(),
        }
    }

    /// Puts `tool` in `slot`, growing the table.
    pub fn put(&mut self, slot: usize, tool: Option<Tool>) {
        if slot >= self.slots.len() {
            self.slots.resize(slot + 1, None);
        }
        self.slots[slot] = tool;
    }

    /// Parses the text of a table file named `file` (for messages).
    pub fn parse(text: &str, file: &str, random: bool) -> ToolTable {
        let mut t = ToolTable::empty(random);
        let mut next_slot = 1;
        for (i, line) in text.lines().enumerate() {
            let problem = |reason: String| TableProblem {
                file: file.to_string(),
                line: i + 1,
                reason,
            };
            let tool = match parse_line(line) {
                Ok(Some(tool)) => tool,
                Ok(None) => continue,
                Err(reason) => {
                    t.problems.push(problem(format!("line skipped: {reason}")));
                    continue;
                }
            };
            if t.slot_of(tool.number).is_some() {
                t.problems.push(problem(format!(
                    "tool {} is listed more than once; line skipped",
                    tool.number
                )));
                continue;
            }
            let slot = if random {
                match usize::try_from(tool.pocket) {
                    Ok(p) if p < POCKETS_MAX => p,
                    _ => {
                        t.problems.push(problem(format!(
                            "pocket {} is outside 0..{}; line skipped",
                            tool.pocket,
                            POCKETS_MAX - 1
                        )));
                        continue;
                    }
                }
            } else {
                if next_slot >= POCKETS_MAX {
                    t.problems.push(problem(format!(
                        "more than {} tools; line skipped",
                        POCKETS_MAX - 1
                    )));
                    continue;
                }
                next_slot += 1;
                next_slot - 1
            };
            if t.tool(slot).is_some() {
                t.problems.push(problem(format!(
                    "pocket {} is listed more than once; line skipped",
                    tool.pocket
                )));
                continue;
            }
            t.put(slot, Some(tool));
        }
        t
    }

    /// Reads a table file.
    pub fn load(path: &Path, random: bool) -> std::io::Result<ToolTable> {
        let text = std::fs::read_to_string(path)?;
        Ok(ToolTable::parse(&text, &path.display().to_string(), random))
    }

    /// The slot holding tool `number` (the spindle, slot 0, included on a
    /// random changer; on a non-random one slot 0 is a copy).
    pub fn slot_of(&self, number: i32) -> Option<usize> {
        let first = if self.random { 0 } else { 1 };
        (first..self.slots.len())
            .find(|&i| self.slots[i].as_ref().is_some_and(|t| t.number == number))
    }

    /// The tool in slot `slot`.
    pub fn tool(&self, slot: usize) -> Option<&Tool> {
        self.slots.get(slot).and_then(Option::as_ref)
    }

    /// The table as LinuxCNC writes it back (random changers save the
    /// table after every change).
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let first = if self.random { 0 } else { 1 };
        for (slot, t) in self.slots.iter().enumerate().skip(first) {
            let Some(t) = t else { continue };
            let pocket = if self.random { slot as i32 } else { t.pocket };
            let _ = write!(s, "T{} P{}", t.number, pocket);
            if t.diameter != 0.0 {
                let _ = write!(s, " D{:.6}", t.diameter);
            }
            for (i, v) in t.offset.iter().enumerate() {
                if *v != 0.0 {
                    let _ = write!(s, " {}{:+.6}", AXES[i] as char, v);
                }
            }
            if t.front_angle != 0.0 {
                let _ = write!(s, " I{:+.6}", t.front_angle);
            }
            if t.back_angle != 0.0 {
                let _ = write!(s, " J{:+.6}", t.back_angle);
            }
            if t.orientation != 0 {
                let _ = write!(s, " Q{}", t.orientation);
            }
            let _ = writeln!(s, " ;{}", t.comment);
        }
        s
    }
}

/// The fuzz target's body: parses arbitrary bytes as a tool table both
/// ways and writes it back. Never panics.
pub fn fuzz_parse(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    for random in [false, true] {
        let t = ToolTable::parse(&text, "fuzz.tbl", random);
        let again = ToolTable::parse(&t.to_text(), "again.tbl", random);
        // What was written reads back to the same tools.
        debug_assert_eq!(
            t.slots.iter().flatten().count(),
            again.slots.iter().flatten().count()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = "\
T1 P1 D0.125 Z+0.511 ;1/8 end mill
T2 P2 D0.0625 Z+0.1 ;1/16 end mill

; a comment line
T3 P3 D0.201 Z+1.273 X0.5 Q2 I10 J-5 ;#7 tap drill
T99999 P99999 Z+0.1 ;big tool number
";

    #[test]
    fn reads_tools_in_file_order_on_a_non_random_changer() {
        let t = ToolTable::parse(TABLE, "sim.tbl", false);
        assert!(t.problems.is_empty(), "{:?}", t.problems);
        assert_eq!(t.tool(1).unwrap().number, 1);
        assert_eq!(t.tool(3).unwrap().offset[2], 1.273);
        assert_eq!(t.tool(3).unwrap().offset[0], 0.5);
        assert_eq!(t.tool(3).unwrap().orientation, 2);
        assert_eq!(t.tool(3).unwrap().comment, "#7 tap drill");
        assert_eq!(t.slot_of(99999), Some(4));
        assert!(t.tool(0).is_none());
    }

    #[test]
    fn random_changers_use_pockets() {
        let t = ToolTable::parse("T5 P0 ;in spindle\nT7 P12\nT8 P1000\n", "r.tbl", true);
        assert_eq!(t.slot_of(5), Some(0));
        assert_eq!(t.slot_of(7), Some(12));
        assert_eq!(t.problems.len(), 1);
        assert_eq!(
            t.problems[0].to_string(),
            "r.tbl:3: pocket 1000 is outside 0..999; line skipped"
        );
    }

    #[test]
    fn bad_lines_name_file_and_line() {
        let t = ToolTable::parse(
            "T1 P1\nT2 P2 Zabc\nP3 D1\nT4 P4 K1\nT1 P5\n",
            "bad.tbl",
            false,
        );
        let msgs: Vec<String> = t.problems.iter().map(|p| p.to_string()).collect();
        assert_eq!(
            msgs,
            [
                "bad.tbl:2: line skipped: 'Zabc': Z needs a number",
                "bad.tbl:3: line skipped: no T word (tool number)",
                "bad.tbl:4: line skipped: unknown word 'K1'",
                "bad.tbl:5: tool 1 is listed more than once; line skipped",
            ]
        );
        assert_eq!(t.slots.iter().flatten().count(), 1);
    }

    #[test]
    fn writes_back_what_it_read() {
        for random in [false, true] {
            let t = ToolTable::parse(TABLE, "sim.tbl", random);
            let again = ToolTable::parse(&t.to_text(), "x", random);
            assert_eq!(t.slots, again.slots);
        }
        fuzz_parse(TABLE.as_bytes());
    }
}
