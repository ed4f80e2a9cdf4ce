//! Task's side of the canonical interface: the interpreter's calls, in
//! program units and the program coordinate system, become [`Op`]s in
//! machine units and machine coordinates (units scaled, the XY rotation,
//! the G5x, G92 and tool length offsets applied, as LinuxCNC's canon
//! does), queued in program order for task to carry out: moves and
//! planner settings for motion's queue, tool and coolant requests for
//! iocontrol, stops and the program end. Calls the machine cannot carry
//! out yet are recorded as a fault naming the G-code, which task turns
//! into a refusal of the program at that line.

use std::collections::VecDeque;

use motion::command::{LineKind, ProbeType, TermCond};
use motion::Command;
use rs274ngc::{
    Arc, Canon, ControlPoint, Direction, FeedReference, InputKind, MotionMode, Plane, Pose,
    ToolEntry, Units,
};

pub use super::op::Op;

mod coords;
mod rates;
mod spindle;
use super::user_m::UserMCodes;
use crate::iocontrol::IoRequest;
pub use rates::AxisRates;

/// The canon task gives the interpreter.
#[derive(Debug)]
pub struct TaskCanon {
    /// What the program asked for, not yet carried out.
    pub ops: VecDeque<Op>,
    /// Where M6 traverses before the change (`[EMCIO]TOOL_CHANGE_POSITION`,
    /// machine coordinates; None for an axis that stays).
    pub tool_change_position: Option<[Option<f64>; 9]>,
    /// A call the machine cannot carry out (the first one).
    pub fault: Option<String>,
    /// The program line of the block being executed.
    pub line: i32,
    /// The last M66 wait ran out of time.
    pub input_timeout: bool,
    /// The M1 switch.
    pub optional_stop: bool,
    /// The block delete switch.
    pub block_delete: bool,
    /// iov2's `toolchanger-faulted` (1 or 0) and the changer's last fault
    /// reason, which the interpreter reads into #5600 and #5601.
    pub toolchanger: (i32, i32),
    /// Machine (user) units per millimetre.
    user_per_mm: f64,
    units: Units,
    plane: Plane,
    /// Offsets in machine units, nine axes.
    g5x: [f64; 9],
    g92: [f64; 9],
    tool_offset: [f64; 9],
    rotation_deg: f64,
    /// Where the last queued move ends, machine coordinates.
    goal: [f64; 9],
    /// Feed rate, program units per minute.
    feed: f64,
    control: (MotionMode, f64),
    tools: Vec<ToolEntry>,
    slot: i32,
    axis_mask: u32,
    /// Each spindle as the program last set it: direction and speed
    /// (rpm, or with constant surface speed the surface speed).
    spindles: [(Direction, f64); motion::sizes::MAX_SPINDLES],
    /// Each spindle's constant surface speed limit, rpm (G96 D; 0: G97).
    css_limit: [f64; motion::sizes::MAX_SPINDLES],
    /// Feed per revolution (G95): the spindle it follows.
    feed_per_rev: Option<i32>,
    /// The feed per revolution motion was last given (machine units per
    /// revolution, 0: off), and for which spindle.
    sent_per_rev: (i32, f64),
    /// Position synchronisation (G33, G33.1, G76) in effect: the spindle
    /// and machine units per revolution.
    synched: Option<(i32, f64)>,
    /// Motion's digital and analog inputs when last synchronised.
    io: motion::channel::IoState,
    /// The last probing move's result: tripped, and where (machine
    /// coordinates), as motion reported it when last synchronised.
    probe: (bool, [f64; 9]),
    /// The user M-code programs task found at start-up.
    pub user_m: UserMCodes,
    /// Each axis's INI velocity and acceleration limits, from which each
    /// move's path limits are worked out.
    pub rates: AxisRates,
}

