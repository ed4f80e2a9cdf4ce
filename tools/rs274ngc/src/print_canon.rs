//! A canon that prints every call, line for line as LinuxCNC's
//! standalone interpreter (rs274) does, and keeps the small world model
//! that interpreter keeps: position, offsets, units, tools, spindle.
//!
//! Each output line is `%5d ` (a running count), the N number of the
//! line being interpreted padded to 7 columns (`N..... ` without one),
//! and the call with its arguments (`%.4f` numbers).

use std::io::Write;

use crate::canon::*;
use crate::cfmt::f;

/// Inch machine: LinuxCNC's standalone interpreter's user units.
pub const STANDALONE_LENGTH_UNITS: f64 = 0.03937007874016;

/// Number of tool table entries the standalone world has.
pub const POCKETS_MAX: usize = 1000;

/// The printing canon and its world model.
pub struct PrintCanon {
    out: Option<Box<dyn Write>>,
    /// Where (PRINT,...) text goes (rs274 writes it to stdout).
    line_number: u32,
    line_text: Vec<u8>,
    position: Pose,
    g5x: Pose,
    g92: Pose,
    units: Units,
    plane: Plane,
    probe: Pose,
    feed_rate: f64,
    speed: f64,
    tool_offset: Pose,
    motion_mode: MotionMode,
    motion_tolerance: f64,
    tools: Vec<ToolEntry>,
    active_slot: i32,
    /// Block delete switch (rs274 -b).
    pub block_delete: bool,
    /// Machine length units per mm (see [`STANDALONE_LENGTH_UNITS`]).
    pub external_length_units: f64,
    /// User M-codes (M100-M199) that have a program.
    pub user_m_codes: Vec<i32>,
    /// (PRINT,...) text goes to standard output rather than the trace
    /// (rs274 with an output file does this).
    pub print_to_stdout: bool,
    write_failed: bool,
}

impl std::fmt::Debug for PrintCanon {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PrintCanon")
            .field("line_number", &self.line_number)
            .finish_non_exhaustive()
    }
}

impl PrintCanon {
    /// A canon printing to `out`; `None` keeps the world model only
    /// (for checking a program without output).
    pub fn new(out: Option<Box<dyn Write>>, tools: Vec<ToolEntry>) -> PrintCanon {
        let mut table = vec![ToolEntry::EMPTY; POCKETS_MAX];
        table[0].toolno = 0;
        for (i, t) in tools.into_iter().enumerate() {
            if i + 1 < POCKETS_MAX {
                table[i + 1] = t;
            }
        }
        PrintCanon {
            out,
            line_number: 1,
            line_text: Vec::new(),
            position: Pose::ZERO,
            g5x: Pose::ZERO,
            g92: Pose::ZERO,
            units: Units::Mm,
            plane: Plane::Xy,
            probe: Pose::ZERO,
            feed_rate: 0.0,
            speed: 0.0,
            tool_offset: Pose::ZERO,
            motion_mode: MotionMode::Continuous,
            motion_tolerance: 0.0,
            tools: table,
            active_slot: 1,
            block_delete: false,
            external_length_units: STANDALONE_LENGTH_UNITS,
            user_m_codes: Vec::new(),
            print_to_stdout: false,
            write_failed: false,
        }
    }

    /// Start with an empty spindle (tool -1), as a random tool changer's
    /// table does.
    pub fn random_toolchanger_spindle(&mut self) {
        self.tools[0].toolno = -1;
    }

    /// True if writing the output failed at some point.
    pub fn write_failed(&self) -> bool {
        self.write_failed
    }

    /// Flush the output.
    pub fn flush(&mut self) {
        if let Some(out) = self.out.as_mut() {
            if out.flush().is_err() {
                self.write_failed = true;
            }
        }
    }

    /// The N-number column: `N` and up to 6 digits padded to 7, or
    /// `N..... `.
    fn nc_line_number(&self) -> String {
        let text = &self.line_text;
        let k = text
            .iter()
            .take_while(|&&b| b == b'\t' || b == b' ' || b == b'/')
            .count();
        match text.get(k) {
            Some(b'n') | Some(b'N') => {
                let digits: String = text[k + 1..]
                    .iter()
                    .take_while(|b| b.is_ascii_digit())
                    .map(|&b| b as char)
                    .collect();
                let pad = 6usize.saturating_sub(digits.len());
                format!("N{digits}{}", " ".repeat(pad))
            }
            _ => "N..... ".to_string(),
        }
    }

