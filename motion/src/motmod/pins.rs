//! The pins and params of `motmod` and their copy into and out of the
//! controller core ([`HalIo::read`], [`HalIo::write`]).

use hal_core::{Component, In, Io, Out, Param, Pin, Result, Ro};

use super::params::MotmodParams;
use crate::core::MotionCore;
use crate::kins::{AXIS_LETTERS, NUM_AXES};

pub(super) type FIn = Pin<f64, In>;
pub(super) type FOut = Pin<f64, Out>;
pub(super) type BIn = Pin<bool, In>;
pub(super) type BOut = Pin<bool, Out>;

pub(super) struct JointPins {
    pub(super) coarse_pos_cmd: FOut,
    pub(super) pos_cmd: FOut,
    pub(super) pos_fb: FOut,
    pub(super) motor_pos_cmd: FOut,
    pub(super) motor_pos_fb: FIn,
    pub(super) motor_offset: FOut,
    pub(super) pos_lim_sw: BIn,
    pub(super) neg_lim_sw: BIn,
    pub(super) amp_enable: BOut,
    pub(super) amp_fault: BIn,
    pub(super) jog_counts: Pin<i32, In>,
    pub(super) jog_enable: BIn,
    pub(super) jog_scale: FIn,
    pub(super) jog_vel_mode: BIn,
    pub(super) vel_cmd: FOut,
    pub(super) acc_cmd: FOut,
    pub(super) jerk_cmd: FOut,
    pub(super) backlash_corr: FOut,
    pub(super) backlash_filt: FOut,
    pub(super) backlash_vel: FOut,
    pub(super) f_error: FOut,
    pub(super) f_error_lim: FOut,
    pub(super) free_pos_cmd: FOut,
    pub(super) free_vel_lim: FOut,
    pub(super) free_tp_enable: BOut,
    pub(super) kb_jog_active: BOut,
    pub(super) wheel_jog_active: BOut,
    pub(super) in_position: BOut,
    pub(super) pos_hard_limit: BOut,
    pub(super) neg_hard_limit: BOut,
    pub(super) active: BOut,
    pub(super) error: BOut,
    pub(super) f_errored: BOut,
    pub(super) faulted: BOut,
    pub(super) jog_accel_fraction: FIn,
    pub(super) unlock: Option<(BOut, BIn)>,
    pub(super) home_sw_in: BIn,
    pub(super) homing: BOut,
    pub(super) homed: BOut,
    pub(super) home_state: Pin<i32, Out>,
    pub(super) index_enable: Pin<bool, Io>,
    pub(super) posthome_cmd: Option<FIn>,
}

impl JointPins {
    pub(super) fn new(c: &Component, n: usize, lockable: bool) -> Result<JointPins> {
        let p = |item: &str| format!("joint.{n}.{item}");
        Ok(JointPins {
            coarse_pos_cmd: c.pin(&p("coarse-pos-cmd"))?,
            pos_cmd: c.pin(&p("pos-cmd"))?,
            pos_fb: c.pin(&p("pos-fb"))?,
            motor_pos_cmd: c.pin(&p("motor-pos-cmd"))?,
            motor_pos_fb: c.pin(&p("motor-pos-fb"))?,
            motor_offset: c.pin(&p("motor-offset"))?,
            pos_lim_sw: c.pin(&p("pos-lim-sw-in"))?,
            neg_lim_sw: c.pin(&p("neg-lim-sw-in"))?,
            amp_enable: c.pin(&p("amp-enable-out"))?,
            amp_fault: c.pin(&p("amp-fault-in"))?,
            jog_counts: c.pin(&p("jog-counts"))?,
            jog_enable: c.pin(&p("jog-enable"))?,
            jog_scale: c.pin(&p("jog-scale"))?,
            jog_vel_mode: c.pin(&p("jog-vel-mode"))?,
            vel_cmd: c.pin(&p("vel-cmd"))?,
            acc_cmd: c.pin(&p("acc-cmd"))?,
            jerk_cmd: c.pin(&p("jerk-cmd"))?,
            backlash_corr: c.pin(&p("backlash-corr"))?,
            backlash_filt: c.pin(&p("backlash-filt"))?,
            backlash_vel: c.pin(&p("backlash-vel"))?,
            f_error: c.pin(&p("f-error"))?,
            f_error_lim: c.pin(&p("f-error-lim"))?,
            free_pos_cmd: c.pin(&p("free-pos-cmd"))?,
            free_vel_lim: c.pin(&p("free-vel-lim"))?,
            free_tp_enable: c.pin(&p("free-tp-enable"))?,
            kb_jog_active: c.pin(&p("kb-jog-active"))?,
            wheel_jog_active: c.pin(&p("wheel-jog-active"))?,
            in_position: c.pin(&p("in-position"))?,
            pos_hard_limit: c.pin(&p("pos-hard-limit"))?,
            neg_hard_limit: c.pin(&p("neg-hard-limit"))?,
            active: c.pin(&p("active"))?,
            error: c.pin(&p("error"))?,
            f_errored: c.pin(&p("f-errored"))?,
            faulted: c.pin(&p("faulted"))?,
            jog_accel_fraction: c.pin_init(&p("jog-accel-fraction"), 1.0)?,
            unlock: if lockable {
                Some((c.pin(&p("unlock"))?, c.pin(&p("is-unlocked"))?))
            } else {
                None
            },
            // The homing module's pins.
            home_sw_in: c.pin(&p("home-sw-in"))?,
            homing: c.pin(&p("homing"))?,
            homed: c.pin(&p("homed"))?,
            home_state: c.pin(&p("home-state"))?,
            index_enable: c.pin(&p("index-enable"))?,
            posthome_cmd: None,
        })
    }
}