impl TaskCanon {
    /// A canon for a machine in `user_per_mm` units (1 for mm, 1/25.4
    /// for inch) with the axes of `axis_mask` (bit 0 X ... bit 8 W).
    pub fn new(user_per_mm: f64, axis_mask: u32) -> TaskCanon {
        TaskCanon {
            tool_change_position: None,
            ops: VecDeque::new(),
            fault: None,
            line: 0,
            input_timeout: false,
            toolchanger: (0, 0),
            optional_stop: false,
            block_delete: false,
            user_per_mm,
            units: if user_per_mm < 0.5 {
                Units::Inches
            } else {
                Units::Mm
            },
            plane: Plane::Xy,
            g5x: [0.0; 9],
            g92: [0.0; 9],
            tool_offset: [0.0; 9],
            rotation_deg: 0.0,
            goal: [0.0; 9],
            feed: 0.0,
            control: (MotionMode::Continuous, 0.0),
            tools: vec![ToolEntry::EMPTY],
            slot: 0,
            axis_mask,
            spindles: [(Direction::Stopped, 0.0); motion::sizes::MAX_SPINDLES],
            css_limit: [0.0; motion::sizes::MAX_SPINDLES],
            feed_per_rev: None,
            sent_per_rev: (0, 0.0),
            synched: None,
            io: motion::channel::IoState::default(),
            user_m: UserMCodes::default(),
            probe: (false, [0.0; 9]),
            rates: AxisRates::default(),
        }
    }

    /// Takes the machine's state before the interpreter synchronises:
    /// where the queue ends (machine coordinates), the tool table (index
    /// 0 the spindle) and the slot of the tool in the spindle.
    /// With it come motion's digital and analog inputs (`io`), which
    /// M66 reads, and the last probing move's result, which G38.n
    /// hands to #5061-#5070.
    pub fn refresh(
        &mut self,
        goal: [f64; 9],
        tools: Vec<ToolEntry>,
        slot: i32,
        io: motion::channel::IoState,
        probe: (bool, [f64; 9]),
    ) {
        self.probe = probe;
        self.goal = goal;
        self.tools = tools;
        self.slot = slot;
        self.io = io;
    }

    /// Drops what the ops from index `from` on would do to the machine
    /// (moves, dwells, outputs, spindle, tool and coolant requests,
    /// stops, messages, input waits), keeping the planner settings the
    /// program's modes set (termination condition, override enables):
    /// lines skipped by a run from a line. As LinuxCNC's task, which
    /// empties its list of the skipped lines' commands.
    pub fn drop_actions_from(&mut self, from: usize) {
        let mut i = from;
        while i < self.ops.len() {
            let keep = match &self.ops[i] {
                Op::Motion(cmd) => !matches!(
                    cmd,
                    Command::Line { .. }
                        | Command::Circle { .. }
                        | Command::RigidTap { .. }
                        | Command::Dwell { .. }
                        | Command::Probe { .. }
                        | Command::SetDout { .. }
                        | Command::SetAout { .. }
                ),
                Op::End => true,
                _ => false,
            };
            if keep {
                i += 1;
            } else {
                self.ops.remove(i);
            }
        }
    }

    /// Whether the ops from index `from` on reload the tool table (the
    /// interpreter must then wait and synchronise).
    pub fn has_reload_from(&self, from: usize) -> bool {
        self.ops
            .iter()
            .skip(from)
            .any(|op| matches!(op, Op::ReloadTools { .. }))
    }

    /// Whether the ops from index `from` on hold a user M-code.
    pub fn has_user_m_from(&self, from: usize) -> bool {
        self.ops
            .iter()
            .skip(from)
            .any(|op| matches!(op, Op::UserM { .. }))
    }

    /// Gives the user M-codes from index `from` on without a program
    /// place the place `at`.
    pub fn place_user_m(&mut self, from: usize, at: &str) {
        for op in self.ops.iter_mut().skip(from) {
            if let Op::UserM { at: place, .. } = op {
                if place.is_empty() {
                    *place = at.to_string();
                }
            }
        }
    }

    /// Queues a motion command to go once the moves before it ended.
    fn after_moves(&mut self, command: Command) {
        self.ops.push_back(Op::AfterMoves {
            command,
            line: self.line,
        });
    }

    /// M62 to M65: digital output `index`, with the next move or (`now`)
    /// once the moves before have ended.
    fn dout(&mut self, index: i32, on: bool, now: bool) {
        let command = Command::SetDout { index, on, now };
        if now {
            self.after_moves(command);
        } else {
            self.ops.push_back(Op::Motion(command));
        }
    }

    /// M67, M68: analog output `index` likewise.
    fn aout(&mut self, index: i32, value: f64, now: bool) {
        let command = Command::SetAout { index, value, now };
        if now {
            self.after_moves(command);
        } else {
            self.ops.push_back(Op::Motion(command));
        }
    }

    /// The offsets in effect, machine units: G5x, G92, tool.
    pub fn offsets(&self) -> [[f64; 9]; 3] {
        [self.g5x, self.g92, self.tool_offset]
    }

    fn refuse(&mut self, what: &str) {
        if self.fault.is_none() {
            self.fault = Some(what.to_string());
        }
    }

