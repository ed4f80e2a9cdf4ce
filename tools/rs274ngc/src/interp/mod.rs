//! The interpreter object and its public interface: open a program,
//! read and execute it block by block (or run MDI lines), query the
//! modal state, reset and exit.
//!
//! Reading and executing are separate steps so a caller can read ahead:
//! [`Interp::read`] parses the next block with the parameters as they
//! are, [`Interp::execute`] runs it. A status of
//! [`Status::ExecuteFinish`] after executing means the block needs the
//! world's answer (a probe result, the position after a tool change, an
//! input): the caller must let the motion queue drain before reading on.

mod named;
mod state;

pub use state::{ActiveCodes, Location};

use std::path::{Path, PathBuf};

use crate::block::{Block, OType};
use crate::canon::{Canon, FeedReference};
use crate::comp::CompQueue;
use crate::config::Config;
use crate::control::Flow;
use crate::error::{InterpError, Result};
use crate::params::{file as param_file, Parameters};
use crate::setup::{Setup, SpindleState};
use crate::source::{Line, Source, LINELEN};
use crate::text::{close_and_downcase, CleanLine};

/// What a read or an execute step ended with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Done; go on.
    Ok,
    /// Done, but the next read needs the world's state first (probe,
    /// tool change, input wait) or, after a read, the line was skipped
    /// by block delete.
    ExecuteFinish,
    /// The program ended (M2, M30).
    Exit,
    /// The closing `%` line was read.
    EndFile,
}

/// The RS274NGC interpreter.
#[derive(Debug)]
pub struct Interp {
    pub(crate) s: Setup,
    pub(crate) params: Parameters,
    pub(crate) config: Config,
    pub(crate) block: Block,
    pub(crate) source: Option<Source>,
    /// Name of the file being read ("" for none).
    pub(crate) filename: String,
    /// The line as read (trailing white space removed).
    pub(crate) raw_line: Vec<u8>,
    /// The line cleaned for reading.
    pub(crate) clean: CleanLine,
    /// Zero when the line is blank (or block-deleted).
    pub(crate) line_length: usize,
    pub(crate) pending_numbered: Vec<(usize, f64)>,
    pub(crate) pending_named: Vec<(String, f64)>,
    pub(crate) flow: Flow,
    pub(crate) comp: CompQueue,
    /// Where in the cleaned line the item being read starts (for error
    /// locations).
    pub(crate) item_start: usize,
    /// The word a refusal is about, when execution knows it.
    pub(crate) refused_word: Option<String>,
    /// A G7x cycle is reading its profile (U, W, A and C read as words).
    pub(crate) reading_profile: bool,
    /// Parameter numbers the parameter file held.
    pub(crate) param_file_numbers: Vec<usize>,
}

