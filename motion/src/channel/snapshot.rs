//! The status snapshot: [`fill_status`] writes it every servo cycle from
//! the controller, [`decode_status`] checks and reads it in a client.

use super::{
    AXES_START, AXIS_WORDS, EOFFSET_START, FAULT_START, IO_START, JOINT_WORDS, PATH_START,
    SPINDLES_START, SPINDLE_WORDS, STATUS_HEADER, STATUS_VERSION, STATUS_WORDS, TRAJ_START,
};
use crate::command::WireError;
use crate::core::{MotionCore, MotionState, OrientState};
use crate::fault::{Fault, FAULT_WORDS};
use crate::homing::HomeState;
use crate::kins::NUM_AXES;
use crate::sizes::{MAX_IO, MAX_JOINTS, MAX_SPINDLES};
use crate::status::{
    AxisState, EoffsetState, IoState, JointState, LastCommand, MotionStatus, SpindleState,
    TrajState,
};
use crate::tp::PlannerType;

/// Status flag bits of the header word 3.
pub(super) mod flag {
    pub const ENABLED: u64 = 1;
    pub const IN_POSITION: u64 = 2;
    pub const ERROR: u64 = 4;
    pub const ON_SOFT_LIMIT: u64 = 8;
    pub const JOG_ACTIVE: u64 = 16;
    pub const HOMING_ACTIVE: u64 = 32;
    pub const ALL_HOMED: u64 = 64;
    pub const ENABLE_INPUT: u64 = 128;
    /// The TELEOP flag (kept while disabled: the mode entered on enable).
    pub const TELEOP_MODE: u64 = 256;
    /// The COORD flag (likewise).
    pub const COORD_MODE: u64 = 512;
}

/// Status flag bits of an axis's first word.
pub(super) mod aflag {
    pub const IN_KINEMATICS: u64 = 1;
    pub const TP_ENABLE: u64 = 2;
    pub const KB_JOG: u64 = 4;
    pub const WHEEL_JOG: u64 = 8;
    pub const MOVING: u64 = 16;
}

/// Status flag bits of a joint's first word.
pub(super) mod jflag {
    pub const ACTIVE: u64 = 1;
    pub const AMP_ENABLED: u64 = 2;
    pub const IN_POSITION: u64 = 4;
    pub const ERROR: u64 = 8;
    pub const POS_HARD_LIMIT: u64 = 16;
    pub const NEG_HARD_LIMIT: u64 = 32;
    pub const FOLLOWING_ERROR: u64 = 64;
    pub const FAULTED: u64 = 128;
    pub const HOMED: u64 = 256;
    pub const HOMING: u64 = 512;
    pub const JOGGING: u64 = 1024;
    /// Bits 16..24 hold the homing state number.
    pub const HOME_STATE_SHIFT: u32 = 16;
}

/// Flag bits of the coordinated-planner block's first word.
pub(super) mod tflag {
    pub const PAUSED: u64 = 1;
    pub const STEPPING: u64 = 2;
    pub const ABORTING: u64 = 4;
    pub const QUEUE_FULL: u64 = 8;
    pub const SCURVE: u64 = 16;
    pub const PROBING: u64 = 32;
    pub const PROBE_TRIPPED: u64 = 64;
    pub const PROBE_INPUT: u64 = 128;
    pub const WAITING_FOR_ATSPEED: u64 = 256;
}

/// Status flag bits of a spindle's first word.
pub(super) mod sflag {
    pub const ON: u64 = 1;
    pub const BRAKE: u64 = 2;
    pub const AT_SPEED: u64 = 4;
    /// An M19 orientation runs.
    pub const ORIENTING: u64 = 8;
    /// The M19 orientation is complete (spindle locked).
    pub const ORIENTED: u64 = 16;
    /// The M19 orientation failed; the fault code is in bits 32-63.
    pub const ORIENT_FAULTED: u64 = 32;
}