    fn emit_line(&mut self, call: &str) {
        let prefix = format!("{:5} {}", self.line_number, self.nc_line_number());
        self.line_number += 1;
        if let Some(out) = self.out.as_mut() {
            let result = out
                .write_all(prefix.as_bytes())
                .and_then(|_| out.write_all(call.as_bytes()))
                .and_then(|_| out.write_all(b"\n"));
            if result.is_err() {
                self.write_failed = true;
            }
        }
    }

    fn six(p: &Pose) -> String {
        format!(
            "{}, {}, {}, {}, {}, {}",
            f(p.x, 4),
            f(p.y, 4),
            f(p.z, 4),
            f(p.a, 4),
            f(p.b, 4),
            f(p.c, 4)
        )
    }

    fn set_abc(&mut self, p: &Pose) {
        self.position.a = p.a;
        self.position.b = p.b;
        self.position.c = p.c;
    }

    fn shift_origin(&mut self, old: Pose, new: &Pose) {
        let pos = &mut self.position;
        pos.x += old.x - new.x;
        pos.y += old.y - new.y;
        pos.z += old.z - new.z;
        pos.a += old.a - new.a;
        pos.b += old.b - new.b;
        pos.c += old.c - new.c;
    }
}

impl Canon for PrintCanon {
    fn set_line_text(&mut self, text: &[u8]) {
        self.line_text.clear();
        self.line_text.extend_from_slice(text);
    }

    fn set_g5x_offset(&mut self, index: i32, o: &Pose) {
        self.emit_line(&format!("SET_G5X_OFFSET({index}, {})", Self::six(o)));
        self.shift_origin(self.g5x, o);
        self.g5x = Pose {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            ..*o
        };
    }

    fn set_g92_offset(&mut self, o: &Pose) {
        self.emit_line(&format!("SET_G92_OFFSET({})", Self::six(o)));
        self.shift_origin(self.g92, o);
        self.g92 = Pose {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            ..*o
        };
    }

    fn set_xy_rotation(&mut self, degrees: f64) {
        self.emit_line(&format!("SET_XY_ROTATION({})", f(degrees, 4)));
    }

    fn use_length_units(&mut self, units: Units) {
        let name = match units {
            Units::Inches => "CANON_UNITS_INCHES",
            Units::Mm => "CANON_UNITS_MM",
            Units::Cm => "UNKNOWN",
        };
        self.emit_line(&format!("USE_LENGTH_UNITS({name})"));
        let k = match (self.units, units) {
            (Units::Mm, Units::Inches) => 1.0 / 25.4,
            (Units::Inches, Units::Mm) => 25.4,
            _ => return,
        };
        self.units = units;
        for p in [&mut self.position, &mut self.g5x, &mut self.g92] {
            if k < 1.0 {
                p.x /= 25.4;
                p.y /= 25.4;
                p.z /= 25.4;
            } else {
                p.x *= k;
                p.y *= k;
                p.z *= k;
            }
        }
    }

    fn select_plane(&mut self, plane: Plane) {
        let name = match plane {
            Plane::Xy => "XY",
            Plane::Yz => "YZ",
            Plane::Xz => "XZ",
            _ => "UNKNOWN",
        };
        self.emit_line(&format!("SELECT_PLANE(CANON_PLANE_{name})"));
        self.plane = plane;
    }

    fn set_feed_reference(&mut self, reference: FeedReference) {
        let name = match reference {
            FeedReference::Workpiece => "CANON_WORKPIECE",
            FeedReference::Xyz => "CANON_XYZ",
        };
        self.emit_line(&format!("SET_FEED_REFERENCE({name})"));
    }

    fn straight_traverse(&mut self, _line: i32, end: &Pose) {
        self.emit_line(&format!("STRAIGHT_TRAVERSE({})", Self::six(end)));
        self.position = Pose {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            ..*end
        };
    }

    fn straight_feed(&mut self, _line: i32, end: &Pose) {
        self.emit_line(&format!("STRAIGHT_FEED({})", Self::six(end)));
        self.position = Pose {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            ..*end
        };
    }

    fn arc_feed(&mut self, _line: i32, arc: &Arc) {
        self.emit_line(&format!(
            "ARC_FEED({}, {}, {}, {}, {}, {}, {}, {}, {})",
            f(arc.first_end, 4),
            f(arc.second_end, 4),
            f(arc.first_axis, 4),
            f(arc.second_axis, 4),
            arc.rotation,
            f(arc.axis_end_point, 4),
            f(arc.rest.a, 4),
            f(arc.rest.b, 4),
            f(arc.rest.c, 4)
        ));
        let p = &mut self.position;
        match self.plane {
            Plane::Yz => (p.x, p.y, p.z) = (arc.axis_end_point, arc.first_end, arc.second_end),
            Plane::Xz => (p.x, p.y, p.z) = (arc.second_end, arc.axis_end_point, arc.first_end),
            _ => (p.x, p.y, p.z) = (arc.first_end, arc.second_end, arc.axis_end_point),
        }
        self.set_abc(&arc.rest);
    }

