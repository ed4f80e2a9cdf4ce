//! Reading a cleaned line into a [`Block`]: line number, words,
//! parameter settings, comments, O-word control lines. Values are
//! evaluated while reading, with the parameters as they are before the
//! line (settings on the line take effect when it is executed).

mod expr;
mod oword;

use crate::block::Block;
use crate::codes::{g_group, m_group, G_80};
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::params::{is_readonly, Parameters};

/// C's conversion of a double to `int` on x86: truncation, and
/// `INT_MIN` for anything out of range.
pub(crate) fn c_int(x: f64) -> i32 {
    if x.is_nan() || !(-2147483648.0..2147483648.0).contains(&x) {
        i32::MIN
    } else {
        x as i32
    }
}

/// The byte at `i`, or 0 past the end (the C string terminator).
pub(crate) fn at(line: &[u8], i: usize) -> u8 {
    line.get(i).copied().unwrap_or(0)
}

impl Interp {
    /// Read all items of a cleaned line into `block`.
    pub(crate) fn read_items(&mut self, block: &mut Block, line: &[u8]) -> Result<()> {
        let mut counter = 0usize;
        if at(line, counter) == b'/' {
            counter += 1;
        }
        if at(line, counter) == b'n' {
            self.item_start = counter;
            self.read_n_number(line, &mut counter, block)?;
        }
        let m_number = if at(line, counter) == b'm' {
            let mut m_counter = counter + 1;
            self.read_integer_value(line, &mut m_counter).ok()
        } else {
            None
        };
        let is_o_line = at(line, counter) == b'o'
            || m_number == Some(98)
            || (m_number == Some(99) && self.flow.call_level > 0);
        if is_o_line {
            self.item_start = counter;
            self.read_o(line, &mut counter, block)?;
            if self.flow.skipping_o.is_some() {
                return Ok(());
            }
            while counter < line.len() {
                self.item_start = counter;
                match line[counter] {
                    b';' => counter = line.len(),
                    b'(' => self.read_comment(line, &mut counter, block)?,
                    _ => return Err(InterpError::UnexpectedAfterO),
                }
            }
            return Ok(());
        }
        if self.flow.skipping_o.is_some() {
            return Ok(());
        }
        while counter < line.len() {
            self.item_start = counter;
            self.read_one_item(line, &mut counter, block)?;
        }
        Ok(())
    }

    pub(crate) fn read_one_item(
        &mut self,
        line: &[u8],
        counter: &mut usize,
        block: &mut Block,
    ) -> Result<()> {
        let letter = line[*counter];
        if !(b' '..=b'z').contains(&letter) {
            return Err(InterpError::BadCharacterCode(letter));
        }
        match letter {
            b'#' => self.read_parameter_setting(line, counter),
            b'(' => self.read_comment(line, counter, block),
            b';' => {
                *counter = line.len();
                Ok(())
            }
            b'g' => self.read_g(line, counter, block),
            b'm' => self.read_m(line, counter, block),
            b'$' | b'@' | b'^' => self.read_special(line, counter, block),
            b'a'..=b'z' if !matches!(letter, b'g' | b'm' | b'n' | b'o') => {
                if !self.axis_present(letter) {
                    return Err(InterpError::BadCharacter(letter as char));
                }
                self.read_letter(line, counter, block)
            }
            _ if letter == b' ' || !letter.is_ascii_graphic() => {
                Err(InterpError::BadCharacterCode(letter))
            }
            _ => Err(InterpError::BadCharacter(letter as char)),
        }
    }

    /// Whether an axis letter names an axis of the machine (other letters
    /// always pass).
    fn axis_present(&self, letter: u8) -> bool {
        let bit = match letter {
            b'x' => 0,
            b'y' => 1,
            b'z' => 2,
            b'a' => 3,
            b'b' => 4,
            b'c' => 5,
            b'u' => 6,
            b'v' => 7,
            b'w' => 8,
            _ => return true,
        };
        // A G7x profile may use U and W (increments) and A and C (corner
        // finishes) whatever the machine's axes.
        let profile_word = matches!(letter, b'a' | b'c' | b'u' | b'w');
        (self.reading_profile && profile_word) || self.s.axis_mask & (1 << bit) != 0
    }

    fn read_n_number(&mut self, line: &[u8], counter: &mut usize, block: &mut Block) -> Result<()> {
        *counter += 1;
        block.n_number = read_integer_unsigned(line, counter)?;
        if at(line, *counter) == b'.' {
            *counter += 1;
            read_integer_unsigned(line, counter)?;
        }
        Ok(())
    }

