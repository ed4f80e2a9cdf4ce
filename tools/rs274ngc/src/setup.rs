//! The interpreter's model of the machine and its modes: positions,
//! offsets, modal state, spindle, coolant, tools, cutter compensation.
//! Positions are in program units in the current coordinate system.

use crate::canon::{Direction, MotionMode, Plane, Pose, ToolEntry, Units};
use crate::codes::G_80;

/// Absolute or incremental distances.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum DistanceMode {
    Absolute,
    Incremental,
}

/// Feed rate modes (G93, G94, G95).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum FeedMode {
    UnitsPerMinute,
    InverseTime,
    UnitsPerRevolution,
}

/// Canned cycle retract modes (G98, G99).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum RetractMode {
    RPlane,
    OldZ,
}

/// Cutter radius compensation side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Side {
    Off,
    Right,
    Left,
}

/// Spindle speed modes (G96, G97).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum SpindleMode {
    ConstantRpm,
    ConstantSurface,
}

/// One spindle's modal state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpindleState {
    /// The programmed speed (S), RPM or surface speed.
    pub speed: f64,
    /// Which way it turns (M3, M4, M5).
    pub turning: Direction,
    /// G96 or G97.
    pub mode: SpindleMode,
}

impl SpindleState {
    /// A spindle at rest: S0, M5, G97.
    pub const STOPPED: SpindleState = SpindleState {
        speed: 0.0,
        turning: Direction::Stopped,
        mode: SpindleMode::ConstantRpm,
    };
}

/// The interpreter's settings.
#[derive(Debug, Clone)]
#[allow(missing_docs)]
pub struct Setup {
    /// The machine's axes (bit 0 X ... bit 8 W), as the canon answers.
    pub axis_mask: u32,
    /// Current position, program units, current coordinate system.
    pub current: Pose,
    /// Programmed (uncompensated) X/Y/Z position for cutter comp.
    pub program_x: f64,
    pub program_y: f64,
    pub program_z: f64,
    /// Work offset of the active coordinate system (G54..G59.3).
    pub origin_offset: Pose,
    /// G52/G92 offset.
    pub axis_offset: Pose,
    /// 1..9 for G54..G59.3.
    pub origin_index: i32,
    /// XY rotation of the active coordinate system, degrees.
    pub rotation_xy: f64,
    pub tool_offset: Pose,
    pub length_units: Units,
    pub plane: Plane,
    pub distance_mode: DistanceMode,
    pub ijk_distance_mode: DistanceMode,
    pub feed_mode: FeedMode,
    pub feed_rate: f64,
    /// Every spindle ([TRAJ]SPINDLES of them, at least one); spindle 0
    /// is the one the named parameters, cycles and M70-M73 know.
    pub spindles: Vec<SpindleState>,
    /// The spindle feed per revolution follows (G95's `$`).
    pub feed_spindle: usize,
    /// The modal motion code (G-code times ten), G80 or -1.
    pub motion_mode: i32,
    pub control_mode: MotionMode,
    pub tolerance: f64,
    pub naivecam_tolerance: f64,
    pub retract_mode: RetractMode,
    pub cutter_comp_side: Side,
    pub cutter_comp_radius: f64,
    pub cutter_comp_orientation: i32,
    pub cutter_comp_firstmove: bool,
    pub arc_not_allowed: bool,
    /// Remembered canned cycle words (modal between cycle blocks).
    /// The last canned cycle's bottom (the third axis word).
    pub cycle_cc: f64,
    pub cycle_i: f64,
    pub cycle_j: f64,
    pub cycle_k: f64,
    pub cycle_l: i32,
    pub cycle_p: f64,
    pub cycle_q: f64,
    pub cycle_r: f64,
    /// Initial level (for G98) of the cycle in progress.
    pub cycle_il: f64,
    pub cycle_il_flag: bool,
    pub mist: bool,
    pub flood: bool,
    pub feed_override: bool,
    pub speed_override: bool,
    pub adaptive_feed: bool,
    pub feed_hold: bool,
    pub lathe_diameter_mode: bool,
    /// Tool table index selected by the last T word (-1 none).
    pub selected_pocket: i32,
    /// Tool number selected by the last T word (-1 none).
    pub selected_tool: i32,
    /// Tool table index of the tool in the spindle.
    pub current_pocket: i32,
    /// The interpreter's copy of the tool table (index 0: spindle).
    pub tool_table: Vec<ToolEntry>,
    /// A probe move was issued: the position must be read back.
    pub probe_flag: bool,
    /// A tool change was issued: position and tool table must be reread.
    pub toolchange_flag: bool,
    /// An M66 wait was issued: the input must be read.
    pub input_flag: bool,
    pub input_index: i32,
    pub input_digital: bool,
    /// The program started with a `%` line, so it must end with one.
    pub percent_flag: bool,
    /// The line number being read (1 for the first line of a file).
    pub sequence_number: i32,
    /// Spindle orientation offset for M19 (INI ORIENT_OFFSET).
    pub orient_offset: f64,
    /// NURBS control points being collected (G5.2 .. G5.3).
    pub nurbs_points: Vec<crate::canon::ControlPoint>,
    pub nurbs_order: u32,
    /// Machine (user) length units per millimetre, from the world.
    pub external_length_units: f64,
}

