//! ClassicLadder's arithmetic expressions, parsed once (by the loader)
//! into a fixed-size postfix program that the realtime side evaluates
//! without allocating.
//!
//! The text is what a project file stores: variables as `@type/num@`
//! (`@200/1@` is %W1), or by name (`%W1`, `%TM0.V`); integer constants in
//! decimal, `$` hex or `'c'` characters; `+ - * / %`, `^` (power), `&`
//! and `|` (bitwise), `!` (logical not), parentheses, and the functions
//! `ABS(v)`, `MINI(v,...)`, `MAXI(v,...)`, `AVG(v,...)`/`MOY(v,...)`. A
//! compare expression has one of `= <> < <= > >=` at its top; an operate
//! expression is `target := expression` (or `=`). Arithmetic is 32-bit
//! wrapping; a division or remainder by zero gives 0 (ClassicLadder's
//! would trap).

mod parse;

use crate::model::{Sizes, VarRef};
use parse::Compiler;

/// The most operations one expression compiles to.
pub const MAX_OPS: usize = 48;
/// The longest expression text accepted.
pub const MAX_TEXT: usize = 200;

/// One postfix operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// Push a constant.
    Const(i32),
    /// Push a variable's value (a bit reads 0 or 1).
    Load(VarRef),
    /// Pop a, push 1 if a is 0, else 0.
    Not,
    /// Pop a, push -a.
    Neg,
    /// Pop b, a; push a + b.
    Add,
    /// a - b.
    Sub,
    /// a * b.
    Mul,
    /// a / b (0 when b is 0).
    Div,
    /// a % b (0 when b is 0).
    Rem,
    /// a to the power b (0 for b < 0, except 1 for a = 1).
    Pow,
    /// a & b.
    And,
    /// a | b.
    Or,
    /// Pop a, push |a|.
    Abs,
    /// Pop n values, push the least.
    Min(u8),
    /// Pop n values, push the greatest.
    Max(u8),
    /// Pop n values, push their mean (truncated).
    Avg(u8),
}

impl Op {
    /// How many values the operation pops and pushes.
    pub fn arity(self) -> (usize, usize) {
        match self {
            Op::Const(_) | Op::Load(_) => (0, 1),
            Op::Not | Op::Neg | Op::Abs => (1, 1),
            Op::Min(n) | Op::Max(n) | Op::Avg(n) => (n as usize, 1),
            _ => (2, 1),
        }
    }
}

/// A comparison at the top of a compare expression.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CmpOp {
    /// `=`.
    Eq,
    /// `<>`.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
}

impl CmpOp {
    /// Applies the comparison.
    pub fn test(self, a: i32, b: i32) -> bool {
        match self {
            CmpOp::Eq => a == b,
            CmpOp::Ne => a != b,
            CmpOp::Lt => a < b,
            CmpOp::Le => a <= b,
            CmpOp::Gt => a > b,
            CmpOp::Ge => a >= b,
        }
    }
}

/// What an expression is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExprForm {
    /// Empty (or a `#` comment): a compare is false, an operate does
    /// nothing.
    Empty,
    /// `left op right`: `ops[..split]` is left, `ops[split..len]` right.
    Compare {
        /// The comparison.
        op: CmpOp,
        /// Where the right side starts.
        split: u8,
    },
    /// `target := ops[..len]`.
    Assign {
        /// The variable written.
        target: VarRef,
    },
}

/// A compiled expression.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Expr {
    /// Its form.
    pub form: ExprForm,
    /// The postfix operations, `len` of them used.
    pub ops: [Op; MAX_OPS],
    /// How many operations are used.
    pub len: u8,
}

/// Why an expression was refused (with the byte offset it was found at).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ExprError {
    /// Text longer than [`MAX_TEXT`].
    #[error("longer than {MAX_TEXT} characters")]
    TooLong,
    /// More operations than [`MAX_OPS`].
    #[error("too complex (more than {MAX_OPS} operations)")]
    TooComplex,
    /// Something unexpected at a position.
    #[error("at character {at}: {what}")]
    Syntax {
        /// Byte offset.
        at: usize,
        /// What was expected or found.
        what: String,
    },
    /// A variable that does not exist in the module.
    #[error("at character {at}: {source}")]
    Var {
        /// Byte offset.
        at: usize,
        /// Why.
        #[source]
        source: crate::model::CellError,
    },
    /// An operate expression writing a read-only variable.
    #[error("{target} cannot be written")]
    ReadOnly {
        /// The variable.
        target: VarRef,
    },
    /// A compiled expression (from shared memory) that does not balance.
    #[error("its operations do not form an expression")]
    Malformed,
}

impl Expr {
    /// The empty expression.
    pub const EMPTY: Expr = Expr {
        form: ExprForm::Empty,
        ops: [Op::Const(0); MAX_OPS],
        len: 0,
    };