    fn straight_probe(&mut self, _line: i32, end: &Pose, _probe_type: u8) {
        let dx = self.position.x - end.x;
        let dy = self.position.y - end.y;
        let dz = self.position.z - end.z;
        let distance = ((dx * dx) + (dy * dy) + (dz * dz)).sqrt();
        self.emit_line(&format!("STRAIGHT_PROBE({})", Self::six(end)));
        self.probe = *end;
        if distance != 0.0 {
            let backoff = if self.units == Units::Mm { 0.254 } else { 0.01 };
            self.position.x = end.x + backoff * (dx / distance);
            self.position.y = end.y + backoff * (dy / distance);
            self.position.z = end.z + backoff * (dz / distance);
        }
        self.set_abc(end);
    }

    fn nurbs_feed(&mut self, _line: i32, points: &[ControlPoint], _order: u32) {
        self.emit_line(&format!("NURBS_FEED({}, ...)", points.len()));
    }

    fn start_speed_feed_synch(
        &mut self,
        _spindle: i32,
        feed_per_revolution: f64,
        velocity_mode: bool,
    ) {
        self.emit_line(&format!(
            "START_SPEED_FEED_SYNC({},{})",
            f(feed_per_revolution, 6),
            i32::from(velocity_mode)
        ));
    }

    fn stop_speed_feed_synch(&mut self) {
        self.emit_line("STOP_SPEED_FEED_SYNCH()");
    }

    fn rigid_tap(&mut self, _line: i32, end: (f64, f64, f64), _scale: f64) {
        self.emit_line(&format!(
            "RIGID_TAP({}, {}, {})",
            f(end.0, 4),
            f(end.1, 4),
            f(end.2, 4)
        ));
    }

    fn dwell(&mut self, seconds: f64) {
        self.emit_line(&format!("DWELL({})", f(seconds, 4)));
    }

    fn set_feed_rate(&mut self, rate: f64) {
        self.emit_line(&format!("SET_FEED_RATE({})", f(rate, 4)));
        self.feed_rate = rate;
    }

    fn set_feed_mode(&mut self, spindle: i32, mode: i32) {
        self.emit_line(&format!("SET_FEED_MODE({spindle}, {mode})"));
    }

    fn set_motion_control_mode(&mut self, mode: MotionMode, tolerance: f64) {
        self.motion_tolerance = 0.0;
        match mode {
            MotionMode::ExactStop => self.emit_line("SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP)"),
            MotionMode::ExactPath => self.emit_line("SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)"),
            MotionMode::Continuous => {
                self.motion_tolerance = tolerance;
                self.emit_line(&format!(
                    "SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, {})",
                    f(tolerance, 6)
                ));
            }
        }
        self.motion_mode = mode;
    }

    fn set_naivecam_tolerance(&mut self, tolerance: f64) {
        self.emit_line(&format!("SET_NAIVECAM_TOLERANCE({})", f(tolerance, 4)));
    }

    fn turn_probe_on(&mut self) {
        self.emit_line("TURN_PROBE_ON()");
    }

    fn turn_probe_off(&mut self) {
        self.emit_line("TURN_PROBE_OFF()");
    }

    fn set_spindle_speed(&mut self, spindle: i32, rpm: f64) {
        self.emit_line(&format!("SET_SPINDLE_SPEED({spindle}, {})", f(rpm, 4)));
        self.speed = rpm;
    }

    fn start_spindle_clockwise(&mut self, spindle: i32) {
        self.emit_line(&format!("START_SPINDLE_CLOCKWISE({spindle})"));
    }

    fn start_spindle_counterclockwise(&mut self, spindle: i32) {
        self.emit_line(&format!("START_SPINDLE_COUNTERCLOCKWISE({spindle})"));
    }

    fn stop_spindle_turning(&mut self, spindle: i32) {
        self.emit_line(&format!("STOP_SPINDLE_TURNING({spindle})"));
    }

    fn set_spindle_mode(&mut self, spindle: i32, css_limit: f64) {
        self.emit_line(&format!("SET_SPINDLE_MODE({spindle} {})", f(css_limit, 4)));
    }

