//! `thc`: torch height control. The arc voltage arrives as a frequency
//! (a Mesa THCAD on an encoder input) and becomes `volts`; while enabled,
//! cutting (`torch-on`, `arc-ok`) and at speed, the Z command gets an
//! offset that moves the torch by `correction-vel` per period toward the
//! requested voltage. With the torch off, the offset is taken back as Z
//! moves up. A singleton: `loadrt thc` makes the one instance `thc`.
//!
//! The offset and the last Z are single-precision in LinuxCNC and so are
//! they here, to give the same outputs.

use hal_core::Result;

use super::z_offset::ZOffset;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin and param values one call reads.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ThcInputs {
    /// Pin `encoder-vel`: the THCAD frequency.
    pub encoder_vel: f64,
    /// Pin `current-vel`.
    pub current_vel: f64,
    /// Pin `requested-vel`.
    pub requested_vel: f64,
    /// Pin `volts-requested`.
    pub volts_requested: f64,
    /// Pin `torch-on`.
    pub torch_on: bool,
    /// Pin `arc-ok`.
    pub arc_ok: bool,
    /// Pin `enable`.
    pub enable: bool,
    /// Pin `z-pos-in`.
    pub z_pos_in: f64,
    /// Param `vel-scale`.
    pub vel_scale: f64,
    /// Param `scale-offset`.
    pub scale_offset: f64,
    /// Param `velocity-tol` (percent, used as `requested * (1/tol)`).
    pub velocity_tol: f64,
    /// Param `voltage-tol`.
    pub voltage_tol: f64,
    /// Param `correction-vel`.
    pub correction_vel: f64,
}

/// The outputs of one call (`None`: not written by this call).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThcOutputs {
    /// Pin `volts`.
    pub volts: f64,
    /// Pin `vel-status` (written only while enabled).
    pub vel_status: Option<bool>,
    /// Pin `z-pos-out`.
    pub z_pos_out: f64,
    /// Pin `z-fb-out`.
    pub z_fb_out: f64,
}

/// The height controller's state.
#[derive(Debug, Clone, Default)]
pub struct Thc {
    /// The Z offset applied.
    pub z: ZOffset,
}

impl Thc {
    /// One call.
    pub fn step(&mut self, i: &ThcInputs) -> ThcOutputs {
        let mut volts = (i.encoder_vel - i.scale_offset) * i.vel_scale;
        if volts < 0.0 {
            volts = 0.0;
        }
        if !i.enable {
            return ThcOutputs {
                volts,
                vel_status: None,
                z_pos_out: i.z_pos_in,
                z_fb_out: i.z_pos_in,
            };
        }
        let min_velocity = (i.requested_vel - i.requested_vel * (1.0 / i.velocity_tol)) as f32;
        let vel_status = i.current_vel > 0.0 && i.current_vel >= f64::from(min_velocity);
        if i.torch_on && i.arc_ok && vel_status {
            self.z.correct(
                volts + i.voltage_tol > i.volts_requested,
                volts - i.voltage_tol < i.volts_requested,
                i.correction_vel,
            );
        }
        if !i.torch_on {
            self.z.take_back(i.z_pos_in);
        }
        ThcOutputs {
            volts,
            vel_status: Some(vel_status),
            z_pos_out: self.z.z_out(i.z_pos_in),
            z_fb_out: i.z_pos_in,
        }
    }
}

