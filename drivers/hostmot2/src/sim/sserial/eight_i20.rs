//! The simulated 8I20's power stage: what the drive does with the
//! current it is told to drive, and what it reports back.
//!
//! The host sends a rotor angle (which the drive uses to commutate) and
//! a current command in amps; the drive answers with its card
//! temperature (°C), its bus voltage and a status and a fault word
//! ([`legacy::EIGHT_I20_STATUS`], [`legacy::EIGHT_I20_FAULT`]).
//!
//! The model (this simulator's, not Mesa's figures): the drive is
//! enabled while process data flow, its enable input is on and no fault
//! is latched; it then drives the commanded current, limited to its
//! maximum current (`status.current-lim`), and reports `status.pid-on`.
//! The bus is a supply of [`EightI20::supply_volts`] sagging 0.05 V per
//! amp; `status.bus-underv` below `nvbusundervmax`, the braking resistor
//! on above `nvbrakeonv` and off again below `nvbrakeoffv`. The card
//! warms toward 25 °C + 0.1 °C/A² × I² with a 30 s time constant. A bus
//! over `nvbusoverv` or under `nvbusundervmin`, a card over 100 °C and
//! the watchdog latch a fault that turns the output off until the
//! channel is started again. Voltages and currents in the card's memory
//! are in hundredths (0.01 V, 0.01 A).

use crate::sserial::legacy;

/// Ambient temperature, °C.
const AMBIENT_C: f64 = 25.0;
/// Temperature rise per amp squared, °C/A².
const HEATING_C_PER_A2: f64 = 0.1;
/// Thermal time constant, s.
const THERMAL_TAU_S: f64 = 30.0;
/// Card temperature that trips the over-temperature fault, °C.
const OVERTEMP_C: f64 = 100.0;
/// Bus sag per amp, V/A.
const SAG_V_PER_A: f64 = 0.05;

/// Limits from the card's memory, in volts and amps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Largest current the drive delivers.
    pub max_current: f64,
    /// Bus voltage under which the drive faults (0: never).
    pub under_min: f64,
    /// Bus voltage under which it reports a low bus.
    pub under_max: f64,
    /// Bus voltage over which the drive faults (0: never).
    pub over: f64,
    /// Braking resistor on above, off below.
    pub brake_on: f64,
    /// Braking resistor off below.
    pub brake_off: f64,
}

/// Fault bits (in the fault word).
mod fault {
    pub const WATCHDOG: u16 = 1 << 0;
    pub const OVERTEMP: u16 = 1 << 2;
    pub const BUS_UNDERV: u16 = 1 << 8;
    pub const BUS_OVERV: u16 = 1 << 10;
}

/// Status bits (in the status word).
mod stat {
    pub const CURRENT_LIM: u16 = 1 << 0;
    pub const BRAKE_ON: u16 = 1 << 1;
    pub const BUS_UNDERV: u16 = 1 << 3;
    pub const NO_ENABLE: u16 = 1 << 8;
    pub const PID_ON: u16 = 1 << 9;
}

/// The drive's state.
#[derive(Debug, Clone, PartialEq)]
pub struct EightI20 {
    /// The DC supply feeding the bus, V.
    pub supply_volts: f64,
    /// The hardware enable input.
    pub enable_input: bool,
    /// Card temperature, °C.
    pub temperature: f64,
    /// The current it drives, A.
    pub current: f64,
    /// The last commanded rotor angle (0..1 of a turn).
    pub angle: f64,
    status: u16,
    faults: u16,
}

impl Default for EightI20 {
    fn default() -> Self {
        EightI20 {
            supply_volts: 160.0,
            enable_input: true,
            temperature: AMBIENT_C,
            current: 0.0,
            angle: 0.0,
            status: 0,
            faults: 0,
        }
    }
}

impl EightI20 {
    /// The bus voltage now.
    pub fn bus_volts(&self) -> f64 {
        (self.supply_volts - SAG_V_PER_A * self.current.abs()).max(0.0)
    }

    /// The status word.
    pub fn status_word(&self) -> u16 {
        self.status
    }

    /// The fault word.
    pub fn fault_word(&self) -> u16 {
        self.faults
    }

    /// Clears the latched faults (a start of the channel).
    pub fn restart(&mut self) {
        self.faults = 0;
    }

    /// Latches the watchdog fault and drops the output.
    pub fn watchdog(&mut self) {
        self.faults |= fault::WATCHDOG;
        self.current = 0.0;
        self.status &= !(stat::PID_ON | stat::CURRENT_LIM);
    }

    /// One process-data cycle: the host's `angle` and `current`
    /// command, with the card's `limits`.
    pub fn command(&mut self, angle: f64, current: f64, limits: &Limits) {
        self.angle = angle;
        let bus = self.bus_volts();
        if limits.over > 0.0 && bus > limits.over {
            self.faults |= fault::BUS_OVERV;
        }
        if limits.under_min > 0.0 && bus < limits.under_min {
            self.faults |= fault::BUS_UNDERV;
        }
        if self.temperature > OVERTEMP_C {
            self.faults |= fault::OVERTEMP;
        }
        let enabled = self.enable_input && self.faults == 0;
        let max = limits.max_current.abs();
        let limited = current.abs() > max;
        self.current = if enabled {
            current.clamp(-max, max)
        } else {
            0.0
        };
        let bus = self.bus_volts();
        let mut s = self.status & stat::BRAKE_ON;
        if bus > limits.brake_on && limits.brake_on > 0.0 {
            s |= stat::BRAKE_ON;
        } else if bus < limits.brake_off {
            s &= !stat::BRAKE_ON;
        }
        if bus < limits.under_max {
            s |= stat::BUS_UNDERV;
        }
        if !self.enable_input {
            s |= stat::NO_ENABLE;
        }
        if enabled {
            s |= stat::PID_ON;
            if limited {
                s |= stat::CURRENT_LIM;
            }
        }
        self.status = s;
    }