pub(super) struct AxisPins {
    pub(super) pos_cmd: FOut,
    pub(super) teleop_vel_cmd: FOut,
    pub(super) teleop_pos_cmd: FOut,
    pub(super) teleop_vel_lim: FOut,
    pub(super) teleop_tp_enable: BOut,
    pub(super) eoffset_enable: BIn,
    pub(super) eoffset_clear: BIn,
    pub(super) eoffset_counts: Pin<i32, In>,
    pub(super) eoffset_scale: FIn,
    pub(super) eoffset: FOut,
    pub(super) eoffset_request: FOut,
    pub(super) jog_enable: BIn,
    pub(super) jog_scale: FIn,
    pub(super) jog_counts: Pin<i32, In>,
    pub(super) jog_vel_mode: BIn,
    pub(super) kb_jog_active: BOut,
    pub(super) wheel_jog_active: BOut,
    pub(super) jog_accel_fraction: FIn,
}

impl AxisPins {
    pub(super) fn new(c: &Component, l: char) -> Result<AxisPins> {
        let p = |item: &str| format!("axis.{l}.{item}");
        Ok(AxisPins {
            pos_cmd: c.pin(&p("pos-cmd"))?,
            teleop_vel_cmd: c.pin(&p("teleop-vel-cmd"))?,
            teleop_pos_cmd: c.pin(&p("teleop-pos-cmd"))?,
            teleop_vel_lim: c.pin(&p("teleop-vel-lim"))?,
            teleop_tp_enable: c.pin(&p("teleop-tp-enable"))?,
            eoffset_enable: c.pin(&p("eoffset-enable"))?,
            eoffset_clear: c.pin(&p("eoffset-clear"))?,
            eoffset_counts: c.pin(&p("eoffset-counts"))?,
            eoffset_scale: c.pin(&p("eoffset-scale"))?,
            eoffset: c.pin(&p("eoffset"))?,
            eoffset_request: c.pin(&p("eoffset-request"))?,
            jog_enable: c.pin(&p("jog-enable"))?,
            jog_scale: c.pin(&p("jog-scale"))?,
            jog_counts: c.pin(&p("jog-counts"))?,
            jog_vel_mode: c.pin(&p("jog-vel-mode"))?,
            kb_jog_active: c.pin(&p("kb-jog-active"))?,
            wheel_jog_active: c.pin(&p("wheel-jog-active"))?,
            jog_accel_fraction: c.pin_init(&p("jog-accel-fraction"), 1.0)?,
        })
    }
}

