//! One program line as the interpreter sees it: its G and M codes and
//! its value words, each with where it was written. The `gcode` crate
//! (maintained, zero-copy, error-tolerant, with spans) splits the text
//! into blocks and words; values are read again here from the source as
//! `f64`, because the crate keeps them as `f32`, which is too coarse for
//! coordinates (seven significant digits).

use super::{Loc, ProgramError};

/// A code (G or M) and where it was written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Code {
    /// 'G' or 'M'.
    pub letter: char,
    /// The number times 10 (G61.1 is 611).
    pub number: u32,
    /// Where it was written.
    pub loc: Loc,
}

impl Code {
    /// The code as written in messages ("G61.1").
    pub fn name(&self) -> String {
        if self.number % 10 == 0 {
            format!("{}{}", self.letter, self.number / 10)
        } else {
            format!("{}{}.{}", self.letter, self.number / 10, self.number % 10)
        }
    }
}

/// A value word (X10.5, F600) and where it was written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Word {
    /// The value.
    pub value: f64,
    /// Where it was written.
    pub loc: Loc,
}

/// One line's codes and words; each value letter at most once.
#[derive(Debug, Clone, Default)]
pub struct Block {
    /// The G and M codes, in order.
    pub codes: Vec<Code>,
    /// Indexed by letter (`b'A'..=b'Z'`).
    pub words: [Option<Word>; 26],
}

impl Block {
    /// The word of `letter` (upper case), if given.
    pub fn get(&self, letter: char) -> Option<Word> {
        self.words[(letter as u8 - b'A') as usize]
    }
}

/// Where each line starts, to turn byte offsets into line and column.
pub struct Lines {
    starts: Vec<usize>,
}

impl Lines {
    /// The line starts of `src`.
    pub fn new(src: &str) -> Lines {
        let mut starts = vec![0];
        starts.extend(src.match_indices('\n').map(|(i, _)| i + 1));
        Lines { starts }
    }

    /// Line and column (from 1) of byte `offset`.
    pub fn loc(&self, src: &str, offset: usize) -> Loc {
        let line = self.starts.partition_point(|&s| s <= offset).max(1);
        let start = self.starts[line - 1];
        let column = src
            .get(start..offset.min(src.len()))
            .map_or(1, |s| s.chars().count() + 1);
        Loc { line, column }
    }
}

/// Reads the number of the word at `start` (its letter first) from the
/// source, as `f64`.
fn value(src: &str, start: usize, length: usize) -> Option<f64> {
    let text = src.get(start + 1..start + length)?;
    let cleaned: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    cleaned.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The largest whole part a G, M or T number may have. The `gcode` crate
/// stores such numbers times ten in a `u32`, and overflows (a panic with
/// overflow checks, a wrapped and therefore wrong code without) from
/// 429496730 on; no code is anywhere near this bound.
const MAX_CODE_MAJOR: u64 = 99_999_999;

/// Finds the first G, M or T word whose number has a whole part above
/// [`MAX_CODE_MAJOR`], walking the text as the `gcode` crate's lexer does
/// (comments in parentheses nest and may span lines, `;` comments run to
/// the end of the line, blanks may stand between letter and number).
/// Returns its byte offset and letter.
fn oversized_code_number(src: &str) -> Option<(usize, char)> {
    let bytes = src.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'(' => {
                let mut depth = 1u32;
                i += 1;
                while i < bytes.len() && depth > 0 {
                    match bytes[i] {
                        b'(' => depth += 1,
                        b')' => depth -= 1,
                        _ => {}
                    }
                    i += 1;
                }
            }
            b';' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            c @ (b'G' | b'g' | b'M' | b'm' | b'T' | b't') => {
                let at = i;
                i += 1;
                while i < bytes.len() && matches!(bytes[i], b' ' | b'\t' | b'\r') {
                    i += 1;
                }
                let mut major: u64 = 0;
                while i < bytes.len() && bytes[i].is_ascii_digit() {
                    major = (major * 10 + u64::from(bytes[i] - b'0')).min(MAX_CODE_MAJOR + 1);
                    i += 1;
                }
                if major > MAX_CODE_MAJOR {
                    return Some((at, char::from(c.to_ascii_uppercase())));
                }
            }
            _ => i += 1,
        }
    }
    None
}

/// Splits `src` into blocks, one per line (empty lines give empty
/// blocks); `file` names it in errors.
pub fn blocks(file: &str, src: &str) -> Result<Vec<(usize, Block)>, ProgramError> {
    let lines = Lines::new(src);
    let err = |offset: usize, message: String| ProgramError {
        file: file.to_string(),
        loc: lines.loc(src, offset),
        message,
    };
    if let Some((offset, code)) = oversized_code_number(src) {
        return Err(err(
            offset,
            format!("{code} code number too large (at most {MAX_CODE_MAJOR})"),
        ));
    }
    let program = match gcode::parse(src) {
        Ok(p) => p,
        Err(diags) => {
            let d = diags
                .iter()
                .min_by_key(|d| d.span.start)
                .expect("a failed parse has a diagnostic");
            let near: String = src
                .get(d.span.start..)
                .unwrap_or("")
                .chars()
                .take_while(|c| *c != '\n')
                .take(20)
                .collect();
            return Err(err(
                d.span.start,
                format!("cannot read this: {:?} (parameters, expressions and O-words are not supported)", near.trim_end()),
            ));
        }
    };
    let mut out = Vec::new();
    for b in &program.blocks {
        let line = lines.loc(src, b.span.start).line;
        let mut block = Block::default();
        let mut add_word =
            |letter: char, start: usize, length: usize| -> Result<(), ProgramError> {
                let l = letter.to_ascii_uppercase();
                if !l.is_ascii_uppercase() {
                    return Err(err(start, format!("'{letter}' is not a word letter")));
                }
                let v = value(src, start, length)
                    .ok_or_else(|| err(start, format!("{l} needs a number")))?;
                let slot = &mut block.words[(l as u8 - b'A') as usize];
                if slot.is_some() {
                    return Err(err(start, format!("{l} word given twice on one line")));
                }
                *slot = Some(Word {
                    value: v,
                    loc: lines.loc(src, start),
                });
                Ok(())
            };
        for w in &b.word_addresses {
            add_word(w.letter, w.span.start, w.span.length)?;
        }
        for c in &b.codes {
            let (letter, number, span, args) = match c {
                gcode::Code::General(g) => ('G', g.number, g.span, &g.args),
                gcode::Code::Miscellaneous(m) => ('M', m.number, m.span, &m.args),
                gcode::Code::ToolChange(t) => {
                    return Err(err(
                        t.span.start,
                        format!("T{} (tool change) is not supported", t.number),
                    ))
                }
                _ => return Err(err(b.span.start, "unsupported code".into())),
            };
            for a in args {
                if matches!(a.value, gcode::Value::Variable(_)) {
                    return Err(err(a.span.start, "parameters (#) are not supported".into()));
                }
                add_word(a.letter, a.span.start, a.span.length)?;
            }
            let minor = number.minor().map_or(0, |m| m.get());
            block.codes.push(Code {
                letter,
                number: number.major() * 10 + minor,
                loc: lines.loc(src, span.start),
            });
        }
        out.push((line, block));
    }
    Ok(out)
}
