//! O-word control flow: subroutines (`sub`/`endsub`/`return`/`call`,
//! Fanuc `M98`/`M99`), conditionals (`if`/`elseif`/`else`/`endif`) and
//! loops (`while`, `do`/`while`, `repeat`, `break`, `continue`).
//!
//! As in LinuxCNC, flow is made by moving in the file: labels remember
//! the byte offset of their line, jumps seek there, and skipping reads
//! lines without executing them until the wanted label comes.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::block::{Block, OType, SUB_PARAMS};
use crate::canon::Canon;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::source::Source;

/// How a subroutine level was entered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CallType {
    /// Level 0 or a level being set up.
    #[default]
    None,
    /// `O... call`.
    OwordSub,
    /// Fanuc `M98`.
    M98Sub,
}

/// One subroutine level (LinuxCNC's call context).
#[derive(Debug, Clone, Default)]
pub struct Context {
    /// Where to continue in the caller's file; `None` when the caller
    /// had no file (an MDI line).
    pub position: Option<u64>,
    /// The caller's line number.
    pub sequence_number: i32,
    /// The caller's file.
    pub filename: String,
    /// The subroutine running at this level.
    pub sub_name: Option<String>,
    /// #1..#30 of the caller.
    pub saved_params: Vec<f64>,
    pub(crate) call_type: CallType,
    /// Remaining M98 L repetitions (-1: none running).
    pub(crate) m98_loop_counter: i32,
    /// Modal state saved by M70/M73.
    pub(crate) saved_state: Option<crate::exec::SavedState>,
    /// M73: restore the saved state on return.
    pub(crate) restore_on_return: bool,
}

/// Where a label's line is.
#[derive(Debug, Clone)]
pub struct Label {
    pub(crate) o_type: OType,
    pub(crate) offset: u64,
    pub(crate) filename: String,
    pub(crate) repeat_count: i32,
    pub(crate) sequence_number: i32,
}

/// The control-flow state.
#[derive(Debug, Clone)]
pub struct Flow {
    pub(crate) call_level: usize,
    pub(crate) contexts: Vec<Context>,
    pub(crate) skipping_o: Option<String>,
    pub(crate) skipping_to_sub: Option<String>,
    pub(crate) skipping_start: i32,
    pub(crate) defining_sub: bool,
    pub(crate) sub_name: Option<String>,
    pub(crate) executed_if: bool,
    pub(crate) doing_break: bool,
    pub(crate) doing_continue: bool,
    pub(crate) test_value: f64,
    pub(crate) return_value: f64,
    pub(crate) value_returned: bool,
    pub(crate) labels: HashMap<String, Label>,
}

impl Default for Flow {
    fn default() -> Self {
        Flow {
            call_level: 0,
            contexts: vec![
                Context {
                    m98_loop_counter: -1,
                    ..Context::default()
                };
                crate::params::CALL_LEVELS + 1
            ],
            skipping_o: None,
            skipping_to_sub: None,
            skipping_start: 0,
            defining_sub: false,
            sub_name: None,
            executed_if: false,
            doing_break: false,
            doing_continue: false,
            test_value: 0.0,
            return_value: 0.0,
            value_returned: false,
            labels: HashMap::new(),
        }
    }
}

impl Interp {
    /// Leave every subroutine level and forget labels and skipping.
    pub(crate) fn unwind_call(&mut self) {
        while self.flow.call_level > 0 {
            let level = self.flow.call_level;
            self.params.clear_level(level);
            let frame = self.flow.contexts[level - 1].clone();
            for (i, v) in frame.saved_params.iter().enumerate() {
                self.params.set(i + 1, *v);
            }
            self.flow.contexts[level - 1].sub_name = None;
            if self.source.is_some() && !frame.filename.is_empty() {
                if frame.filename != self.filename {
                    if let Ok(source) = Source::open(Path::new(&frame.filename)) {
                        self.source = Some(source);
                        self.filename = frame.filename.clone();
                    }
                }
                if let (Some(source), Some(pos)) = (self.source.as_mut(), frame.position) {
                    let _ = source.seek(pos);
                }
                self.s.sequence_number = frame.sequence_number;
            }
            self.flow.call_level -= 1;
        }
        self.flow.sub_name = None;
        self.flow.defining_sub = false;
        self.flow.skipping_o = None;
        self.flow.skipping_to_sub = None;
        self.flow.labels.clear();
        self.comp.clear();
    }