    /// Lets `dt_ns` pass: the card warms or cools.
    pub fn advance(&mut self, dt_ns: u64) {
        let dt = dt_ns as f64 * 1e-9;
        let target = AMBIENT_C + HEATING_C_PER_A2 * self.current * self.current;
        let k = (dt / THERMAL_TAU_S).min(1.0);
        self.temperature += (target - self.temperature) * k;
    }

    /// The values of the card's input records, by record name.
    pub fn inputs(&self) -> Vec<(String, f64)> {
        let mut v = vec![
            ("card-temp".to_string(), self.temperature.round()),
            ("bus-voltage".to_string(), self.bus_volts()),
        ];
        let words = [
            ("status", &legacy::EIGHT_I20_STATUS, self.status),
            ("fault", &legacy::EIGHT_I20_FAULT, self.faults),
        ];
        for (prefix, names, word) in words {
            for (bit, name) in names.iter().enumerate() {
                if let Some(n) = name {
                    let on = word & (1 << bit) != 0;
                    v.push((format!("{prefix}.{n}"), f64::from(u8::from(on))));
                }
            }
        }
        v
    }

    /// The Smart Serial status bits the card shows for its faults.
    pub fn cs_status(&self) -> u32 {
        use crate::sserial::status as s;
        let mut st = 0;
        if self.faults & fault::OVERTEMP != 0 {
            st |= s::OVER_TEMPERATURE;
        }
        if self.faults & fault::BUS_OVERV != 0 {
            st |= s::OVER_VOLTAGE;
        }
        if self.faults & fault::BUS_UNDERV != 0 {
            st |= s::UNDER_VOLTAGE;
        }
        if st != 0 {
            st |= s::REMOTE_FAULT;
        }
        st
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> Limits {
        Limits {
            max_current: 20.0,
            under_min: 50.0,
            under_max: 60.0,
            over: 390.0,
            brake_on: 370.0,
            brake_off: 360.0,
        }
    }

    fn input(d: &EightI20, name: &str) -> f64 {
        d.inputs().into_iter().find(|(n, _)| n == name).unwrap().1
    }

    #[test]
    fn drives_the_current_within_its_limit() {
        let mut d = EightI20::default();
        d.command(0.25, 5.0, &limits());
        assert_eq!(d.current, 5.0);
        assert_eq!(input(&d, "status.pid-on"), 1.0);
        assert_eq!(input(&d, "status.current-lim"), 0.0);
        assert!((d.bus_volts() - 159.75).abs() < 1e-9);
        d.command(0.25, -35.0, &limits());
        assert_eq!(d.current, -20.0);
        assert_eq!(input(&d, "status.current-lim"), 1.0);
        d.enable_input = false;
        d.command(0.25, 5.0, &limits());
        assert_eq!(d.current, 0.0);
        assert_eq!(input(&d, "status.no-enable"), 1.0);
        assert_eq!(input(&d, "status.pid-on"), 0.0);
    }

    #[test]
    fn warms_with_current_and_latches_faults() {
        let mut d = EightI20::default();
        d.command(0.0, 20.0, &limits());
        for _ in 0..300 {
            d.advance(1_000_000_000);
        }
        assert!((d.temperature - 65.0).abs() < 0.5, "{}", d.temperature);
        d.temperature = 101.0;
        d.command(0.0, 20.0, &limits());
        assert_eq!(d.current, 0.0);
        assert_eq!(input(&d, "fault.overtemp"), 1.0);
        assert_ne!(d.cs_status() & crate::sserial::status::OVER_TEMPERATURE, 0);
        d.temperature = 30.0;
        d.command(0.0, 1.0, &limits());
        assert_eq!(d.current, 0.0, "latched until restarted");
        d.restart();
        d.supply_volts = 400.0;
        d.command(0.0, 1.0, &limits());
        assert_eq!(input(&d, "fault.bus-overv"), 1.0);
        d.restart();
        d.supply_volts = 375.0;
        d.command(0.0, 0.0, &limits());
        assert_eq!(input(&d, "status.brake-on"), 1.0);
        d.supply_volts = 365.0;
        d.command(0.0, 0.0, &limits());
        assert_eq!(input(&d, "status.brake-on"), 1.0, "hysteresis");
        d.supply_volts = 40.0;
        d.command(0.0, 0.0, &limits());
        assert_eq!(input(&d, "status.bus-underv"), 1.0);
        assert_eq!(input(&d, "fault.bus-underv"), 1.0);
        d.restart();
        d.supply_volts = 160.0;
        d.command(0.0, 2.0, &limits());
        d.watchdog();
        assert_eq!(d.current, 0.0);
        assert_eq!(input(&d, "fault.watchdog"), 1.0);
    }
}
