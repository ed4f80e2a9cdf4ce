//! `moveoff`: offsets applied to joint positions from HAL, typically
//! while a program is paused. With `power-on`, `move-enable` and
//! `apply-offsets` all TRUE the `offset-in-M` inputs are followed within
//! the `offset-min/max/vel/accel-M` limits; `pos-plusoffset-M` and
//! `fb-minusoffset-M` carry them to the position loop. When an enable
//! drops the offsets return to zero, back along the recorded waypoints
//! when `backtrack-enable` is set. `personality` is the number of joints
//! (3 when not given, at most 9).
//!
//! Two functions, `read-inputs` then `write-outputs`, usually in the
//! servo thread. LinuxCNC keeps one state for all instances of the
//! module; here each instance has its own.

pub mod limiter;
pub mod logic;

use std::sync::Arc;

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;
use crate::shared::Exclusive;
use limiter::Limits;
use logic::{InputVars, Moveoff, OutputVars, MAX_JOINTS};

/// What moveoff writes to stderr.
pub static TEXTS: &[&str] =
    &["moveoff: WARNING: apply-offsets deasserted before the offsets were removed\n"];

/// Pins of one joint.
struct Joint {
    offset_in: Pin<f64, In>,
    pos: Pin<f64, In>,
    fb: Pin<f64, In>,
    offset_current: Pin<f64, Out>,
    pos_plusoffset: Pin<f64, Out>,
    fb_minusoffset: Pin<f64, Out>,
    vel: Pin<f64, In>,
    accel: Pin<f64, In>,
    min: Pin<f64, In>,
    max: Pin<f64, In>,
}

/// Every pin of an instance, shared by its two functions.
struct Pins {
    power_on: Pin<bool, In>,
    move_enable: Pin<bool, In>,
    apply_offsets: Pin<bool, In>,
    backtrack_enable: Pin<bool, In>,
    epsilon: Pin<f64, In>,
    waypoint_threshold: Pin<f64, In>,
    waypoint_sample_secs: Pin<f64, In>,
    warning: Pin<bool, Out>,
    offset_applied: Pin<bool, Out>,
    waypoint_limit: Pin<bool, Out>,
    waypoint_ct: Pin<i32, Out>,
    waypoint_percent_used: Pin<i32, Out>,
    joints: Vec<Joint>,
    dbg_waypoint_limit_test: Pin<bool, In>,
    dbg_state: Pin<i32, Out>,
}

fn pins(inst: &mut Inst<'_, '_>, n: usize) -> Result<Pins> {
    let power_on = inst.pin_in("power-on")?;
    let move_enable = inst.pin_in("move-enable")?;
    let apply_offsets = inst.pin_in("apply-offsets")?;
    let backtrack_enable = inst.pin_in_init("backtrack-enable", true)?;
    let epsilon = inst.pin_in_init("epsilon", 0.0005)?;
    let waypoint_threshold = inst.pin_in_init("waypoint-threshold", 0.02)?;
    let waypoint_sample_secs = inst.pin_in_init("waypoint-sample-secs", 0.02)?;
    let warning = inst.pin_out("warning")?;
    let offset_applied = inst.pin_out("offset-applied")?;
    let waypoint_limit = inst.pin_out("waypoint-limit")?;
    let waypoint_ct = inst.pin_out("waypoint-ct")?;
    let waypoint_percent_used = inst.pin_out("waypoint-percent-used")?;
    let d = Limits::default();
    let mut joints = Vec::with_capacity(n);
    for m in 0..n {
        joints.push(Joint {
            offset_in: inst.pin_in(&format!("offset-in-{m}"))?,
            pos: inst.pin_in(&format!("pos-{m}"))?,
            fb: inst.pin_in(&format!("fb-{m}"))?,
            offset_current: inst.pin_out(&format!("offset-current-{m}"))?,
            pos_plusoffset: inst.pin_out(&format!("pos-plusoffset-{m}"))?,
            fb_minusoffset: inst.pin_out(&format!("fb-minusoffset-{m}"))?,
            vel: inst.pin_in_init(&format!("offset-vel-{m}"), d.maxv)?,
            accel: inst.pin_in_init(&format!("offset-accel-{m}"), d.maxa)?,
            min: inst.pin_in_init(&format!("offset-min-{m}"), d.min)?,
            max: inst.pin_in_init(&format!("offset-max-{m}"), d.max)?,
        });
    }
    Ok(Pins {
        power_on,
        move_enable,
        apply_offsets,
        backtrack_enable,
        epsilon,
        waypoint_threshold,
        waypoint_sample_secs,
        warning,
        offset_applied,
        waypoint_limit,
        waypoint_ct,
        waypoint_percent_used,
        joints,
        dbg_waypoint_limit_test: inst.pin_in("dbg-waypoint-limit-test")?,
        dbg_state: inst.pin_out("dbg-state")?,
    })
}