    fn queue_line(&mut self, line: i32, end: &Pose, kind: LineKind) {
        if kind == LineKind::Feed {
            self.sync_feed_mode();
        }
        let goal = self.to_machine(end);
        self.line_to(goal, kind, line);
    }

    /// Queues a straight move to `goal` (machine coordinates) with the
    /// path limits the axes allow along it: a rapid at that speed, a feed
    /// at its feed rate (a spindle-synchronised one at the speed the
    /// spindle sets), at most that. A move of no length is not queued
    /// unless it is spindle-synchronised, as in LinuxCNC's canon.
    fn line_to(&mut self, goal: [f64; 9], kind: LineKind, line: i32) {
        let synched = kind == LineKind::Feed && self.synched.is_some();
        let rates = match self.rates.straight(&self.goal, &goal) {
            Some(rates) => rates,
            None if synched => rates::MoveRates::UNCAPPED,
            None => {
                // `G0` with no axis word, `G1 X0` at X0: nothing to send.
                self.goal = goal;
                return;
            }
        };
        let vel = match kind {
            LineKind::Traverse => rates.vel,
            LineKind::Feed => rates.cap(self.synched_speed().unwrap_or(self.feed_per_second())),
        };
        self.goal = goal;
        self.ops.push_back(Op::Motion(Command::Line {
            end: motion::Pose(goal),
            vel,
            ini_maxvel: rates.vel,
            acc: rates.acc,
            kind,
            id: line,
        }));
    }

    fn set_offset(&mut self, which: Offset, p: &Pose) {
        let v = self.scaled(p);
        match which {
            Offset::G5x => self.g5x = v,
            Offset::G92 => self.g92 = v,
            Offset::Tool => self.tool_offset = v,
        }
    }
}

/// Which offset a call sets.
#[derive(Clone, Copy)]
enum Offset {
    G5x,
    G92,
    Tool,
}

impl Canon for TaskCanon {
    fn set_line_text(&mut self, _text: &[u8]) {}

    fn set_g5x_offset(&mut self, _index: i32, offset: &Pose) {
        self.set_offset(Offset::G5x, offset);
    }
    fn set_g92_offset(&mut self, offset: &Pose) {
        self.set_offset(Offset::G92, offset);
    }
    fn set_xy_rotation(&mut self, degrees: f64) {
        self.rotation_deg = degrees;
    }
    fn use_length_units(&mut self, units: Units) {
        self.units = units;
    }
    fn select_plane(&mut self, plane: Plane) {
        self.plane = plane;
    }
    fn set_feed_reference(&mut self, _reference: FeedReference) {}