    fn orient_spindle(&mut self, spindle: i32, orientation: f64, mode: i32) {
        self.emit_line(&format!(
            "ORIENT_SPINDLE({spindle}, {}, {mode})",
            f(orientation, 4)
        ));
    }

    fn wait_spindle_orient_complete(&mut self, spindle: i32, timeout: f64) {
        self.emit_line(&format!(
            "SPINDLE.{spindle}.WAIT_ORIENT_COMPLETE({})",
            f(timeout, 4)
        ));
    }

    fn use_tool_length_offset(&mut self, o: &Pose) {
        self.tool_offset = *o;
        self.emit_line(&format!(
            "USE_TOOL_LENGTH_OFFSET({} {} {}, {} {} {}, {} {} {})",
            f(o.x, 4),
            f(o.y, 4),
            f(o.z, 4),
            f(o.a, 4),
            f(o.b, 4),
            f(o.c, 4),
            f(o.u, 4),
            f(o.v, 4),
            f(o.w, 4)
        ));
    }

    fn select_tool(&mut self, tool: i32) {
        self.emit_line(&format!("SELECT_TOOL({tool})"));
    }

    fn start_change(&mut self) {
        self.emit_line("START_CHANGE()");
    }

    fn change_tool(&mut self, index: i32) {
        self.emit_line(&format!("CHANGE_TOOL({index})"));
        self.active_slot = index;
        if let Some(entry) = usize::try_from(index)
            .ok()
            .and_then(|i| self.tools.get(i))
            .copied()
        {
            self.tools[0] = entry;
        }
    }

    fn change_tool_number(&mut self, index: i32) {
        self.emit_line(&format!("CHANGE_TOOL_NUMBER({index})"));
        self.active_slot = index;
    }

    fn reload_tool_data(&mut self) {
        // Standalone rs274's table lives in memory only: reloading keeps
        // what G10 L1/L10/L11 wrote into it.
        self.emit_line("RELOAD_TOOLDATA()");
    }

    fn set_tool_table_entry(&mut self, index: i32, e: &ToolEntry) {
        if let Some(slot) = usize::try_from(index)
            .ok()
            .and_then(|i| self.tools.get_mut(i))
        {
            slot.toolno = e.toolno;
            slot.offset = e.offset;
            slot.diameter = e.diameter;
            slot.frontangle = e.frontangle;
            slot.backangle = e.backangle;
            slot.orientation = e.orientation;
        }
        let o = &e.offset;
        self.emit_line(&format!(
            "SET_TOOL_TABLE_ENTRY({index}, {}, {} {} {} {} {} {} {} {} {}, {}, {}, {})",
            e.toolno,
            f(o.x, 4),
            f(o.y, 4),
            f(o.z, 4),
            f(o.a, 4),
            f(o.b, 4),
            f(o.c, 4),
            f(o.u, 4),
            f(o.v, 4),
            f(o.w, 4),
            f(e.frontangle, 4),
            f(e.backangle, 4),
            e.orientation
        ));
    }

    fn flood_on(&mut self) {
        self.emit_line("FLOOD_ON()");
    }
    fn flood_off(&mut self) {
        self.emit_line("FLOOD_OFF()");
    }
    fn mist_on(&mut self) {
        self.emit_line("MIST_ON()");
    }
    fn mist_off(&mut self) {
        self.emit_line("MIST_OFF()");
    }
    fn enable_feed_override(&mut self) {
        self.emit_line("ENABLE_FEED_OVERRIDE()");
    }
    fn disable_feed_override(&mut self) {
        self.emit_line("DISABLE_FEED_OVERRIDE()");
    }
    fn enable_speed_override(&mut self, spindle: i32) {
        self.emit_line(&format!("ENABLE_SPEED_OVERRIDE({spindle})"));
    }
    fn disable_speed_override(&mut self, spindle: i32) {
        self.emit_line(&format!("DISABLE_SPEED_OVERRIDE({spindle})"));
    }
    fn enable_adaptive_feed(&mut self) {
        self.emit_line("ENABLE_ADAPTIVE_FEED()");
    }
    fn disable_adaptive_feed(&mut self) {
        self.emit_line("DISABLE_ADAPTIVE_FEED()");
    }
    fn enable_feed_hold(&mut self) {
        self.emit_line("ENABLE_FEED_HOLD()");
    }
    fn disable_feed_hold(&mut self) {
        self.emit_line("DISABLE_FEED_HOLD()");
    }
    fn set_motion_output_bit(&mut self, index: i32) {
        self.emit_line(&format!("SET_MOTION_OUTPUT_BIT({index})"));
    }
    fn clear_motion_output_bit(&mut self, index: i32) {
        self.emit_line(&format!("CLEAR_MOTION_OUTPUT_BIT({index})"));
    }
    fn set_aux_output_bit(&mut self, index: i32) {
        self.emit_line(&format!("SET_AUX_OUTPUT_BIT({index})"));
    }
    fn clear_aux_output_bit(&mut self, index: i32) {
        self.emit_line(&format!("CLEAR_AUX_OUTPUT_BIT({index})"));
    }
    fn set_motion_output_value(&mut self, index: i32, value: f64) {
        self.emit_line(&format!("SET_MOTION_OUTPUT_VALUE({index},{})", f(value, 6)));
    }
    fn set_aux_output_value(&mut self, index: i32, value: f64) {
        self.emit_line(&format!("SET_AUX_OUTPUT_VALUE({index},{})", f(value, 6)));
    }
    fn wait_input(
        &mut self,
        _index: i32,
        _kind: InputKind,
        _wait_type: i32,
        _timeout: f64,
    ) -> Result<(), ()> {
        Ok(())
    }
    fn user_m_code(&mut self, number: i32, p: f64, q: f64) {
        self.emit_line(&format!("USER_M_CODE({number}, {}, {})", f(p, 4), f(q, 4)));
    }