/// Fills `out` (at least [`STATUS_WORDS`] long) with the snapshot of
/// `core`. Realtime-safe: no allocation.
pub fn fill_status(core: &MotionCore, last: LastCommand, served: u64, out: &mut [u64]) {
    out.iter_mut().for_each(|w| *w = 0);
    let n = core.num_joints().min(MAX_JOINTS);
    out[0] = STATUS_VERSION;
    out[1] = n as u64;
    out[2] = match core.state() {
        MotionState::Disabled => 0,
        MotionState::Free => 1,
        MotionState::Teleop => 2,
        MotionState::Coord => 3,
    };
    let bit = |b: bool, f: u64| if b { f } else { 0 };
    out[3] = bit(core.is_enabled(), flag::ENABLED)
        | bit(core.in_position(), flag::IN_POSITION)
        | bit(core.error(), flag::ERROR)
        | bit(core.on_soft_limit(), flag::ON_SOFT_LIMIT)
        | bit(core.jog_is_active(), flag::JOG_ACTIVE)
        | bit(core.homing_active(), flag::HOMING_ACTIVE)
        | bit(core.is_all_homed(), flag::ALL_HOMED)
        | bit(core.inputs.enable, flag::ENABLE_INPUT)
        | bit(core.teleop_mode(), flag::TELEOP_MODE)
        | bit(core.coord_mode(), flag::COORD_MODE);
    out[4] = core.heartbeat();
    out[5] = last.serial;
    out[6] = last.code;
    out[7] = core.scale().to_bits();
    out[8] = core.override_limit_mask() as u64;
    out[9] = served;
    let (reported, last_event) = core.events().reported();
    out[10] = reported;
    out[11] = last_event;
    out[FAULT_START..][..FAULT_WORDS].copy_from_slice(&core.events().fault_words());
    // Read through references: this runs every servo cycle.
    for j in 0..n {
        let s = core.joint_ref(j);
        let w = &mut out[STATUS_HEADER + j * JOINT_WORDS..][..JOINT_WORDS];
        w[0] = bit(s.active, jflag::ACTIVE)
            | bit(s.enabled, jflag::AMP_ENABLED)
            | bit(s.inpos, jflag::IN_POSITION)
            | bit(s.error, jflag::ERROR)
            | bit(s.phl, jflag::POS_HARD_LIMIT)
            | bit(s.nhl, jflag::NEG_HARD_LIMIT)
            | bit(s.ferror_flag, jflag::FOLLOWING_ERROR)
            | bit(s.fault, jflag::FAULTED)
            | bit(s.homed, jflag::HOMED)
            | bit(core.joint_homing(j), jflag::HOMING)
            | bit(s.kb_jog_active, jflag::JOGGING)
            | ((core.home_state(j).number() as u64 & 0xff) << jflag::HOME_STATE_SHIFT);
        w[1] = s.pos_cmd.to_bits();
        w[2] = s.pos_fb.to_bits();
        w[3] = s.vel_cmd.to_bits();
        w[4] = s.ferror.to_bits();
        w[5] = s.ferror_limit.to_bits();
        w[6] = s.cfg.min_pos_limit.to_bits();
        w[7] = s.cfg.max_pos_limit.to_bits();
    }
    let (pose, _) = core.carte_pos_cmd();
    for (a, &p) in pose.0.iter().enumerate() {
        let s = core.axis_ref(a);
        let tp = &s.teleop_tp;
        let w = &mut out[AXES_START + a * AXIS_WORDS..][..AXIS_WORDS];
        w[0] = bit(core.axis_in_kinematics(a), aflag::IN_KINEMATICS)
            | bit(tp.enable, aflag::TP_ENABLE)
            | bit(s.kb_jog_active, aflag::KB_JOG)
            | bit(s.wheel_jog_active, aflag::WHEEL_JOG)
            | bit(tp.active, aflag::MOVING);
        w[1] = p.to_bits();
        w[2] = tp.curr_vel.to_bits();
        w[3] = s.cfg.min_pos_limit.to_bits();
        w[4] = s.cfg.max_pos_limit.to_bits();
    }
    let tp = core.planner();
    let (feed, rapid, _) = core.overrides();
    let (tripped, probed) = core.probe_result();
    let w = &mut out[TRAJ_START..][..super::TRAJ_WORDS];
    w[0] = bit(tp.paused, tflag::PAUSED)
        | bit(tp.stepping, tflag::STEPPING)
        | bit(tp.aborting, tflag::ABORTING)
        | bit(tp.queue_full, tflag::QUEUE_FULL)
        | bit(tp.planner == PlannerType::SCurve, tflag::SCURVE)
        | bit(core.probing(), tflag::PROBING)
        | bit(tripped, tflag::PROBE_TRIPPED)
        | bit(core.inputs.probe_input, tflag::PROBE_INPUT)
        | bit(tp.waiting_for_atspeed, tflag::WAITING_FOR_ATSPEED);
    w[1] = tp.exec_id as i64 as u64;
    w[2] = tp.depth as u64;
    w[3] = tp.current_vel.to_bits();
    w[4] = tp.requested_vel.to_bits();
    w[5] = tp.distance_to_go.to_bits();
    w[6] = feed.to_bits();
    w[7] = rapid.to_bits();
    w[8] = tp.motion_type() as i64 as u64;
    w[9] = tp.net_scale.to_bits();
    for (o, v) in w[10..19].iter_mut().zip(probed.0) {
        *o = v.to_bits();
    }
    let (fb, _) = core.carte_pos_fb();
    for (o, v) in w[19..28].iter_mut().zip(fb.0) {
        *o = v.to_bits();
    }
    for (o, v) in w[28..37].iter_mut().zip(core.planner_goal().0) {
        *o = v.to_bits();
    }
    fill_spindles(core, &mut out[SPINDLES_START..]);
    fill_io(core, &mut out[IO_START..]);
    fill_eoffsets(core, &mut out[EOFFSET_START..]);
    fill_path(core, &tp, &mut out[PATH_START..]);
}

