//! `ohmic`: ohmic (touch) sensing through a Mesa THCAD card read as a
//! frequency by an encoder: scales the frequency to the card's volts and
//! the sensing circuit's volts, sets `ohmic-on` above the threshold
//! while probing and clears it below `ohmic-low`, and shows `arc-on` at
//! the card's full scale.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin values one call reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OhmicInputs {
    /// Pin `thcad-0-volt-freq` (Hz).
    pub zero_volt_freq: f64,
    /// Pin `thcad-max-volt-freq` (Hz).
    pub max_volt_freq: f64,
    /// Pin `thcad-divide`.
    pub divide: f64,
    /// Pin `thcad-fullscale` (volts).
    pub fullscale: f64,
    /// Pin `velocity-in` (the encoder's frequency).
    pub velocity_in: f64,
    /// Pin `volt-divider`.
    pub volt_divider: f64,
    /// Pin `ohmic-threshold`.
    pub threshold: f64,
    /// Pin `ohmic-low`.
    pub low: f64,
    /// Pin `is-probing`.
    pub is_probing: bool,
}

impl Default for OhmicInputs {
    /// The pins' defaults.
    fn default() -> Self {
        OhmicInputs {
            zero_volt_freq: 0.0,
            max_volt_freq: 0.0,
            divide: 32.0,
            fullscale: 5.0,
            velocity_in: 0.0,
            volt_divider: 4.9,
            threshold: 18.0,
            low: 5.0,
            is_probing: false,
        }
    }
}

/// The outputs: (thcad-volts, ohmic-volts, arc-on) and the new
/// `ohmic-on` (`None`: unchanged).
pub fn ohmic(i: &OhmicInputs) -> (f64, f64, bool, Option<bool>) {
    let vel_scale = 1.0 / ((i.max_volt_freq - i.zero_volt_freq) / i.fullscale / i.divide);
    let scale_offset = i.zero_volt_freq / i.divide;
    let thcad_volts = (i.velocity_in - scale_offset) * vel_scale;
    let ohmic_volts = thcad_volts * i.volt_divider;
    let on = if i.is_probing {
        // LinuxCNC compares with the truth value of `threshold &&
        // is-probing` (1 or 0), not with the threshold itself.
        let level = if i.threshold != 0.0 { 1.0 } else { 0.0 };
        Some(ohmic_volts > level)
    } else if ohmic_volts < i.low {
        Some(false)
    } else {
        None
    };
    (thcad_volts, ohmic_volts, thcad_volts >= i.fullscale, on)
}

/// The `ohmic` component.
pub struct Ohmic;
impl HalComp for Ohmic {
    const NAME: &'static str = "ohmic";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let d = OhmicInputs::default();
        let zero = inst.pin_in::<f64>("thcad-0-volt-freq")?;
        let max = inst.pin_in::<f64>("thcad-max-volt-freq")?;
        let divide = inst.pin_in_init::<f64>("thcad-divide", d.divide)?;
        let fullscale = inst.pin_in_init::<f64>("thcad-fullscale", d.fullscale)?;
        let velocity_in = inst.pin_in::<f64>("velocity-in")?;
        let volt_divider = inst.pin_in_init::<f64>("volt-divider", d.volt_divider)?;
        let threshold = inst.pin_in_init::<f64>("ohmic-threshold", d.threshold)?;
        let low = inst.pin_in_init::<f64>("ohmic-low", d.low)?;
        let arc_on = inst.pin_out::<bool>("arc-on")?;
        let thcad_volts = inst.pin_out::<f64>("thcad-volts")?;
        let ohmic_volts = inst.pin_out::<f64>("ohmic-volts")?;
        let ohmic_on = inst.pin_out::<bool>("ohmic-on")?;
        let is_probing = inst.pin_in::<bool>("is-probing")?;
        inst.funct("_", true, move |_| {
            let (tv, ov, arc, on) = ohmic(&OhmicInputs {
                zero_volt_freq: zero.get(),
                max_volt_freq: max.get(),
                divide: divide.get(),
                fullscale: fullscale.get(),
                velocity_in: velocity_in.get(),
                volt_divider: volt_divider.get(),
                threshold: threshold.get(),
                low: low.get(),
                is_probing: is_probing.get(),
            });
            thcad_volts.set(tv);
            ohmic_volts.set(ov);
            if let Some(on) = on {
                ohmic_on.set(on);
            }
            arc_on.set(arc);
        })
    }
}
halcomp_module!(pub MODULE, Ohmic, "ohmic sensing with a Mesa THCAD");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    fn card(freq: f64) -> OhmicInputs {
        OhmicInputs {
            zero_volt_freq: 122900.0,
            max_volt_freq: 925700.0,
            velocity_in: freq,
            ..Default::default()
        }
    }

    #[test]
    fn scaling_thresholds_and_arc() {
        let (tv, ov, arc, on) = ohmic(&card(122900.0 / 32.0));
        assert!(tv.abs() < 1e-12 && ov.abs() < 1e-12 && !arc);
        assert_eq!(on, Some(false), "below ohmic-low");
        let full = 925700.0 / 32.0;
        let (tv, _, arc, _) = ohmic(&card(full));
        assert!((tv - 5.0).abs() < 1e-9 && arc == (tv >= 5.0));
        // Probing: on above 1 V of sensed voltage (LinuxCNC's quirk).
        let mut i = card((122900.0 + 0.5 * (925700.0 - 122900.0) / 5.0) / 32.0);
        i.is_probing = true;
        let (_, ov, _, on) = ohmic(&i);
        assert!((ov - 0.5 * 4.9).abs() < 1e-9);
        assert_eq!(on, Some(true));
        i.is_probing = false;
        assert_eq!(ohmic(&i).3, Some(false), "2.45 V is below ohmic-low");
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("ohmic");
        h.load(&MODULE, &["names=ohmicsense"]).unwrap();
        h.check_pins(
            "ohmicsense",
            &[
                "thcad-0-volt-freq float in 0",
                "thcad-max-volt-freq float in 0",
                "thcad-divide float in 32",
                "thcad-fullscale float in 5",
                "velocity-in float in 0",
                "volt-divider float in 4.9",
                "ohmic-threshold float in 18",
                "ohmic-low float in 5",
                "arc-on bit out 0",
                "thcad-volts float out 0",
                "ohmic-volts float out 0",
                "ohmic-on bit out 0",
                "is-probing bit in 0",
            ],
        );
        h.thread(&["ohmicsense"]);
        h.set("ohmicsense.thcad-max-volt-freq", Float(160.0));
        h.expect(
            &[("ohmicsense.velocity-in", Float(5.0))],
            "ohmicsense.arc-on",
            Bit(true),
        );
    }
}
