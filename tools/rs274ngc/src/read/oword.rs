//! O-word lines (`o100 sub`, `o<name> call [1] [2]`, `o1 if [#1 GT 2]`)
//! and Fanuc-style `M98 P...` / `M99`.

use super::at;
use crate::block::{Block, OType, SUB_PARAMS};
use crate::error::{InterpError, Result};
use crate::interp::Interp;

/// A name between `<` and `>`; the counter is left after the `>`.
pub(crate) fn read_name(line: &[u8], counter: &mut usize) -> Result<String> {
    *counter += 1;
    let start = *counter;
    while *counter < line.len() {
        if line[*counter] == b'>' {
            let name = String::from_utf8_lossy(&line[start..*counter]).into_owned();
            *counter += 1;
            return Ok(name);
        }
        *counter += 1;
    }
    Err(InterpError::NamedParameterNotTerminated)
}

const KEYWORDS: [(&[u8], OType); 15] = [
    (b"sub", OType::Sub),
    (b"endsub", OType::Endsub),
    (b"call", OType::Call),
    (b"do", OType::Do),
    (b"while", OType::While),
    (b"repeat", OType::Repeat),
    (b"if", OType::If),
    (b"elseif", OType::Elseif),
    (b"else", OType::Else),
    (b"endif", OType::Endif),
    (b"break", OType::Break),
    (b"continue", OType::Continue),
    (b"endwhile", OType::Endwhile),
    (b"endrepeat", OType::Endrepeat),
    (b"return", OType::Return),
];

impl Interp {
    /// Read an O-word line (or M98/M99) into `block`.
    pub(crate) fn read_o(
        &mut self,
        line: &[u8],
        counter: &mut usize,
        block: &mut Block,
    ) -> Result<()> {
        let name = if at(line, *counter) == b'm' {
            self.read_fanuc_call(line, counter, block)?
        } else {
            *counter += 1;
            let name = if at(line, *counter) == b'<' {
                read_name(line, counter)?
            } else {
                self.read_integer_value(line, counter)?.to_string()
            };
            block.o_type = OType::None;
            for (word, kind) in KEYWORDS {
                if line.get(*counter..*counter + word.len()) == Some(word) {
                    *counter += word.len();
                    block.o_type = kind;
                    break;
                }
            }
            if block.o_type == OType::None && matches!(at(line, *counter), b'(' | b';' | 0) {
                if self.config.disable_fanuc_style_sub {
                    return Err(InterpError::FanucDisabledO);
                }
                block.o_type = OType::Fanuc;
            }
            name
        };
        block.o_name = match block.o_type {
            OType::Sub
            | OType::Fanuc
            | OType::Endsub
            | OType::Call
            | OType::M98
            | OType::Return
            | OType::M99 => name,
            _ => format!("{}#{}", self.scope_name(), name),
        };
        self.read_o_arguments(line, counter, block)
    }

    /// The name of the subroutine local O-words belong to.
    fn scope_name(&self) -> String {
        if self.flow.call_level > 0 {
            self.flow.contexts[self.flow.call_level]
                .sub_name
                .clone()
                .unwrap_or_default()
        } else if self.flow.defining_sub {
            self.flow.sub_name.clone().unwrap_or_default()
        } else {
            String::new()
        }
    }

    /// `M98 P.. L..` or `M99`; returns the subroutine name.
    fn read_fanuc_call(
        &mut self,
        line: &[u8],
        counter: &mut usize,
        block: &mut Block,
    ) -> Result<String> {
        let mut n = *counter + 1;
        let number = self.read_integer_value(line, &mut n)?;
        if number == 98 {
            if self.config.disable_fanuc_style_sub {
                return Err(InterpError::FanucDisabledM98);
            }
            block.o_type = OType::M98;
            *counter = n;
            while *counter < line.len() {
                self.item_start = *counter;
                self.read_one_item(line, counter, block)?;
            }
            if !block.p_flag {
                return Err(InterpError::M98NoP);
            }
            let p = block.p_number;
            let mut n = super::c_int(p.floor());
            if p - n as f64 > 0.9999 {
                n = super::c_int(p.ceil());
            } else if p - n as f64 > 0.0001 {
                return Err(InterpError::NonInteger);
            }
            Ok(n.to_string())
        } else {
            if self.config.disable_fanuc_style_sub {
                return Err(InterpError::FanucDisabledM99);
            }
            if self.flow.defining_sub {
                return Err(InterpError::M99InSub);
            }
            block.o_type = OType::M99;
            *counter = n;
            Ok(self.flow.contexts[self.flow.call_level]
                .sub_name
                .clone()
                .unwrap_or_default())
        }
    }

    fn read_o_arguments(
        &mut self,
        line: &[u8],
        counter: &mut usize,
        block: &mut Block,
    ) -> Result<()> {
        let skipping_other =
            |this: &Interp, name: &str| this.flow.skipping_o.as_deref().is_some_and(|s| s != name);
        match block.o_type {
            OType::Sub | OType::Fanuc => {
                if self.flow.defining_sub {
                    return Err(InterpError::NestedSubDefinition);
                }
            }
            OType::Endsub | OType::Return | OType::M99 => {
                if skipping_other(self, &block.o_name) {
                    return Ok(());
                }
                if block.o_type != OType::M99 && at(line, *counter) == b'[' {
                    let value = self.read_real_expression(line, counter)?;
                    self.flow.return_value = value;
                    self.flow.value_returned = true;
                } else {
                    self.flow.return_value = 0.0;
                    self.flow.value_returned = false;
                }
            }
            _ if self.flow.defining_sub => block.o_type = OType::None,
            OType::Call => {
                if self.flow.skipping_o.is_some() {
                    block.o_type = OType::None;
                    return Ok(());
                }
                block.params.clear();
                while matches!(at(line, *counter), b'[' | b'(') {
                    if at(line, *counter) == b'(' {
                        *counter += 1;
                        while *counter < line.len() && line[*counter] != b')' {
                            *counter += 1;
                        }
                        *counter += 1;
                        continue;
                    }
                    if block.params.len() >= SUB_PARAMS {
                        return Err(InterpError::TooManySubParams);
                    }
                    let value = self.read_real_expression(line, counter)?;
                    block.params.push(value);
                }
            }
            OType::M98 => block.params.clear(),
            OType::While | OType::Repeat | OType::If | OType::Elseif => {
                if skipping_other(self, &block.o_name) {
                    return Ok(());
                }
                if at(line, *counter) != b'[' {
                    return Err(InterpError::LeftBracketMissingAfter(block.o_type.name()));
                }
                self.flow.test_value = self.read_real_expression(line, counter)?;
            }
            OType::Do
            | OType::Else
            | OType::Endif
            | OType::Break
            | OType::Continue
            | OType::Endwhile
            | OType::Endrepeat => {}
            OType::None => return Err(InterpError::UnknownOControl),
        }
        Ok(())
    }
}