/// Bit 0 of the path block's flags word: the controller reports it.
const PATH_REPORTED: u64 = 1;

/// The path block: override enables, kinematics type, distance to go.
fn fill_path(core: &MotionCore, tp: &crate::tp::PlannerStatus, out: &mut [u64]) {
    out[0] = PATH_REPORTED | u64::from(core.enables()) << 8 | (core.kins_type() as u64) << 16;
    for (o, v) in out[1..=NUM_AXES].iter_mut().zip(tp.dtg.0) {
        *o = v.to_bits();
    }
}

/// Decodes the path block into `traj` (left as not reported when the
/// flags word is zero).
fn decode_path(w: &[u64], traj: &mut TrajState) {
    if w[0] & PATH_REPORTED == 0 {
        return;
    }
    traj.enables = Some((w[0] >> 8) as u8);
    traj.kinematics_type = Some(i32::from((w[0] >> 16) as u8));
    for (d, v) in traj.dtg.iter_mut().zip(&w[1..=NUM_AXES]) {
        *d = f64::from_bits(*v);
    }
}

/// Flags word of the external-offset block.
mod eflag {
    pub const ACTIVE: u64 = 1;
    pub const LIMITED: u64 = 2;
}

/// The external-offset block: flags, applied offsets, requests.
fn fill_eoffsets(core: &MotionCore, out: &mut [u64]) {
    out[0] = if core.eoffset_active() {
        eflag::ACTIVE
    } else {
        0
    } | if core.eoffset_limited() {
        eflag::LIMITED
    } else {
        0
    };
    for a in 0..NUM_AXES {
        let e = &core.axis_ref(a).eoffset;
        out[1 + a] = e.applied().to_bits();
        out[1 + NUM_AXES + a] = e.request().to_bits();
    }
}

/// Decodes the external-offset block (all zero from a controller that
/// does not report it).
fn decode_eoffsets(w: &[u64]) -> EoffsetState {
    let mut applied = [0.0; NUM_AXES];
    let mut requested = [0.0; NUM_AXES];
    for a in 0..NUM_AXES {
        applied[a] = f64::from_bits(w[1 + a]);
        requested[a] = f64::from_bits(w[1 + NUM_AXES + a]);
    }
    EoffsetState {
        active: w[0] & eflag::ACTIVE != 0,
        limited: w[0] & eflag::LIMITED != 0,
        applied,
        requested,
    }
}

/// The I/O block: counts, digital bits, analog values.
fn fill_io(core: &MotionCore, out: &mut [u64]) {
    let cfg = core.config();
    out[0] = cfg.num_dio as u64 | (cfg.num_aio as u64) << 8;
    let io = core.io_outputs();
    let mut din = 0u64;
    let mut dout = 0u64;
    for i in 0..MAX_IO {
        if core.inputs.din[i] {
            din |= 1 << i;
        }
        if io.dout[i] {
            dout |= 1 << i;
        }
        out[3 + i] = core.inputs.ain[i].to_bits();
        out[3 + MAX_IO + i] = io.aout[i].to_bits();
    }
    out[1] = din;
    out[2] = dout;
}

