//! The pins of `plasmac`, named, typed and directed as LinuxCNC 2.9's
//! (`man 9 plasmac`), with its defaults. [`Inputs`] and [`Outputs`] are
//! plain values one call reads and writes; [`InPins`] and [`OutPins`]
//! hold the HAL handles and move those values in and out.

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::Inst;

/// Declares a value struct, its `Default` (the pins' defaults), a handle
/// struct and the code that makes the pins and copies between the two.
macro_rules! pin_set {
    (
        $(#[$vm:meta])* values $values:ident,
        $(#[$hm:meta])* handles $handles:ident,
        $dir:ident, $make:ident, $copy:ident,
        { $( $(#[$fm:meta])* $field:ident : $ty:ty = $pin:literal, $init:expr; )* }
    ) => {
        $(#[$vm])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $values {
            $( $(#[$fm])* pub $field: $ty, )*
        }

        impl Default for $values {
            fn default() -> Self {
                $values { $( $field: $init, )* }
            }
        }

        $(#[$hm])*
        pub struct $handles {
            $( $field: Pin<$ty, $dir>, )*
        }

        impl $handles {
            /// Makes every pin of the set on `inst`, at its default.
            pub fn new(inst: &mut Inst<'_, '_>) -> Result<$handles> {
                Ok($handles { $( $field: inst.$make::<$ty>($pin, $init)?, )* })
            }
        }

        pin_set!(@copy $copy, $handles, $values, $( $field ),*);
    };
    (@copy read, $handles:ident, $values:ident, $( $field:ident ),*) => {
        impl $handles {
            /// Reads every pin into `v`.
            pub fn read(&self, v: &mut $values) {
                $( v.$field = self.$field.get(); )*
            }
        }
    };
    (@copy write, $handles:ident, $values:ident, $( $field:ident ),*) => {
        impl $handles {
            /// Writes `v` to every pin.
            pub fn write(&self, v: &$values) {
                $( self.$field.set(v.$field); )*
            }
        }
    };
}

pin_set! {
    /// The input pins, as one call reads them.
    values Inputs,
    /// The handles of the input pins.
    handles InPins, In, pin_in_init, read,
    {
        /// Arc start failure timeout (s).
        arc_fail_delay: f64 = "arc-fail-delay", 0.0;
        /// Arc lost delay during a cut (s).
        arc_lost_delay: f64 = "arc-lost-delay", 0.0;
        /// Highest arc voltage that is an Arc OK in mode 0.
        arc_ok_high: f64 = "arc-ok-high", 0.0;
        /// The external Arc OK input (modes 1 and 2).
        arc_ok_in: bool = "arc-ok-in", false;
        /// Lowest arc voltage that is an Arc OK in mode 0.
        arc_ok_low: f64 = "arc-ok-low", 0.0;
        /// Attempts at starting the arc.
        arc_max_starts: i32 = "arc-max-starts", 0;
        /// Raw arc voltage (modes 0 and 1).
        arc_voltage_in: f64 = "arc-voltage-in", 0.0;
        /// Taken from the raw arc voltage so that 0 V reads 0.
        arc_voltage_offset: f64 = "arc-voltage-offset", 0.0;
        /// Scale from the raw arc voltage to volts.
        arc_voltage_scale: f64 = "arc-voltage-scale", 0.0;
        /// THC activates by itself once the voltage is steady.
        thc_auto: bool = "thc-auto", false;
        /// X maximum limit.
        axis_x_max_limit: f64 = "axis-x-max-limit", 0.0;
        /// X minimum limit.
        axis_x_min_limit: f64 = "axis-x-min-limit", 0.0;
        /// X position (axis.x.pos-cmd).
        axis_x_position: f64 = "axis-x-position", 0.0;
        /// Y maximum limit.
        axis_y_max_limit: f64 = "axis-y-max-limit", 0.0;
        /// Y minimum limit.
        axis_y_min_limit: f64 = "axis-y-min-limit", 0.0;
        /// Y position (axis.y.pos-cmd).
        axis_y_position: f64 = "axis-y-position", 0.0;
        /// Z maximum limit.
        axis_z_max_limit: f64 = "axis-z-max-limit", 0.0;
        /// Z minimum limit.
        axis_z_min_limit: f64 = "axis-z-min-limit", 0.0;
        /// Z position (joint.N.pos-fb).
        axis_z_position: f64 = "axis-z-position", 0.0;
        /// Torch breakaway switch.
        breakaway: bool = "breakaway", false;
        /// Asks for a consumable change (while paused).
        consumable_change: bool = "consumable-change", false;
        /// Enables corner lock (velocity anti-dive).
        cornerlock_enable: bool = "cornerlock-enable", false;
        /// Corner lock threshold, percent of the requested feed rate.
        cornerlock_threshold: f64 = "cornerlock-threshold", 0.0;
        /// Machine velocity (motion.current-vel), units per second.
        current_velocity: f64 = "current-velocity", 0.0;
        /// Cut feed rate of the material (units per minute).
        cut_feed_rate: f64 = "cut-feed-rate", 0.0;
        /// Cut height above the probed zero.
        cut_height: f64 = "cut-height", 0.0;
        /// Asks for cut recovery (while paused).
        cut_recovery: bool = "cut-recovery", false;
        /// Cut voltage of the material.
        cut_volts: f64 = "cut-volts", 0.0;
        /// Starts a cut (spindle.0.on).
        cutting_start: bool = "cutting-start", false;
        /// Prints state changes.
        debug_print: bool = "debug-print", false;
        /// External E-stop.
        external_estop: bool = "external-estop", false;
        /// Feed override from the GUI.
        feed_override: f64 = "feed-override", 0.0;
        /// Adaptive feed reduction, percent (motion.analog-out-03).
        feed_reduction: f64 = "feed-reduction", 0.0;
        /// Float switch.
        float_switch: bool = "float-switch", false;
        /// Float switch travel.
        float_switch_travel: f64 = "float-switch-travel", 0.0;
        /// Current G-code scale.
        gcode_scale: f64 = "gcode-scale", 1.0;
        /// Height override (volts added to the target).
        height_override: f64 = "height-override", 0.0;
        /// Torch height change per volt.
        height_per_volt: f64 = "height-per-volt", 0.0;
        /// The machine is homed.
        homed: bool = "homed", false;
        /// Arc OK not required (motion.digital-out-01).
        ignore_arc_ok_0: bool = "ignore-arc-ok-0", false;
        /// Arc OK not required.
        ignore_arc_ok_1: bool = "ignore-arc-ok-1", false;
        /// For G-code portability between GUIs; not used here.
        kerf_width: f64 = "kerf-width", 0.0;
        /// Overrides the jog inhibit.
        override_jog: bool = "override-jog", false;
        /// Offset probe deployed.
        offset_set_probe: bool = "offset-set-probe", false;
        /// Scribe deployed for setting offsets.
        offset_set_scribe: bool = "offset-set-scribe", false;
        /// Laser offset for cut recovery.
        laser_recovery_start: i32 = "laser-recovery-start", 0;
        /// Alignment laser X offset (scaled units).
        laser_x_offset: i32 = "laser-x-offset", 0;
        /// Alignment laser Y offset (scaled units).
        laser_y_offset: i32 = "laser-y-offset", 0;
        /// Low-pass cut-off of the arc voltage (Hz, 0: none).
        lowpass_frequency: f64 = "lowpass-frequency", 0.0;
        /// The machine is on.
        machine_is_on: bool = "machine-is-on", false;
        /// Maximum height offset.
        max_offset: i32 = "max-offset", 5;
        /// Arc OK not required in mesh mode.
        mesh_arc_ok: bool = "mesh-arc-ok", false;
        /// Mesh cutting mode.
        mesh_enable: bool = "mesh-enable", false;
        /// Operating mode 0, 1 or 2.
        mode: i32 = "mode", 0;
        /// motion.motion-type.
        motion_type: i32 = "motion-type", 0;
        /// External THC down (mode 2).
        move_down: bool = "move-down", false;
        /// External THC up (mode 2).
        move_up: bool = "move-up", false;
        /// Multiple tools allowed.
        multi_tool: bool = "multi-tool", true;
        /// Wait for the offset probe to deploy (s).
        offset_probe_delay: f64 = "offset-probe-delay", 0.0;
        /// Offset probe X offset.
        offset_probe_x: f64 = "offset-probe-x", 0.0;
        /// Offset probe Y offset.
        offset_probe_y: f64 = "offset-probe-y", 0.0;
        /// External offsets are active (motion.eoffset-active).
        offsets_active: bool = "offsets-active", false;
        /// Debounce periods for the ohmic sense going on.
        ohmic_sense_on_delay: i32 = "ohmic-sense-on-delay", 3;
        /// Debounce periods for the ohmic sense going off.
        ohmic_sense_off_delay: i32 = "ohmic-sense-off-delay", 3;
        /// Ohmic sense relay.
        ohmic_sense_in: bool = "ohmic-sense-in", false;
        /// Ohmic attempts before falling back to the float switch.
        ohmic_max_attempts: i32 = "ohmic-max-attempts", 0;
        /// Ohmic probe input.
        ohmic_probe: bool = "ohmic-probe", false;
        /// Enables the ohmic probe.
        ohmic_probe_enable: bool = "ohmic-probe-enable", false;
        /// Z offset of the ohmic probe.
        ohmic_probe_offset: f64 = "ohmic-probe-offset", 0.0;
        /// Tests for a shorted torch.
        ohmic_test: bool = "ohmic-test", false;
        /// Arc OK samples required (mode 0).
        ok_sample_counts: i32 = "ok-sample-counts", 10;
        /// Arc OK voltage deviation allowed (mode 0).
        ok_sample_threshold: f64 = "ok-sample-threshold", 10.0;
        /// Pause at the end of a cut (s).
        pause_at_end: f64 = "pause-at-end", 0.0;
        /// Speed of paused motion, -1 to 1.
        paused_motion_speed: f64 = "paused-motion-speed", 0.0;
        /// THC derivative gain.
        pid_d_gain: f64 = "pid-d-gain", 0.0;
        /// THC integral gain.
        pid_i_gain: f64 = "pid-i-gain", 0.0;
        /// THC proportional gain.
        pid_p_gain: f64 = "pid-p-gain", 0.0;
        /// Pierce time (s).
        pierce_delay: f64 = "pierce-delay", 0.0;
        /// Probe down velocity (units per minute).
        probe_feed_rate: f64 = "probe-feed-rate", 0.0;
        /// Final probe speed (offset counts per period).
        probe_final_speed: i32 = "probe-final-speed", 1;
        /// Pierce height.
        pierce_height: f64 = "pierce-height", 0.0;
        /// Height above the Z minimum limit where slow probing begins.
        probe_start_height: f64 = "probe-start-height", 0.0;
        /// Probe test only.
        probe_test: bool = "probe-test", false;
        /// halui.program.is-idle.
        program_is_idle: bool = "program-is-idle", false;
        /// halui.program.is-paused.
        program_is_paused: bool = "program-is-paused", false;
        /// halui.program.is-running.
        program_is_running: bool = "program-is-running", false;
        /// Puddle jump delay (s).
        puddle_jump_delay: f64 = "puddle-jump-delay", 0.0;
        /// Puddle jump height, percent of the pierce height.
        puddle_jump_height: f64 = "puddle-jump-height", 0.0;
        /// Deprecated in LinuxCNC; not used.
        requested_velocity: f64 = "requested-velocity", 0.0;
        /// Requested feed rate (motion.feed-upm), G-code units per minute.
        feed_upm: f64 = "feed-upm", 0.0;
        /// Offset counts per 0.001 mm.
        resolution: i32 = "resolution", 100;
        /// Time from an arc failure to the next attempt (s).
        restart_delay: f64 = "restart-delay", 0.0;
        /// Safe traverse height above the probed zero (0: Z maximum).
        safe_height: f64 = "safe-height", 0.0;
        /// Delay from scribe arm to scribe on (s).
        scribe_arm_delay: f64 = "scribe-arm-delay", 0.0;
        /// Delay from scribe on to motion (s).
        scribe_on_delay: f64 = "scribe-on-delay", 0.0;
        /// Starts a scribe (spindle.1.on).
        scribe_start: bool = "scribe-start", false;
        /// Feed rate to the pierce and cut heights (units per minute).
        setup_feed_rate: f64 = "setup-feed-rate", 0.0;
        /// Skip the IHS within this distance of the last cut's end.
        skip_ihs_distance: f64 = "skip-ihs-distance", 0.0;
        /// Starts a spot (spindle.2.on).
        spotting_start: bool = "spotting-start", false;
        /// Voltage that starts the spotting time.
        spotting_threshold: f64 = "spotting-threshold", 0.0;
        /// Torch-off delay once the spotting threshold is reached (ms).
        spotting_time: f64 = "spotting-time", 0.0;
        /// Delay from the cut feed rate to THC on (s), without auto THC.
        thc_delay: f64 = "thc-delay", 0.0;
        /// THC disable (motion.digital-out-02).
        thc_disable: bool = "thc-disable", false;
        /// THC enable.
        thc_enable: bool = "thc-enable", false;
        /// Highest THC speed (units per minute).
        thc_feed_rate: f64 = "thc-feed-rate", 0.0;
        /// Steady samples before auto THC.
        thc_sample_counts: i32 = "thc-sample-counts", 50;
        /// Voltage deviation of a steady sample (auto THC).
        thc_sample_threshold: f64 = "thc-sample-threshold", 1.0;
        /// Voltage errors below this make no correction.
        thc_threshold: f64 = "thc-threshold", 0.0;
        /// Enables the torch.
        torch_enable: bool = "torch-enable", false;
        /// Turns the torch off (motion.digital-out-03).
        torch_off: bool = "torch-off", false;
        /// Starts a torch pulse.
        torch_pulse_start: bool = "torch-pulse-start", false;
        /// Torch pulse time (s).
        torch_pulse_time: f64 = "torch-pulse-time", 0.0;
        /// Machine units per mm.
        units_per_mm: f64 = "units-per-mm", 0.0;
        /// Sample the target voltage at cut height.
        use_auto_volts: bool = "use-auto-volts", false;
        /// Enables void lock.
        voidlock_enable: bool = "voidlock-enable", false;
        /// Periods over the slope that lock.
        voidlock_on_cycles: i32 = "voidlock-on-cycles", 2;
        /// Periods under the slope that unlock.
        voidlock_off_cycles: i32 = "voidlock-off-cycles", 10;
        /// Void lock slope (volts per second).
        voidlock_slope: i32 = "voidlock-slope", 500;
        /// X offset for consumable change and cut recovery (counts).
        x_offset: i32 = "x-offset", 0;
        /// axis.x.eoffset.
        x_offset_current: f64 = "x-offset-current", 0.0;
        /// Feed rate of consumable change moves (units per minute).
        xy_feed_rate: f64 = "xy-feed-rate", 0.0;
        /// Y offset for consumable change and cut recovery (counts).
        y_offset: i32 = "y-offset", 0;
        /// axis.y.eoffset.
        y_offset_current: f64 = "y-offset-current", 0.0;
        /// axis.z.eoffset.
        z_offset_current: f64 = "z-offset-current", 0.0;
        /// Voltages within plus or minus this read zero.
        zero_window: f64 = "zero-window", 0.1;
        /// Low cut voltage: THC holds below it (0: off).
        low_cut_volts: i32 = "low-cut-volts", 0;
        /// Samples averaged for the target voltage.
        target_samples: i32 = "target-samples", 6;
    }
}

pin_set! {
    /// The output pins, as one call writes them.
    values Outputs,
    /// The handles of the output pins.
    handles OutPins, Out, pin_out_init, write,
    {
        /// motion.adaptive-feed.
        adaptive_feed: f64 = "adaptive-feed", 0.0;
        /// Arc OK.
        arc_ok_out: bool = "arc-ok-out", false;
        /// Arc voltage in volts.
        arc_voltage_out: f64 = "arc-voltage-out", 0.0;
        /// Consumables are being changed.
        consumable_changing: bool = "consumable-changing", false;
        /// Corner lock holds the THC.
        cornerlock_is_locked: bool = "cornerlock-is-locked", false;
        /// Length cut in this job.
        cut_length: f64 = "cut-length", 0.0;
        /// Recovering from a cut error.
        cut_recovering: bool = "cut-recovering", false;
        /// Cut time of this job (s).
        cut_time: f64 = "cut-time", 0.0;
        /// Stops a manual cut (halui.spindle.0.stop).
        cutting_stop: bool = "cutting-stop", false;
        /// motion.feed-hold.
        feed_hold: bool = "feed-hold", false;
        /// motion.jog-inhibit.
        jog_inhibit: bool = "jog-inhibit", false;
        /// Laser recovery status.
        laser_recovery_state: i32 = "laser-recovery-state", 0;
        /// THC moving down.
        led_down: bool = "led-down", false;
        /// THC moving up.
        led_up: bool = "led-up", false;
        /// axis.<x y z>.eoffset-scale.
        offset_scale: f64 = "offset-scale", 0.0;
        /// On only while probing with the ohmic probe.
        ohmic_enable: bool = "ohmic-enable", false;
        /// Debounced ohmic sense.
        ohmic_sense_out: bool = "ohmic-sense-out", false;
        /// Paused motion is active.
        paused_motion: bool = "paused-motion", false;
        /// Time paused in this job (s).
        paused_time: f64 = "paused-time", 0.0;
        /// Torch starts.
        pierce_count: i32 = "pierce-count", 0;
        /// The Z minimum limit was reached in a probe test.
        probe_test_error: bool = "probe-test-error", false;
        /// Probe time of this job (s).
        probe_time: f64 = "probe-time", 0.0;
        /// halui.program.pause.
        program_pause: bool = "program-pause", false;
        /// halui.program.resume.
        program_resume: bool = "program-resume", false;
        /// halui.program.run.
        program_run: bool = "program-run", false;
        /// halui.program.stop.
        program_stop: bool = "program-stop", false;
        /// Rapid time of this job (s).
        rapid_time: f64 = "rapid-time", 0.0;
        /// Run time of this job (s).
        run_time: f64 = "run-time", 0.0;
        /// The safe height was lowered to fit under the Z maximum.
        safe_height_is_limited: bool = "safe-height-is-limited", false;
        /// A float, ohmic or breakaway sensor is active.
        sensor_active: bool = "sensor-active", false;
        /// Arms the scribe.
        scribe_arm: bool = "scribe-arm", false;
        /// Scribe on.
        scribe_on: bool = "scribe-on", false;
        /// The state, numbered as LinuxCNC's.
        state_out: i32 = "state-out", 0;
        /// The stop type, numbered as LinuxCNC's.
        stop_type_out: i32 = "stop-type-out", 0;
        /// THC is correcting.
        thc_active: bool = "thc-active", false;
        /// THC is enabled.
        thc_enabled: bool = "thc-enabled", false;
        /// Torch on.
        torch_on: bool = "torch-on", false;
        /// Torch time of this job (s).
        torch_time: f64 = "torch-time", 0.0;
        /// Void lock holds the THC.
        voidlock_is_locked: bool = "voidlock-is-locked", false;
        /// axis.x.eoffset-counts.
        x_offset_counts: i32 = "x-offset-counts", 0;
        /// axis.<x y>.eoffset-enable.
        xy_offset_enable: bool = "xy-offset-enable", false;
        /// axis.y.eoffset-counts.
        y_offset_counts: i32 = "y-offset-counts", 0;
        /// Z height above the probed zero.
        z_height: f64 = "z-height", 0.0;
        /// axis.z.eoffset-counts.
        z_offset_counts: i32 = "z-offset-counts", 0;
        /// axis.z.eoffset-enable.
        z_offset_enable: bool = "z-offset-enable", false;
        /// Z distance from the last probed height.
        z_relative: f64 = "z-relative", 0.0;
        /// Current feed rate per minute.
        current_feed_rate: f64 = "current-feed-rate", 0.0;
        /// Requested feed rate per minute.
        requested_feed_rate: f64 = "requested-feed-rate", 0.0;
        /// THC target voltage.
        target_volts: f64 = "target-volts", 0.0;
    }
}