impl Default for Setup {
    fn default() -> Self {
        Setup {
            axis_mask: 0x1ff,
            current: Pose::ZERO,
            program_x: 0.0,
            program_y: 0.0,
            program_z: 0.0,
            origin_offset: Pose::ZERO,
            axis_offset: Pose::ZERO,
            origin_index: 1,
            rotation_xy: 0.0,
            tool_offset: Pose::ZERO,
            length_units: Units::Mm,
            plane: Plane::Xy,
            distance_mode: DistanceMode::Absolute,
            ijk_distance_mode: DistanceMode::Incremental,
            feed_mode: FeedMode::UnitsPerMinute,
            feed_rate: 0.0,
            spindles: vec![SpindleState::STOPPED],
            feed_spindle: 0,
            motion_mode: G_80,
            control_mode: MotionMode::Continuous,
            tolerance: 0.0,
            naivecam_tolerance: 0.0,
            retract_mode: RetractMode::RPlane,
            cutter_comp_side: Side::Off,
            cutter_comp_radius: 0.0,
            cutter_comp_orientation: 0,
            cutter_comp_firstmove: true,
            arc_not_allowed: false,
            cycle_cc: 0.0,
            cycle_i: 0.0,
            cycle_j: 0.0,
            cycle_k: 0.0,
            cycle_l: 0,
            cycle_p: 0.0,
            cycle_q: 0.0,
            cycle_r: 0.0,
            cycle_il: 0.0,
            cycle_il_flag: false,
            mist: false,
            flood: false,
            feed_override: true,
            speed_override: true,
            adaptive_feed: false,
            feed_hold: true,
            lathe_diameter_mode: false,
            selected_pocket: -1,
            selected_tool: 0,
            current_pocket: 0,
            tool_table: Vec::new(),
            probe_flag: false,
            toolchange_flag: false,
            input_flag: false,
            input_index: 0,
            input_digital: false,
            percent_flag: false,
            sequence_number: 0,
            orient_offset: 0.0,
            nurbs_points: Vec::new(),
            nurbs_order: 3,
            external_length_units: 1.0,
        }
    }
}

impl Setup {
    /// The tool table entry at `index`, or an empty one.
    pub fn tool(&self, index: i32) -> ToolEntry {
        usize::try_from(index)
            .ok()
            .and_then(|i| self.tool_table.get(i).copied())
            .unwrap_or(ToolEntry::EMPTY)
    }

    /// Mutable tool table entry at `index`, growing the table if needed.
    pub fn tool_mut(&mut self, index: i32) -> &mut ToolEntry {
        let i = usize::try_from(index).unwrap_or(0);
        if self.tool_table.len() <= i {
            self.tool_table.resize(i + 1, ToolEntry::EMPTY);
        }
        &mut self.tool_table[i]
    }

    /// Millimetres per program unit.
    pub fn mm_per_unit(&self) -> f64 {
        self.length_units.mm_per_unit()
    }
}