/// The spindle pins: the commanded state and speed out (LinuxCNC's
/// `output_to_hal`), the at-speed, inhibit, speed and fault inputs in.
/// The orient handshake (M19): angle, mode, orient and locked out,
/// is-oriented and orient-fault in. The index pins wait for spindle
/// synchronised moves.
pub(super) struct SpindlePins {
    pub(super) amp_fault: BIn,
    pub(super) inhibit: BIn,
    pub(super) at_speed: BIn,
    pub(super) speed_in: FIn,
    pub(super) on: BOut,
    pub(super) forward: BOut,
    pub(super) reverse: BOut,
    pub(super) brake: BOut,
    pub(super) speed_out: FOut,
    pub(super) speed_out_abs: FOut,
    pub(super) speed_out_rps: FOut,
    pub(super) speed_out_rps_abs: FOut,
    pub(super) speed_cmd_rps: FOut,
    pub(super) orient: (FOut, Pin<i32, Out>, BOut, BOut, BIn, Pin<i32, In>),
    /// `index-enable` and `revs`.
    pub(super) sync: (Pin<bool, Io>, FIn),
}

impl SpindlePins {
    pub(super) fn new(c: &Component, n: usize) -> Result<SpindlePins> {
        let p = |item: &str| format!("spindle.{n}.{item}");
        // Created in LinuxCNC's order.
        let sync = (c.pin(&p("index-enable"))?, c.pin(&p("revs"))?);
        let speed_in = c.pin(&p("speed-in"))?;
        // Default TRUE, so machines without the feedback do not wait.
        let at_speed = c.pin_init(&p("at-speed"), true)?;
        Ok(SpindlePins {
            sync,
            speed_in,
            at_speed,
            on: c.pin(&p("on"))?,
            forward: c.pin(&p("forward"))?,
            reverse: c.pin(&p("reverse"))?,
            brake: c.pin(&p("brake"))?,
            speed_out: c.pin(&p("speed-out"))?,
            speed_out_abs: c.pin(&p("speed-out-abs"))?,
            speed_out_rps: c.pin(&p("speed-out-rps"))?,
            speed_out_rps_abs: c.pin(&p("speed-out-rps-abs"))?,
            speed_cmd_rps: c.pin(&p("speed-cmd-rps"))?,
            inhibit: c.pin(&p("inhibit"))?,
            amp_fault: c.pin(&p("amp-fault-in"))?,
            orient: (
                c.pin(&p("orient-angle"))?,
                c.pin(&p("orient-mode"))?,
                c.pin(&p("orient"))?,
                c.pin(&p("locked"))?,
                c.pin(&p("is-oriented"))?,
                c.pin(&p("orient-fault"))?,
            ),
        })
    }

    /// Copies the inputs of spindle `n` into the core.
    fn read(&self, n: usize, inp: &mut crate::core::MotionInputs) {
        inp.spindle_amp_fault[n] = self.amp_fault.get();
        inp.spindle_at_speed[n] = self.at_speed.get();
        inp.spindle_inhibit[n] = self.inhibit.get();
        inp.spindle_speed_in[n] = self.speed_in.get();
        inp.spindle_revs[n] = self.sync.1.get();
        inp.spindle_index_enable[n] = self.sync.0.get();
        inp.spindle_is_oriented[n] = self.orient.4.get();
        inp.spindle_orient_fault[n] = self.orient.5.get();
    }

    /// Writes what the core commands spindle `n` to do.
    fn write(&self, n: usize, core: &MotionCore) {
        let o = core.spindle_output(n);
        self.on.set(o.on);
        self.forward.set(o.forward);
        self.reverse.set(o.reverse);
        self.brake.set(o.brake);
        self.speed_out.set(o.speed);
        self.speed_out_abs.set(o.speed.abs());
        self.speed_out_rps.set(o.speed / 60.0);
        self.speed_out_rps_abs.set((o.speed / 60.0).abs());
        self.speed_cmd_rps.set(o.cmd_rps);
        // Set only: the encoder clears it at the index.
        if core.spindle_index_arm(n) {
            self.sync.0.set(true);
        }
        let (angle, mode, orient, locked, _, _) = &self.orient;
        angle.set(o.orient_angle);
        mode.set(o.orient_mode);
        orient.set(o.orient);
        locked.set(o.locked);
    }
}

