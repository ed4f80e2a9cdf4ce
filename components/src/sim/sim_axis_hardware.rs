//! `sim_axis_hardware`: simulated home and limit switches for the X, Y,
//! Z, A, U and V axes from their positions: a home switch within
//! half of `homesw-hyst` of `homesw-pos`, limit switches over windows
//! (shifted inward by `limit-offset`), and their combinations.

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The axes, in LinuxCNC's order.
pub const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'U', 'V'];

/// One axis's inputs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisInputs {
    /// `<A>current-pos`.
    pub current_pos: f64,
    /// `<A>homesw-pos`.
    pub homesw_pos: f64,
    /// `<A>maxsw-upper`.
    pub maxsw_upper: f64,
    /// `<A>maxsw-lower`.
    pub maxsw_lower: f64,
    /// `<A>minsw-upper`.
    pub minsw_upper: f64,
    /// `<A>minsw-lower`.
    pub minsw_lower: f64,
    /// `<A>homesw-hyst`.
    pub homesw_hyst: f64,
}

/// One axis's switches: (home, max, min).
pub fn axis_switches(a: &AxisInputs, limit_offset: f64) -> (bool, bool, bool) {
    let half = 0.5 * a.homesw_hyst;
    let d = a.current_pos - a.homesw_pos;
    let home = !(d < -half || d > half);
    let window = |x: f64, max: f64, min: f64| !(x >= max || x <= min);
    let max = window(a.current_pos, a.maxsw_upper, a.maxsw_lower + limit_offset);
    let min = window(a.current_pos, a.minsw_upper - limit_offset, a.minsw_lower);
    (home, max, min)
}

/// The pins of one axis.
struct AxisPins {
    current_pos: Pin<f64, In>,
    homesw_pos: Pin<f64, In>,
    maxsw_upper: Pin<f64, In>,
    maxsw_lower: Pin<f64, In>,
    minsw_upper: Pin<f64, In>,
    minsw_lower: Pin<f64, In>,
    homesw_hyst: Pin<f64, In>,
    homesw_out: Pin<bool, Out>,
    maxsw_out: Pin<bool, Out>,
    minsw_out: Pin<bool, Out>,
    bothsw_out: Pin<bool, Out>,
    maxsw_homesw_out: Pin<bool, Out>,
    minsw_homesw_out: Pin<bool, Out>,
    bothsw_homesw_out: Pin<bool, Out>,
}