/// Decodes the I/O block.
fn decode_io(w: &[u64]) -> Result<IoState, WireError> {
    let (num_dio, num_aio) = ((w[0] & 0xff) as usize, ((w[0] >> 8) & 0xff) as usize);
    if num_dio > MAX_IO || num_aio > MAX_IO || w[0] >> 16 != 0 {
        return Err(WireError::BadStatus);
    }
    let bit = |word: u64, i: usize| word & (1 << i) != 0;
    Ok(IoState {
        din: (0..num_dio).map(|i| bit(w[1], i)).collect(),
        dout: (0..num_dio).map(|i| bit(w[2], i)).collect(),
        ain: (0..num_aio).map(|i| f64::from_bits(w[3 + i])).collect(),
        aout: (0..num_aio)
            .map(|i| f64::from_bits(w[3 + MAX_IO + i]))
            .collect(),
    })
}

/// The spindle block: the count, then one block per spindle.
fn fill_spindles(core: &MotionCore, out: &mut [u64]) {
    let n = core.config().num_spindles.min(MAX_SPINDLES);
    out[0] = n as u64;
    let bit = |b: bool, f: u64| if b { f } else { 0 };
    for i in 0..n {
        let s = core.spindle(i);
        let o = core.spindle_output(i);
        let w = &mut out[1 + i * SPINDLE_WORDS..][..SPINDLE_WORDS];
        w[0] = bit(s.on, sflag::ON)
            | bit(s.brake, sflag::BRAKE)
            | bit(core.inputs.spindle_at_speed[i], sflag::AT_SPEED)
            | match s.orient {
                OrientState::None => 0,
                OrientState::InProgress => sflag::ORIENTING,
                OrientState::Complete => sflag::ORIENTED,
                OrientState::Faulted => sflag::ORIENT_FAULTED,
            }
            | (u64::from(s.orient_fault as u32) << 32);
        w[1] = s.speed.to_bits();
        w[2] = s.scale.to_bits();
        w[3] = o.speed.to_bits();
        w[4] = core.inputs.spindle_speed_in[i].to_bits();
    }
}

/// Decodes the spindle block.
fn decode_spindles(w: &[u64]) -> Result<Vec<SpindleState>, WireError> {
    let n = usize::try_from(w[0]).map_err(|_| WireError::BadStatus)?;
    if n > MAX_SPINDLES {
        return Err(WireError::BadStatus);
    }
    Ok((0..n)
        .map(|i| {
            let b = 1 + i * SPINDLE_WORDS;
            let f = |k: usize| f64::from_bits(w[b + k]);
            SpindleState {
                on: w[b] & sflag::ON != 0,
                brake: w[b] & sflag::BRAKE != 0,
                at_speed: w[b] & sflag::AT_SPEED != 0,
                speed: f(1),
                scale: f(2),
                speed_out: f(3),
                speed_in: f(4),
                orient: if w[b] & sflag::ORIENT_FAULTED != 0 {
                    OrientState::Faulted
                } else if w[b] & sflag::ORIENTED != 0 {
                    OrientState::Complete
                } else if w[b] & sflag::ORIENTING != 0 {
                    OrientState::InProgress
                } else {
                    OrientState::None
                },
                orient_fault: (w[b] >> 32) as u32 as i32,
            }
        })
        .collect())
}