    fn read_comment(&mut self, line: &[u8], counter: &mut usize, block: &mut Block) -> Result<()> {
        *counter += 1;
        let start = *counter;
        while *counter < line.len() && line[*counter] != b')' {
            *counter += 1;
        }
        block.comment = Some(line[start..*counter].to_vec());
        *counter += 1;
        Ok(())
    }

    fn read_g(&mut self, line: &[u8], counter: &mut usize, block: &mut Block) -> Result<()> {
        *counter += 1;
        let value_read = 10.0 * self.read_real_value(line, counter)?;
        let mut value = c_int(value_read.floor());
        let frac = value_read - value as f64;
        if frac > 0.999 {
            value = c_int(value_read.ceil());
        } else if frac > 0.001 {
            return Err(InterpError::GCodeOutOfRange);
        }
        if value > 999 {
            return Err(InterpError::GCodeOutOfRange);
        }
        if value < 0 {
            return Err(InterpError::NegativeG);
        }
        let mode = g_group(value).ok_or(InterpError::UnknownG)?;
        if value == G_80 && block.g_modes[mode] != -1 {
            return Ok(());
        }
        if block.g_modes[mode] != G_80 && block.g_modes[mode] != -1 {
            return Err(InterpError::TwoGCodesSameGroup);
        }
        block.g_modes[mode] = value;
        Ok(())
    }

    fn read_m(&mut self, line: &[u8], counter: &mut usize, block: &mut Block) -> Result<()> {
        *counter += 1;
        let value = self.read_integer_value(line, counter)?;
        if value < 0 {
            return Err(InterpError::NegativeM);
        }
        if value > 199 {
            return Err(InterpError::MCodeTooBig(value));
        }
        let mode = m_group(value).ok_or(InterpError::UnknownM(value))?;
        if block.m_modes[mode] != -1 {
            return Err(InterpError::TwoMCodesSameGroup);
        }
        block.m_modes[mode] = value;
        block.m_count += 1;
        if (100..200).contains(&value) {
            block.user_m = true;
        }
        Ok(())
    }

    /// `$` spindle selection, `@` polar radius, `^` polar angle.
    fn read_special(&mut self, line: &[u8], counter: &mut usize, block: &mut Block) -> Result<()> {
        let letter = line[*counter];
        *counter += 1;
        if letter == b'$' && block.dollar_flag {
            return Err(InterpError::MultipleDollar);
        }
        let value = self.read_real_value(line, counter)?;
        match letter {
            b'$' => {
                block.dollar_flag = true;
                block.dollar_number = value;
            }
            b'@' => {
                block.radius_flag = true;
                block.radius = value;
            }
            _ => {
                block.theta_flag = true;
                block.theta = value;
            }
        }
        Ok(())
    }

