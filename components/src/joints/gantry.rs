//! `gantry`: drives several joints (motors) from one axis, squaring the
//! gantry while homing. While the axis moves toward the home switches
//! (the sign of `search-vel`) and not all switches are on, a joint whose
//! switch is on stops and its offset absorbs the motion instead; once all
//! are on, the joints move in lock-step again with their new offsets.
//! `personality` is the number of joints (1 to 7).
//!
//! Functions `read` (feedback and home/limit, before motion) and `write`
//! (joint commands, after motion). The offsets and the last command are
//! single precision, as in LinuxCNC.

use std::sync::Arc;

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::shared::Exclusive;

/// Most joints.
pub const MAX_JOINTS: usize = 7;

/// The state the two functions share.
#[derive(Debug, Clone, Default)]
pub struct Gantry {
    offset: [f32; MAX_JOINTS],
    prev_cmd: f32,
    fb_joint: usize,
    latching: bool,
}

/// What `read` computes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReadOut {
    /// `home`: all switches on (or, once latched, any still on).
    pub home: bool,
    /// `limit`: any switch on.
    pub limit: bool,
    /// `position-fb`, if updated.
    pub position_fb: Option<f64>,
}

impl Gantry {
    /// The offset of joint `j`.
    pub fn offset(&self, j: usize) -> f32 {
        self.offset[j]
    }

    /// `read`: from each joint's home switch and feedback.
    pub fn read(&mut self, homes: &[bool], fbs: &[f64]) -> ReadOut {
        let mut home = homes[0];
        let mut limit = homes[0];
        for &h in &homes[1..] {
            if !self.latching {
                home &= h;
            } else {
                home |= h;
            }
            self.latching = home;
            limit |= h;
        }
        let feedback = |j: usize| fbs[j] + f64::from(self.offset[j]);
        let position_fb = if homes[self.fb_joint] && !home {
            // The feedback joint stopped on its switch: follow one still
            // moving.
            homes.iter().position(|&h| !h).map(|j| {
                self.fb_joint = j;
                feedback(j)
            })
        } else {
            Some(feedback(self.fb_joint))
        };
        ReadOut {
            home,
            limit,
            position_fb,
        }
    }

    /// `write`: the joint commands for axis command `cmd`; `home` is the
    /// current `home` output.
    pub fn write(
        &mut self,
        cmd: f64,
        search_vel: f64,
        home: bool,
        homes: &[bool],
        cmds: &mut [f64],
    ) {
        let delta = (cmd - f64::from(self.prev_cmd)) as f32;
        self.prev_cmd = cmd as f32;
        if f64::from(delta) * search_vel > 0.0 && !home {
            for (o, &h) in self.offset.iter_mut().zip(homes) {
                if h {
                    *o += delta;
                }
            }
        }
        for (c, o) in cmds.iter_mut().zip(&self.offset) {
            *c = cmd - f64::from(*o);
        }
    }
}

/// The pins of one joint.
struct Joint {
    pos_cmd: Pin<f64, Out>,
    pos_fb: Pin<f64, In>,
    home: Pin<bool, In>,
    offset: Pin<f64, Out>,
}

/// The `gantry` component.
pub struct GantryComp;
impl HalComp for GantryComp {
    const NAME: &'static str = "gantry";
    const PERSONALITY: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let n = inst.array_len(MAX_JOINTS, inst.personality)?;
        if n == 0 {
            return Err(inst.bad_param(
                "personality",
                format!("{}: a gantry needs at least one joint", inst.prefix),
            ));
        }
        let mut joints = Vec::with_capacity(n);
        for j in 0..n {
            joints.push(Joint {
                pos_cmd: inst.pin_out(&format!("joint.{j:02}.pos-cmd"))?,
                pos_fb: inst.pin_in(&format!("joint.{j:02}.pos-fb"))?,
                home: inst.pin_in(&format!("joint.{j:02}.home"))?,
                offset: inst.pin_out(&format!("joint.{j:02}.offset"))?,
            });
        }
        let joints = Arc::new(joints);
        let position_cmd = inst.pin_in::<f64>("position-cmd")?;
        let position_fb = inst.pin_out::<f64>("position-fb")?;
        let home = Arc::new(inst.pin_out::<bool>("home")?);
        let limit = inst.pin_out::<bool>("limit")?;
        let search_vel = inst.pin_in::<f64>("search-vel")?;
        let state = Arc::new(Exclusive::new(Gantry::default()));

