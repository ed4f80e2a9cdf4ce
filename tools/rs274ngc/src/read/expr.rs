//! Values: numbers, `#` parameters, bracketed expressions with
//! LinuxCNC's operator precedence (`**` over `* / MOD` over `+ -` over
//! the comparisons over `AND OR XOR`, left to right within a level) and
//! the functions (`ABS ... TAN`, `ATAN[a]/[b]`, `EXISTS[#...]`).

use super::{at, c_int};
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::ld;
use crate::params::Parameters;

/// Binary operators and the closing bracket, as read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Op {
    DividedBy,
    Modulo,
    Power,
    Times,
    And,
    Xor,
    Minus,
    Or,
    Plus,
    RightBracket,
    Lt,
    Eq,
    Ne,
    Le,
    Ge,
    Gt,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Op::RightBracket => 1,
            Op::And | Op::Xor | Op::Or => 2,
            Op::Lt | Op::Eq | Op::Ne | Op::Le | Op::Ge | Op::Gt => 3,
            Op::Minus | Op::Plus => 4,
            Op::DividedBy | Op::Modulo | Op::Times => 5,
            Op::Power => 6,
        }
    }
}

/// Unary functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Unary {
    Abs,
    Acos,
    Asin,
    Atan,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
    Exists,
}

/// Two numbers this close are equal for EQ and NE (LE and GE compare
/// exactly, as LinuxCNC 2.9 does).
const TOLERANCE_EQUAL: f64 = 0.0001;

fn apply_binary(left: f64, op: Op, right: f64) -> Result<f64> {
    let truth = |b: bool| if b { 1.0 } else { 0.0 };
    Ok(match op {
        Op::DividedBy => {
            if right == 0.0 {
                return Err(InterpError::DivideByZero);
            }
            left / right
        }
        Op::Modulo => {
            let m = left % right;
            if m < 0.0 {
                m + right.abs()
            } else {
                m
            }
        }
        Op::Power => {
            if left < 0.0 && right.floor() != right {
                return Err(InterpError::NegativeToNonIntegerPower);
            }
            left.powf(right)
        }
        Op::Times => left * right,
        Op::And => truth(left != 0.0 && right != 0.0),
        Op::Xor => truth((left == 0.0) != (right == 0.0)),
        Op::Minus => left - right,
        Op::Or => truth(left != 0.0 || right != 0.0),
        Op::Plus => left + right,
        Op::Lt => truth(left < right),
        Op::Eq => truth((left - right).abs() < TOLERANCE_EQUAL),
        Op::Ne => truth((left - right).abs() >= TOLERANCE_EQUAL),
        Op::Le => truth(left <= right),
        Op::Ge => truth(left >= right),
        Op::Gt => truth(left > right),
        Op::RightBracket => return Err(InterpError::UnknownOperation),
    })
}

#[allow(clippy::manual_range_contains)]
fn apply_unary(x: f64, op: Unary) -> Result<f64> {
    Ok(match op {
        Unary::Abs => x.abs(),
        // Written as LinuxCNC's C comparisons: a NaN passes them and is
        // reported later as "not a number".
        Unary::Acos => {
            if x < -1.0 || x > 1.0 {
                return Err(InterpError::AcosRange);
            }
            ld::rad_to_deg(x.acos())
        }
        Unary::Asin => {
            if x < -1.0 || x > 1.0 {
                return Err(InterpError::AsinRange);
            }
            ld::rad_to_deg(x.asin())
        }
        Unary::Cos => ld::cos_deg(x),
        Unary::Exp => x.exp(),
        Unary::Fix => x.floor(),
        Unary::Fup => x.ceil(),
        Unary::Ln => {
            if x <= 0.0 {
                return Err(InterpError::LnRange);
            }
            x.ln()
        }
        Unary::Round => c_int(x + if x < 0.0 { -0.5 } else { 0.5 }) as f64,
        Unary::Sin => ld::sin_deg(x),
        Unary::Sqrt => {
            if x < 0.0 {
                return Err(InterpError::NegativeSqrt);
            }
            x.sqrt()
        }
        Unary::Tan => ld::tan_deg(x),
        Unary::Atan | Unary::Exists => x,
    })
}