    fn find_label(&self, name: &str) -> Option<&Label> {
        self.flow.labels.get(name)
    }

    fn save_label(&mut self, block: &Block) -> Result<()> {
        if let Some(label) = self.find_label(&block.o_name) {
            return Err(if self.s.sequence_number - 1 == label.sequence_number {
                InterpError::SubIllegalLocation(
                    self.filename.clone(),
                    self.s.sequence_number,
                    block.o_name.clone(),
                )
            } else {
                InterpError::SubRedefined(
                    self.filename.clone(),
                    self.s.sequence_number,
                    block.o_name.clone(),
                    label.filename.clone(),
                )
            });
        }
        self.flow.labels.insert(
            block.o_name.clone(),
            Label {
                o_type: block.o_type,
                offset: block.offset,
                filename: self.filename.clone(),
                repeat_count: -1,
                sequence_number: self.s.sequence_number - 1,
            },
        );
        Ok(())
    }

    fn line_text_lossy(&self) -> String {
        String::from_utf8_lossy(&self.raw_line).into_owned()
    }

    /// Execute an O-word line.
    pub(crate) fn convert_control_functions(
        &mut self,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if let Some(skip) = &self.flow.skipping_o {
            if *skip != block.o_name {
                return Ok(());
            }
        }
        if self.flow.skipping_to_sub.is_some() && !matches!(block.o_type, OType::Sub | OType::Fanuc)
        {
            return Ok(());
        }
        match block.o_type {
            OType::None => Ok(()),
            OType::Sub | OType::Fanuc => self.control_sub(block),
            OType::Endsub | OType::Return | OType::M99 => self.control_return(block, canon),
            OType::Call | OType::M98 => self.control_call(block),
            OType::Do => {
                self.flow.skipping_o = None;
                if self.find_label(&block.o_name).is_none() {
                    self.save_label(block)?;
                }
                Ok(())
            }
            OType::Repeat => self.control_repeat(block),
            OType::While => self.control_while(block),
            OType::If => self.control_if(block),
            OType::Elseif | OType::Else | OType::Endif => self.control_else(block),
            OType::Break | OType::Continue => self.control_break(block),
            OType::Endwhile | OType::Endrepeat => self.control_end_loop(block),
        }
    }

    fn control_sub(&mut self, block: &Block) -> Result<()> {
        let call_type = self.flow.contexts[self.flow.call_level].call_type;
        if block.o_type == OType::Fanuc && !matches!(call_type, CallType::M98Sub | CallType::None) {
            return Err(InterpError::FanucSubNeedsM98);
        }
        if block.o_type == OType::Sub && !matches!(call_type, CallType::OwordSub | CallType::None) {
            return Err(InterpError::SubNeedsCall);
        }
        if self.flow.skipping_o.is_some() {
            self.save_label(block)?;
            self.flow.skipping_o = None;
        }
        self.flow.skipping_to_sub = None;
        if block.o_type == OType::Fanuc || self.flow.call_level != 0 {
            return Ok(());
        }
        if self.flow.defining_sub {
            return Err(InterpError::NestedSubDefinition);
        }
        self.save_label(block)?;
        self.flow.skipping_o = Some(block.o_name.clone());
        self.flow.skipping_start = self.s.sequence_number;
        self.flow.defining_sub = true;
        self.flow.sub_name = Some(block.o_name.clone());
        Ok(())
    }

