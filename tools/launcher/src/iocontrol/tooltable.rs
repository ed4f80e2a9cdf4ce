//! LinuxCNC's tool table file (`[EMCIO]TOOL_TABLE`): one tool per line,
//! words `T<tool> P<pocket>` and optionally `D<diameter>`, the offsets
//! `X Y Z A B C U V W`, `I<front angle> J<back angle> Q<orientation>`,
//! then `;` and a comment. Lines that are empty or only a comment are
//! kept as they are.
//!
//! A line that cannot be read (a bad number, no `T` or `P`, a tool or
//! random-changer pocket given twice, more tools than slots) is named
//! with its file and line. A reload is complete or changes nothing, and
//! the caller keeps what it had; at start, as in LinuxCNC, the lines that
//! read make the table and the others are said and left out whole (and
//! the file is then never written back, so none of it is lost). Comments and words this reader does
//! not know are kept byte for byte (a Latin-1 comment is not UTF-8, and
//! need not be) and written back as they were.
//!
//! Where a tool sits: on a non-random changer the tools take the slots
//! 1, 2, 3... in file order (their `P` is only reported on
//! `tool-prep-pocket`); on a random changer the slot is the pocket number
//! and slot 0 is the spindle. Slot 0 is always the spindle.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use hal_core::files::{limits, read_user_file, FileError};

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
    /// Words this reader does not know, as they were in the file.
    pub extra: Vec<Vec<u8>>,
    /// The bytes after `;`, as they were in the file (any encoding).
    pub comment: Vec<u8>,
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
            extra: Vec::new(),
            comment: Vec::new(),
        }
    }

    /// The tool as the interpreter's tool table holds it.
    pub fn entry(&self) -> rs274ngc::ToolEntry {
        let [x, y, z, a, b, c, u, v, w] = self.offset;
        rs274ngc::ToolEntry {
            toolno: self.number,
            pocketno: self.pocket,
            offset: rs274ngc::Pose {
                x,
                y,
                z,
                a,
                b,
                c,
                u,
                v,
                w,
            },
            diameter: self.diameter,
            frontangle: self.front_angle,
            backangle: self.back_angle,
            orientation: self.orientation,
        }
    }
}

/// A line that could not be read, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableProblem {
    /// The file as named.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong with it.
    pub reason: String,
}

impl std::fmt::Display for TableProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.reason)
    }
}

/// Why a tool table could not be read completely.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    /// The file itself (missing, not a regular file, too large).
    #[error(transparent)]
    File(#[from] FileError),
    /// Lines that cannot be read; nothing of the table is used.
    #[error("{}", lines(.0))]
    Lines(Vec<TableProblem>),
}

fn lines(problems: &[TableProblem]) -> String {
    let all: Vec<String> = problems.iter().map(ToString::to_string).collect();
    format!(
        "the tool table cannot be read completely, so none of it is used:\n  {}",
        all.join("\n  ")
    )
}

/// A line of the file as the table keeps it for writing back.
#[derive(Debug, Clone, PartialEq)]
enum Layout {
    /// Empty or only a comment: written back as it was.
    Kept(Vec<u8>),
    /// A tool's line: the next tool in slot order goes here.
    Tool,
}

/// A tool table: slot 0 is the spindle.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolTable {
    /// Slots; `None` is empty. Only as long as the highest slot used (at
    /// most [`POCKETS_MAX`]).
    pub slots: Vec<Option<Tool>>,
    /// Whether slots are pockets (random changer).
    pub random: bool,
    /// The file's lines, for writing back.
    layout: Vec<Layout>,
}

const AXES: &[u8; 9] = b"XYZABCUVW";

