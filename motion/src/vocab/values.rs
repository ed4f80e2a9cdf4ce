//! The values a refusal names: a direction of travel, a quantity that was
//! out of range, a feature that is not supported.

use super::coded::coded_enum;

coded_enum! {
    /// Which way a jog would move.
    pub enum Direction {
        /// Towards larger positions.
        Positive = 0 => "positive",
        /// Towards smaller positions.
        Negative = 1 => "negative",
    }
}

coded_enum! {
    /// What a [`Reject::BadValue`](super::Reject::BadValue) is about.
    pub enum Quantity {
        /// The scale.
        Scale = 0 => "scale",
        /// The minimum limit.
        MinimumLimit = 1 => "minimum limit",
        /// The maximum limit.
        MaximumLimit = 2 => "maximum limit",
        /// The velocity limit.
        VelocityLimit = 3 => "velocity limit",
        /// The acceleration limit.
        AccelerationLimit = 4 => "acceleration limit",
        /// The minimum following error.
        MinimumFerror = 5 => "minimum following error",
        /// The maximum following error.
        MaximumFerror = 6 => "maximum following error",
        /// The backlash.
        Backlash = 7 => "backlash",
        /// The motor offset.
        MotorOffset = 8 => "motor offset",
        /// The world home coordinate.
        WorldHomeCoordinate = 9 => "world home coordinate",
        /// The jog increment.
        JogIncrement = 10 => "jog increment",
        /// The jog position.
        JogPosition = 11 => "jog position",
        /// The jog target.
        JogTarget = 12 => "jog target",
        /// A coordinate of a queued move's end point or arc.
        Coordinate = 13 => "coordinate",
        /// The dwell time.
        DwellTime = 14 => "dwell time",
        /// The blend tolerance.
        BlendTolerance = 15 => "blend tolerance",
        /// The jerk limit.
        JerkLimit = 16 => "jerk limit",
        /// A screw-compensation value.
        CompValue = 17 => "compensation value",
        /// The planner type.
        PlannerType = 18 => "planner type",
        /// The spindle speed.
        SpindleSpeed = 19 => "spindle speed",
        /// An analog output's value.
        AnalogValue = 20 => "analog output value",
        /// A spindle orientation angle (M19 R).
        OrientAngle = 21 => "spindle orientation angle",
        /// A feed per revolution (G95).
        FeedPerRev = 22 => "feed per revolution",
        /// A constant surface speed setting (G96).
        SurfaceSpeed = 23 => "constant surface speed",
        /// An external offset's share of an axis's limits
        /// (`OFFSET_AV_RATIO`, 0..=0.9).
        EoffsetRatio = 24 => "external offset ratio (OFFSET_AV_RATIO, 0 to 0.9)",
        /// A queued move's own path speed cap (SET_LINE's ini_maxvel).
        MoveSpeedCap = 25 => "move's speed cap (ini_maxvel)",
        /// A queued move's own path acceleration cap (SET_LINE's acc).
        MoveAccelerationCap = 26 => "move's acceleration cap",
        /// The trajectory velocity or INI velocity of SET_VEL.
        TrajVelocity = 27 => "trajectory velocity",
        /// An arc blend setting (SETUP_ARC_BLENDS).
        ArcBlendSetting = 28 => "arc blend setting",
        /// A tool offset coordinate (SET_OFFSET).
        ToolOffset = 29 => "tool offset",
        /// A spindle speed limit (SET_SPINDLE_PARAMS).
        SpindleSpeedLimit = 30 => "spindle speed limit",
    }
}

coded_enum! {
    /// What a [`Reject::Unsupported`](super::Reject::Unsupported) refuses.
    pub enum Feature {
        /// Teleop and coordinated modes need inverse kinematics.
        WorldModeWithoutInverse = 1 => "teleop and coordinated modes need inverse kinematics",
    }
}