/// The machine-wide pins and params.
pub(super) struct MotionPins {
    pub(super) probe_input: BIn,
    pub(super) adaptive_feed: FIn,
    pub(super) feed_hold: BIn,
    pub(super) feed_inhibit: BIn,
    pub(super) homing_inhibit: BIn,
    pub(super) jog_inhibit: BIn,
    pub(super) jog_stop: BIn,
    pub(super) jog_stop_immediate: BIn,
    pub(super) enable: BIn,
    pub(super) switchkins_type: Option<FIn>,
    pub(super) misc_error: Vec<BIn>,
    pub(super) motion_enabled: BOut,
    pub(super) in_position: BOut,
    pub(super) coord_mode: BOut,
    pub(super) teleop_mode: BOut,
    pub(super) coord_error: BOut,
    pub(super) on_soft_limit: BOut,
    pub(super) current_vel: FOut,
    pub(super) jog_is_active: BOut,
    pub(super) is_all_homed: BOut,
    pub(super) last_period: Pin<u32, Out>,
    pub(super) debug_bit_0: Param<bool, Ro>,
    pub(super) debug_float_3: Param<f64, Ro>,
    pub(super) debug_s32_0: Param<i32, Ro>,
    /// The coordinated planner's outputs: `motion.program-line`,
    /// `motion.motion-type`, `motion.requested-vel`,
    /// `motion.distance-to-go`, `motion.feed-upm`.
    pub(super) program_line: Pin<i32, Out>,
    pub(super) motion_type: Pin<i32, Out>,
    pub(super) requested_vel: FOut,
    pub(super) distance_to_go: FOut,
    pub(super) feed_upm: FOut,
    /// `motion.digital-in-NN`/`digital-out-NN` (or named) pairs.
    pub(super) dio: Vec<(BIn, BOut)>,
    /// `motion.analog-in-NN`/`analog-out-NN` (or named) pairs.
    pub(super) aio: Vec<(FIn, FOut)>,
    /// `motion.eoffset-limited` and `motion.eoffset-active`.
    pub(super) eoffset: (BOut, BOut),
    /// `motion.tooloffset.L`: the tool offset SET_OFFSET gave.
    pub(super) tooloffset: Vec<FOut>,
    /// Pins and params later milestones drive; they hold their defaults.
    pub(super) _later: LaterPins,
}

/// Outputs of parts that come later (reverse run, the feed rate in fixed
/// units, which needs the machine's units, the interpreter's metadata)
/// and the stale LinuxCNC debug params: they hold their
/// defaults.
pub(super) struct LaterPins {
    pub(super) _tp_reverse: BOut,
    pub(super) _feed: [FOut; 4],
    pub(super) _interp: InterpPins,
    pub(super) _debug_bit_1: Param<bool, Ro>,
    pub(super) _debug_floats: [Param<f64, Ro>; 3],
    pub(super) _debug_s32_1: Param<i32, Ro>,
    pub(super) _traj: (Param<f64, Ro>, Param<f64, Ro>, Param<u32, Ro>),
    pub(super) _tc: Vec<Param<f64, Ro>>,
}

/// `motion.interp.*`: the interpreter's line number, motion type, feed
/// rate, arc and heading (s32, float, `iscircle`).
pub(super) type InterpPins = ([Pin<i32, Out>; 2], [FOut; 7], BOut);

/// The synchronised digital and analog I/O pins (`motion.digital-in-NN`
/// or `motion.din-NAME`, and so on).
#[allow(clippy::type_complexity)]
fn sync_io_pins(c: &Component, p: &MotmodParams) -> Result<(Vec<(BIn, BOut)>, Vec<(FIn, FOut)>)> {
    let (mut din, mut dout) = (0, 0);
    let mut dio = Vec::with_capacity(p.dio.count);
    for n in 0..p.dio.count {
        let i = io_pin_name("din", "digital-in", &p.dio.inputs, n, &mut din);
        let o = io_pin_name("dout", "digital-out", &p.dio.outputs, n, &mut dout);
        dio.push((c.pin(&i)?, c.pin(&o)?));
    }
    let (mut ain, mut aout) = (0, 0);
    let mut aio = Vec::with_capacity(p.aio.count);
    for n in 0..p.aio.count {
        let i = io_pin_name("ain", "analog-in", &p.aio.inputs, n, &mut ain);
        let o = io_pin_name("aout", "analog-out", &p.aio.outputs, n, &mut aout);
        aio.push((c.pin(&i)?, c.pin(&o)?));
    }
    Ok((dio, aio))
}

