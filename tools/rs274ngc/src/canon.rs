//! The canonical machining interface: the calls the interpreter makes to
//! move and switch things, and the questions it asks the world (where
//! the machine is, what is in the tool table). LinuxCNC's task implements
//! the same set ("canon"); here it is a trait the caller implements.
//!
//! Coordinates the interpreter passes are in program units (what
//! [`Canon::use_length_units`] last said) in the program coordinate system,
//! exactly as LinuxCNC's canonical calls receive them.

/// A position or offset on all nine axes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub u: f64,
    pub v: f64,
    pub w: f64,
}

impl Pose {
    /// All axes zero.
    pub const ZERO: Pose = Pose {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        a: 0.0,
        b: 0.0,
        c: 0.0,
        u: 0.0,
        v: 0.0,
        w: 0.0,
    };
}

/// Length units of a program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Units {
    Inches,
    Mm,
    Cm,
}

impl Units {
    /// Millimetres per unit.
    pub fn mm_per_unit(self) -> f64 {
        match self {
            Units::Inches => 25.4,
            Units::Mm => 1.0,
            Units::Cm => 10.0,
        }
    }
}

/// The active plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Plane {
    Xy,
    Yz,
    Xz,
    Uv,
    Vw,
    Uw,
}

/// Path control modes (G61, G61.1, G64).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum MotionMode {
    ExactStop,
    ExactPath,
    Continuous,
}

/// What feed rates refer to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum FeedReference {
    Workpiece,
    Xyz,
}

/// Direction of spindle rotation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Direction {
    Stopped,
    Clockwise,
    CounterClockwise,
}

/// Kinds of input M66 waits for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum InputKind {
    Digital,
    Analog,
}

/// One tool table entry. Lengths are in the machine's (user) units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct ToolEntry {
    /// Tool number; -1 for an empty entry.
    pub toolno: i32,
    /// The pocket the tool lives in (P), as written in the table.
    pub pocketno: i32,
    pub offset: Pose,
    pub diameter: f64,
    pub frontangle: f64,
    pub backangle: f64,
    pub orientation: i32,
}

impl ToolEntry {
    /// An empty entry (no tool).
    pub const EMPTY: ToolEntry = ToolEntry {
        toolno: -1,
        pocketno: 0,
        offset: Pose::ZERO,
        diameter: 0.0,
        frontangle: 0.0,
        backangle: 0.0,
        orientation: 0,
    };
}

/// An arc or helix: the end point in the plane, the centre, the turn
/// count (positive counter-clockwise) and the end on the plane's axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// End point, first axis of the plane (X in G17).
    pub first_end: f64,
    /// End point, second axis of the plane (Y in G17).
    pub second_end: f64,
    /// Centre, first axis.
    pub first_axis: f64,
    /// Centre, second axis.
    pub second_axis: f64,
    /// Turns: +1 one counter-clockwise turn or less, -1 clockwise, 2 and
    /// more for full extra turns.
    pub rotation: i32,
    /// End point on the axis normal to the plane.
    pub axis_end_point: f64,
    /// End points of the other axes (the x/y/z fields are unused).
    pub rest: Pose,
}

/// A NURBS control point.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub struct ControlPoint {
    pub x: f64,
    pub y: f64,
    pub weight: f64,
}

/// The calls the interpreter makes and the questions it asks. Every
/// method is one of LinuxCNC's canonical functions; the names are
/// theirs in lower case.
pub trait Canon {
    /// The text of the line being interpreted (for traces and displays);
    /// empty between programs.
    fn set_line_text(&mut self, text: &[u8]);

    // -- representation ---------------------------------------------------
    /// SET_G5X_OFFSET: the origin of work coordinate system `index` (1-9).
    fn set_g5x_offset(&mut self, index: i32, offset: &Pose);
    /// SET_G92_OFFSET.
    fn set_g92_offset(&mut self, offset: &Pose);
    /// SET_XY_ROTATION, degrees.
    fn set_xy_rotation(&mut self, degrees: f64);
    /// USE_LENGTH_UNITS.
    fn use_length_units(&mut self, units: Units);
    /// SELECT_PLANE.
    fn select_plane(&mut self, plane: Plane);
    /// SET_FEED_REFERENCE.
    fn set_feed_reference(&mut self, reference: FeedReference);