        let (js, st, hm) = (joints.clone(), state.clone(), home.clone());
        let mut homes = vec![false; n];
        let mut fbs = vec![0.0; n];
        inst.funct("read", true, move |_| {
            for (j, p) in js.iter().enumerate() {
                homes[j] = p.home.get();
                fbs[j] = p.pos_fb.get();
            }
            if let Some(r) = st.try_with(|g| g.read(&homes, &fbs)) {
                hm.set(r.home);
                limit.set(r.limit);
                if let Some(fb) = r.position_fb {
                    position_fb.set(fb);
                }
            }
        })?;
        let mut homes = vec![false; n];
        let mut cmds = vec![0.0; n];
        inst.funct("write", true, move |_| {
            for (j, p) in joints.iter().enumerate() {
                homes[j] = p.home.get();
            }
            state.try_with(|g| {
                g.write(
                    position_cmd.get(),
                    search_vel.get(),
                    home.get(),
                    &homes,
                    &mut cmds,
                );
                for (j, p) in joints.iter().enumerate() {
                    p.pos_cmd.set(cmds[j]);
                    p.offset.set(f64::from(g.offset(j)));
                }
            });
        })
    }
}
halcomp_module!(pub MODULE, GantryComp, "drive multiple joints from a single axis");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn home_needs_every_switch_and_release_needs_every_switch_off() {
        let mut g = Gantry::default();
        let fbs = [0.0; 3];
        let r = g.read(&[true, false, true], &fbs);
        assert!(!r.home && r.limit);
        assert!(g.read(&[true, true, true], &fbs).home);
        // Latched: home stays on until every switch is off.
        assert!(g.read(&[false, true, false], &fbs).home);
        assert!(!g.read(&[false, false, false], &fbs).home);
    }

    #[test]
    fn a_joint_on_its_switch_stops_while_the_others_catch_up() {
        let mut g = Gantry::default();
        let mut cmds = [0.0; 2];
        // Searching in the positive direction.
        g.write(0.0, 1.0, false, &[false, false], &mut cmds);
        g.write(1.0, 1.0, false, &[true, false], &mut cmds);
        assert_eq!(cmds, [0.0, 1.0], "joint 0 held, joint 1 moves on");
        assert_eq!(g.offset(0), 1.0);
        g.write(1.5, 1.0, true, &[true, true], &mut cmds);
        assert_eq!(cmds, [0.5, 1.5], "all home: lock-step with the offset");
        // Moving away from home never changes offsets.
        g.write(1.0, 1.0, false, &[true, false], &mut cmds);
        assert_eq!(g.offset(0), 1.0);
    }

    #[test]
    fn feedback_follows_a_joint_still_moving() {
        let mut g = Gantry::default();
        let r = g.read(&[true, false], &[5.0, 7.0]);
        assert_eq!(r.position_fb, Some(7.0));
        let r = g.read(&[false, false], &[5.0, 7.5]);
        assert_eq!(r.position_fb, Some(7.5), "stays on joint 1");
    }

    #[test]
    fn pins_functions_and_a_run() {
        let mut h = TestHost::new("gantry");
        h.check_load_fails(&MODULE, &["personality=8"]);
        h.check_load_fails(&MODULE, &["personality=0"]);
        h.load(&MODULE, &["personality=2"]).unwrap();
        let mut want = vec![
            "position-cmd float in 0".to_string(),
            "position-fb float out 0".into(),
            "home bit out 0".into(),
            "limit bit out 0".into(),
            "search-vel float in 0".into(),
        ];
        for j in 0..2 {
            want.push(format!("joint.{j:02}.pos-cmd float out 0"));
            want.push(format!("joint.{j:02}.pos-fb float in 0"));
            want.push(format!("joint.{j:02}.home bit in 0"));
            want.push(format!("joint.{j:02}.offset float out 0"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("gantry.0", &want);
        assert_eq!(h.functs(), ["gantry.0.read", "gantry.0.write"]);
        h.thread(&["gantry.0.read", "gantry.0.write"]);
        h.expect(
            &[("gantry.0.position-cmd", Float(3.0))],
            "gantry.0.joint.01.pos-cmd",
            Float(3.0),
        );
        h.expect(
            &[("gantry.0.joint.00.home", Bit(true))],
            "gantry.0.limit",
            Bit(true),
        );
    }
}