    /// Parses `text` as a compare block's expression.
    pub fn compare(text: &str, sizes: &Sizes) -> Result<Expr, ExprError> {
        let text = text.trim_end();
        if blank(text) {
            return Ok(Expr::EMPTY);
        }
        check_len(text)?;
        let b = text.as_bytes();
        let pos = b
            .iter()
            .position(|c| matches!(c, b'<' | b'>' | b'='))
            .ok_or_else(|| ExprError::Syntax {
                at: 0,
                what: "no comparison (= <> < <= > >=)".into(),
            })?;
        let two = b.get(pos..pos + 2).unwrap_or(&b[pos..]);
        let (op, width) = match two {
            b"<>" => (CmpOp::Ne, 2),
            b"<=" => (CmpOp::Le, 2),
            b">=" => (CmpOp::Ge, 2),
            b"==" => (CmpOp::Eq, 2),
            [b'<', ..] => (CmpOp::Lt, 1),
            [b'>', ..] => (CmpOp::Gt, 1),
            _ => (CmpOp::Eq, 1),
        };
        let mut c = Compiler::new(text, sizes);
        c.end = pos;
        c.whole()?;
        let split = c.len;
        c.pos = pos + width;
        c.end = text.len();
        c.whole()?;
        Ok(c.finish(ExprForm::Compare {
            op,
            split: split as u8,
        }))
    }

    /// Parses `text` as an operate block's `target := expression`.
    pub fn assign(text: &str, sizes: &Sizes) -> Result<Expr, ExprError> {
        let text = text.trim_end();
        if blank(text) {
            return Ok(Expr::EMPTY);
        }
        check_len(text)?;
        let mut c = Compiler::new(text, sizes);
        c.skip_spaces();
        let target = c.variable()?;
        if !target.kind.is_writable() {
            return Err(ExprError::ReadOnly { target });
        }
        c.skip_spaces();
        if c.peek() == Some(b':') {
            c.pos += 1;
        }
        if c.peek() != Some(b'=') {
            return Err(c.syntax("expected := after the target variable"));
        }
        c.pos += 1;
        c.whole()?;
        Ok(c.finish(ExprForm::Assign { target }))
    }

    /// The operations in use.
    pub fn used(&self) -> &[Op] {
        &self.ops[..(self.len as usize).min(MAX_OPS)]
    }

    /// Checks that the operations balance (each part leaves one value),
    /// so evaluation never runs past its stack: what the realtime side
    /// does with an expression it decoded.
    pub fn check(&self) -> Result<(), ExprError> {
        let ops = self.used();
        match self.form {
            ExprForm::Empty => Ok(()),
            ExprForm::Assign { .. } => balanced(ops),
            ExprForm::Compare { split, .. } => {
                let split = split as usize;
                if split > ops.len() {
                    return Err(ExprError::Malformed);
                }
                balanced(&ops[..split])?;
                balanced(&ops[split..])
            }
        }
    }
}

fn blank(text: &str) -> bool {
    let t = text.trim_start();
    t.is_empty() || t.starts_with('#')
}

fn check_len(text: &str) -> Result<(), ExprError> {
    if text.len() > MAX_TEXT {
        Err(ExprError::TooLong)
    } else {
        Ok(())
    }
}

fn balanced(ops: &[Op]) -> Result<(), ExprError> {
    let mut depth = 0usize;
    for op in ops {
        let (pop, push) = op.arity();
        if pop > depth || (pop == 0 && matches!(op, Op::Min(_) | Op::Max(_) | Op::Avg(_))) {
            return Err(ExprError::Malformed);
        }
        depth = depth - pop + push;
    }
    if depth == 1 {
        Ok(())
    } else {
        Err(ExprError::Malformed)
    }
}

/// Evaluates `ops` (a balanced sequence) with `read` giving variables.
pub fn eval(ops: &[Op], read: &impl Fn(VarRef) -> i32) -> i32 {
    let mut stack = [0i32; MAX_OPS];
    let mut sp = 0usize;
    for op in ops {
        let (pop, _) = op.arity();
        if pop > sp {
            return 0;
        }
        let args = &stack[sp - pop..sp];
        let v = match *op {
            Op::Const(c) => c,
            Op::Load(v) => read(v),
            Op::Not => (args[0] == 0) as i32,
            Op::Neg => args[0].wrapping_neg(),
            Op::Abs => args[0].wrapping_abs(),
            Op::Add => args[0].wrapping_add(args[1]),
            Op::Sub => args[0].wrapping_sub(args[1]),
            Op::Mul => args[0].wrapping_mul(args[1]),
            Op::Div => args[0].checked_div(args[1]).unwrap_or(0),
            Op::Rem => args[0].checked_rem(args[1]).unwrap_or(0),
            Op::Pow => power(args[0], args[1]),
            Op::And => args[0] & args[1],
            Op::Or => args[0] | args[1],
            Op::Min(_) => args.iter().copied().min().unwrap_or(0),
            Op::Max(_) => args.iter().copied().max().unwrap_or(0),
            Op::Avg(n) => {
                let sum: i64 = args.iter().map(|&a| a as i64).sum();
                (sum / (n.max(1) as i64)) as i32
            }
        };
        sp -= pop;
        if sp >= MAX_OPS {
            return 0;
        }
        stack[sp] = v;
        sp += 1;
    }
    if sp == 0 {
        0
    } else {
        stack[sp - 1]
    }
}

