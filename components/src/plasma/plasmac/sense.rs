//! What `plasmac` senses every period, in every state: the arc voltage
//! (offset, scaled, low-pass filtered, zeroed near zero), Arc OK (from
//! the voltage in mode 0, from `arc-ok-in` in modes 1 and 2) and the
//! debounced ohmic sense.

use super::pins::Inputs;

/// The filters and counters behind the senses.
#[derive(Debug, Clone, Default)]
pub struct Senses {
    /// The filtered arc voltage.
    pub volts: f64,
    /// The voltage of the previous period (for the Arc OK deviation).
    last_volts: f64,
    /// Consecutive in-window samples (mode 0 Arc OK).
    ok_count: i32,
    /// Arc OK as last decided.
    pub arc_ok: bool,
    /// Debounce count of the ohmic sense.
    ohmic_count: i32,
    /// The debounced ohmic sense.
    pub ohmic_sense: bool,
}

impl Senses {
    /// One period of `dt` seconds.
    pub fn update(&mut self, i: &Inputs, dt: f64) {
        self.voltage(i, dt);
        self.arc_ok(i);
        self.ohmic(i);
    }

    fn voltage(&mut self, i: &Inputs, dt: f64) {
        let raw = (i.arc_voltage_in - i.arc_voltage_offset) * i.arc_voltage_scale;
        let mut v = if i.lowpass_frequency > 0.0 && dt > 0.0 {
            let alpha = 1.0 - (-std::f64::consts::TAU * i.lowpass_frequency * dt).exp();
            self.volts + alpha * (raw - self.volts)
        } else {
            raw
        };
        if !v.is_finite() {
            v = 0.0;
        }
        self.last_volts = self.volts;
        self.volts = if v.abs() < i.zero_window { 0.0 } else { v };
    }

    fn arc_ok(&mut self, i: &Inputs) {
        if i.mode > 0 {
            self.arc_ok = i.arc_ok_in;
            self.ok_count = 0;
            return;
        }
        let in_window = self.volts >= i.arc_ok_low
            && self.volts <= i.arc_ok_high
            && self.volts > 0.0
            && (self.volts - self.last_volts).abs() <= i.ok_sample_threshold;
        if in_window {
            self.ok_count = self.ok_count.saturating_add(1);
        } else {
            self.ok_count = 0;
        }
        self.arc_ok = self.ok_count >= i.ok_sample_counts.max(1);
    }

    fn ohmic(&mut self, i: &Inputs) {
        if i.ohmic_sense_in == self.ohmic_sense {
            self.ohmic_count = 0;
            return;
        }
        self.ohmic_count = self.ohmic_count.saturating_add(1);
        let need = if i.ohmic_sense_in {
            i.ohmic_sense_on_delay
        } else {
            i.ohmic_sense_off_delay
        };
        if self.ohmic_count >= need {
            self.ohmic_sense = i.ohmic_sense_in;
            self.ohmic_count = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs() -> Inputs {
        Inputs {
            arc_voltage_scale: 1.0,
            arc_ok_low: 60.0,
            arc_ok_high: 250.0,
            ok_sample_counts: 3,
            ..Inputs::default()
        }
    }

    #[test]
    fn mode_0_arc_ok_needs_steady_samples_in_the_window() {
        let mut s = Senses::default();
        let mut i = inputs();
        i.arc_voltage_in = 120.0;
        s.update(&i, 0.001); // jump from 0: not steady
        assert!(!s.arc_ok);
        s.update(&i, 0.001);
        s.update(&i, 0.001);
        assert!(!s.arc_ok);
        s.update(&i, 0.001);
        assert!(s.arc_ok);
        i.arc_voltage_in = 300.0;
        s.update(&i, 0.001);
        assert!(!s.arc_ok);
        i.mode = 1;
        i.arc_ok_in = true;
        s.update(&i, 0.001);
        assert!(s.arc_ok);
    }

    #[test]
    fn voltage_is_offset_scaled_and_zeroed_near_zero() {
        let mut s = Senses::default();
        let mut i = inputs();
        i.arc_voltage_in = 10.04;
        i.arc_voltage_offset = 10.0;
        i.arc_voltage_scale = 2.0;
        s.update(&i, 0.001);
        assert_eq!(s.volts, 0.0);
        i.arc_voltage_in = 60.0;
        s.update(&i, 0.001);
        assert_eq!(s.volts, 100.0);
        i.lowpass_frequency = 100.0;
        i.arc_voltage_in = 10.0;
        s.update(&i, 0.001);
        assert!(s.volts > 0.0 && s.volts < 100.0, "{}", s.volts);
    }

    #[test]
    fn ohmic_sense_is_debounced_both_ways() {
        let mut s = Senses::default();
        let mut i = inputs();
        i.ohmic_sense_in = true;
        s.update(&i, 0.001);
        s.update(&i, 0.001);
        assert!(!s.ohmic_sense);
        s.update(&i, 0.001);
        assert!(s.ohmic_sense);
        i.ohmic_sense_in = false;
        i.ohmic_sense_off_delay = 1;
        s.update(&i, 0.001);
        assert!(!s.ohmic_sense);
    }
}