fn starts(line: &[u8], at_index: usize, word: &[u8]) -> bool {
    line.get(at_index..at_index + word.len()) == Some(word)
}

impl Interp {
    /// A real value: number, parameter, expression or function.
    pub(crate) fn read_real_value(&mut self, line: &[u8], counter: &mut usize) -> Result<f64> {
        let c = at(line, *counter);
        if c == 0 {
            return Err(InterpError::NoCharactersForValue);
        }
        let c1 = at(line, *counter + 1);
        let value = if c == b'[' {
            self.read_real_expression(line, counter)?
        } else if c == b'#' {
            self.read_parameter(line, counter, false)?
        } else if c == b'+' && c1 != 0 && !c1.is_ascii_digit() && c1 != b'.' {
            *counter += 1;
            self.read_real_value(line, counter)?
        } else if c == b'-' && c1 != 0 && !c1.is_ascii_digit() && c1 != b'.' {
            *counter += 1;
            -self.read_real_value(line, counter)?
        } else if c.is_ascii_lowercase() {
            self.read_unary(line, counter)?
        } else {
            read_real_number(line, counter)?
        };
        if value.is_nan() {
            return Err(InterpError::NotANumber);
        }
        if value.is_infinite() {
            return Err(InterpError::Infinity);
        }
        Ok(value)
    }

    /// A value that must be within 0.0001 of an integer.
    pub(crate) fn read_integer_value(&mut self, line: &[u8], counter: &mut usize) -> Result<i32> {
        let value = self.read_real_value(line, counter)?;
        let mut n = c_int(value.floor());
        let frac = value - n as f64;
        if frac > 0.9999 {
            n = c_int(value.ceil());
        } else if frac > 0.0001 {
            return Err(InterpError::NonInteger);
        }
        Ok(n)
    }

    /// `[ ... ]`, evaluated with the precedence stack.
    pub(crate) fn read_real_expression(&mut self, line: &[u8], counter: &mut usize) -> Result<f64> {
        *counter += 1;
        let mut values = vec![self.read_real_value(line, counter)?];
        let mut ops = vec![read_operation(line, counter)?];
        while ops[0] != Op::RightBracket {
            values.push(self.read_real_value(line, counter)?);
            ops.push(read_operation(line, counter)?);
            let mut top = ops.len() - 1;
            if ops[top].precedence() > ops[top - 1].precedence() {
                continue;
            }
            while ops[top].precedence() <= ops[top - 1].precedence() {
                values[top - 1] = apply_binary(values[top - 1], ops[top - 1], values[top])?;
                ops[top - 1] = ops[top];
                values.truncate(top);
                ops.truncate(top);
                if top > 1 && ops[top - 1].precedence() <= ops[top - 2].precedence() {
                    top -= 1;
                } else {
                    break;
                }
            }
        }
        Ok(values[0])
    }

    fn read_unary(&mut self, line: &[u8], counter: &mut usize) -> Result<f64> {
        let op = read_operation_unary(line, counter)?;
        if at(line, *counter) != b'[' {
            return Err(InterpError::LeftBracketMissingAfterUnary);
        }
        if op == Unary::Exists {
            *counter += 1;
            if at(line, *counter) != b'#' {
                return Err(InterpError::ExpectedHash);
            }
            let exists = self.read_parameter(line, counter, true)?;
            if at(line, *counter) != b']' {
                return Err(InterpError::ExpectedRightBracket);
            }
            *counter += 1;
            return Ok(exists);
        }
        let value = self.read_real_expression(line, counter)?;
        if op == Unary::Atan {
            if at(line, *counter) != b'/' {
                return Err(InterpError::SlashMissingAfterAtan);
            }
            *counter += 1;
            if at(line, *counter) != b'[' {
                return Err(InterpError::LeftBracketMissingAfterAtanSlash);
            }
            let second = self.read_real_expression(line, counter)?;
            return Ok(ld::rad_to_deg(value.atan2(second)));
        }
        apply_unary(value, op)
    }

