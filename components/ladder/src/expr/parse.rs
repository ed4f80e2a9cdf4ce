//! The compiler of expression text to postfix [`Op`]s: recursive
//! descent over ClassicLadder's precedence (`|`, `&`, `+ -`, `* / %`,
//! `^`, then terms).

use super::{Expr, ExprError, ExprForm, Op, MAX_OPS};
use crate::model::{Sizes, VarKind, VarRef};

/// A recursive-descent compiler from text to postfix.
pub(super) struct Compiler<'a> {
    text: &'a [u8],
    pub(super) pos: usize,
    pub(super) end: usize,
    sizes: &'a Sizes,
    ops: [Op; MAX_OPS],
    pub(super) len: usize,
    depth: usize,
}

impl<'a> Compiler<'a> {
    pub(super) fn new(text: &'a str, sizes: &'a Sizes) -> Compiler<'a> {
        Compiler {
            text: text.as_bytes(),
            pos: 0,
            end: text.len(),
            sizes,
            ops: [Op::Const(0); MAX_OPS],
            len: 0,
            depth: 0,
        }
    }

    pub(super) fn finish(self, form: ExprForm) -> Expr {
        Expr {
            form,
            ops: self.ops,
            len: self.len as u8,
        }
    }

    pub(super) fn syntax(&self, what: &str) -> ExprError {
        ExprError::Syntax {
            at: self.pos,
            what: what.to_string(),
        }
    }

    pub(super) fn peek(&self) -> Option<u8> {
        if self.pos < self.end {
            self.text.get(self.pos).copied()
        } else {
            None
        }
    }

    pub(super) fn skip_spaces(&mut self) {
        while self.peek() == Some(b' ') || self.peek() == Some(b'\t') {
            self.pos += 1;
        }
    }

    fn emit(&mut self, op: Op) -> Result<(), ExprError> {
        if self.len >= MAX_OPS {
            return Err(ExprError::TooComplex);
        }
        self.ops[self.len] = op;
        self.len += 1;
        Ok(())
    }

    /// An expression filling the rest of `pos..end`.
    pub(super) fn whole(&mut self) -> Result<(), ExprError> {
        self.or()?;
        self.skip_spaces();
        if self.pos < self.end {
            return Err(self.syntax("unexpected character"));
        }
        Ok(())
    }

    fn binary(
        &mut self,
        table: &[(u8, Op)],
        next: fn(&mut Self) -> Result<(), ExprError>,
    ) -> Result<(), ExprError> {
        next(self)?;
        loop {
            self.skip_spaces();
            let Some(c) = self.peek() else { return Ok(()) };
            let Some(&(_, op)) = table.iter().find(|(ch, _)| *ch == c) else {
                return Ok(());
            };
            self.pos += 1;
            next(self)?;
            self.emit(op)?;
        }
    }

    fn or(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > 32 {
            return Err(ExprError::TooComplex);
        }
        let r = self.binary(&[(b'|', Op::Or)], Self::and);
        self.depth -= 1;
        r
    }

    fn and(&mut self) -> Result<(), ExprError> {
        self.binary(&[(b'&', Op::And)], Self::add_sub)
    }

    fn add_sub(&mut self) -> Result<(), ExprError> {
        self.binary(&[(b'+', Op::Add), (b'-', Op::Sub)], Self::mul_div)
    }

    fn mul_div(&mut self) -> Result<(), ExprError> {
        self.binary(
            &[(b'*', Op::Mul), (b'/', Op::Div), (b'%', Op::Rem)],
            Self::pow,
        )
    }

    fn pow(&mut self) -> Result<(), ExprError> {
        self.term()?;
        self.skip_spaces();
        if self.peek() == Some(b'^') {
            self.pos += 1;
            self.depth += 1;
            if self.depth > 32 {
                return Err(ExprError::TooComplex);
            }
            self.pow()?;
            self.depth -= 1;
            self.emit(Op::Pow)?;
        }
        Ok(())
    }

    fn term(&mut self) -> Result<(), ExprError> {
        self.skip_spaces();
        match self.peek() {
            Some(b'(') => {
                self.pos += 1;
                self.or()?;
                self.skip_spaces();
                if self.peek() != Some(b')') {
                    return Err(self.syntax("missing )"));
                }
                self.pos += 1;
                Ok(())
            }
            Some(b'!') => {
                self.pos += 1;
                self.depth += 1;
                if self.depth > 32 {
                    return Err(ExprError::TooComplex);
                }
                self.term()?;
                self.depth -= 1;
                self.emit(Op::Not)
            }
            Some(b'-') => {
                self.pos += 1;
                if self.peek().is_some_and(|c| c.is_ascii_digit() || c == b'$') {
                    let v = self.constant()?;
                    self.emit(Op::Const(v.wrapping_neg()))
                } else {
                    self.depth += 1;
                    if self.depth > 32 {
                        return Err(ExprError::TooComplex);
                    }
                    self.term()?;
                    self.depth -= 1;
                    self.emit(Op::Neg)
                }
            }
            Some(c) if c.is_ascii_digit() || c == b'$' || c == b'\'' => {
                let v = self.constant()?;
                self.emit(Op::Const(v))
            }
            Some(b'@' | b'%') => {
                let v = self.variable()?;
                self.emit(Op::Load(v))
            }
            Some(c) if c.is_ascii_uppercase() => self.function(),
            Some(_) => Err(self.syntax("expected a number, variable, function or (")),
            None => Err(self.syntax("expression ends too early")),
        }
    }

    fn constant(&mut self) -> Result<i32, ExprError> {
        let mut v: i32 = 0;
        match self.peek() {
            Some(b'$') => {
                self.pos += 1;
                let start = self.pos;
                while let Some(d) = self.peek().and_then(|c| (c as char).to_digit(16)) {
                    v = v.wrapping_mul(16).wrapping_add(d as i32);
                    self.pos += 1;
                }
                if self.pos == start {
                    return Err(self.syntax("hex digits expected after $"));
                }
            }
            Some(b'\'') => {
                self.pos += 1;
                loop {
                    match self.peek() {
                        Some(b'\'') => break,
                        Some(c) => {
                            v = v.wrapping_mul(256).wrapping_add(c as i32);
                            self.pos += 1;
                        }
                        None => {
                            return Err(self.syntax("missing closing ' of a character constant"))
                        }
                    }
                }
                self.pos += 1;
            }
            _ => {
                while let Some(d) = self.peek().and_then(|c| (c as char).to_digit(10)) {
                    v = v.wrapping_mul(10).wrapping_add(d as i32);
                    self.pos += 1;
                }
            }
        }
        Ok(v)
    }

    fn number(&mut self) -> Result<i64, ExprError> {
        let start = self.pos;
        let mut v: i64 = 0;
        while let Some(d) = self.peek().and_then(|c| (c as char).to_digit(10)) {
            v = v.saturating_mul(10).saturating_add(d as i64);
            self.pos += 1;
        }
        if self.pos == start {
            return Err(self.syntax("digits expected"));
        }
        Ok(v)
    }

    pub(super) fn variable(&mut self) -> Result<VarRef, ExprError> {
        let at = self.pos;
        let var = match self.peek() {
            Some(b'@') => {
                self.pos += 1;
                let code = self.number()?;
                if self.peek() != Some(b'/') {
                    return Err(self.syntax("expected / in @type/number@"));
                }
                self.pos += 1;
                let num = self.number()?;
                match self.peek() {
                    Some(b'@') => self.pos += 1,
                    Some(b'[') => return Err(self.syntax("indexed variables are not supported")),
                    _ => return Err(self.syntax("expected @ closing @type/number@")),
                }
                VarRef::from_codes(code, num, self.sizes)
            }
            Some(b'%') => {
                self.pos += 1;
                let start = self.pos;
                while self.peek().is_some_and(|c| c.is_ascii_uppercase()) {
                    self.pos += 1;
                }
                let prefix = &self.text[start..self.pos];
                let num = self.number()?;
                let mut suffix: &[u8] = b"";
                if self.peek() == Some(b'.') {
                    self.pos += 1;
                    let s = self.pos;
                    if self.peek().is_some_and(|c| c.is_ascii_uppercase()) {
                        self.pos += 1;
                    }
                    suffix = &self.text[s..self.pos];
                }
                let kind = named_kind(prefix, suffix).ok_or_else(|| ExprError::Syntax {
                    at,
                    what: "not a ClassicLadder variable name".into(),
                })?;
                VarRef::from_codes(kind.code() as i64, num, self.sizes)
            }
            _ => return Err(self.syntax("expected a variable")),
        };
        var.map_err(|source| ExprError::Var { at, source })
    }

    fn function(&mut self) -> Result<(), ExprError> {
        let start = self.pos;
        while self.peek().is_some_and(|c| c.is_ascii_uppercase()) {
            self.pos += 1;
        }
        let name = &self.text[start..self.pos];
        let make: fn(u8) -> Op = match name {
            b"ABS" => |_| Op::Abs,
            b"MINI" => Op::Min,
            b"MAXI" => Op::Max,
            b"AVG" | b"MOY" => Op::Avg,
            _ => {
                self.pos = start;
                return Err(self.syntax("unknown function (ABS, MINI, MAXI, AVG)"));
            }
        };
        if self.peek() != Some(b'(') {
            return Err(self.syntax("expected ( after the function name"));
        }
        let mut n: u8 = 0;
        loop {
            self.pos += 1;
            self.skip_spaces();
            let v = self.variable()?;
            self.emit(Op::Load(v))?;
            n = n.checked_add(1).ok_or(ExprError::TooComplex)?;
            self.skip_spaces();
            match self.peek() {
                Some(b',') => continue,
                Some(b')') => break,
                _ => return Err(self.syntax("expected , or ) in the function's variables")),
            }
        }
        self.pos += 1;
        if name == b"ABS" && n != 1 {
            return Err(self.syntax("ABS takes one variable"));
        }
        self.emit(make(n))
    }
}