    fn straight_traverse(&mut self, line: i32, end: &Pose) {
        self.queue_line(line, end, LineKind::Traverse);
    }
    fn straight_feed(&mut self, line: i32, end: &Pose) {
        self.queue_line(line, end, LineKind::Feed);
    }
    fn arc_feed(&mut self, line: i32, arc: &Arc) {
        let mut end = arc.rest;
        // The centre in program coordinates and the axis it turns about.
        let (center, normal) = match self.plane {
            Plane::Xy => {
                (end.x, end.y, end.z) = (arc.first_end, arc.second_end, arc.axis_end_point);
                ((arc.first_axis, arc.second_axis, end.z), [0.0, 0.0, 1.0])
            }
            Plane::Yz => {
                (end.y, end.z, end.x) = (arc.first_end, arc.second_end, arc.axis_end_point);
                ((end.x, arc.first_axis, arc.second_axis), [1.0, 0.0, 0.0])
            }
            Plane::Xz => {
                (end.z, end.x, end.y) = (arc.first_end, arc.second_end, arc.axis_end_point);
                ((arc.second_axis, end.y, arc.first_axis), [0.0, 1.0, 0.0])
            }
            Plane::Uv | Plane::Vw | Plane::Uw => return self.refuse("arcs in the UVW planes"),
        };
        let goal = self.to_machine(&end);
        let c = self.to_machine(&Pose {
            x: center.0,
            y: center.1,
            z: center.2,
            ..end
        });
        let (s, co) = self.rotation_deg.to_radians().sin_cos();
        let normal = [
            normal[0] * co - normal[1] * s,
            normal[0] * s + normal[1] * co,
            normal[2],
        ];
        let turns = if arc.rotation > 0 {
            arc.rotation - 1
        } else {
            arc.rotation
        };
        let center = [c[0], c[1], c[2]];
        // An arc motion cannot make goes to it without caps of its own
        // (0), so that motion refuses it, naming the line, rather than
        // task dropping it.
        let rates = self
            .rates
            .arc(&self.goal, &goal, center, normal, turns)
            .unwrap_or(rates::MoveRates::UNCAPPED);
        self.goal = goal;
        self.sync_feed_mode();
        self.ops.push_back(Op::Motion(Command::Circle {
            end: motion::Pose(goal),
            center,
            normal,
            turns,
            vel: rates.cap(self.feed_per_second()),
            ini_maxvel: rates.vel,
            acc: rates.acc,
            id: line,
        }));
    }
    fn straight_probe(&mut self, line: i32, end: &Pose, probe_type: u8) {
        let Some(probe) = ProbeType::from_bits(u64::from(probe_type)) else {
            return self.refuse(&format!("probe type {probe_type}"));
        };
        let goal = self.to_machine(end);
        self.goal = goal;
        self.ops.push_back(Op::Motion(Command::Probe {
            end: motion::Pose(goal),
            vel: self.feed_per_second(),
            probe,
            id: line,
        }));
        if !probe.no_error {
            self.ops.push_back(Op::ProbeCheck { probe, line });
        }
    }
    fn nurbs_feed(&mut self, _line: i32, _points: &[ControlPoint], _order: u32) {
        self.refuse("NURBS moves (G5.2)");
    }
    fn start_speed_feed_synch(&mut self, spindle: i32, per_rev: f64, velocity_mode: bool) {
        self.start_synch(spindle, per_rev, velocity_mode);
    }
    fn stop_speed_feed_synch(&mut self) {
        self.stop_synch();
    }
    fn rigid_tap(&mut self, line: i32, end: (f64, f64, f64), scale: f64) {
        self.queue_rigid_tap(line, end, scale);
    }
    fn dwell(&mut self, seconds: f64) {
        self.ops.push_back(Op::Motion(Command::Dwell {
            seconds,
            id: self.line,
        }));
    }
    fn set_feed_rate(&mut self, rate: f64) {
        self.feed = rate;
    }
    fn set_feed_mode(&mut self, spindle: i32, mode: i32) {
        self.feed_per_rev = (mode == 1).then_some(spindle);
        if mode == 1 && self.spindle_mut(spindle).is_none() {
            self.feed_per_rev = None;
        }
        if mode == 0 {
            // As LinuxCNC's canon: units per minute (G94, and the end of
            // a program) ends any synchronisation with the spindle.
            self.stop_synch();
        }
    }
    fn set_motion_control_mode(&mut self, mode: MotionMode, tolerance: f64) {
        self.control = (mode, tolerance);
        let cond = match mode {
            MotionMode::ExactStop => TermCond::Stop,
            MotionMode::ExactPath => TermCond::ExactPath,
            MotionMode::Continuous => TermCond::Blend,
        };
        let tolerance = tolerance * self.units.mm_per_unit() * self.user_per_mm;
        self.ops
            .push_back(Op::Motion(Command::SetTermCond { cond, tolerance }));
    }
    fn set_naivecam_tolerance(&mut self, _tolerance: f64) {}
    fn turn_probe_on(&mut self) {}
    fn turn_probe_off(&mut self) {}

    fn set_spindle_speed(&mut self, spindle: i32, rpm: f64) {
        self.queue_spindle(spindle, None, Some(rpm));
    }
    fn start_spindle_clockwise(&mut self, spindle: i32) {
        self.queue_spindle(spindle, Some(Direction::Clockwise), None);
    }
    fn start_spindle_counterclockwise(&mut self, spindle: i32) {
        self.queue_spindle(spindle, Some(Direction::CounterClockwise), None);
    }
    fn stop_spindle_turning(&mut self, spindle: i32) {
        self.queue_spindle(spindle, Some(Direction::Stopped), None);
    }
    fn set_spindle_mode(&mut self, spindle: i32, css_limit: f64) {
        if self.spindle_mut(spindle).is_some() {
            self.css_limit[spindle as usize] = css_limit.abs();
        }
    }
    fn orient_spindle(&mut self, spindle: i32, orientation: f64, mode: i32) {
        if self.spindle_mut(spindle).is_none() {
            return;
        }
        // The spindle stops to orient: every spindle counts as stopped.
        for s in &mut self.spindles {
            s.0 = Direction::Stopped;
        }
        self.after_moves(Command::SpindleOrient {
            spindle,
            angle: orientation,
            mode,
        });
    }
    fn wait_spindle_orient_complete(&mut self, spindle: i32, timeout: f64) {
        self.ops.push_back(Op::WaitOrient {
            spindle,
            timeout,
            line: self.line,
        });
    }