    fn control_return(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        if block.o_type == OType::M99 && self.flow.call_level == 0 {
            return Err(InterpError::M99Bug);
        }
        if self.flow.call_level == 0 && self.flow.sub_name.is_none() {
            return Err(InterpError::StandaloneReturn(
                self.s.sequence_number,
                self.line_text_lossy(),
            ));
        }
        let level = self.flow.call_level;
        let call_type = self.flow.contexts[level].call_type;
        if call_type == CallType::M98Sub && block.o_type != OType::M99 {
            return Err(InterpError::FanucSubNeedsM99);
        }
        if call_type == CallType::OwordSub && !matches!(block.o_type, OType::Endsub | OType::Return)
        {
            return Err(InterpError::SubNeedsEndsub);
        }
        if self.flow.skipping_o.is_some() && block.o_type == OType::Endsub {
            self.flow.skipping_o = None;
        }
        if level == 0 {
            if block.o_type == OType::Endsub {
                if !self.flow.defining_sub {
                    return Err(InterpError::NotInSubDefinition);
                }
                self.flow.skipping_o = None;
                self.flow.defining_sub = false;
                self.flow.sub_name = None;
            }
            return Ok(());
        }
        let frame = self.flow.contexts[level - 1].clone();
        if call_type != CallType::M98Sub {
            for (i, v) in frame.saved_params.iter().enumerate() {
                self.params.set(i + 1, *v);
            }
        }
        match frame.position {
            None => {
                self.source = None;
                self.filename.clear();
            }
            Some(position) => {
                if self.source.is_none() {
                    return Err(InterpError::FileNotOpen);
                }
                if self.filename != frame.filename {
                    let source = Source::open(Path::new(&frame.filename)).map_err(|e| {
                        InterpError::CannotReopen(frame.filename.clone(), e.to_string())
                    })?;
                    self.source = Some(source);
                    self.filename = frame.filename.clone();
                }
                if let Some(source) = self.source.as_mut() {
                    source.seek(position)?;
                }
                self.s.sequence_number = frame.sequence_number;
            }
        }
        self.leave_context(canon)?;
        self.flow.sub_name = self.flow.contexts[self.flow.call_level].sub_name.clone();
        Ok(())
    }

    fn leave_context(&mut self, canon: &mut dyn Canon) -> Result<()> {
        let level = self.flow.call_level;
        self.params.clear_level(level);
        let leaving = std::mem::take(&mut self.flow.contexts[level]);
        self.flow.contexts[level].m98_loop_counter = -1;
        self.flow.call_level -= 1;
        if leaving.restore_on_return {
            if let Some(state) = leaving.saved_state {
                self.restore_state(&state, canon)?;
            }
        }
        Ok(())
    }

    fn control_call(&mut self, block: &mut Block) -> Result<()> {
        self.flow.call_level += 1;
        if self.flow.call_level >= crate::params::CALL_LEVELS {
            self.flow.call_level -= 1;
            return Err(InterpError::TooManySubLevels);
        }
        let level = self.flow.call_level;
        self.flow.contexts[level] = Context {
            sub_name: Some(block.o_name.clone()),
            call_type: if block.o_type == OType::M98 {
                CallType::M98Sub
            } else {
                CallType::OwordSub
            },
            m98_loop_counter: -1,
            ..Context::default()
        };
        self.flow.skipping_o = None;
        let previous = level - 1;
        if block.o_type != OType::M98 {
            let saved: Vec<f64> = (1..=SUB_PARAMS).map(|i| self.params.get(i)).collect();
            self.flow.contexts[previous].saved_params = saved;
            for i in 0..SUB_PARAMS {
                self.params
                    .set(i + 1, block.params.get(i).copied().unwrap_or(0.0));
            }
        }
        let position = self.source.as_ref().map(|s| s.tell());
        let frame = &mut self.flow.contexts[previous];
        frame.position = position;
        frame.filename = self.filename.clone();
        frame.sequence_number = self.s.sequence_number;
        if self.config.features.oword_n_args {
            let count = block.params.len() as f64;
            self.params.store_named("n_args", count, level)?;
        }
        if block.o_type == OType::M98 && block.l_flag {
            let frame = &mut self.flow.contexts[previous];
            if frame.m98_loop_counter == -1 {
                frame.m98_loop_counter = block.l_number;
            }
            frame.m98_loop_counter -= 1;
            if frame.m98_loop_counter > 0 {
                frame.position = Some(block.offset);
                frame.sequence_number -= 1;
            } else {
                frame.m98_loop_counter = -1;
            }
            if block.l_number == 0 {
                return Ok(());
            }
        }
        self.control_back_to(block)
    }