/// `motion.misc-error-NN` or `motion.err-NAME`.
fn misc_error_pins(c: &Component, p: &MotmodParams) -> Result<Vec<BIn>> {
    let mut misc_error = Vec::with_capacity(p.num_misc_error);
    for n in 0..p.num_misc_error {
        let name = match p.misc_error_names.get(n) {
            Some(name) => format!("motion.err-{name}"),
            None => format!("motion.misc-error-{n:02}"),
        };
        misc_error.push(c.pin(&name)?);
    }
    Ok(misc_error)
}

/// `motion.interp.*`.
fn interp_pins(c: &Component) -> Result<InterpPins> {
    let s32 = [
        c.pin("motion.interp.line-number")?,
        c.pin("motion.interp.motion-type")?,
    ];
    let float = [
        c.pin("motion.interp.feedrate")?,
        c.pin("motion.interp.arc-radius")?,
        c.pin("motion.interp.arc-center-x")?,
        c.pin("motion.interp.arc-center-y")?,
        c.pin("motion.interp.arc-center-z")?,
        c.pin("motion.interp.heading")?,
        c.pin("motion.interp.normal-heading")?,
    ];
    Ok((s32, float, c.pin("motion.interp.iscircle")?))
}

/// `motion.debug-*`: two bits, four floats, two s32.
#[allow(clippy::type_complexity)]
fn debug_params(
    c: &Component,
) -> Result<(
    [Param<bool, Ro>; 2],
    [Param<f64, Ro>; 4],
    [Param<i32, Ro>; 2],
)> {
    let bits = [
        c.param("motion.debug-bit-0", false)?,
        c.param("motion.debug-bit-1", false)?,
    ];
    let floats = [
        c.param("motion.debug-float-0", 0.0)?,
        c.param("motion.debug-float-1", 0.0)?,
        c.param("motion.debug-float-2", 0.0)?,
        c.param("motion.debug-float-3", 0.0)?,
    ];
    let s32 = [
        c.param("motion.debug-s32-0", 0)?,
        c.param("motion.debug-s32-1", 0)?,
    ];
    Ok((bits, floats, s32))
}

/// `traj.*` and `tc.N.*`: the planner's debug params.
#[allow(clippy::type_complexity)]
fn planner_params(
    c: &Component,
) -> Result<(
    (Param<f64, Ro>, Param<f64, Ro>, Param<u32, Ro>),
    Vec<Param<f64, Ro>>,
)> {
    let traj = (
        c.param("traj.pos_out", 0.0)?,
        c.param("traj.vel_out", 0.0)?,
        c.param("traj.active_tc", 0u32)?,
    );
    let mut tc = Vec::with_capacity(12);
    for n in 0..4 {
        tc.push(c.param(&format!("tc.{n}.pos"), 0.0)?);
        tc.push(c.param(&format!("tc.{n}.vel"), 0.0)?);
        tc.push(c.param(&format!("tc.{n}.acc"), 0.0)?);
    }
    Ok((traj, tc))
}

fn io_pin_name(
    prefix_named: &str,
    prefix_num: &str,
    names: &[String],
    n: usize,
    numbered: &mut usize,
) -> String {
    match names.get(n) {
        Some(name) => format!("motion.{prefix_named}-{name}"),
        None => {
            let s = format!("motion.{prefix_num}-{:02}", *numbered);
            *numbered += 1;
            s
        }
    }
}