/// Parses one line (without its newline). `Ok(None)` for a line without
/// a tool.
pub fn parse_line(line: &[u8]) -> Result<Option<Tool>, String> {
    let (data, comment) = match line.iter().position(|&b| b == b';') {
        Some(i) => (&line[..i], line[i + 1..].to_vec()),
        None => (line, Vec::new()),
    };
    let words: Vec<&[u8]> = data
        .split(|b| b.is_ascii_whitespace())
        .filter(|w| !w.is_empty())
        .collect();
    if words.is_empty() {
        return Ok(None);
    }
    let mut number = None;
    let mut pocket = None;
    let mut tool = Tool::new(0, 0);
    tool.comment = comment;
    for word in words {
        let letter = word[0].to_ascii_uppercase();
        let known = b"TPDIJQ".contains(&letter) || AXES.contains(&letter);
        if !known {
            tool.extra.push(word.to_vec());
            continue;
        }
        let shown = String::from_utf8_lossy(word);
        let rest = std::str::from_utf8(&word[1..]).unwrap_or("");
        let letter = letter as char;
        // A whole number, also written as one with a zero fraction
        // (`Q0.0`, which GUIs' tool editors write); `Q1.5` is refused,
        // not cut to 1.
        let int = || {
            rest.parse::<i32>()
                .ok()
                .or_else(|| {
                    let v = rest.parse::<f64>().ok()?;
                    let whole = v.is_finite()
                        && v.fract() == 0.0
                        && v >= f64::from(i32::MIN)
                        && v <= f64::from(i32::MAX);
                    whole.then_some(v as i32)
                })
                .ok_or_else(|| format!("'{shown}': {letter} needs a whole number"))
        };
        let real = || {
            rest.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{shown}': {letter} needs a number"))
        };
        match letter {
            'T' => number = Some(int()?),
            'P' => pocket = Some(int()?),
            'D' => tool.diameter = real()?,
            'I' => tool.front_angle = real()?,
            'J' => tool.back_angle = real()?,
            'Q' => tool.orientation = int()?,
            c => {
                let i = AXES.iter().position(|&a| a == c as u8).unwrap_or(0);
                tool.offset[i] = real()?;
            }
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
            layout: Vec::new(),
        }
    }

    /// Puts `tool` in `slot`, growing the table.
    pub fn put(&mut self, slot: usize, tool: Option<Tool>) {
        if slot >= self.slots.len() {
            self.slots.resize(slot + 1, None);
        }
        self.slots[slot] = tool;
    }

    /// Parses the bytes of a table file named `file` (for messages):
    /// every line, or an error listing each line that cannot be read.
    pub fn parse(bytes: &[u8], file: &str, random: bool) -> Result<ToolTable, TableError> {
        let (t, problems) = ToolTable::parse_skipping(bytes, file, random);
        if problems.is_empty() {
            Ok(t)
        } else {
            Err(TableError::Lines(problems))
        }
    }

    /// Parses what can be read: the table of every line that reads, and
    /// the lines that did not (each left out whole, never half read, so
    /// a tool is either as written or absent, and an absent tool is
    /// refused when a program asks for it).
    pub fn parse_skipping(
        bytes: &[u8],
        file: &str,
        random: bool,
    ) -> (ToolTable, Vec<TableProblem>) {
        let mut t = ToolTable::empty(random);
        let mut problems = Vec::new();
        let mut next_slot = 1;
        let text = bytes.strip_suffix(b"\n").unwrap_or(bytes);
        for (i, line) in text.split(|&b| b == b'\n').enumerate() {
            if bytes.is_empty() {
                break;
            }
            let mut problem = |reason: String| {
                problems.push(TableProblem {
                    file: file.to_string(),
                    line: i + 1,
                    reason,
                })
            };
            let tool = match parse_line(line) {
                Ok(Some(tool)) => tool,
                Ok(None) => {
                    t.layout.push(Layout::Kept(line.to_vec()));
                    continue;
                }
                Err(reason) => {
                    problem(reason);
                    continue;
                }
            };
            if t.slot_of(tool.number).is_some() {
                problem(format!("tool {} is listed more than once", tool.number));
                continue;
            }
            let slot = if random {
                match usize::try_from(tool.pocket) {
                    Ok(p) if p < POCKETS_MAX => p,
                    _ => {
                        problem(format!(
                            "pocket {} is outside 0..{}",
                            tool.pocket,
                            POCKETS_MAX - 1
                        ));
                        continue;
                    }
                }
            } else {
                if next_slot >= POCKETS_MAX {
                    problem(format!("more than {} tools", POCKETS_MAX - 1));
                    continue;
                }
                next_slot += 1;
                next_slot - 1
            };
            if t.tool(slot).is_some() {
                problem(format!("pocket {} is listed more than once", tool.pocket));
                continue;
            }
            t.put(slot, Some(tool));
            t.layout.push(Layout::Tool);
        }
        (t, problems)
    }

    /// Reads a table file: a regular file of at most
    /// [`limits::TOOL_TABLE`] bytes, read completely or not at all.
    pub fn load(path: &Path, random: bool) -> Result<ToolTable, TableError> {
        let bytes = read_user_file(path, limits::TOOL_TABLE, "tool table")?;
        ToolTable::parse(&bytes, &path.display().to_string(), random)
    }

    /// The slot holding tool `number` (the spindle, slot 0, included on a
    /// random changer; on a non-random one slot 0 is a copy).
    pub fn slot_of(&self, number: i32) -> Option<usize> {
        let first = if self.random { 0 } else { 1 };
        (first..self.slots.len())
            .find(|&i| self.slots[i].as_ref().is_some_and(|t| t.number == number))
    }

    /// Reads a table file at start as LinuxCNC does: the lines that
    /// read, with the ones that do not listed (the caller says them and
    /// keeps the file from being written back while any line was left
    /// out, so nothing of it is lost).
    pub fn load_skipping(
        path: &Path,
        random: bool,
    ) -> Result<(ToolTable, Vec<TableProblem>), FileError> {
        let bytes = read_user_file(path, limits::TOOL_TABLE, "tool table")?;
        Ok(ToolTable::parse_skipping(
            &bytes,
            &path.display().to_string(),
            random,
        ))
    }

    /// The tool in slot `slot`.
    pub fn tool(&self, slot: usize) -> Option<&Tool> {
        self.slots.get(slot).and_then(Option::as_ref)
    }

    /// The tools in the order they are written (slot order; a
    /// non-random changer's spindle copy left out), with their pockets.
    fn in_file_order(&self) -> impl Iterator<Item = (i32, &Tool)> {
        let first = if self.random { 0 } else { 1 };
        self.slots
            .iter()
            .enumerate()
            .skip(first)
            .filter_map(move |(slot, t)| {
                let t = t.as_ref()?;
                Some((if self.random { slot as i32 } else { t.pocket }, t))
            })
    }

    /// The table as LinuxCNC writes it back (random changers save the
    /// table after every change): comment and empty lines where they
    /// were, the tools in slot order on the tool lines, each tool's
    /// unknown words and comment as read.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        let mut tools = self.in_file_order();
        for line in &self.layout {
            match line {
                Layout::Kept(bytes) => {
                    out.extend_from_slice(bytes);
                    out.push(b'\n');
                }
                Layout::Tool => {
                    if let Some((pocket, t)) = tools.next() {
                        tool_line(&mut out, pocket, t);
                    }
                }
            }
        }
        for (pocket, t) in tools {
            tool_line(&mut out, pocket, t);
        }
        out
    }

    /// Writes the table to `path` ([`ToolTable::to_bytes`]), replacing the
    /// file whole: a new file renamed over the old one, so a crash leaves
    /// the old table or the new, never half of one.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        hal_core::files::replace_file(path, &self.to_bytes())
    }
}