    /// Jump to a label: seek to it if known, else open `name.ngc` from
    /// the subroutine path (or keep reading this file) and skip to it.
    fn control_back_to(&mut self, block: &Block) -> Result<()> {
        let name = block
            .o_name
            .rsplit('/')
            .next()
            .unwrap_or(&block.o_name)
            .to_string();
        if let Some(label) = self.flow.labels.get(&name).cloned() {
            if label.filename != self.filename {
                let source = Source::open(Path::new(&label.filename))
                    .map_err(|_| InterpError::UnableToOpenFile(label.filename.clone()))?;
                self.source = Some(source);
                self.filename = label.filename.clone();
            }
            if let Some(source) = self.source.as_mut() {
                source.seek(label.offset)?;
            }
            self.s.sequence_number = label.sequence_number;
            return Ok(());
        }
        if let Some(path) = self.find_ngc_file(&block.o_name) {
            let source = Source::open(&path)
                .map_err(|_| InterpError::UnableToOpenFile(block.o_name.clone()))?;
            self.s.sequence_number = 0;
            self.source = Some(source);
            self.filename = path.display().to_string();
        }
        self.flow.skipping_o = Some(name.clone());
        self.flow.skipping_to_sub = Some(name);
        self.flow.skipping_start = self.s.sequence_number;
        Ok(())
    }

    /// `name.ngc` in the program prefix or the subroutine path.
    fn find_ngc_file(&self, name: &str) -> Option<PathBuf> {
        let file = format!("{name}.ngc");
        let here = PathBuf::from(".");
        let prefix = std::iter::once(self.config.program_prefix.as_ref().unwrap_or(&here));
        prefix
            .chain(self.config.subroutine_path.iter())
            .map(|dir| dir.join(&file))
            .find(|p| p.is_file())
    }

    fn control_repeat(&mut self, block: &Block) -> Result<()> {
        if let Some(label) = self.find_label(&block.o_name) {
            if self.s.sequence_number != label.sequence_number + 1 {
                return Err(InterpError::DuplicateLoopLabel(
                    self.s.sequence_number,
                    self.line_text_lossy(),
                    label.sequence_number + 1,
                ));
            }
        } else {
            self.save_label(block)?;
        }
        self.flow.skipping_o = None;
        let test = self.flow.test_value;
        let label = self
            .flow
            .labels
            .get_mut(&block.o_name)
            .ok_or(InterpError::UnknownOwordNumber)?;
        if label.o_type != block.o_type {
            return Ok(());
        }
        if label.repeat_count == -1 {
            label.repeat_count = crate::block::round_to_int(test);
        }
        if label.repeat_count > 0 {
            label.repeat_count -= 1;
        } else {
            label.repeat_count = -1;
            self.flow.skipping_o = Some(block.o_name.clone());
            self.flow.skipping_start = self.s.sequence_number;
        }
        Ok(())
    }

    fn control_while(&mut self, block: &Block) -> Result<()> {
        match self.find_label(&block.o_name) {
            Some(label) => {
                if label.o_type != OType::Do && self.s.sequence_number != label.sequence_number + 1
                {
                    return Err(InterpError::DuplicateLoopLabel(
                        self.s.sequence_number,
                        self.line_text_lossy(),
                        label.sequence_number + 1,
                    ));
                }
            }
            None => self.save_label(block)?,
        }
        self.flow.skipping_o = None;
        let is_while = self.find_label(&block.o_name).map(|l| l.o_type) == Some(OType::While);
        if is_while {
            if self.flow.test_value == 0.0 {
                self.flow.skipping_o = Some(block.o_name.clone());
                self.flow.skipping_start = self.s.sequence_number;
            }
        } else if self.flow.test_value != 0.0 && !self.flow.doing_break {
            self.control_back_to(block)?;
        } else {
            self.flow.doing_break = false;
        }
        Ok(())
    }

    fn control_if(&mut self, block: &Block) -> Result<()> {
        if let Some(label) = self.find_label(&block.o_name) {
            if self.s.sequence_number != label.sequence_number + 1 {
                return Err(InterpError::DuplicateIfLabel(
                    self.s.sequence_number,
                    label.sequence_number + 1,
                    self.line_text_lossy(),
                ));
            }
        } else {
            self.save_label(block)?;
        }
        if self.flow.test_value != 0.0 {
            self.flow.skipping_o = None;
            self.flow.executed_if = true;
        } else {
            self.flow.skipping_o = Some(block.o_name.clone());
            self.flow.skipping_start = self.s.sequence_number;
            self.flow.executed_if = false;
        }
        Ok(())
    }