/// The `thc` component.
pub struct ThcComp;
impl HalComp for ThcComp {
    const NAME: &'static str = "thc";
    const SINGLETON: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let encoder_vel = inst.pin_in::<f64>("encoder-vel")?;
        let current_vel = inst.pin_in::<f64>("current-vel")?;
        let requested_vel = inst.pin_in::<f64>("requested-vel")?;
        let volts_requested = inst.pin_in::<f64>("volts-requested")?;
        // Declared by LinuxCNC but never read: the tolerance is the
        // `velocity-tol` param.
        let _vel_tol = inst.pin_in::<f64>("vel-tol")?;
        let torch_on = inst.pin_in::<bool>("torch-on")?;
        let arc_ok = inst.pin_in::<bool>("arc-ok")?;
        let enable = inst.pin_in::<bool>("enable")?;
        let z_pos_in = inst.pin_in::<f64>("z-pos-in")?;
        let z_pos_out = inst.pin_out::<f64>("z-pos-out")?;
        let z_fb_out = inst.pin_out::<f64>("z-fb-out")?;
        let volts = inst.pin_out::<f64>("volts")?;
        let vel_status = inst.pin_out::<bool>("vel-status")?;
        let vel_scale = inst.param_rw::<f64>("vel-scale", 0.0)?;
        let scale_offset = inst.param_rw::<f64>("scale-offset", 0.0)?;
        let velocity_tol = inst.param_rw::<f64>("velocity-tol", 0.0)?;
        let voltage_tol = inst.param_rw::<f64>("voltage-tol", 0.0)?;
        let correction_vel = inst.param_rw::<f64>("correction-vel", 0.0)?;
        let mut thc = Thc::default();
        inst.funct("_", true, move |_| {
            let o = thc.step(&ThcInputs {
                encoder_vel: encoder_vel.get(),
                current_vel: current_vel.get(),
                requested_vel: requested_vel.get(),
                volts_requested: volts_requested.get(),
                torch_on: torch_on.get(),
                arc_ok: arc_ok.get(),
                enable: enable.get(),
                z_pos_in: z_pos_in.get(),
                vel_scale: vel_scale.get(),
                scale_offset: scale_offset.get(),
                velocity_tol: velocity_tol.get(),
                voltage_tol: voltage_tol.get(),
                correction_vel: correction_vel.get(),
            });
            volts.set(o.volts);
            if let Some(s) = o.vel_status {
                vel_status.set(s);
            }
            z_pos_out.set(o.z_pos_out);
            z_fb_out.set(o.z_fb_out);
        })
    }
}
halcomp_module!(pub MODULE, ThcComp, "torch height control");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    fn cutting() -> ThcInputs {
        ThcInputs {
            encoder_vel: 120.0,
            current_vel: 100.0,
            requested_vel: 100.0,
            volts_requested: 100.0,
            torch_on: true,
            arc_ok: true,
            enable: true,
            z_pos_in: 1.0,
            vel_scale: 1.0,
            scale_offset: 20.0,
            velocity_tol: 10.0,
            voltage_tol: 1.0,
            correction_vel: 0.01,
        }
    }

    #[test]
    fn volts_are_scaled_and_never_negative() {
        let mut t = Thc::default();
        let mut i = cutting();
        assert_eq!(t.step(&i).volts, 100.0);
        i.encoder_vel = 5.0;
        assert_eq!(t.step(&i).volts, 0.0);
    }

    #[test]
    fn corrects_toward_the_requested_voltage_when_at_speed() {
        let mut t = Thc::default();
        let mut i = cutting();
        i.encoder_vel = 130.0; // 110 V: too high, torch moves down
        let o = t.step(&i);
        assert_eq!(o.vel_status, Some(true));
        assert_eq!(t.z.offset, -0.01f32);
        assert_eq!(o.z_pos_out, 1.0 + f64::from(-0.01f32));
        assert_eq!(o.z_fb_out, 1.0);
        i.encoder_vel = 110.0; // 90 V: up again
        t.step(&i);
        t.step(&i);
        assert_eq!(
            t.z.offset,
            ((-0.01f32 as f64 + 0.01) as f32 as f64 + 0.01) as f32
        );
        // Within tolerance both rules apply and cancel (in f32 steps).
        let before = t.z.offset;
        i.encoder_vel = 120.0;
        t.step(&i);
        assert_eq!(
            t.z.offset,
            ((before as f64 - 0.01) as f32 as f64 + 0.01) as f32
        );
        // Below speed: no correction.
        i.encoder_vel = 130.0;
        i.current_vel = 50.0;
        let before = t.z.offset;
        assert_eq!(t.step(&i).vel_status, Some(false));
        assert_eq!(t.z.offset, before);
    }

    #[test]
    fn offset_is_taken_back_as_z_rises_with_the_torch_off() {
        let mut t = Thc::default();
        t.z.offset = -0.5;
        let mut i = cutting();
        i.torch_on = false;
        i.z_pos_in = 0.0;
        t.step(&i); // remembers z
        i.z_pos_in = 0.2;
        t.step(&i);
        assert_eq!(t.z.offset, -0.5f32 + 0.2f32);
        // A negative offset is raised by the whole rise, even past zero
        // (LinuxCNC's rule for that side).
        i.z_pos_in = 1.0;
        t.step(&i);
        let z_diff = (1.0 - f64::from(0.2f32)) as f32;
        assert_eq!(t.z.offset, (-0.5f32 + 0.2f32) + z_diff);
        // A positive offset larger than the rise shrinks by it, else
        // goes to zero.
        i.z_pos_in = 1.25;
        t.step(&i);
        assert_eq!(t.z.offset, (-0.5f32 + 0.2f32) + z_diff - 0.25);
        i.z_pos_in = 3.0;
        t.step(&i);
        assert_eq!(t.z.offset, 0.0);
        // Disabled: Z passes through, vel-status untouched.
        i.enable = false;
        let o = t.step(&i);
        assert_eq!((o.z_pos_out, o.vel_status), (3.0, None));
    }

    #[test]
    fn singleton_pins_params_and_a_run() {
        let mut h = TestHost::new("thc");
        h.check_load_fails(&MODULE, &["count=1"]);
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "thc",
            &[
                "encoder-vel float in 0",
                "current-vel float in 0",
                "requested-vel float in 0",
                "volts-requested float in 0",
                "vel-tol float in 0",
                "torch-on bit in 0",
                "arc-ok bit in 0",
                "enable bit in 0",
                "z-pos-in float in 0",
                "z-pos-out float out 0",
                "z-fb-out float out 0",
                "volts float out 0",
                "vel-status bit out 0",
            ],
        );
        h.check_params(
            "thc",
            &[
                "vel-scale float rw 0",
                "scale-offset float rw 0",
                "velocity-tol float rw 0",
                "voltage-tol float rw 0",
                "correction-vel float rw 0",
            ],
        );
        assert_eq!(h.functs(), ["thc"]);
        h.thread(&["thc"]);
        h.setp("thc.vel-scale", Float(2.0));
        h.expect(&[("thc.encoder-vel", Float(3.0))], "thc.volts", Float(6.0));
        h.expect(&[("thc.z-pos-in", Float(4.0))], "thc.z-pos-out", Float(4.0));
        h.set("thc.enable", Bit(true));
        h.expect(&[], "thc.z-fb-out", Float(4.0));
    }
}
