//! `carousel`: drives a carousel tool changer to the requested pocket,
//! reading its position from gray, binary or BCD encoders, one sensor per
//! pocket, an index plus pocket sensor, or encoder counts.
//!
//! `loadrt carousel pockets=N[,N...] [encoding=...] [dir=...]
//! [num_sense=...] [parity=...]` makes one instance `carousel.<i>` per
//! `pockets` entry (see [`config`]). LinuxCNC's `debounce` param is kept
//! but, as there, has no effect.

pub mod config;
pub mod machine;
pub mod position;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Pin, Result};

use crate::halcomp::{hal_name, load_instances};
use crate::timing::write_changed;
use config::{configs, Config, PARAMS};
use machine::{Carousel, CarouselVars};

/// The `carousel` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "carousel",
    params: PARAMS,
    help: "orient a toolchanger carousel using various encoding schemes",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let configs = configs(args)?;
    let base = hal_name(MODULE.name);
    let instances = (0..configs.len())
        .map(|i| (format!("{base}.{i}"), configs[i].sense as i64))
        .collect();
    load_instances(host, MODULE.name, instances, |inst, i| {
        build(inst, configs[i])
    })
}

/// Writes `new` to a read-only param if it differs from `old`.
fn put<T: hal_core::PinValue + PartialEq>(p: &hal_core::Param<T, hal_core::Ro>, old: T, new: T) {
    if old != new {
        p.set(new);
    }
}

