//! `laserpower`: laser power scaled by the ratio of actual to requested
//! velocity (so corners are not burnt), between `min-power` and
//! `max-power`. In raster mode the power is `raster-power`; in vector
//! mode it ramps from the previous `vector-power` to the new one along
//! the move (by `distance-to-go`).

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Velocities below this count as zero.
pub const ZERO: f64 = 0.00005;

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LaserVars {
    /// Pin `min-power`.
    pub min_power: f64,
    /// Pin `max-power`.
    pub max_power: f64,
    /// Pin `req-velocity`.
    pub req_velocity: f64,
    /// Pin `cur-velocity`.
    pub cur_velocity: f64,
    /// Pin `enabled`.
    pub enabled: bool,
    /// Pin `raster-mode`.
    pub raster_mode: bool,
    /// Pin `raster-power`.
    pub raster_power: f64,
    /// Pin `vector-power`.
    pub vector_power: f64,
    /// Pin `distance-to-go`.
    pub distance_to_go: f64,
    /// Pin `power`.
    pub power: f64,
    /// Pin `command-power` (read back).
    pub command_power: f64,
    /// Pin `start-power` (read back).
    pub start_power: f64,
    /// Pin `start-distance` (read back).
    pub start_distance: f64,
    /// Pin `vel-scale` (read back).
    pub vel_scale: f64,
}

/// The previous vector power and distance to go.
#[derive(Debug, Clone, Default)]
pub struct LaserPower {
    previous_vector_power: f64,
    previous_distance_to_go: f64,
}

impl LaserPower {
    /// One call.
    pub fn step(&mut self, v: &mut LaserVars) {
        v.vel_scale = if v.req_velocity.abs() < ZERO || v.cur_velocity.abs() < ZERO {
            0.0
        } else {
            v.cur_velocity.abs() / v.req_velocity.abs()
        };
        if v.raster_mode {
            v.command_power = v.raster_power;
        } else {
            if self.previous_distance_to_go < v.distance_to_go
                || (v.vector_power - self.previous_vector_power).abs() >= ZERO
            {
                // A new move, or a new power during one: ramp from the
                // previous power over the distance left.
                v.start_power = self.previous_vector_power;
                v.start_distance = v.distance_to_go;
            }
            self.previous_vector_power = v.vector_power;
            self.previous_distance_to_go = v.distance_to_go;
            v.command_power = v.start_power
                + (v.vector_power - v.start_power) * (1.0 - v.distance_to_go / v.start_distance);
        }
        v.power = if !v.enabled || v.command_power < 0.0 {
            0.0
        } else {
            (v.max_power - v.min_power) * v.vel_scale * (v.command_power / 100.0) + v.min_power
        };
    }
}

/// The `laserpower` component.
pub struct LaserPowerComp;
impl HalComp for LaserPowerComp {
    const NAME: &'static str = "laserpower";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let min_power = inst.pin_in::<f64>("min-power")?;
        let max_power = inst.pin_in::<f64>("max-power")?;
        let req_velocity = inst.pin_in::<f64>("req-velocity")?;
        let cur_velocity = inst.pin_in::<f64>("cur-velocity")?;
        let enabled = inst.pin_in::<bool>("enabled")?;
        let raster_mode = inst.pin_in::<bool>("raster-mode")?;
        let raster_power = inst.pin_in::<f64>("raster-power")?;
        let vector_power = inst.pin_in::<f64>("vector-power")?;
        let distance_to_go = inst.pin_in::<f64>("distance-to-go")?;
        let power = inst.pin_out::<f64>("power")?;
        let command_power = inst.pin_out::<f64>("command-power")?;
        let start_power = inst.pin_out::<f64>("start-power")?;
        let start_distance = inst.pin_out::<f64>("start-distance")?;
        let vel_scale = inst.pin_out::<f64>("vel-scale")?;
        let mut l = LaserPower::default();
        inst.funct("_", true, move |_| {
            let mut v = LaserVars {
                min_power: min_power.get(),
                max_power: max_power.get(),
                req_velocity: req_velocity.get(),
                cur_velocity: cur_velocity.get(),
                enabled: enabled.get(),
                raster_mode: raster_mode.get(),
                raster_power: raster_power.get(),
                vector_power: vector_power.get(),
                distance_to_go: distance_to_go.get(),
                power: power.get(),
                command_power: command_power.get(),
                start_power: start_power.get(),
                start_distance: start_distance.get(),
                vel_scale: vel_scale.get(),
            };
            l.step(&mut v);
            vel_scale.set(v.vel_scale);
            start_power.set(v.start_power);
            start_distance.set(v.start_distance);
            command_power.set(v.command_power);
            power.set(v.power);
        })
    }
}
halcomp_module!(pub MODULE, LaserPowerComp, "scales laser power output based upon velocity and distance to go");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn raster_power_scales_with_velocity() {
        let mut l = LaserPower::default();
        let mut v = LaserVars {
            min_power: 10.0,
            max_power: 110.0,
            req_velocity: 100.0,
            cur_velocity: 50.0,
            enabled: true,
            raster_mode: true,
            raster_power: 80.0,
            ..Default::default()
        };
        l.step(&mut v);
        assert_eq!(v.vel_scale, 0.5);
        assert_eq!(v.power, 100.0 * 0.5 * 0.8 + 10.0);
        v.cur_velocity = 0.0;
        l.step(&mut v);
        assert_eq!(v.power, 10.0, "standing still: minimum power");
        v.enabled = false;
        l.step(&mut v);
        assert_eq!(v.power, 0.0);
    }

    #[test]
    fn vector_power_ramps_along_the_move() {
        let mut l = LaserPower::default();
        let mut v = LaserVars {
            max_power: 100.0,
            req_velocity: 1.0,
            cur_velocity: 1.0,
            enabled: true,
            vector_power: 100.0,
            distance_to_go: 10.0,
            ..Default::default()
        };
        l.step(&mut v);
        assert_eq!((v.start_power, v.start_distance), (0.0, 10.0));
        assert_eq!(v.command_power, 0.0);
        v.distance_to_go = 5.0;
        l.step(&mut v);
        assert_eq!(v.command_power, 50.0);
        v.distance_to_go = 0.0;
        l.step(&mut v);
        assert_eq!((v.command_power, v.power), (100.0, 100.0));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("laserpower");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "laserpower.0",
            &[
                "min-power float in 0",
                "max-power float in 0",
                "req-velocity float in 0",
                "cur-velocity float in 0",
                "enabled bit in 0",
                "raster-mode bit in 0",
                "raster-power float in 0",
                "vector-power float in 0",
                "distance-to-go float in 0",
                "power float out 0",
                "command-power float out 0",
                "start-power float out 0",
                "start-distance float out 0",
                "vel-scale float out 0",
            ],
        );
        h.thread(&["laserpower.0"]);
        h.set("laserpower.0.min-power", Float(5.0));
        h.expect(
            &[
                ("laserpower.0.enabled", Bit(true)),
                ("laserpower.0.raster-mode", Bit(true)),
            ],
            "laserpower.0.power",
            Float(5.0),
        );
    }
}
