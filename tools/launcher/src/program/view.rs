//! What status readers see of the program side, and starting the
//! interpreter afresh (the `stat`, `status` and `reset-interpreter`
//! requests).

use super::Ended;
use super::{IoControl, MotionLink, Program, ProgramError};

/// What status readers see of the program side ([`Program::view`]).
pub struct ProgramView<'a> {
    /// The open program.
    pub file: Option<&'a std::path::Path>,
    /// The program line of the last block read.
    pub read_line: i32,
    /// The modal codes, feed and speed in effect.
    pub codes: rs274ngc::ActiveCodes,
    /// MDI lines waiting to run.
    pub queued_mdi: usize,
    /// How deep in subroutine calls the interpreter is (0: the main
    /// program).
    pub call_level: usize,
    /// The XY rotation of the active coordinate system, degrees.
    pub rotation_xy: f64,
    /// The return code of the interpreter's last error (0: none yet).
    pub interpreter_errcode: i32,
}

impl Program {
    /// The open program, if any; the program line read last; the
    /// interpreter's modal codes; the MDI lines waiting.
    pub fn view(&self) -> ProgramView<'_> {
        ProgramView {
            file: self.file.as_deref(),
            read_line: self.read_line,
            codes: self.interp.active_codes(),
            queued_mdi: self.mdi.len(),
            call_level: self.interp.call_level(),
            rotation_xy: self.interp.settings().rotation_xy,
            interpreter_errcode: self.interp_errcode,
        }
    }

    /// Starts the interpreter afresh (LinuxCNC's reset_interpreter): its
    /// start-up modal state and the parameter file as saved, then the
    /// INI's `RS274NGC_STARTUP_CODE` (in the next cycle). Refused while
    /// something runs.
    pub fn reset_interpreter(
        &mut self,
        motion: &MotionLink,
        io: &IoControl,
    ) -> Result<(), ProgramError> {
        if !self.settled() {
            return Err(ProgramError::Running {
                hint: " (abort it before resetting the interpreter)",
            });
        }
        self.initialised = false;
        self.synch(motion, io)?;
        self.startup_due = self.startup_code.is_some();
        Ok(())
    }

    /// The program's lines of `task-cmd status`.
    pub fn status(&self, motion: Option<&MotionLink>) -> String {
        let motion_line = motion
            .and_then(MotionLink::status)
            .map_or(0, |s| s.traj.exec_id);
        let codes = self.interp.active_codes();
        let g: Vec<String> = codes
            .g
            .iter()
            .filter(|g| **g >= 0)
            .map(|g| rs274ngc::g_text(*g))
            .collect();
        let m: Vec<String> = codes
            .m
            .iter()
            .filter(|m| **m >= 0)
            .map(|m| format!("M{m}"))
            .collect();
        let [g5x, g92, tool] = self.canon.offsets();
        let xyz = |a: [f64; 9]| format!("{:.4} {:.4} {:.4}", a[0], a[1], a[2]);
        let spindle = motion
            .and_then(MotionLink::status)
            .and_then(|s| s.spindles.first().copied())
            .map_or("unknown".to_string(), |s| spindle_text(&s));
        let mut s = format!(
            "program: {}\ninterp: {}\ncurrent line: {}\nmotion line: {motion_line}\n\
             modal: {} {} F{} S{}\noffsets: g5x {} g92 {} tool {}\nspindle: {spindle}\n",
            self.file
                .as_deref()
                .map_or("none".to_string(), |p| p.display().to_string()),
            self.state.name(),
            self.read_line,
            g.join(" "),
            m.join(" "),
            codes.feed,
            codes.speed,
            xyz(g5x),
            xyz(g92),
            xyz(tool),
        );
        if let Some(Ended::Failed(why)) = &self.last_end {
            s.push_str(&format!("last run: {why}\n"));
        }
        s
    }
}

/// Spindle 0 as `task-cmd status` shows it.
fn spindle_text(s: &motion::channel::SpindleState) -> String {
    let turning = match s.speed {
        _ if !s.on => "stopped".to_string(),
        v if v < 0.0 => format!("counterclockwise {} rpm", -v),
        v => format!("clockwise {v} rpm"),
    };
    let mut out = turning;
    if s.scale != 1.0 {
        out.push_str(&format!(", override {}", s.scale));
    }
    if s.brake {
        out.push_str(", brake on");
    }
    out
}