fn build(inst: &mut crate::halcomp::Inst<'_, '_>, cfg: Config) -> Result<()> {
    let pocket_number = inst.pin_in::<i32>("pocket-number")?;
    let enable = inst.pin_in::<bool>("enable")?;
    let active = inst.pin_out::<bool>("active")?;
    let ready = inst.pin_out::<bool>("ready")?;
    let strobe = inst.pin_in_init::<bool>("strobe", true)?;
    let parity = inst.pin_in::<bool>("parity")?;
    let sense: Vec<Pin<bool, In>> = (0..cfg.sense)
        .map(|i| inst.pin_in(&format!("sense-{i}")))
        .collect::<Result<_>>()?;
    let rev_pulse = inst.pin_in::<f64>("rev-pulse")?;
    let fwd_dc = inst.pin_in::<f64>("fwd-dc")?;
    let rev_dc = inst.pin_in::<f64>("rev-dc")?;
    let hold_dc = inst.pin_in::<f64>("hold-dc")?;
    let align_dc = inst.pin_in::<f64>("align-dc")?;
    let decel_time = inst.pin_in::<f64>("decel-time")?;
    let counts = inst.pin_in::<i32>("counts")?;
    let scale = inst.pin_in_init::<i32>("scale", 100)?;
    let width = inst.pin_in::<i32>("width")?;
    let home_offset = inst.pin_in::<i32>("home-offset")?;
    let index_enable = inst.pin_io::<bool>("index-enable", false)?;
    let jog_fwd = inst.pin_in::<bool>("jog-fwd")?;
    let jog_rev = inst.pin_in::<bool>("jog-rev")?;
    let motor_fwd = inst.pin_out::<bool>("motor-fwd")?;
    let motor_rev = inst.pin_out::<bool>("motor-rev")?;
    let parity_error = inst.pin_out::<bool>("parity-error")?;
    let current_position = inst.pin_out::<i32>("current-position")?;
    let motor_vel = inst.pin_out::<f64>("motor-vel")?;
    let homed = inst.pin_out::<bool>("homed")?;
    let unhome = inst.pin_in::<bool>("unhome")?;
    let state = inst.param_ro::<i32>("state", 0)?;
    let homing = inst.param_ro::<bool>("homing", false)?;
    let timer = inst.param_ro::<f64>("timer", 0.0)?;
    let motor_dir = inst.param_ro::<i32>("motor-dir", 0)?;
    let _debounce = inst.param_ro::<u32>("debounce", 0)?;
    let mut machine = Carousel::default();
    let mut v = CarouselVars {
        sense: vec![false; cfg.sense],
        ..Default::default()
    };
    inst.funct("_", true, move |ctx| {
        v.pocket_number = pocket_number.get();
        v.enable = enable.get();
        v.active = active.get();
        v.ready = ready.get();
        v.strobe = strobe.get();
        v.parity = parity.get();
        for (b, p) in v.sense.iter_mut().zip(&sense) {
            *b = p.get();
        }
        v.rev_pulse = rev_pulse.get();
        v.fwd_dc = fwd_dc.get();
        v.rev_dc = rev_dc.get();
        v.hold_dc = hold_dc.get();
        v.align_dc = align_dc.get();
        v.decel_time = decel_time.get();
        v.counts = counts.get();
        v.scale = scale.get();
        v.width = width.get();
        v.home_offset = home_offset.get();
        v.index_enable = index_enable.get();
        v.jog_fwd = jog_fwd.get();
        v.jog_rev = jog_rev.get();
        v.motor_fwd = motor_fwd.get();
        v.motor_rev = motor_rev.get();
        v.parity_error = parity_error.get();
        v.current_position = current_position.get();
        v.motor_vel = motor_vel.get();
        v.homed = homed.get();
        v.unhome = unhome.get();
        v.state = state.get();
        v.homing = homing.get();
        v.timer = timer.get();
        v.motor_dir = motor_dir.get();
        let old = (
            v.active,
            v.ready,
            v.index_enable,
            v.motor_fwd,
            v.motor_rev,
            v.parity_error,
            v.current_position,
            v.motor_vel,
            v.homed,
        );
        let old_params = (v.state, v.homing, v.timer, v.motor_dir);
        machine.step(&cfg, &mut v, ctx.fperiod());
        write_changed(&active, old.0, v.active);
        write_changed(&ready, old.1, v.ready);
        write_changed(&index_enable, old.2, v.index_enable);
        write_changed(&motor_fwd, old.3, v.motor_fwd);
        write_changed(&motor_rev, old.4, v.motor_rev);
        write_changed(&parity_error, old.5, v.parity_error);
        write_changed(&current_position, old.6, v.current_position);
        write_changed(&motor_vel, old.7, v.motor_vel);
        write_changed(&homed, old.8, v.homed);
        put(&state, old_params.0, v.state);
        put(&homing, old_params.1, v.homing);
        put(&timer, old_params.2, v.timer);
        put(&motor_dir, old_params.3, v.motor_dir);
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, S32};

    const COMMON_PINS: &[&str] = &[
        "pocket-number s32 in 0",
        "enable bit in 0",
        "active bit out 0",
        "ready bit out 0",
        "strobe bit in 1",
        "parity bit in 0",
        "rev-pulse float in 0",
        "fwd-dc float in 0",
        "rev-dc float in 0",
        "hold-dc float in 0",
        "align-dc float in 0",
        "decel-time float in 0",
        "counts s32 in 0",
        "scale s32 in 100",
        "width s32 in 0",
        "home-offset s32 in 0",
        "index-enable bit io 0",
        "jog-fwd bit in 0",
        "jog-rev bit in 0",
        "motor-fwd bit out 0",
        "motor-rev bit out 0",
        "parity-error bit out 0",
        "current-position s32 out 0",
        "motor-vel float out 0",
        "homed bit out 0",
        "unhome bit in 0",
    ];

    #[test]
    fn instances_follow_pockets_with_their_sense_pins() {
        let h = TestHost::new("carousel-pins");
        h.load(&MODULE, &["pockets=8,6", "encoding=gray,index"])
            .unwrap();
        let mut want: Vec<&str> = COMMON_PINS.to_vec();
        want.extend([
            "sense-0 bit in 0",
            "sense-1 bit in 0",
            "sense-2 bit in 0",
            "sense-3 bit in 0",
        ]);
        h.check_pins("carousel.0", &want);
        let mut want: Vec<&str> = COMMON_PINS.to_vec();
        want.extend(["sense-0 bit in 0", "sense-1 bit in 0"]);
        h.check_pins("carousel.1", &want);
        h.check_params(
            "carousel.1",
            &[
                "state s32 ro 0",
                "homing bit ro 0",
                "timer float ro 0",
                "motor-dir s32 ro 0",
                "debounce u32 ro 0",
            ],
        );
        assert_eq!(h.functs(), ["carousel.0", "carousel.1"]);
    }

    #[test]
    fn bad_parameters_leave_nothing() {
        let h = TestHost::new("carousel-bad");
        for bad in [
            &["encoding=octal"][..],
            &["pockets=33", "encoding=single"],
            &["count=2"],
            &["names=a"],
            &["parity=5"],
        ] {
            h.check_load_fails(&MODULE, bad);
        }
    }

    #[test]
    fn moves_to_a_pocket_in_a_thread() {
        let mut h = TestHost::new("carousel-run");
        h.load(&MODULE, &["pockets=4", "encoding=binary", "num_sense=2"])
            .unwrap();
        h.thread(&["carousel.0"]);
        h.set("carousel.0.sense-0", Bit(true)); // position 1
        h.set("carousel.0.pocket-number", S32(3));
        h.expect(
            &[("carousel.0.enable", Bit(true))],
            "carousel.0.active",
            Bit(true),
        );
        assert_eq!(h.getp("carousel.0.state"), S32(2));
        h.set("carousel.0.sense-0", Bit(false));
        h.set("carousel.0.sense-1", Bit(true)); // position 2
        h.run(2);
        assert_eq!(h.get("carousel.0.current-position"), S32(2));
        h.expect(
            &[("carousel.0.sense-0", Bit(true))],
            "carousel.0.ready",
            Bit(true),
        );
        assert_eq!(h.get("carousel.0.active"), Bit(false));
    }
}
