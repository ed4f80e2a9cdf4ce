//! `thcud`: torch height control from a controller's up/down signals.
//! While enabled, cutting and at speed (within `velocity-tol` percent of
//! the requested velocity), `torch-up`/`torch-down` move the Z offset by
//! `correction-vel` per period; with the torch off the offset is taken
//! back as Z rises. A singleton: `loadrt thcud` makes `thcud`.

use hal_core::Result;

use super::z_offset::ZOffset;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin and param values one call reads.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ThcudInputs {
    /// Pin `torch-up`.
    pub torch_up: bool,
    /// Pin `torch-down`.
    pub torch_down: bool,
    /// Pin `current-vel`.
    pub current_vel: f64,
    /// Pin `requested-vel`.
    pub requested_vel: f64,
    /// Pin `torch-on`.
    pub torch_on: bool,
    /// Pin `arc-ok`.
    pub arc_ok: bool,
    /// Pin `enable`.
    pub enable: bool,
    /// Pin `z-pos-in`.
    pub z_pos_in: f64,
    /// Param `velocity-tol` (percent).
    pub velocity_tol: f64,
    /// Param `correction-vel`.
    pub correction_vel: f64,
}

/// The outputs of one call; `None`: not written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThcudOutputs {
    /// Pin `z-pos-out`.
    pub z_pos_out: f64,
    /// Pin `z-fb-out`.
    pub z_fb_out: f64,
    /// Pin `vel-status`.
    pub vel_status: Option<bool>,
    /// Pin `removing-offset`.
    pub removing_offset: Option<bool>,
}

/// One call on `z`.
pub fn thcud(z: &mut ZOffset, i: &ThcudInputs) -> ThcudOutputs {
    if !i.enable {
        return ThcudOutputs {
            z_pos_out: i.z_pos_in,
            z_fb_out: i.z_pos_in,
            vel_status: None,
            removing_offset: None,
        };
    }
    let min_velocity = (i.requested_vel - i.requested_vel * (i.velocity_tol * 0.01)) as f32;
    let vel_status = i.current_vel > 0.0 && i.current_vel >= f64::from(min_velocity);
    if i.torch_on && i.arc_ok && vel_status {
        z.correct(i.torch_down, i.torch_up, i.correction_vel);
    }
    let removing_offset = (!i.torch_on).then(|| z.take_back(i.z_pos_in));
    ThcudOutputs {
        z_pos_out: z.z_out(i.z_pos_in),
        z_fb_out: i.z_pos_in,
        vel_status: Some(vel_status),
        removing_offset,
    }
}

/// The `thcud` component.
pub struct Thcud;
impl HalComp for Thcud {
    const NAME: &'static str = "thcud";
    const SINGLETON: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let torch_up = inst.pin_in::<bool>("torch-up")?;
        let torch_down = inst.pin_in::<bool>("torch-down")?;
        let current_vel = inst.pin_in::<f64>("current-vel")?;
        let requested_vel = inst.pin_in::<f64>("requested-vel")?;
        let torch_on = inst.pin_in::<bool>("torch-on")?;
        let arc_ok = inst.pin_in::<bool>("arc-ok")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let z_pos_in = inst.pin_in::<f64>("z-pos-in")?;
        let z_pos_out = inst.pin_out::<f64>("z-pos-out")?;
        let z_fb_out = inst.pin_out::<f64>("z-fb-out")?;
        // Declared by LinuxCNC, never written.
        let _cur_offset = inst.pin_out::<f64>("cur-offset")?;
        let vel_status = inst.pin_out::<bool>("vel-status")?;
        let removing_offset = inst.pin_out::<bool>("removing-offset")?;
        let velocity_tol = inst.param_rw::<f64>("velocity-tol", 0.0)?;
        let correction_vel = inst.param_rw::<f64>("correction-vel", 0.0)?;
        let mut z = ZOffset::default();
        inst.funct("_", true, move |_| {
            let o = thcud(
                &mut z,
                &ThcudInputs {
                    torch_up: torch_up.get(),
                    torch_down: torch_down.get(),
                    current_vel: current_vel.get(),
                    requested_vel: requested_vel.get(),
                    torch_on: torch_on.get(),
                    arc_ok: arc_ok.get(),
                    enable: enable.get(),
                    z_pos_in: z_pos_in.get(),
                    velocity_tol: velocity_tol.get(),
                    correction_vel: correction_vel.get(),
                },
            );
            if let Some(s) = o.vel_status {
                vel_status.set(s);
            }
            if let Some(r) = o.removing_offset {
                removing_offset.set(r);
            }
            z_pos_out.set(o.z_pos_out);
            z_fb_out.set(o.z_fb_out);
        })
    }
}
halcomp_module!(pub MODULE, Thcud, "torch height control up/down input");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    fn cutting() -> ThcudInputs {
        ThcudInputs {
            current_vel: 95.0,
            requested_vel: 100.0,
            torch_on: true,
            arc_ok: true,
            enable: true,
            z_pos_in: 1.0,
            velocity_tol: 10.0,
            correction_vel: 0.001,
            ..Default::default()
        }
    }

    #[test]
    fn up_and_down_move_the_offset_when_at_speed() {
        let mut z = ZOffset::default();
        let mut i = cutting();
        i.torch_up = true;
        let o = thcud(&mut z, &i);
        assert_eq!(o.vel_status, Some(true));
        assert_eq!(z.offset, 0.001f32);
        assert_eq!(o.z_pos_out, 1.0 + f64::from(0.001f32));
        i.current_vel = 80.0; // below 90% of requested
        assert_eq!(thcud(&mut z, &i).vel_status, Some(false));
        assert_eq!(z.offset, 0.001f32);
        i.torch_on = false;
        i.z_pos_in = 2.0;
        assert_eq!(thcud(&mut z, &i).removing_offset, Some(true));
        assert_eq!(z.offset, 0.0);
        i.enable = false;
        let o = thcud(&mut z, &i);
        assert_eq!((o.z_pos_out, o.vel_status), (2.0, None));
    }

    #[test]
    fn singleton_pins_and_a_run() {
        let mut h = TestHost::new("thcud");
        h.check_load_fails(&MODULE, &["names=x"]);
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "thcud",
            &[
                "torch-up bit in 0",
                "torch-down bit in 0",
                "current-vel float in 0",
                "requested-vel float in 0",
                "torch-on bit in 0",
                "arc-ok bit in 0",
                "enable bit in 0",
                "z-pos-in float in 0",
                "z-pos-out float out 0",
                "z-fb-out float out 0",
                "cur-offset float out 0",
                "vel-status bit out 0",
                "removing-offset bit out 0",
            ],
        );
        h.check_params(
            "thcud",
            &["velocity-tol float rw 0", "correction-vel float rw 0"],
        );
        h.thread(&["thcud"]);
        h.set("thcud.enable", Bit(true));
        h.expect(
            &[("thcud.z-pos-in", Float(3.0))],
            "thcud.z-pos-out",
            Float(3.0),
        );
    }
}