fn power(a: i32, b: i32) -> i32 {
    if b < 0 {
        return if a == 1 { 1 } else { 0 };
    }
    let mut r: i32 = 1;
    for _ in 0..b.min(64) {
        r = r.wrapping_mul(a);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::VarKind;

    fn run(e: &Expr, vals: &[(VarKind, u32, i32)]) -> (i32, i32) {
        let read = |v: VarRef| {
            vals.iter()
                .find(|(k, i, _)| *k == v.kind && *i == v.index)
                .map_or(0, |t| t.2)
        };
        match e.form {
            ExprForm::Compare { split, .. } => (
                eval(&e.used()[..split as usize], &read),
                eval(&e.used()[split as usize..], &read),
            ),
            _ => (eval(e.used(), &read), 0),
        }
    }

    #[test]
    fn smithy_expressions() {
        let s = Sizes::default();
        let e = Expr::compare("(@270/0@-1)&3=@200/1@", &s).unwrap();
        assert!(matches!(e.form, ExprForm::Compare { op: CmpOp::Eq, .. }));
        assert_eq!(
            run(&e, &[(VarKind::WordInput, 0, 6), (VarKind::Word, 1, 1)]),
            (1, 1)
        );
        assert_eq!(run(&e, &[(VarKind::WordInput, 0, 4)]), (3, 0));
        let a = Expr::assign("@200/1@=2", &s).unwrap();
        assert_eq!(
            a.form,
            ExprForm::Assign {
                target: VarRef {
                    kind: VarKind::Word,
                    index: 1
                }
            }
        );
        assert_eq!(run(&a, &[]).0, 2);
    }

    #[test]
    fn precedence_functions_and_names() {
        let s = Sizes::default();
        let a = Expr::assign("%W0 := 2+3*4^2-$10/(7%4)", &s).unwrap();
        assert_eq!(run(&a, &[]).0, 2 + 3 * 16 - 16 / 3);
        let m = Expr::assign("%QW1:=MAXI(%W1,%W2)+ABS(%W3)-MINI(@200/1@,@200/2@)", &s).unwrap();
        let vals = [
            (VarKind::Word, 1, 5),
            (VarKind::Word, 2, -7),
            (VarKind::Word, 3, -4),
        ];
        assert_eq!(run(&m, &vals).0, 5 + 4 + 7);
        let c = Expr::compare("%TM0.V>=10", &s).unwrap();
        assert!(matches!(c.form, ExprForm::Compare { op: CmpOp::Ge, .. }));
        assert_eq!(run(&Expr::assign("%W0=7/0", &s).unwrap(), &[]).0, 0);
        assert_eq!(run(&Expr::assign("%W0=!0+-3", &s).unwrap(), &[]).0, -2);
    }

    #[test]
    fn refusals_say_where() {
        let s = Sizes::default();
        for (text, want) in [
            ("@200/100@=1", "past the 100"),
            ("@200/1=1", "expected @ closing"),
            ("%I0:=1", "cannot be written"),
            ("@200/1@ 5", "expected :="),
            ("%W0=1+", "ends too early"),
            ("%W0=FOO(@200/1@)", "unknown function"),
            ("%Z3=1", "not a ClassicLadder variable"),
        ] {
            let e = Expr::assign(text, &s).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
        assert!(Expr::compare("@200/1@+1", &s)
            .unwrap_err()
            .to_string()
            .contains("no comparison"));
        let deep = format!("%W0={}1{}", "(".repeat(40), ")".repeat(40));
        assert!(Expr::assign(&deep, &s).is_err());
        assert!(Expr::compare("", &s).unwrap() == Expr::EMPTY);
    }

    #[test]
    fn check_refuses_unbalanced() {
        let mut e = Expr::EMPTY;
        e.form = ExprForm::Assign {
            target: VarRef {
                kind: VarKind::Word,
                index: 0,
            },
        };
        e.ops[0] = Op::Add;
        e.len = 1;
        assert!(e.check().is_err());
        e.ops[0] = Op::Const(1);
        assert!(e.check().is_ok());
        e.len = 60;
        assert!(e.check().is_err());
    }
}