    fn use_tool_length_offset(&mut self, offset: &Pose) {
        self.set_offset(Offset::Tool, offset);
        // Motion shows it (motion.tooloffset.L) from when the moves
        // before have ended, as LinuxCNC's task sends SET_OFFSET.
        self.after_moves(Command::SetToolOffset {
            offset: motion::Pose(self.tool_offset),
        });
    }
    fn select_tool(&mut self, tool: i32) {
        self.ops.push_back(Op::Io(IoRequest::Prepare { tool }));
    }
    fn start_change(&mut self) {
        self.ops.push_back(Op::Io(IoRequest::StartChange));
    }
    fn change_tool(&mut self, index: i32) {
        if let Some(entry) = usize::try_from(index)
            .ok()
            .and_then(|i| self.tools.get(i))
            .copied()
        {
            self.tools[0] = entry;
        }
        self.slot = index;
        if let Some(position) = self.tool_change_position {
            // As LinuxCNC's canon: a traverse to the change position in
            // machine coordinates, before the load, even when the tool is
            // in the spindle already (none when the machine is there).
            // The interpreter takes the new position when it synchronises
            // after M6.
            let mut goal = self.goal;
            for (g, p) in goal.iter_mut().zip(position) {
                if let Some(p) = p {
                    *g = p;
                }
            }
            self.line_to(goal, LineKind::Traverse, self.line);
        }
        self.ops.push_back(Op::Io(IoRequest::Load));
    }
    fn change_tool_number(&mut self, index: i32) {
        let tool = usize::try_from(index)
            .ok()
            .and_then(|i| self.tools.get(i))
            .map_or(0, |e| e.toolno.max(0));
        self.slot = index;
        self.ops.push_back(Op::Io(IoRequest::SetNumber { tool }));
    }
    fn reload_tool_data(&mut self) {
        self.ops.push_back(Op::ReloadTools { line: self.line });
    }
    fn set_tool_table_entry(&mut self, index: i32, entry: &ToolEntry) {
        match usize::try_from(index)
            .ok()
            .and_then(|i| self.tools.get_mut(i))
        {
            Some(slot) => {
                *slot = *entry;
                self.ops.push_back(Op::Io(IoRequest::SetEntry {
                    slot: index,
                    entry: *entry,
                }));
            }
            None => self.refuse("a tool table entry outside the table (G10 L1)"),
        }
    }

    fn flood_on(&mut self) {
        self.ops.push_back(Op::Io(IoRequest::Flood(true)));
    }
    fn flood_off(&mut self) {
        self.ops.push_back(Op::Io(IoRequest::Flood(false)));
    }
    fn mist_on(&mut self) {
        self.ops.push_back(Op::Io(IoRequest::Mist(true)));
    }
    fn mist_off(&mut self) {
        self.ops.push_back(Op::Io(IoRequest::Mist(false)));
    }
    fn enable_feed_override(&mut self) {
        self.ops
            .push_back(Op::Motion(Command::FeedScaleEnable { on: true }));
    }
    fn disable_feed_override(&mut self) {
        self.ops
            .push_back(Op::Motion(Command::FeedScaleEnable { on: false }));
    }
    fn enable_speed_override(&mut self, _spindle: i32) {
        self.ops
            .push_back(Op::Motion(Command::SpindleScaleEnable { on: true }));
    }
    fn disable_speed_override(&mut self, _spindle: i32) {
        self.ops
            .push_back(Op::Motion(Command::SpindleScaleEnable { on: false }));
    }
    fn enable_adaptive_feed(&mut self) {
        self.ops
            .push_back(Op::Motion(Command::AdaptiveFeedEnable { on: true }));
    }
    fn disable_adaptive_feed(&mut self) {
        self.ops
            .push_back(Op::Motion(Command::AdaptiveFeedEnable { on: false }));
    }
    fn enable_feed_hold(&mut self) {
        self.ops
            .push_back(Op::Motion(Command::FeedHoldEnable { on: true }));
    }
    fn disable_feed_hold(&mut self) {
        self.ops
            .push_back(Op::Motion(Command::FeedHoldEnable { on: false }));
    }
    fn set_motion_output_bit(&mut self, index: i32) {
        self.dout(index, true, false);
    }
    fn clear_motion_output_bit(&mut self, index: i32) {
        self.dout(index, false, false);
    }
    fn set_aux_output_bit(&mut self, index: i32) {
        self.dout(index, true, true);
    }
    fn clear_aux_output_bit(&mut self, index: i32) {
        self.dout(index, false, true);
    }
    fn set_motion_output_value(&mut self, index: i32, value: f64) {
        self.aout(index, value, false);
    }
    fn set_aux_output_value(&mut self, index: i32, value: f64) {
        self.aout(index, value, true);
    }
    fn wait_input(
        &mut self,
        index: i32,
        kind: InputKind,
        wait_type: i32,
        timeout: f64,
    ) -> Result<(), ()> {
        let digital = kind == InputKind::Digital;
        let count = if digital {
            self.io.din.len()
        } else {
            self.io.ain.len()
        };
        if usize::try_from(index).map_or(true, |i| i >= count) {
            return Err(());
        }
        self.ops.push_back(Op::WaitInput {
            index,
            digital,
            mode: wait_type,
            timeout,
        });
        Ok(())
    }
    fn user_m_code(&mut self, number: i32, p: f64, q: f64) {
        match self.user_m.program(number) {
            Some(program) => {
                let program = program.to_path_buf();
                self.ops.push_back(Op::UserM {
                    number,
                    program,
                    p,
                    q,
                    at: String::new(),
                });
            }
            // The interpreter asks `user_m_code_defined` first; a number
            // without a program does not get here.
            None => self.refuse(&format!("user M-code M{number} without a program")),
        }
    }