/// The `moveoff` component.
pub struct MoveoffComp;
impl HalComp for MoveoffComp {
    const NAME: &'static str = "moveoff";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let joints = if inst.personality == 0 {
            3
        } else {
            inst.personality
        };
        let n = inst.array_len(MAX_JOINTS, joints)?;
        let pins = Arc::new(pins(inst, n)?);
        let state = Arc::new(Exclusive::new(Moveoff::new(n)));
        let notice = Notice::new(TEXTS);

        let (p, s) = (pins.clone(), state.clone());
        inst.funct("read-inputs", true, move |ctx| {
            let mut v = InputVars {
                power_on: p.power_on.get(),
                move_enable: p.move_enable.get(),
                apply_offsets: p.apply_offsets.get(),
                backtrack_enable: p.backtrack_enable.get(),
                epsilon: p.epsilon.get(),
                waypoint_threshold: p.waypoint_threshold.get(),
                waypoint_sample_secs: p.waypoint_sample_secs.get(),
                dbg_waypoint_limit_test: p.dbg_waypoint_limit_test.get(),
                offset_applied: p.offset_applied.get(),
                waypoint_limit: p.waypoint_limit.get(),
                warning: p.warning.get(),
                ..Default::default()
            };
            for (r, j) in p.joints.iter().enumerate() {
                v.offset_in[r] = j.offset_in.get();
                v.offset_current[r] = j.offset_current.get();
            }
            let now = ctx.now_ns() as i64;
            if s.try_with(|m| m.read_inputs(&mut v, now, ctx.period())) == Some(true) {
                notice.post(0);
            }
            p.offset_applied.set(v.offset_applied);
            p.waypoint_limit.set(v.waypoint_limit);
            p.warning.set(v.warning);
        })?;

        inst.funct("write-outputs", true, move |_| {
            let mut v = OutputVars {
                waypoint_limit: pins.waypoint_limit.get(),
                ..Default::default()
            };
            for (r, j) in pins.joints.iter().enumerate() {
                v.pos[r] = j.pos.get();
                v.fb[r] = j.fb.get();
                v.limits[r] = Limits {
                    min: j.min.get(),
                    max: j.max.get(),
                    maxv: j.vel.get(),
                    maxa: j.accel.get(),
                };
                v.offset_current[r] = j.offset_current.get();
                v.pos_plusoffset[r] = j.pos_plusoffset.get();
                v.fb_minusoffset[r] = j.fb_minusoffset.get();
            }
            if state.try_with(|m| m.write_outputs(&mut v)).is_none() {
                return;
            }
            for (r, j) in pins.joints.iter().enumerate() {
                j.offset_current.set(v.offset_current[r]);
                j.pos_plusoffset.set(v.pos_plusoffset[r]);
                j.fb_minusoffset.set(v.fb_minusoffset[r]);
            }
            pins.offset_applied.set(v.offset_applied);
            pins.waypoint_limit.set(v.waypoint_limit);
            pins.waypoint_ct.set(v.waypoint_ct);
            pins.waypoint_percent_used.set(v.waypoint_percent_used);
            pins.dbg_state.set(v.dbg_state);
        })
    }
}
halcomp_module!(pub MODULE, MoveoffComp, "component for HAL-only offsets");

#[cfg(test)]
mod tests;