/// The kind a `%NAMEn.S` variable name means.
fn named_kind(prefix: &[u8], suffix: &[u8]) -> Option<VarKind> {
    use VarKind::*;
    Some(match (prefix, suffix) {
        (b"B", b"") => Bit,
        (b"I", b"") => Input,
        (b"Q", b"") => Output,
        (b"E", b"") => ErrorBit,
        (b"W", b"") => Word,
        (b"IW", b"") => WordInput,
        (b"QW", b"") => WordOutput,
        (b"IF", b"") => FloatInput,
        (b"QF", b"") => FloatOutput,
        (b"T", b"D") => TimerDone,
        (b"T", b"R") => TimerRunning,
        (b"T", b"P") => TimerPreset,
        (b"T", b"V") => TimerValue,
        (b"TM", b"Q") => TimerIecDone,
        (b"TM", b"P") => TimerIecPreset,
        (b"TM", b"V") => TimerIecValue,
        (b"M", b"R") => MonostableRunning,
        (b"M", b"P") => MonostablePreset,
        (b"M", b"V") => MonostableValue,
        (b"C", b"D") => CounterDone,
        (b"C", b"E") => CounterEmpty,
        (b"C", b"F") => CounterFull,
        (b"C", b"P") => CounterPreset,
        (b"C", b"V") => CounterValue,
        _ => return None,
    })
}