/// Decodes a snapshot, validating its header.
pub fn decode_status(w: &[u64]) -> Result<MotionStatus, WireError> {
    if w.len() < STATUS_WORDS {
        return Err(WireError::BadStatus);
    }
    if w[0] != STATUS_VERSION {
        return Err(WireError::BadVersion { found: w[0] });
    }
    let n = usize::try_from(w[1]).map_err(|_| WireError::BadStatus)?;
    if n > MAX_JOINTS {
        return Err(WireError::BadStatus);
    }
    let mode = match w[2] {
        0 => "DISABLED",
        1 => "FREE",
        2 => "TELEOP",
        3 => "COORD",
        _ => return Err(WireError::BadStatus),
    };
    let f = |i: usize| f64::from_bits(w[i]);
    let h = w[3];
    let joints = (0..n)
        .map(|j| {
            let b = STATUS_HEADER + j * JOINT_WORDS;
            let fl = w[b];
            let on = |m: u64| fl & m != 0;
            Ok(JointState {
                active: on(jflag::ACTIVE),
                amp_enabled: on(jflag::AMP_ENABLED),
                in_position: on(jflag::IN_POSITION),
                error: on(jflag::ERROR),
                pos_hard_limit: on(jflag::POS_HARD_LIMIT),
                neg_hard_limit: on(jflag::NEG_HARD_LIMIT),
                following_error: on(jflag::FOLLOWING_ERROR),
                faulted: on(jflag::FAULTED),
                homed: on(jflag::HOMED),
                homing: on(jflag::HOMING),
                jogging: on(jflag::JOGGING),
                home_state: HomeState::from_number(((fl >> jflag::HOME_STATE_SHIFT) & 0xff) as i32)
                    .ok_or(WireError::BadStatus)?,
                pos_cmd: f(b + 1),
                pos_fb: f(b + 2),
                vel_cmd: f(b + 3),
                ferror: f(b + 4),
                ferror_limit: f(b + 5),
                min_limit: f(b + 6),
                max_limit: f(b + 7),
            })
        })
        .collect::<Result<Vec<_>, WireError>>()?;
    let axes = (0..NUM_AXES)
        .map(|a| {
            let b = AXES_START + a * AXIS_WORDS;
            let on = |m: u64| w[b] & m != 0;
            AxisState {
                in_kinematics: on(aflag::IN_KINEMATICS),
                tp_enable: on(aflag::TP_ENABLE),
                kb_jogging: on(aflag::KB_JOG),
                wheel_jogging: on(aflag::WHEEL_JOG),
                moving: on(aflag::MOVING),
                pos_cmd: f(b + 1),
                vel_cmd: f(b + 2),
                min_limit: f(b + 3),
                max_limit: f(b + 4),
            }
        })
        .collect();
    Ok(MotionStatus {
        enabled: h & flag::ENABLED != 0,
        mode,
        teleop_mode: h & flag::TELEOP_MODE != 0,
        coord_mode: h & flag::COORD_MODE != 0,
        in_position: h & flag::IN_POSITION != 0,
        error: h & flag::ERROR != 0,
        on_soft_limit: h & flag::ON_SOFT_LIMIT != 0,
        jog_active: h & flag::JOG_ACTIVE != 0,
        homing_active: h & flag::HOMING_ACTIVE != 0,
        all_homed: h & flag::ALL_HOMED != 0,
        enable_input: h & flag::ENABLE_INPUT != 0,
        heartbeat: w[4],
        last: LastCommand {
            serial: w[5],
            code: w[6],
        },
        scale: f(7),
        override_mask: w[8],
        served: w[9],
        events_reported: w[10],
        last_event: crate::events::Event::from_word(w[11]),
        faults_reported: w[FAULT_START],
        last_fault: w[FAULT_START..][..FAULT_WORDS]
            .try_into()
            .ok()
            .and_then(|f| Fault::from_words(&f)),
        joints,
        axes,
        traj: {
            let mut traj = decode_traj(&w[TRAJ_START..])?;
            decode_path(&w[PATH_START..], &mut traj);
            traj
        },
        spindles: decode_spindles(&w[SPINDLES_START..])?,
        io: decode_io(&w[IO_START..])?,
        eoffset: decode_eoffsets(&w[EOFFSET_START..]),
    })
}

/// Decodes the coordinated-planner block.
fn decode_traj(w: &[u64]) -> Result<TrajState, WireError> {
    let f = |i: usize| f64::from_bits(w[i]);
    let int = |i: usize| i32::try_from(w[i] as i64).map_err(|_| WireError::BadStatus);
    let on = |m: u64| w[0] & m != 0;
    let mut probed = [0.0; 9];
    let mut pos_fb = [0.0; 9];
    let mut goal = [0.0; 9];
    for i in 0..9 {
        probed[i] = f(10 + i);
        pos_fb[i] = f(19 + i);
        goal[i] = f(28 + i);
    }
    Ok(TrajState {
        exec_id: int(1)?,
        depth: w[2],
        queue_full: on(tflag::QUEUE_FULL),
        paused: on(tflag::PAUSED),
        stepping: on(tflag::STEPPING),
        aborting: on(tflag::ABORTING),
        scurve: on(tflag::SCURVE),
        probing: on(tflag::PROBING),
        probe_tripped: on(tflag::PROBE_TRIPPED),
        probe_input: on(tflag::PROBE_INPUT),
        waiting_for_atspeed: on(tflag::WAITING_FOR_ATSPEED),
        current_vel: f(3),
        requested_vel: f(4),
        distance_to_go: f(5),
        feed_scale: f(6),
        rapid_scale: f(7),
        net_scale: f(9),
        motion_type: int(8)?,
        probed,
        pos_fb,
        goal,
        dtg: [0.0; 9],
        enables: None,
        kinematics_type: None,
    })
}