impl MotionPins {
    pub(super) fn new(c: &Component, p: &MotmodParams, switchable: bool) -> Result<MotionPins> {
        let probe_input = c.pin("motion.probe-input")?;
        let adaptive_feed = c.pin_init("motion.adaptive-feed", 1.0)?;
        let feed_hold = c.pin("motion.feed-hold")?;
        let feed_inhibit = c.pin("motion.feed-inhibit")?;
        let homing_inhibit = c.pin("motion.homing-inhibit")?;
        let jog_inhibit = c.pin("motion.jog-inhibit")?;
        let jog_stop = c.pin("motion.jog-stop")?;
        let jog_stop_immediate = c.pin("motion.jog-stop-immediate")?;
        let tp_reverse = c.pin("motion.tp-reverse")?;
        // Default TRUE, so simple machines can leave it unconnected.
        let enable = c.pin_init("motion.enable", true)?;
        let is_all_homed = c.pin("motion.is-all-homed")?;
        let feed_upm = c.pin("motion.feed-upm")?;
        let feed = [
            c.pin("motion.feed-inches-per-minute")?,
            c.pin("motion.feed-inches-per-second")?,
            c.pin("motion.feed-mm-per-minute")?,
            c.pin("motion.feed-mm-per-second")?,
        ];
        let (dio, aio) = sync_io_pins(c, p)?;
        let misc_error = misc_error_pins(c, p)?;
        let motion_enabled = c.pin("motion.motion-enabled")?;
        let in_position = c.pin("motion.in-position")?;
        let motion_type = c.pin("motion.motion-type")?;
        let coord_mode = c.pin("motion.coord-mode")?;
        let teleop_mode = c.pin("motion.teleop-mode")?;
        let coord_error = c.pin("motion.coord-error")?;
        let on_soft_limit = c.pin("motion.on-soft-limit")?;
        let current_vel = c.pin("motion.current-vel")?;
        let requested_vel = c.pin("motion.requested-vel")?;
        let distance_to_go = c.pin("motion.distance-to-go")?;
        let program_line = c.pin("motion.program-line")?;
        let jog_is_active = c.pin("motion.jog-is-active")?;
        let interp = interp_pins(c)?;
        let ([debug_bit_0, debug_bit_1], debug_floats, [debug_s32_0, debug_s32_1]) =
            debug_params(c)?;
        let [debug_float_0, debug_float_1, debug_float_2, debug_float_3] = debug_floats;
        let (traj, tc) = planner_params(c)?;
        let last_period = c.pin("motion.servo.last-period")?;
        let mut tooloffset = Vec::with_capacity(NUM_AXES);
        for l in AXIS_LETTERS {
            tooloffset.push(c.pin(&format!("motion.tooloffset.{l}"))?);
        }
        let switchkins_type = if switchable {
            Some(c.pin("motion.switchkins-type")?)
        } else {
            None
        };
        Ok(MotionPins {
            probe_input,
            adaptive_feed,
            feed_hold,
            feed_inhibit,
            homing_inhibit,
            jog_inhibit,
            jog_stop,
            jog_stop_immediate,
            enable,
            switchkins_type,
            misc_error,
            motion_enabled,
            in_position,
            coord_mode,
            teleop_mode,
            coord_error,
            on_soft_limit,
            current_vel,
            jog_is_active,
            is_all_homed,
            last_period,
            debug_bit_0,
            debug_float_3,
            debug_s32_0,
            program_line,
            motion_type,
            requested_vel,
            distance_to_go,
            feed_upm,
            dio,
            aio,
            eoffset: (
                c.pin("motion.eoffset-limited")?,
                c.pin("motion.eoffset-active")?,
            ),
            tooloffset,
            _later: LaterPins {
                _tp_reverse: tp_reverse,
                _feed: feed,
                _interp: interp,
                _debug_bit_1: debug_bit_1,
                _debug_floats: [debug_float_0, debug_float_1, debug_float_2],
                _debug_s32_1: debug_s32_1,
                _traj: traj,
                _tc: tc,
            },
        })
    }
}

/// Every pin the controller function reads or writes.
pub(super) struct HalIo {
    pub(super) motion: MotionPins,
    pub(super) spindles: Vec<SpindlePins>,
    pub(super) joints: Vec<JointPins>,
    pub(super) axes: Vec<AxisPins>,
}

impl HalIo {
    /// Creates every pin and param of `motmod`: the machine's, then each
    /// spindle's, joint's and axis's.
    pub(super) fn new(c: &Component, p: &MotmodParams, switchable: bool) -> Result<HalIo> {
        let motion = MotionPins::new(c, p, switchable)?;
        let mut spindles = Vec::with_capacity(p.num_spindles);
        for n in 0..p.num_spindles {
            spindles.push(SpindlePins::new(c, n)?);
        }
        let mut joints = Vec::with_capacity(p.num_joints);
        for n in 0..p.num_joints {
            let lockable = n < 32 && p.unlock_joints_mask & (1 << n) != 0;
            joints.push(JointPins::new(c, n, lockable)?);
        }
        let first_extra = p.num_joints - p.num_extrajoints;
        for (n, jp) in joints.iter_mut().enumerate().skip(first_extra) {
            jp.posthome_cmd = Some(c.pin(&format!("joint.{n}.posthome-cmd"))?);
        }
        let mut axes = Vec::with_capacity(NUM_AXES);
        for l in AXIS_LETTERS {
            axes.push(AxisPins::new(c, l)?);
        }
        Ok(HalIo {
            motion,
            spindles,
            joints,
            axes,
        })
    }