    /// `#n`, `##n`, `#[expr]` or `#<name>`; with `check_exists`, 1.0 if
    /// the parameter exists and 0.0 if not.
    pub(crate) fn read_parameter(
        &mut self,
        line: &[u8],
        counter: &mut usize,
        check_exists: bool,
    ) -> Result<f64> {
        *counter += 1;
        if at(line, *counter) == b'<' {
            let name = super::oword::read_name(line, counter)?;
            let found = self.find_named_param(&name)?;
            if check_exists {
                return Ok(if found.is_some() { 1.0 } else { 0.0 });
            }
            // While a subroutine is being defined (skipped over), its
            // names need not exist yet.
            if found.is_none() && self.flow.defining_sub {
                return Ok(0.0);
            }
            return found.ok_or(InterpError::NamedParameterUndefined(name));
        }
        let index = self.read_integer_value(line, counter)?;
        if check_exists {
            return Ok(if Parameters::check_index(index).is_ok() {
                1.0
            } else {
                0.0
            });
        }
        let index = Parameters::check_index(index)?;
        if (5420..=5428).contains(&index) && self.s.cutter_comp_side != crate::setup::Side::Off {
            return Err(InterpError::PositionWithComp);
        }
        Ok(self.numbered_param(index))
    }
}

/// A number: a run of signs then a run of digits and points, converted
/// as C++ streams do (one sign, at most one point, all of it used).
fn read_real_number(line: &[u8], counter: &mut usize) -> Result<f64> {
    let start = *counter;
    let mut end = start;
    while matches!(at(line, end), b'+' | b'-') {
        end += 1;
    }
    while matches!(at(line, end), b'0'..=b'9' | b'.') {
        end += 1;
    }
    let text = String::from_utf8_lossy(&line[start..end]).into_owned();
    let body = text.strip_prefix(['+', '-']).unwrap_or(&text);
    let digits_ok = body.bytes().any(|b| b.is_ascii_digit());
    let first_point = body.find('.');
    let valid_prefix = if !digits_ok || body.starts_with(['+', '-']) {
        None
    } else {
        // The stream stops at a second point; what follows is trailing.
        let cut = match first_point {
            Some(p) => body[p + 1..].find('.').map(|q| p + 1 + q),
            None => None,
        };
        let number_part = &body[..cut.unwrap_or(body.len())];
        let number_digits = number_part.bytes().any(|b| b.is_ascii_digit());
        number_digits.then_some((number_part, cut.is_some()))
    };
    match valid_prefix {
        None => Err(InterpError::BadNumber(text)),
        Some((_, true)) => Err(InterpError::BadNumberTrailing(text)),
        Some((number, false)) => {
            let normal = if number.ends_with('.') {
                format!("{number}0")
            } else {
                number.to_string()
            };
            let normal = if normal.starts_with('.') {
                format!("0{normal}")
            } else {
                normal
            };
            let magnitude: f64 = normal
                .parse()
                .map_err(|_| InterpError::BadNumber(text.clone()))?;
            *counter = end;
            Ok(if text.starts_with('-') {
                -magnitude
            } else {
                magnitude
            })
        }
    }
}

fn read_operation(line: &[u8], counter: &mut usize) -> Result<Op> {
    let c = at(line, *counter);
    *counter += 1;
    let next = at(line, *counter);
    let next2 = at(line, *counter + 1);
    let (op, extra) = match c {
        b'+' => (Op::Plus, 0),
        b'-' => (Op::Minus, 0),
        b'/' => (Op::DividedBy, 0),
        b'*' if next == b'*' => (Op::Power, 1),
        b'*' => (Op::Times, 0),
        b']' => (Op::RightBracket, 0),
        b'a' if next == b'n' && next2 == b'd' => (Op::And, 2),
        b'm' if next == b'o' && next2 == b'd' => (Op::Modulo, 2),
        b'o' if next == b'r' => (Op::Or, 1),
        b'x' if next == b'o' && next2 == b'r' => (Op::Xor, 2),
        b'e' if next == b'q' => (Op::Eq, 1),
        b'n' if next == b'e' => (Op::Ne, 1),
        b'g' if next == b'e' => (Op::Ge, 1),
        b'g' if next == b't' => (Op::Gt, 1),
        b'l' if next == b'e' => (Op::Le, 1),
        b'l' if next == b't' => (Op::Lt, 1),
        b'a' | b'm' | b'o' | b'x' | b'e' | b'n' | b'g' | b'l' => {
            return Err(InterpError::UnknownOperationName(c as char))
        }
        0 => return Err(InterpError::UnclosedExpression),
        _ => return Err(InterpError::UnknownOperation),
    };
    *counter += extra;
    Ok(op)
}