/// The `sim_axis_hardware` component.
pub struct SimAxisHardware;
impl HalComp for SimAxisHardware {
    const NAME: &'static str = "sim_axis_hardware";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let mut axes = Vec::with_capacity(AXES.len());
        for a in AXES {
            axes.push(AxisPins {
                current_pos: inst.pin_in(&format!("{a}current-pos"))?,
                homesw_pos: inst.pin_in_init(&format!("{a}homesw-pos"), 1.0)?,
                maxsw_upper: inst.pin_in(&format!("{a}maxsw-upper"))?,
                maxsw_lower: inst.pin_in(&format!("{a}maxsw-lower"))?,
                minsw_upper: inst.pin_in(&format!("{a}minsw-upper"))?,
                minsw_lower: inst.pin_in(&format!("{a}minsw-lower"))?,
                homesw_hyst: inst.pin_in_init(&format!("{a}homesw-hyst"), 0.02)?,
                homesw_out: inst.pin_out(&format!("{a}homesw-out"))?,
                maxsw_out: inst.pin_out(&format!("{a}maxsw-out"))?,
                minsw_out: inst.pin_out(&format!("{a}minsw-out"))?,
                bothsw_out: inst.pin_out(&format!("{a}bothsw-out"))?,
                maxsw_homesw_out: inst.pin_out(&format!("{a}maxsw-homesw-out"))?,
                minsw_homesw_out: inst.pin_out(&format!("{a}minsw-homesw-out"))?,
                bothsw_homesw_out: inst.pin_out(&format!("{a}bothsw-homesw-out"))?,
            });
        }
        let homesw_all = inst.pin_out::<bool>("homesw-all")?;
        let limitsw_all = inst.pin_out::<bool>("limitsw-all")?;
        let limitsw_homesw_all = inst.pin_out::<bool>("limitsw-homesw-all")?;
        let limit_offset = inst.pin_in_init::<f64>("limit-offset", 0.01)?;
        inst.funct("update", true, move |_| {
            let offset = limit_offset.get();
            let (mut any_home, mut any_limit) = (false, false);
            for (k, p) in axes.iter().enumerate() {
                let (home, max, min) = axis_switches(
                    &AxisInputs {
                        current_pos: p.current_pos.get(),
                        homesw_pos: p.homesw_pos.get(),
                        maxsw_upper: p.maxsw_upper.get(),
                        maxsw_lower: p.maxsw_lower.get(),
                        minsw_upper: p.minsw_upper.get(),
                        minsw_lower: p.minsw_lower.get(),
                        homesw_hyst: p.homesw_hyst.get(),
                    },
                    offset,
                );
                p.homesw_out.set(home);
                p.maxsw_out.set(max);
                p.minsw_out.set(min);
                p.bothsw_out.set(max || min);
                // LinuxCNC never sets the A axis's combined pins.
                if AXES[k] != 'A' {
                    p.maxsw_homesw_out.set(max || home);
                    p.minsw_homesw_out.set(min || home);
                    p.bothsw_homesw_out.set(max || min || home);
                }
                any_home |= home;
                any_limit |= max || min;
            }
            homesw_all.set(any_home);
            limitsw_all.set(any_limit);
            limitsw_homesw_all.set(any_home || any_limit);
        })
    }
}
halcomp_module!(pub MODULE, SimAxisHardware, "simulate home and limit switches");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn switches() {
        let a = AxisInputs {
            current_pos: 1.005,
            homesw_pos: 1.0,
            homesw_hyst: 0.02,
            maxsw_upper: 12.0,
            maxsw_lower: 10.0,
            minsw_upper: -10.0,
            minsw_lower: -12.0,
        };
        assert_eq!(axis_switches(&a, 0.01), (true, false, false));
        let at_max = AxisInputs {
            current_pos: 10.5,
            ..a
        };
        assert_eq!(axis_switches(&at_max, 0.01), (false, true, false));
        // The offset moves the max switch's lower edge up.
        let edge = AxisInputs {
            current_pos: 10.005,
            ..a
        };
        assert_eq!(axis_switches(&edge, 0.01), (false, false, false));
        let at_min = AxisInputs {
            current_pos: -11.0,
            ..a
        };
        assert_eq!(axis_switches(&at_min, 0.01), (false, false, true));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("sim-axis-hw");
        h.load(&MODULE, &[]).unwrap();
        let mut want = vec![
            "homesw-all bit out 0".to_string(),
            "limitsw-all bit out 0".into(),
            "limitsw-homesw-all bit out 0".into(),
            "limit-offset float in 0.01".into(),
        ];
        for a in AXES {
            for p in [
                "current-pos float in 0",
                "homesw-pos float in 1",
                "maxsw-upper float in 0",
                "maxsw-lower float in 0",
                "minsw-upper float in 0",
                "minsw-lower float in 0",
                "homesw-hyst float in 0.02",
                "homesw-out bit out 0",
                "maxsw-out bit out 0",
                "minsw-out bit out 0",
                "bothsw-out bit out 0",
                "maxsw-homesw-out bit out 0",
                "minsw-homesw-out bit out 0",
                "bothsw-homesw-out bit out 0",
            ] {
                want.push(format!("{a}{p}"));
            }
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("sim-axis-hardware.0", &want);
        assert_eq!(h.functs(), ["sim-axis-hardware.0.update"]);
        h.thread(&["sim-axis-hardware.0.update"]);
        h.expect(
            &[("sim-axis-hardware.0.Acurrent-pos", Float(1.0))],
            "sim-axis-hardware.0.Ahomesw-out",
            Bit(true),
        );
        assert_eq!(h.get("sim-axis-hardware.0.homesw-all"), Bit(true));
        assert_eq!(h.get("sim-axis-hardware.0.Abothsw-homesw-out"), Bit(false));
    }
}