    /// The label of an `elseif`/`else`/`endif`, checked to be an `if`.
    fn if_label(&self, block: &Block) -> Result<()> {
        let Some(label) = self.find_label(&block.o_name) else {
            return Err(InterpError::UndefinedOLabel(
                self.s.sequence_number,
                self.line_text_lossy(),
            ));
        };
        if label.o_type != OType::If {
            return Err(if block.o_type == OType::Endif {
                InterpError::NoMatchingEndif(
                    self.s.sequence_number,
                    block.o_name.clone(),
                    label.o_type.name(),
                    label.sequence_number + 1,
                    self.line_text_lossy(),
                )
            } else {
                InterpError::NoMatchingIf(
                    self.s.sequence_number,
                    self.line_text_lossy(),
                    label.o_type.name(),
                    label.sequence_number + 1,
                )
            });
        }
        Ok(())
    }

    fn control_else(&mut self, block: &Block) -> Result<()> {
        self.if_label(block)?;
        let skipping_this = self.flow.skipping_o.as_deref() == Some(block.o_name.as_str());
        match block.o_type {
            OType::Elseif => {
                if self.flow.skipping_o.is_some() && !skipping_this {
                    return Ok(());
                }
                if self.flow.executed_if {
                    self.flow.skipping_o = Some(block.o_name.clone());
                    self.flow.skipping_start = self.s.sequence_number;
                } else if self.flow.test_value != 0.0 {
                    self.flow.skipping_o = None;
                    self.flow.executed_if = true;
                }
            }
            OType::Else => {
                if self.flow.executed_if {
                    self.flow.skipping_o = Some(block.o_name.clone());
                    self.flow.skipping_start = self.s.sequence_number;
                } else if skipping_this {
                    self.flow.executed_if = true;
                    self.flow.skipping_o = None;
                }
            }
            _ => {
                self.flow.skipping_o = None;
                self.flow.executed_if = true;
            }
        }
        Ok(())
    }

    fn loop_label(&self, block: &Block) -> Result<OType> {
        let Some(label) = self.find_label(&block.o_name) else {
            return Err(InterpError::UndefinedOLabel(
                self.s.sequence_number,
                self.line_text_lossy(),
            ));
        };
        Ok(label.o_type)
    }

    fn control_break(&mut self, block: &Block) -> Result<()> {
        let kind = self.loop_label(block)?;
        if kind != OType::While && kind != OType::Do {
            let label = &self.flow.labels[&block.o_name];
            return Err(InterpError::NoMatchingWhile(
                self.s.sequence_number,
                self.line_text_lossy(),
                kind.name(),
                label.sequence_number + 1,
            ));
        }
        if block.o_type == OType::Continue
            && self.flow.skipping_o.as_deref() == Some(block.o_name.as_str())
        {
            return Ok(());
        }
        self.flow.skipping_o = Some(block.o_name.clone());
        self.flow.skipping_start = self.s.sequence_number;
        if block.o_type == OType::Break {
            self.flow.doing_break = true;
        } else {
            self.flow.doing_continue = true;
        }
        Ok(())
    }

    fn control_end_loop(&mut self, block: &Block) -> Result<()> {
        let kind = self.loop_label(block)?;
        let expected = if block.o_type == OType::Endrepeat {
            OType::Repeat
        } else {
            OType::While
        };
        if kind != expected {
            let label = &self.flow.labels[&block.o_name];
            return Err(InterpError::NoMatchingLoop(
                self.s.sequence_number,
                self.line_text_lossy(),
                kind.name(),
                label.sequence_number + 1,
            ));
        }
        if self.flow.skipping_o.as_deref() == Some(block.o_name.as_str()) {
            self.flow.skipping_o = None;
            if self.flow.doing_continue {
                self.flow.doing_continue = false;
                self.control_back_to(block)?;
            }
            return Ok(());
        }
        self.control_back_to(block)
    }
}