    /// Copies the HAL inputs into the core.
    pub(super) fn read(&self, core: &mut MotionCore) {
        let m = &self.motion;
        let inp = &mut core.inputs;
        inp.enable = m.enable.get();
        inp.probe_input = m.probe_input.get();
        inp.adaptive_feed = m.adaptive_feed.get();
        inp.feed_hold = m.feed_hold.get();
        inp.feed_inhibit = m.feed_inhibit.get();
        inp.homing_inhibit = m.homing_inhibit.get();
        inp.jog_inhibit = m.jog_inhibit.get();
        inp.jog_stop = m.jog_stop.get();
        inp.jog_stop_immediate = m.jog_stop_immediate.get();
        if let Some(p) = &m.switchkins_type {
            inp.switchkins_type = p.get();
        }
        for (slot, pin) in inp.misc_error.iter_mut().zip(&m.misc_error) {
            *slot = pin.get();
        }
        for (n, s) in self.spindles.iter().enumerate() {
            s.read(n, inp);
        }
        for (slot, (din, _)) in inp.din.iter_mut().zip(&m.dio) {
            *slot = din.get();
        }
        for (slot, (ain, _)) in inp.ain.iter_mut().zip(&m.aio) {
            *slot = ain.get();
        }
        for (ji, jp) in core.joint_inputs.iter_mut().zip(&self.joints) {
            ji.motor_pos_fb = jp.motor_pos_fb.get();
            ji.pos_lim_sw = jp.pos_lim_sw.get();
            ji.neg_lim_sw = jp.neg_lim_sw.get();
            ji.amp_fault = jp.amp_fault.get();
            ji.home_sw = jp.home_sw_in.get();
            ji.index_enable = jp.index_enable.get();
            ji.jog_counts = jp.jog_counts.get();
            ji.jog_enable = jp.jog_enable.get();
            ji.jog_scale = jp.jog_scale.get();
            ji.jog_vel_mode = jp.jog_vel_mode.get();
            ji.jog_accel_fraction = jp.jog_accel_fraction.get();
            if let Some(p) = &jp.posthome_cmd {
                ji.posthome_cmd = p.get();
            }
            if let Some((_, is_unlocked)) = &jp.unlock {
                ji.is_unlocked = is_unlocked.get();
            }
        }
        for (ai, ap) in core.axis_inputs.iter_mut().zip(&self.axes) {
            ai.jog_counts = ap.jog_counts.get();
            ai.jog_enable = ap.jog_enable.get();
            ai.jog_scale = ap.jog_scale.get();
            ai.jog_vel_mode = ap.jog_vel_mode.get();
            ai.jog_accel_fraction = ap.jog_accel_fraction.get();
            ai.eoffset.enable = ap.eoffset_enable.get();
            ai.eoffset.clear = ap.eoffset_clear.get();
            ai.eoffset.counts = ap.eoffset_counts.get();
            ai.eoffset.scale = ap.eoffset_scale.get();
        }
    }