    // -- motion -----------------------------------------------------------
    /// STRAIGHT_TRAVERSE (G0).
    fn straight_traverse(&mut self, line: i32, end: &Pose);
    /// STRAIGHT_FEED (G1).
    fn straight_feed(&mut self, line: i32, end: &Pose);
    /// ARC_FEED (G2, G3).
    fn arc_feed(&mut self, line: i32, arc: &Arc);
    /// STRAIGHT_PROBE (G38.n); `probe_type` bit 0: no error if the probe
    /// does not trip, bit 1: move until it opens.
    fn straight_probe(&mut self, line: i32, end: &Pose, probe_type: u8);
    /// NURBS_FEED (G5, G5.1, G5.2/G5.3).
    fn nurbs_feed(&mut self, line: i32, points: &[ControlPoint], order: u32);
    /// START_SPEED_FEED_SYNCH (G33, G33.1, G76): the feeds that follow
    /// move `feed_per_revolution` program units per revolution of
    /// `spindle`; `velocity_mode` ties velocity rather than position to
    /// the spindle.
    fn start_speed_feed_synch(
        &mut self,
        spindle: i32,
        feed_per_revolution: f64,
        velocity_mode: bool,
    );
    /// STOP_SPEED_FEED_SYNCH: the feeds that follow are timed again.
    fn stop_speed_feed_synch(&mut self);
    /// RIGID_TAP (G33.1): feed to `end` (X, Y, Z) synchronised with the
    /// spindle, reverse it (`scale` times as fast) and come back.
    fn rigid_tap(&mut self, line: i32, end: (f64, f64, f64), scale: f64);
    /// DWELL, seconds.
    fn dwell(&mut self, seconds: f64);
    /// SET_FEED_RATE.
    fn set_feed_rate(&mut self, rate: f64);
    /// SET_FEED_MODE: 0 units per minute (or inverse time), 1 per rev.
    fn set_feed_mode(&mut self, spindle: i32, mode: i32);
    /// SET_MOTION_CONTROL_MODE.
    fn set_motion_control_mode(&mut self, mode: MotionMode, tolerance: f64);
    /// SET_NAIVECAM_TOLERANCE.
    fn set_naivecam_tolerance(&mut self, tolerance: f64);
    /// TURN_PROBE_ON.
    fn turn_probe_on(&mut self);
    /// TURN_PROBE_OFF.
    fn turn_probe_off(&mut self);

    // -- spindle ----------------------------------------------------------
    /// SET_SPINDLE_SPEED.
    fn set_spindle_speed(&mut self, spindle: i32, rpm: f64);
    /// START_SPINDLE_CLOCKWISE.
    fn start_spindle_clockwise(&mut self, spindle: i32);
    /// START_SPINDLE_COUNTERCLOCKWISE.
    fn start_spindle_counterclockwise(&mut self, spindle: i32);
    /// STOP_SPINDLE_TURNING.
    fn stop_spindle_turning(&mut self, spindle: i32);
    /// SET_SPINDLE_MODE: 0 for constant RPM, else the CSS speed limit.
    fn set_spindle_mode(&mut self, spindle: i32, css_limit: f64);
    /// ORIENT_SPINDLE (M19).
    fn orient_spindle(&mut self, spindle: i32, orientation: f64, mode: i32);
    /// WAIT_SPINDLE_ORIENT_COMPLETE.
    fn wait_spindle_orient_complete(&mut self, spindle: i32, timeout: f64);

    // -- tools ------------------------------------------------------------
    /// USE_TOOL_LENGTH_OFFSET.
    fn use_tool_length_offset(&mut self, offset: &Pose);
    /// SELECT_TOOL (T word), the tool number.
    fn select_tool(&mut self, tool: i32);
    /// START_CHANGE (M6 begins).
    fn start_change(&mut self);
    /// CHANGE_TOOL (M6), the tool table index of the tool.
    fn change_tool(&mut self, index: i32);
    /// CHANGE_TOOL_NUMBER (M61), the tool table index.
    fn change_tool_number(&mut self, index: i32);
    /// SET_TOOL_TABLE_ENTRY (G10 L1/L10/L11).
    fn set_tool_table_entry(&mut self, index: i32, entry: &ToolEntry);
    /// RELOAD_TOOLDATA (G10 L0): the world reloads its tool table; the
    /// interpreter then reads it again through [`Canon::tool_table`].
    fn reload_tool_data(&mut self);