    fn comment(&mut self, _text: &str) {}
    fn message(&mut self, text: &str) {
        self.ops.push_back(Op::Message(text.to_string()));
    }
    fn print(&mut self, text: &str) {
        self.ops.push_back(Op::Message(text.to_string()));
    }
    fn log_open(&mut self, _name: &str) {}
    fn log_append(&mut self, _name: &str) {}
    fn log_close(&mut self) {}
    fn log(&mut self, _text: &str) {}
    fn program_stop(&mut self) {
        self.ops.push_back(Op::Stop { optional: false });
    }
    fn optional_program_stop(&mut self) {
        self.ops.push_back(Op::Stop { optional: true });
    }
    fn program_end(&mut self) {
        self.ops.push_back(Op::End);
    }
    fn pallet_shuttle(&mut self) {}
    fn on_reset(&mut self) {}
    fn finish(&mut self) {}

    fn position(&self) -> Pose {
        self.to_program(self.goal)
    }
    fn probe_position(&self) -> Pose {
        self.to_program(self.probe.1)
    }
    fn probe_tripped(&self) -> bool {
        self.probe.0
    }
    fn length_unit_type(&self) -> Units {
        self.units
    }
    fn external_length_units(&self) -> f64 {
        self.user_per_mm
    }
    fn external_angle_units(&self) -> f64 {
        1.0
    }
    fn feed_rate(&self) -> f64 {
        self.feed
    }
    fn tool_length_offset(&self) -> Pose {
        self.unscaled(self.tool_offset)
    }
    fn tool_table(&self) -> Vec<ToolEntry> {
        self.tools.clone()
    }
    fn queue_empty(&self) -> bool {
        self.ops.is_empty()
    }
    fn digital_input(&self, index: i32, default: bool) -> bool {
        usize::try_from(index)
            .ok()
            .and_then(|i| self.io.din.get(i))
            .copied()
            .unwrap_or(default)
    }
    fn analog_input(&self, index: i32, default: f64) -> f64 {
        usize::try_from(index)
            .ok()
            .and_then(|i| self.io.ain.get(i))
            .copied()
            .unwrap_or(default)
    }
    fn input_timed_out(&self) -> bool {
        self.input_timeout
    }
    fn toolchanger_fault(&self) -> i32 {
        self.toolchanger.0
    }
    fn toolchanger_reason(&self) -> i32 {
        self.toolchanger.1
    }
    fn block_delete(&self) -> bool {
        self.block_delete
    }
    fn optional_stop(&self) -> bool {
        self.optional_stop
    }
    fn user_m_code_defined(&self, number: i32) -> bool {
        self.user_m.program(number).is_some()
    }
    fn motion_control_mode(&self) -> (MotionMode, f64) {
        self.control
    }
    fn tool_slot(&self) -> i32 {
        self.slot
    }
    fn axis_mask(&self) -> u32 {
        self.axis_mask
    }
}

#[cfg(test)]
#[path = "canon_tests.rs"]
mod tests;