    /// The word letters other than G, M, N and O.
    fn read_letter(&mut self, line: &[u8], counter: &mut usize, block: &mut Block) -> Result<()> {
        let letter = line[*counter];
        *counter += 1;
        let multiple = match letter {
            b'a' => block.a_flag,
            b'b' => block.b_flag,
            b'c' => block.c_flag,
            b'd' => block.d_flag,
            b'e' => block.e_flag,
            b'f' => block.f_flag,
            b'h' => block.h_flag,
            b'i' => block.i_flag,
            b'j' => block.j_flag,
            b'k' => block.k_flag,
            b'l' => block.l_number > -1,
            b'p' => block.p_number > -1.0,
            b'q' => block.q_number > -1.0,
            b'r' => block.r_flag,
            b's' => block.s_flag,
            b't' => block.t_flag,
            b'u' => return self.read_uvw(line, counter, block, letter),
            b'v' => return self.read_uvw(line, counter, block, letter),
            b'w' => return self.read_uvw(line, counter, block, letter),
            b'x' => block.x_flag,
            b'y' => block.y_flag,
            b'z' => block.z_flag,
            _ => return Err(InterpError::BadCharacter(letter as char)),
        };
        if multiple {
            return Err(InterpError::MultipleWords(letter as char));
        }
        match letter {
            b'h' | b'l' | b't' => {
                let value = self.read_integer_value(line, counter)?;
                match letter {
                    b'h' => {
                        if value < -1 {
                            return Err(InterpError::NegativeH);
                        }
                        block.h_flag = true;
                        block.h_number = value;
                    }
                    b'l' => {
                        if value < 0 {
                            return Err(InterpError::NegativeL);
                        }
                        block.l_flag = true;
                        block.l_number = value;
                    }
                    _ => {
                        if value < 0 {
                            return Err(InterpError::NegativeTool);
                        }
                        block.t_flag = true;
                        block.t_number = value;
                    }
                }
                return Ok(());
            }
            _ => {}
        }
        let value = self.read_real_value(line, counter)?;
        let (flag, number) = match letter {
            b'a' => (&mut block.a_flag, &mut block.a_number),
            b'b' => (&mut block.b_flag, &mut block.b_number),
            b'c' => (&mut block.c_flag, &mut block.c_number),
            b'd' => (&mut block.d_flag, &mut block.d_number),
            b'e' => (&mut block.e_flag, &mut block.e_number),
            b'f' => {
                if value < 0.0 {
                    return Err(InterpError::NegativeF);
                }
                (&mut block.f_flag, &mut block.f_number)
            }
            b'i' => (&mut block.i_flag, &mut block.i_number),
            b'j' => (&mut block.j_flag, &mut block.j_number),
            b'k' => (&mut block.k_flag, &mut block.k_number),
            b'p' => (&mut block.p_flag, &mut block.p_number),
            b'q' => (&mut block.q_flag, &mut block.q_number),
            b'r' => (&mut block.r_flag, &mut block.r_number),
            b's' => {
                if value < 0.0 {
                    return Err(InterpError::NegativeS);
                }
                (&mut block.s_flag, &mut block.s_number)
            }
            b'x' => {
                block.x_flag = true;
                block.x_number = if self.s.lathe_diameter_mode {
                    value / 2.0
                } else {
                    value
                };
                return Ok(());
            }
            b'y' => (&mut block.y_flag, &mut block.y_number),
            _ => (&mut block.z_flag, &mut block.z_number),
        };
        *flag = true;
        *number = value;
        Ok(())
    }

    fn read_uvw(
        &mut self,
        line: &[u8],
        counter: &mut usize,
        block: &mut Block,
        letter: u8,
    ) -> Result<()> {
        let (flag, err) = match letter {
            b'u' => (block.u_flag, InterpError::MultipleU),
            b'v' => (block.v_flag, InterpError::MultipleV),
            _ => (block.w_flag, InterpError::MultipleW),
        };
        if flag {
            return Err(err);
        }
        let value = self.read_real_value(line, counter)?;
        match letter {
            b'u' => (block.u_flag, block.u_number) = (true, value),
            b'v' => (block.v_flag, block.v_number) = (true, value),
            _ => (block.w_flag, block.w_number) = (true, value),
        }
        Ok(())
    }

    /// `#n=value` or `#<name>=value`: remembered, applied at execution.
    fn read_parameter_setting(&mut self, line: &[u8], counter: &mut usize) -> Result<()> {
        *counter += 1;
        if at(line, *counter) == b'<' {
            let name = oword::read_name(line, counter)?;
            self.add_named_param(&name);
            if at(line, *counter) != b'=' {
                return Err(InterpError::EqualSignMissing);
            }
            *counter += 1;
            let value = self.read_real_value(line, counter)?;
            self.pending_named.push((name, value));
        } else {
            let index = self.read_integer_value(line, counter)?;
            let index = Parameters::check_index(index)?;
            if is_readonly(index as i32) {
                return Err(InterpError::ParameterReadonly);
            }
            if at(line, *counter) != b'=' {
                return Err(InterpError::EqualSignMissing);
            }
            *counter += 1;
            let value = self.read_real_value(line, counter)?;
            self.pending_numbered.push((index, value));
        }
        Ok(())
    }
}

/// Digits of an unsigned integer (line numbers).
fn read_integer_unsigned(line: &[u8], counter: &mut usize) -> Result<i32> {
    let start = *counter;
    let mut n = start;
    while at(line, n).is_ascii_digit() {
        n += 1;
    }
    if n == start {
        return Err(InterpError::BadUnsignedInteger);
    }
    let text = std::str::from_utf8(&line[start..n]).unwrap_or("0");
    // sscanf("%d") of a number too big for int: glibc saturates.
    let value = text.parse::<i64>().unwrap_or(i64::MAX);
    *counter = n;
    Ok(value.clamp(i32::MIN as i64, i32::MAX as i64) as i32)
}