impl Interp {
    /// A new interpreter; call [`Interp::init`] before use.
    pub fn new(config: Config) -> Interp {
        Interp {
            s: Setup::default(),
            params: Parameters::default(),
            config,
            block: Block::default(),
            source: None,
            filename: String::new(),
            raw_line: Vec::new(),
            clean: CleanLine::default(),
            line_length: 0,
            pending_numbered: Vec::new(),
            pending_named: Vec::new(),
            flow: Flow::default(),
            comp: CompQueue::default(),
            item_start: 0,
            refused_word: None,
            reading_profile: false,
            param_file_numbers: Vec::new(),
        }
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Initialise: read the parameter file, set up the coordinate
    /// system it names, and synchronise with the world.
    pub fn init(&mut self, canon: &mut dyn Canon) -> Result<()> {
        self.s = Setup {
            orient_offset: self.config.orient_offset,
            spindles: vec![SpindleState::STOPPED; self.config.spindle_count()],
            ..Setup::default()
        };
        self.s.axis_mask = canon.axis_mask();
        self.s.external_length_units = canon.external_length_units();
        self.s.length_units = canon.length_unit_type();
        canon.use_length_units(self.s.length_units);
        self.params = Parameters::default();
        if let Some(path) = self.config.parameter_file.clone() {
            self.param_file_numbers = param_file::restore(&path, &mut self.params)?;
        }
        let mut origin = (self.params.get(5220) + 0.0001) as i32;
        if !(1..=9).contains(&origin) {
            origin = 1;
            self.params.set(5220, 1.0);
        }
        self.s.origin_index = origin;
        let k = 5200 + origin as usize * 20;
        self.s.origin_offset = self.user_pose_from_params(k + 1);
        canon.set_g5x_offset(origin, &self.s.origin_offset);
        if self.config.disable_g92_persistence {
            for n in 5210..5220 {
                self.params.set(n, 0.0);
            }
        }
        self.s.axis_offset = if self.params.get(5210) != 0.0 {
            self.user_pose_from_params(5211)
        } else {
            crate::canon::Pose::ZERO
        };
        canon.set_g92_offset(&self.s.axis_offset);
        self.s.rotation_xy = self.params.get(k + 10);
        canon.set_xy_rotation(self.s.rotation_xy);
        canon.set_feed_reference(FeedReference::Xyz);
        self.params.set(5599, 1.0);
        self.flow = Flow::default();
        self.comp = CompQueue::default();
        self.synch(canon)?;
        self.save_parameters()?;
        Ok(())
    }

    /// Take the world's state (position, feed, coolant, spindle, tools).
    pub fn synch(&mut self, canon: &mut dyn Canon) -> Result<()> {
        let (mode, tolerance) = canon.motion_control_mode();
        self.s.control_mode = mode;
        self.s.tolerance = tolerance;
        self.s.current = canon.position();
        self.s.current_pocket = canon.tool_slot();
        self.s.feed_rate = canon.feed_rate();
        self.s.length_units = canon.length_unit_type();
        self.load_tool_table(canon);
        Ok(())
    }

    /// Open a program file. A first line holding only `%` means the
    /// program must end with another `%` line.
    pub fn open(&mut self, path: &Path, canon: &mut dyn Canon) -> Result<()> {
        if self.source.is_some() {
            return Err(InterpError::FileAlreadyOpen);
        }
        if path.as_os_str().len() > LINELEN - 1 {
            return Err(InterpError::FileNameTooLong);
        }
        let source = Source::open(path).map_err(|e| match e {
            InterpError::Io { .. } => InterpError::UnableToOpenFile(path.display().to_string()),
            other => other,
        })?;
        self.open_source(source, canon)
    }

    /// Open a program held in memory; `name` stands for its file name.
    pub fn open_bytes(&mut self, name: &Path, bytes: Vec<u8>, canon: &mut dyn Canon) -> Result<()> {
        if self.source.is_some() {
            return Err(InterpError::FileAlreadyOpen);
        }
        self.open_source(Source::from_bytes(name, bytes), canon)
    }

    fn open_source(&mut self, mut source: Source, canon: &mut dyn Canon) -> Result<()> {
        let path = source.path().to_path_buf();
        let first = loop {
            match source.read_line()? {
                None => return Err(InterpError::NoPercentAtEnd),
                Some(Line::TooLong(_)) => return Err(InterpError::CommandTooLong),
                Some(Line::Text(t)) if t.is_empty() => continue,
                Some(Line::Text(t)) => break t,
            }
        };
        let trimmed: Vec<u8> = first
            .iter()
            .copied()
            .skip_while(|&b| crate::source::is_c_space(b))
            .collect();
        if trimmed == b"%" {
            self.s.percent_flag = true;
            self.s.sequence_number = 1;
        } else {
            source.seek(0)?;
            self.s.percent_flag = false;
            self.s.sequence_number = 0;
        }
        self.filename = path.display().to_string();
        self.source = Some(source);
        self.reset(canon);
        Ok(())
    }

    /// Close the program file and reset.
    pub fn close(&mut self, canon: &mut dyn Canon) {
        self.source = None;
        self.s.percent_flag = false;
        if !self.config.lazy_close {
            self.reset(canon);
        }
    }

    /// Reset the reading state: leave any subroutine, stop skipping,
    /// drop queued cutter-compensation moves.
    pub fn reset(&mut self, canon: &mut dyn Canon) {
        self.raw_line.clear();
        canon.set_line_text(&self.raw_line);
        self.clean = CleanLine::default();
        self.line_length = 0;
        self.unwind_call();
        canon.on_reset();
    }

    /// Stop the program where it is (task's abort): close it, leave any
    /// subroutine, drop queued moves and reset, whatever
    /// [`Config::lazy_close`] says; the modal state and parameters stay.
    pub fn abort(&mut self, canon: &mut dyn Canon) {
        self.source = None;
        self.s.percent_flag = false;
        self.reset(canon);
    }

    /// Save the parameter file and reset; the end of a session.
    pub fn exit(&mut self, canon: &mut dyn Canon) -> Result<()> {
        let saved = self.save_parameters();
        self.reset(canon);
        saved
    }

    fn save_parameters(&mut self) -> Result<()> {
        match self.config.parameter_file.clone() {
            Some(path) => param_file::save(&path, &self.params),
            None => Ok(()),
        }
    }

    /// Read the next line of the open program into the current block.
    pub fn read(&mut self, canon: &mut dyn Canon) -> Result<Status> {
        let status = self.read_line(None, canon);
        if status.is_err() {
            self.unwind_call();
        }
        status
    }

    /// Read an MDI line (a command not from the file).
    pub fn read_mdi(&mut self, text: &[u8], canon: &mut dyn Canon) -> Result<Status> {
        let status = self.read_line(Some(text), canon);
        if status.is_err() {
            self.unwind_call();
        }
        status
    }

    pub(crate) fn read_line(
        &mut self,
        command: Option<&[u8]>,
        canon: &mut dyn Canon,
    ) -> Result<Status> {
        self.refused_word = None;
        self.item_start = 0;
        self.read_inputs(canon)?;
        if command.is_none() && self.source.is_none() {
            return Err(InterpError::FileNotOpen);
        }
        self.set_position_parameters();
        if let Some(source) = &self.source {
            self.block.offset = source.tell();
        }
        let status = match self.read_text(command, canon) {
            Ok(status) => status,
            Err(e) => {
                self.flow.skipping_to_sub = None;
                return Err(e);
            }
        };
        match status {
            Status::Ok | Status::ExecuteFinish => {
                if self.line_length != 0 {
                    let line = std::mem::take(&mut self.clean);
                    let mut block = std::mem::take(&mut self.block);
                    let parsed = self.parse_line(&line.bytes, &mut block);
                    self.clean = line;
                    self.block = block;
                    parsed?;
                } else if self.block.o_type != OType::None {
                    self.block.o_type = OType::None;
                }
            }
            _ => {}
        }
        Ok(status)
    }

    /// The world's answers a queue-busting block asked for.
    fn read_inputs(&mut self, canon: &mut dyn Canon) -> Result<()> {
        if self.s.probe_flag {
            self.set_probe_data(canon);
            self.s.probe_flag = false;
        }
        if self.s.toolchange_flag {
            self.s.current = canon.position();
            self.load_tool_table(canon);
            self.s.toolchange_flag = false;
        }
        self.params.set(5600, canon.toolchanger_fault() as f64);
        self.params.set(5601, canon.toolchanger_reason() as f64);
        if self.s.input_flag {
            let value = if canon.input_timed_out() {
                -1.0
            } else if self.s.input_digital {
                let default = self.params.get(5399) != 0.0;
                if canon.digital_input(self.s.input_index, default) {
                    1.0
                } else {
                    0.0
                }
            } else {
                canon.analog_input(self.s.input_index, self.params.get(5399))
            };
            self.params.set(5399, value);
            self.s.input_flag = false;
        }
        Ok(())
    }

    fn set_position_parameters(&mut self) {
        let c = self.s.current;
        for (i, v) in [c.x, c.y, c.z, c.a, c.b, c.c, c.u, c.v, c.w]
            .into_iter()
            .enumerate()
        {
            self.params.set(5420 + i, v);
        }
    }

    /// Read one line of text (from the file or the command) and clean it.
    fn read_text(&mut self, command: Option<&[u8]>, canon: &mut dyn Canon) -> Result<Status> {
        match command {
            None => {
                let source = self.source.as_mut().ok_or(InterpError::FileNotOpen)?;
                let line = source.read_line()?;
                let Some(line) = line else {
                    if let Some(sub) = self.flow.skipping_to_sub.clone() {
                        return Err(InterpError::EofSeekingSub(
                            self.filename.clone(),
                            sub,
                            self.flow.skipping_start,
                        ));
                    }
                    return Err(if self.s.percent_flag {
                        InterpError::NoPercentAtEnd
                    } else {
                        InterpError::NoPercentOrEnd
                    });
                };
                self.s.sequence_number += 1;
                match line {
                    Line::TooLong(start) => {
                        self.raw_line = start;
                        canon.set_line_text(&self.raw_line);
                        return Err(InterpError::CommandTooLong);
                    }
                    Line::Text(text) => self.raw_line = text,
                }
                canon.set_line_text(&self.raw_line);
                self.clean = close_and_downcase(&self.raw_line)?;
                if self.clean.bytes == b"%" && self.s.percent_flag {
                    canon.finish();
                    let skipping = self
                        .flow
                        .skipping_o
                        .clone()
                        .or_else(|| self.flow.skipping_to_sub.clone());
                    if let Some(name) = skipping {
                        return Err(InterpError::SubNotFoundBeforeEof(name));
                    }
                    return Ok(Status::EndFile);
                }
            }
            Some(text) => {
                if text.len() >= LINELEN {
                    return Err(InterpError::CommandTooLong);
                }
                self.raw_line = text.to_vec();
                canon.set_line_text(&self.raw_line);
                self.clean = close_and_downcase(text)?;
            }
        }
        self.pending_numbered.clear();
        self.pending_named.clear();
        let deleted = self.clean.bytes.first() == Some(&b'/');
        self.line_length = if self.clean.bytes.is_empty() || (deleted && canon.block_delete()) {
            0
        } else {
            self.clean.bytes.len()
        };
        Ok(if deleted {
            Status::ExecuteFinish
        } else {
            Status::Ok
        })
    }

    /// Read the items of a line into `block` and check them.
    fn parse_line(&mut self, line: &[u8], block: &mut Block) -> Result<()> {
        let offset = block.offset;
        *block = Block {
            offset,
            ..Block::default()
        };
        self.read_items(block, line)?;
        if self.flow.skipping_o.is_none() {
            self.enhance_block(block)?;
            self.check_items(block)?;
        }
        Ok(())
    }

    /// Execute the block last read.
    pub fn execute(&mut self, canon: &mut dyn Canon) -> Result<Status> {
        let status = self.execute_inner(canon);
        if status.is_err() {
            self.unwind_call();
        }
        status
    }

    /// Read and execute an MDI line, running any subroutine it calls to
    /// its end.
    pub fn execute_mdi(&mut self, text: &[u8], canon: &mut dyn Canon) -> Result<Status> {
        let status = self.read_mdi(text, canon)?;
        if status != Status::Ok && status != Status::ExecuteFinish {
            return Ok(status);
        }
        if status == Status::ExecuteFinish && canon.block_delete() {
            return Ok(Status::Ok);
        }
        let started_call = self.block.o_type != OType::None;
        let mut status = self.execute(canon)?;
        if started_call {
            while self.flow.call_level > 0 {
                self.read(canon)?;
                status = self.execute(canon)?;
                if status == Status::Exit {
                    return Ok(status);
                }
            }
            canon.finish();
            status = Status::Ok;
        }
        Ok(status)
    }

    fn execute_inner(&mut self, canon: &mut dyn Canon) -> Result<Status> {
        self.line_number_into_block();
        if self.block.o_type != OType::None {
            let mut block = std::mem::take(&mut self.block);
            let result = self.convert_control_functions(&mut block, canon);
            self.block = block;
            result?;
            return Ok(Status::Ok);
        }
        if self.flow.skipping_o.is_some() {
            return Ok(Status::Ok);
        }
        for (index, value) in std::mem::take(&mut self.pending_numbered) {
            self.params.set(index, value);
        }
        for (name, value) in std::mem::take(&mut self.pending_named) {
            self.store_named_param(&name, value)?;
        }
        if self.line_length == 0 {
            return Ok(Status::Ok);
        }
        let mut block = std::mem::take(&mut self.block);
        let status = self.execute_block(&mut block, canon);
        self.block = block;
        status
    }

    fn line_number_into_block(&mut self) {
        self.block.line_number = self.s.sequence_number;
    }

    /// The raw text of the line last read.
    pub fn line_text(&self) -> &[u8] {
        &self.raw_line
    }

    /// The line number in the file of the line last read.
    pub fn sequence_number(&self) -> i32 {
        self.s.sequence_number
    }

    /// The name of the file being read.
    pub fn file_name(&self) -> &str {
        &self.filename
    }

    /// The current call level (0 in the main program).
    pub fn call_level(&self) -> usize {
        self.flow.call_level
    }

    /// The interpreter's settings (positions, offsets, modes).
    pub fn settings(&self) -> &Setup {
        &self.s
    }

    /// Numbered parameter `index` (1..=5601).
    pub fn parameter(&self, index: usize) -> f64 {
        self.numbered_param(index)
    }

    /// Where the last refusal happened: file, line, column and word.
    pub fn error_location(&self) -> Location {
        Location {
            file: PathBuf::from(&self.filename),
            line: self.s.sequence_number.max(1) as usize,
            column: self.clean.column(self.item_start),
            word: self
                .refused_word
                .clone()
                .unwrap_or_else(|| self.word_at_item()),
        }
    }

    fn word_at_item(&self) -> String {
        let bytes = &self.clean.bytes;
        let start = self.item_start.min(bytes.len());
        let mut end = start;
        while end < bytes.len() {
            let b = bytes[end];
            if end > start && (b.is_ascii_lowercase() || b == b'(' || b == b';') {
                break;
            }
            end += 1;
        }
        String::from_utf8_lossy(&bytes[start..end]).to_uppercase()
    }
}