    fn comment(&mut self, text: &str) {
        self.emit_line(&format!("COMMENT(\"{text}\")"));
    }
    fn message(&mut self, text: &str) {
        self.emit_line(&format!("MESSAGE(\"{text}\")"));
    }
    fn print(&mut self, text: &str) {
        if let Some(out) = self.out.as_mut() {
            if writeln!(out, "{text}").is_err() {
                self.write_failed = true;
            }
        }
    }
    fn log_open(&mut self, name: &str) {
        self.emit_line(&format!("LOGOPEN(\"{name}\")"));
    }
    fn log_append(&mut self, name: &str) {
        self.emit_line(&format!("LOGAPPEND(\"{name}\")"));
    }
    fn log_close(&mut self) {
        self.emit_line("LOGCLOSE()");
    }
    fn log(&mut self, text: &str) {
        self.emit_line(&format!("LOG(\"{text}\")"));
    }
    fn program_stop(&mut self) {
        self.emit_line("PROGRAM_STOP()");
    }
    fn optional_program_stop(&mut self) {
        self.emit_line("OPTIONAL_PROGRAM_STOP()");
    }
    fn program_end(&mut self) {
        self.emit_line("PROGRAM_END()");
    }
    fn pallet_shuttle(&mut self) {
        self.emit_line("PALLET_SHUTTLE()");
    }
    fn on_reset(&mut self) {
        self.emit_line("ON_RESET()");
    }
    fn finish(&mut self) {
        self.emit_line("FINISH()");
    }

    fn position(&self) -> Pose {
        Pose {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            ..self.position
        }
    }
    fn probe_position(&self) -> Pose {
        Pose {
            u: 0.0,
            v: 0.0,
            w: 0.0,
            ..self.probe
        }
    }
    fn probe_tripped(&self) -> bool {
        false
    }
    fn length_unit_type(&self) -> Units {
        self.units
    }
    fn external_length_units(&self) -> f64 {
        self.external_length_units
    }
    fn external_angle_units(&self) -> f64 {
        1.0
    }
    fn feed_rate(&self) -> f64 {
        self.feed_rate
    }
    fn tool_length_offset(&self) -> Pose {
        self.tool_offset
    }
    fn tool_table(&self) -> Vec<ToolEntry> {
        self.tools.clone()
    }
    fn queue_empty(&self) -> bool {
        true
    }
    fn digital_input(&self, _index: i32, default: bool) -> bool {
        default
    }
    fn analog_input(&self, _index: i32, default: f64) -> f64 {
        default
    }
    fn toolchanger_fault(&self) -> i32 {
        0
    }
    fn toolchanger_reason(&self) -> i32 {
        0
    }
    fn block_delete(&self) -> bool {
        self.block_delete
    }
    fn optional_stop(&self) -> bool {
        true
    }
    fn user_m_code_defined(&self, number: i32) -> bool {
        self.user_m_codes.contains(&number)
    }
    fn motion_control_mode(&self) -> (MotionMode, f64) {
        (self.motion_mode, self.motion_tolerance)
    }
    fn tool_slot(&self) -> i32 {
        self.active_slot
    }
    /// Standalone rs274 has X Y Z A B C only.
    fn axis_mask(&self) -> u32 {
        0x3f
    }
}