/// Appends one tool's line.
fn tool_line(out: &mut Vec<u8>, pocket: i32, t: &Tool) {
    let mut s = format!("T{} P{}", t.number, pocket);
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
    out.extend_from_slice(s.as_bytes());
    for w in &t.extra {
        out.push(b' ');
        out.extend_from_slice(w);
    }
    out.extend_from_slice(b" ;");
    out.extend_from_slice(&t.comment);
    out.push(b'\n');
}

/// Where a table that was read completely is saved back; unset while the
/// file on disk could not be read, so a write-back never replaces a file
/// the user is still fixing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SaveTo {
    path: PathBuf,
    blocked: bool,
}

impl SaveTo {
    /// The table at `path`, read completely.
    pub fn new(path: PathBuf) -> SaveTo {
        SaveTo {
            path,
            blocked: false,
        }
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the last read of the file was complete (or the table was
    /// saved since).
    pub fn allowed(&self) -> bool {
        !self.blocked
    }

    /// Records whether the last read of the file was complete.
    pub fn set_read_complete(&mut self, complete: bool) {
        self.blocked = !complete;
    }
}

/// The fuzz target's body: parses arbitrary bytes as a tool table both
/// ways and writes it back. Never panics.
pub fn fuzz_parse(data: &[u8]) {
    for random in [false, true] {
        let Ok(t) = ToolTable::parse(data, "fuzz.tbl", random) else {
            continue;
        };
        let written = t.to_bytes();
        // What was written reads back: the same tools in the same slots
        // with the same unknown words and comments (numbers as written,
        // to six decimals), and from then on writes the same bytes.
        let again = ToolTable::parse(&written, "again.tbl", random)
            .unwrap_or_else(|e| panic!("a written table does not read back: {e}"));
        let key = |t: &ToolTable| -> Vec<_> {
            t.slots
                .iter()
                .map(|s| {
                    s.as_ref()
                        .map(|t| (t.number, t.extra.clone(), t.comment.clone()))
                })
                .collect()
        };
        assert_eq!(key(&t), key(&again));
        let twice = again.to_bytes();
        let third = ToolTable::parse(&twice, "third.tbl", random)
            .unwrap_or_else(|e| panic!("a written table does not read back: {e}"));
        assert_eq!(twice, third.to_bytes());
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

    fn parse(text: &[u8], random: bool) -> ToolTable {
        ToolTable::parse(text, "t.tbl", random).unwrap()
    }

    fn problems(text: &[u8], random: bool) -> Vec<String> {
        match ToolTable::parse(text, "bad.tbl", random) {
            Err(TableError::Lines(p)) => p.iter().map(ToString::to_string).collect(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn reads_tools_in_file_order_on_a_non_random_changer() {
        let t = parse(TABLE.as_bytes(), false);
        assert_eq!(t.tool(1).unwrap().number, 1);
        assert_eq!(t.tool(3).unwrap().offset[2], 1.273);
        assert_eq!(t.tool(3).unwrap().offset[0], 0.5);
        assert_eq!(t.tool(3).unwrap().orientation, 2);
        assert_eq!(t.tool(3).unwrap().comment, b"#7 tap drill");
        assert_eq!(t.slot_of(99999), Some(4));
        assert!(t.tool(0).is_none());
    }

    #[test]
    fn whole_numbers_may_carry_a_zero_fraction_but_not_a_real_one() {
        // The line gmoccapy's tool editor writes.
        let t = parse(
            b"T1 P101 Z-12.7129 D1.0 I0.0 J0.0 Q0.0 ;3/4 roughing\nT2.0 P2 Q2.000\n",
            false,
        );
        assert_eq!(t.tool(1).unwrap().orientation, 0);
        assert_eq!(t.tool(1).unwrap().pocket, 101);
        assert_eq!(t.tool(2).unwrap().number, 2);
        assert_eq!(t.tool(2).unwrap().orientation, 2);
        assert_eq!(
            problems(b"T3 P3 Q1.5\nT4 P4 Q1e10\n", false),
            [
                "bad.tbl:1: 'Q1.5': Q needs a whole number",
                "bad.tbl:2: 'Q1e10': Q needs a whole number"
            ]
        );
    }

    #[test]
    fn start_skips_what_does_not_read_and_keeps_the_rest() {
        let (t, skipped) = ToolTable::parse_skipping(
            b"TOOLNO POCKET\n1 1 +0.5 0.1 old\nT2 P2 Z0.1\n",
            "o.tbl",
            false,
        );
        assert_eq!(t.slot_of(2), Some(1));
        assert_eq!(t.slots.iter().flatten().count(), 1);
        let said: Vec<String> = skipped.iter().map(ToString::to_string).collect();
        assert_eq!(
            said,
            [
                "o.tbl:1: 'TOOLNO': T needs a whole number",
                "o.tbl:2: no T word (tool number)"
            ]
        );
    }

    #[test]
    fn random_changers_use_pockets() {
        let t = parse(b"T5 P0 ;in spindle\nT7 P12\n", true);
        assert_eq!(t.slot_of(5), Some(0));
        assert_eq!(t.slot_of(7), Some(12));
        assert_eq!(
            problems(b"T5 P0\nT8 P1000\n", true),
            ["bad.tbl:2: pocket 1000 is outside 0..999"]
        );
    }

    #[test]
    fn a_table_with_a_bad_line_is_refused_whole_naming_file_and_line() {
        assert_eq!(
            problems(b"T1 P1\nT2 P2 Zabc\nP3 D1\nT4 P4 Z\xf8\nT1 P5\n", false),
            [
                "bad.tbl:2: 'Zabc': Z needs a number",
                "bad.tbl:3: no T word (tool number)",
                "bad.tbl:4: 'Z\u{fffd}': Z needs a number",
                "bad.tbl:5: tool 1 is listed more than once",
            ]
        );
        let e = ToolTable::parse(b"T1 P1\nT2 Px\n", "x.tbl", false).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the tool table cannot be read completely, so none of it is used:\n  \
             x.tbl:2: 'Px': P needs a whole number"
        );
    }

    #[test]
    fn latin1_comments_and_unknown_words_survive_byte_for_byte() {
        // The line of the report: a Latin-1 comment (0xf8 is 'ø').
        let text = b"T1 P1 D6 Z0.1 ;Bohrer \xf86mm\n; Werkzeuge \xfc\nT2 P2 K7 %x ;\n";
        for random in [false, true] {
            let t = parse(text, random);
            assert_eq!(t.tool(1).unwrap().comment, b"Bohrer \xf86mm");
            let two = t.slots.iter().flatten().find(|t| t.number == 2).unwrap();
            assert_eq!(two.extra, [b"K7".to_vec(), b"%x".to_vec()]);
            assert_eq!(
                t.to_bytes(),
                b"T1 P1 D6.000000 Z+0.100000 ;Bohrer \xf86mm\n; Werkzeuge \xfc\nT2 P2 K7 %x ;\n"
            );
        }
    }

    #[test]
    fn writes_back_what_it_read_with_comment_lines_in_place() {
        let random_table = TABLE.replace("T99999 P99999", "T99999 P999");
        for (table, random) in [(TABLE, false), (random_table.as_str(), true)] {
            let t = parse(table.as_bytes(), random);
            let again = parse(&t.to_bytes(), random);
            assert_eq!(t.slots, again.slots);
            assert_eq!(t.to_bytes(), again.to_bytes());
        }
        let t = parse(TABLE.as_bytes(), false);
        let text = String::from_utf8(t.to_bytes()).unwrap();
        assert_eq!(text.lines().nth(2), Some(""));
        assert_eq!(text.lines().nth(3), Some("; a comment line"));
        fuzz_parse(TABLE.as_bytes());
        fuzz_parse(b"T1 P1 X-0.0000001 ;\r\r\n");
    }

    #[test]
    fn a_save_replaces_the_file_whole() {
        let d = std::env::temp_dir().join(format!("tooltable-save-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("t.tbl");
        std::fs::write(&p, TABLE).unwrap();
        std::fs::write(&p, TABLE.replace("P99999", "P999")).unwrap();
        let mut t = ToolTable::load(&p, true).unwrap();
        t.slots.swap(0, 1);
        t.save(&p).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), t.to_bytes());
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            1,
            "no file left beside it"
        );
        std::fs::remove_dir_all(&d).unwrap();
    }
}