    // -- coolant, overrides, I/O -----------------------------------------
    /// FLOOD_ON.
    fn flood_on(&mut self);
    /// FLOOD_OFF.
    fn flood_off(&mut self);
    /// MIST_ON.
    fn mist_on(&mut self);
    /// MIST_OFF.
    fn mist_off(&mut self);
    /// ENABLE_FEED_OVERRIDE.
    fn enable_feed_override(&mut self);
    /// DISABLE_FEED_OVERRIDE.
    fn disable_feed_override(&mut self);
    /// ENABLE_SPEED_OVERRIDE.
    fn enable_speed_override(&mut self, spindle: i32);
    /// DISABLE_SPEED_OVERRIDE.
    fn disable_speed_override(&mut self, spindle: i32);
    /// ENABLE_ADAPTIVE_FEED.
    fn enable_adaptive_feed(&mut self);
    /// DISABLE_ADAPTIVE_FEED.
    fn disable_adaptive_feed(&mut self);
    /// ENABLE_FEED_HOLD.
    fn enable_feed_hold(&mut self);
    /// DISABLE_FEED_HOLD.
    fn disable_feed_hold(&mut self);
    /// SET_MOTION_OUTPUT_BIT (M62).
    fn set_motion_output_bit(&mut self, index: i32);
    /// CLEAR_MOTION_OUTPUT_BIT (M63).
    fn clear_motion_output_bit(&mut self, index: i32);
    /// SET_AUX_OUTPUT_BIT (M64).
    fn set_aux_output_bit(&mut self, index: i32);
    /// CLEAR_AUX_OUTPUT_BIT (M65).
    fn clear_aux_output_bit(&mut self, index: i32);
    /// SET_MOTION_OUTPUT_VALUE (M67).
    fn set_motion_output_value(&mut self, index: i32, value: f64);
    /// SET_AUX_OUTPUT_VALUE (M68).
    fn set_aux_output_value(&mut self, index: i32, value: f64);
    /// WAIT (M66): start waiting for an input. `Ok(())` when the wait is
    /// set up; `Err(())` when the input index is out of range.
    #[allow(clippy::result_unit_err)]
    fn wait_input(
        &mut self,
        index: i32,
        kind: InputKind,
        wait_type: i32,
        timeout: f64,
    ) -> Result<(), ()>;
    /// A user M-code (M100-M199) with its P and Q values.
    fn user_m_code(&mut self, number: i32, p: f64, q: f64);

    // -- messages and program flow -----------------------------------------
    /// COMMENT.
    fn comment(&mut self, text: &str);
    /// MESSAGE ((MSG,...) and (DEBUG,...)).
    fn message(&mut self, text: &str);
    /// (PRINT,...): text for the operator's terminal.
    fn print(&mut self, text: &str);
    /// LOGOPEN.
    fn log_open(&mut self, name: &str);
    /// LOGAPPEND.
    fn log_append(&mut self, name: &str);
    /// LOGCLOSE.
    fn log_close(&mut self);
    /// LOG.
    fn log(&mut self, text: &str);
    /// PROGRAM_STOP (M0, M60).
    fn program_stop(&mut self);
    /// OPTIONAL_PROGRAM_STOP (M1).
    fn optional_program_stop(&mut self);
    /// PROGRAM_END (M2, M30).
    fn program_end(&mut self);
    /// PALLET_SHUTTLE (M30, M60).
    fn pallet_shuttle(&mut self);
    /// ON_RESET.
    fn on_reset(&mut self);
    /// FINISH (the closing % of a program).
    fn finish(&mut self);

    // -- questions --------------------------------------------------------
    /// The current position in program units and the program coordinate
    /// system (asked after probing and tool changes).
    fn position(&self) -> Pose;
    /// Where the probe tripped, program units.
    fn probe_position(&self) -> Pose;
    /// Whether the last probe move tripped.
    fn probe_tripped(&self) -> bool;
    /// The length units the machine is currently told.
    fn length_unit_type(&self) -> Units;
    /// Machine (user) length units per millimetre: 1.0 for a metric
    /// machine, 1/25.4 for an inch one. Tool tables and parameter files
    /// are in these units.
    fn external_length_units(&self) -> f64;
    /// Machine angle units per degree.
    fn external_angle_units(&self) -> f64;
    /// The current feed rate.
    fn feed_rate(&self) -> f64;
    /// The tool length offset in effect, program units.
    fn tool_length_offset(&self) -> Pose;
    /// The whole tool table, index 0 being the spindle.
    fn tool_table(&self) -> Vec<ToolEntry>;
    /// The motion queue has drained (a probe or tool change is complete).
    fn queue_empty(&self) -> bool;
    /// An input's value after an M66 wait; `default` when unknown.
    fn digital_input(&self, index: i32, default: bool) -> bool;
    /// An analog input's value after an M66 wait.
    fn analog_input(&self, index: i32, default: f64) -> f64;
    /// Toolchanger fault flag (#5600).
    fn toolchanger_fault(&self) -> i32;
    /// Toolchanger fault reason (#5601).
    fn toolchanger_reason(&self) -> i32;
    /// Whether the last M66 wait ran out of time (#5399 becomes −1, as
    /// LinuxCNC's task reports it); a canon that never waits says no.
    fn input_timed_out(&self) -> bool {
        false
    }
    /// Block delete switch: lines starting with `/` are skipped when on.
    fn block_delete(&self) -> bool;
    /// Optional stop switch (M1 stops when on).
    fn optional_stop(&self) -> bool;
    /// Whether a user M-code program exists for M`number`.
    fn user_m_code_defined(&self, number: i32) -> bool;
    /// The path control mode in effect and its tolerance.
    fn motion_control_mode(&self) -> (MotionMode, f64);
    /// The tool table index of the tool in the spindle.
    fn tool_slot(&self) -> i32;
    /// The machine's axes, bit 0 X, 1 Y, 2 Z, 3 A, 4 B, 5 C, 6 U, 7 V,
    /// 8 W; a word for a missing axis is a bad character.
    fn axis_mask(&self) -> u32;
}