fn read_operation_unary(line: &[u8], counter: &mut usize) -> Result<Unary> {
    let c = at(line, *counter);
    *counter += 1;
    let i = *counter;
    let table: &[(&[u8], Unary)] = match c {
        b'a' => &[
            (b"bs", Unary::Abs),
            (b"cos", Unary::Acos),
            (b"sin", Unary::Asin),
            (b"tan", Unary::Atan),
        ],
        b'c' => &[(b"os", Unary::Cos)],
        b'e' => &[(b"xp", Unary::Exp), (b"xists", Unary::Exists)],
        b'f' => &[(b"ix", Unary::Fix), (b"up", Unary::Fup)],
        b'l' => &[(b"n", Unary::Ln)],
        b'r' => &[(b"ound", Unary::Round)],
        b's' => &[(b"in", Unary::Sin), (b"qrt", Unary::Sqrt)],
        b't' => &[(b"an", Unary::Tan)],
        _ => return Err(InterpError::UnknownUnary),
    };
    for (rest, op) in table {
        if starts(line, i, rest) {
            *counter += rest.len();
            return Ok(*op);
        }
    }
    Err(InterpError::UnknownWord(c as char))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(text: &str) -> Result<f64> {
        let mut interp = Interp::new(Default::default());
        let line = crate::text::close_and_downcase(text.as_bytes()).unwrap();
        let mut counter = 0;
        interp.read_real_value(&line.bytes, &mut counter)
    }

    #[test]
    fn precedence_and_functions() {
        assert!((eval("[2 - 3 * 4 / 5]").unwrap() + 0.4).abs() < 1e-12);
        assert_eq!(eval("[2 ** 3 * 2]").unwrap(), 16.0);
        assert_eq!(eval("[1 + 2 GT 2 AND 1]").unwrap(), 1.0);
        assert_eq!(eval("[-7 MOD 3]").unwrap(), 2.0);
        assert_eq!(eval("ATAN[1]/[1]").unwrap(), 45.0);
        assert_eq!(eval("ROUND[-2.5]").unwrap(), -3.0);
        assert_eq!(eval("FUP[1.2]").unwrap(), 2.0);
        assert_eq!(eval("[1 EQ 1.00001]").unwrap(), 1.0);
        assert_eq!(eval("EXISTS[#<nope>]").unwrap(), 0.0);
        assert_eq!(eval("--1").unwrap(), 1.0);
    }

    #[test]
    fn errors_have_linuxcnc_texts() {
        let text = |s: &str| eval(s).unwrap_err().to_string();
        assert_eq!(text("[1/0]"), "Attempt to divide by zero");
        assert_eq!(text("[1"), "Unclosed expression");
        assert_eq!(text("[1 foo 2]"), "Unknown operation");
        assert_eq!(text("SQRT[-1]"), "Negative argument to sqrt");
        assert_eq!(
            text("1.2.3"),
            "bad number format (trailing characters) parsing '1.2.3'"
        );
        assert_eq!(
            text("."),
            "bad number format (conversion failed) parsing '.'"
        );
        assert_eq!(text("#<nope>"), "Named parameter #<nope> not defined");
        assert_eq!(text("#6000"), "Parameter number out of range");
        assert_eq!(text("[1 AMD 2]"), "Unknown operation name starting with a");
        assert_eq!(text("COZ[1]"), "Unknown word starting with c");
    }
}