    /// Writes the core's results to the HAL outputs.
    pub(super) fn write(&self, core: &MotionCore) {
        let m = &self.motion;
        m.motion_enabled.set(core.is_enabled());
        m.in_position.set(core.in_position());
        // LinuxCNC's COORD and TELEOP flags: kept while disabled.
        m.coord_mode.set(core.coord_mode());
        m.teleop_mode.set(core.teleop_mode());
        m.coord_error.set(core.error());
        m.on_soft_limit.set(core.on_soft_limit());
        m.current_vel.set(core.current_vel());
        m.jog_is_active.set(core.jog_is_active());
        m.is_all_homed.set(core.is_all_homed());
        m.debug_bit_0
            .set(core.num_joints() > 1 && core.joint_ref(1).free_tp.active);
        m.debug_float_3.set(match self.spindles.first() {
            Some(s) if s.inhibit.get() => 0.0,
            Some(_) => 1.0,
            None => 0.0,
        });
        m.debug_s32_0.set(core.override_limit_mask() as i32);
        for (n, s) in self.spindles.iter().enumerate() {
            s.write(n, core);
        }
        let io = core.io_outputs();
        for ((_, dout), v) in m.dio.iter().zip(io.dout) {
            dout.set(v);
        }
        for ((_, aout), v) in m.aio.iter().zip(io.aout) {
            aout.set(v);
        }
        let tp = core.planner();
        let coord = core.state() == crate::core::MotionState::Coord;
        m.program_line.set(if coord { tp.exec_id } else { 0 });
        m.motion_type.set(if coord { tp.motion_type() } else { 0 });
        m.requested_vel.set(tp.requested_vel);
        m.distance_to_go.set(tp.distance_to_go);
        m.feed_upm.set(tp.requested_vel * 60.0);
        m.eoffset.0.set(core.eoffset_limited());
        m.eoffset.1.set(core.eoffset_active());
        for (pin, v) in m.tooloffset.iter().zip(core.tool_offset().0) {
            pin.set(v);
        }
        for (j, jp) in self.joints.iter().enumerate() {
            let jt = core.joint_ref(j);
            jp.motor_offset.set(jt.motor_offset);
            jp.motor_pos_cmd.set(jt.motor_pos_cmd);
            jp.pos_cmd.set(jt.pos_cmd);
            jp.pos_fb.set(jt.pos_fb);
            jp.amp_enable.set(jt.enabled);
            jp.coarse_pos_cmd.set(jt.coarse_pos);
            jp.vel_cmd.set(jt.vel_cmd);
            jp.acc_cmd.set(jt.acc_cmd);
            jp.jerk_cmd.set(jt.jerk_cmd);
            jp.backlash_corr.set(jt.backlash_corr);
            jp.backlash_filt.set(jt.backlash_filt);
            jp.backlash_vel.set(jt.backlash_vel);
            jp.f_error.set(jt.ferror);
            jp.f_error_lim.set(jt.ferror_limit);
            jp.free_pos_cmd.set(jt.free_tp.pos_cmd);
            jp.free_vel_lim.set(jt.free_tp.max_vel);
            jp.free_tp_enable.set(jt.free_tp.enable);
            jp.kb_jog_active.set(jt.kb_jog_active);
            jp.wheel_jog_active.set(jt.wheel_jog_active);
            jp.active.set(jt.active);
            jp.in_position.set(jt.inpos);
            jp.error.set(jt.error);
            jp.pos_hard_limit.set(jt.phl);
            jp.neg_hard_limit.set(jt.nhl);
            jp.f_errored.set(jt.ferror_flag);
            jp.faulted.set(jt.fault);
            jp.homing.set(jt.homing);
            jp.homed.set(jt.homed);
            jp.home_state.set(core.home_state(j).number());
            // Only the edges: the encoder drives the same signal.
            if let Some(v) = core.index_enable_drive(j) {
                jp.index_enable.set(v);
            }
            if let Some((unlock, _)) = &jp.unlock {
                unlock.set(core.unlock_output(j));
            }
        }
        let (pose, _) = core.carte_pos_cmd();
        for (a, ap) in self.axes.iter().enumerate() {
            let ax = core.axis_ref(a);
            // As LinuxCNC: the position without the external offset,
            // which has pins of its own.
            let o = ax.eoffset.applied();
            ap.pos_cmd
                .set(if o != 0.0 { pose.0[a] - o } else { pose.0[a] });
            ap.eoffset.set(o);
            ap.eoffset_request.set(ax.eoffset.request());
            ap.teleop_pos_cmd.set(ax.teleop_tp.pos_cmd);
            ap.teleop_vel_cmd.set(ax.teleop_tp.curr_vel);
            ap.teleop_vel_lim.set(ax.teleop_tp.max_vel);
            ap.teleop_tp_enable.set(ax.teleop_tp.enable);
            ap.kb_jog_active.set(ax.kb_jog_active);
            ap.wheel_jog_active.set(ax.wheel_jog_active);
        }
    }
}
