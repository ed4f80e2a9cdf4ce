//! [`VfdModel`]: the drive and its spindle motor, protocol-free. The
//! inverter ramps its output frequency towards the commanded one at its
//! acceleration or deceleration rate; the motor is the driver layer's
//! [`DcMotor`] plant with the output frequency as its drive (slip and
//! inertia make its speed lag the frequency). Time passes only through
//! [`VfdModel::advance`].

use hal_driver::plant::{DcMotor, DcMotorParams};

/// The drive's and motor's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VfdParams {
    /// Maximum output frequency, Hz.
    pub max_freq_hz: f64,
    /// Lowest running frequency, Hz.
    pub min_freq_hz: f64,
    /// Base frequency (full voltage from here up), Hz.
    pub base_freq_hz: f64,
    /// Motor speed at the maximum frequency, rpm.
    pub rpm_at_max_freq: f64,
    /// Ramp rate up, Hz per second.
    pub accel_hz_per_s: f64,
    /// Ramp rate down, Hz per second.
    pub decel_hz_per_s: f64,
    /// Rated motor voltage, V.
    pub rated_volts: f64,
    /// Rated motor current, A.
    pub rated_amps: f64,
    /// Motor poles.
    pub poles: u16,
    /// DC bus voltage, V.
    pub dc_bus_volts: f64,
}

impl Default for VfdParams {
    /// A 2.2 kW water-cooled router spindle: 24 000 rpm at 400 Hz, a
    /// 120 Hz floor, 400 Hz per second ramps.
    fn default() -> VfdParams {
        VfdParams {
            max_freq_hz: 400.0,
            min_freq_hz: 120.0,
            base_freq_hz: 400.0,
            rpm_at_max_freq: 24_000.0,
            accel_hz_per_s: 400.0,
            decel_hz_per_s: 400.0,
            rated_volts: 220.0,
            rated_amps: 10.0,
            poles: 2,
            dc_bus_volts: 311.0,
        }
    }
}

/// What the drive was told to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunCommand {
    /// Ramp down and stay off.
    Stop,
    /// Run forward at the set frequency.
    Forward,
    /// Run in reverse at the set frequency.
    Reverse,
}

/// Mechanical time constant of spindle and motor, s.
const MOTOR_TAU_S: f64 = 0.05;
/// Longest step of the simulation, ns: the ramp is sampled this often.
const STEP_NS: u64 = 1_000_000;

/// A VFD driving a spindle motor.
#[derive(Debug, Clone)]
pub struct VfdModel {
    params: VfdParams,
    command: RunCommand,
    set_freq_hz: f64,
    out_freq_hz: f64,
    motor: DcMotor,
    fault: u16,
    braking: bool,
}

impl VfdModel {
    /// A stopped drive.
    pub fn new(params: VfdParams) -> VfdModel {
        VfdModel {
            motor: DcMotor::new(motor_params(&params)),
            params,
            command: RunCommand::Stop,
            set_freq_hz: 0.0,
            out_freq_hz: 0.0,
            fault: 0,
            braking: false,
        }
    }

    /// The constants.
    pub fn params(&self) -> &VfdParams {
        &self.params
    }

    /// Changes the constants (a parameter written over the line); the
    /// motor keeps its speed.
    pub fn set_params(&mut self, params: VfdParams) {
        let mut motor = DcMotor::new(motor_params(&params));
        motor.set_position(self.motor.position());
        // Carry the present speed over by letting the new motor reach
        // it: an instant change of constants keeps the shaft's state.
        let speed = self.motor.velocity();
        self.motor = motor;
        self.preset_speed(speed);
        self.params = params;
    }

    fn preset_speed(&mut self, revs_per_s: f64) {
        // DcMotor has no speed setter; drive it at the speed's frequency
        // for many time constants and restore the position.
        let pos = self.motor.position();
        let k = self.motor.params().speed_per_volt;
        if k > 0.0 && revs_per_s != 0.0 {
            self.motor.set_volts(revs_per_s / k);
            self.motor.advance((MOTOR_TAU_S * 40.0 * 1e9) as u64);
        }
        self.motor.set_position(pos);
    }

    /// Commands run or stop; a faulted drive ignores run commands.
    pub fn set_command(&mut self, command: RunCommand) {
        if self.fault == 0 || command == RunCommand::Stop {
            self.command = command;
        }
    }

    /// The last run command.
    pub fn command(&self) -> RunCommand {
        self.command
    }

    /// Sets the frequency set point, clamped to 0..=maximum.
    pub fn set_frequency(&mut self, hz: f64) {
        self.set_freq_hz = if hz.is_finite() {
            hz.clamp(0.0, self.params.max_freq_hz)
        } else {
            0.0
        };
    }

    /// The frequency set point, Hz.
    pub fn set_frequency_hz(&self) -> f64 {
        self.set_freq_hz
    }

    /// Trips the drive with fault `code` (non-zero): the output switches
    /// off at once and the motor coasts.
    pub fn trip(&mut self, code: u16) {
        self.fault = code.max(1);
        self.command = RunCommand::Stop;
        self.out_freq_hz = 0.0;
        self.braking = false;
    }

    /// Clears a fault.
    pub fn reset_fault(&mut self) {
        self.fault = 0;
    }

    /// The fault code, 0 when healthy.
    pub fn fault(&self) -> u16 {
        self.fault
    }

    /// The frequency the drive ramps towards, signed by direction.
    fn target_hz(&self) -> f64 {
        if self.fault != 0 {
            return 0.0;
        }
        let p = &self.params;
        let f = self.set_freq_hz.max(p.min_freq_hz).min(p.max_freq_hz);
        match self.command {
            RunCommand::Stop => 0.0,
            RunCommand::Forward => f,
            RunCommand::Reverse => -f,
        }
    }

    /// Lets `dt_ns` pass.
    pub fn advance(&mut self, dt_ns: u64) {
        let mut left = dt_ns;
        while left > 0 {
            let step = left.min(STEP_NS);
            left -= step;
            let dt = step as f64 * 1e-9;
            let target = self.target_hz();
            let diff = target - self.out_freq_hz;
            // Moving away from zero accelerates; towards it decelerates.
            let slowing = target.abs() < self.out_freq_hz.abs()
                || target.signum() * self.out_freq_hz.signum() < 0.0;
            let rate = if slowing {
                self.params.decel_hz_per_s
            } else {
                self.params.accel_hz_per_s
            };
            let max_change = rate * dt;
            self.braking = slowing && diff.abs() > 0.0;
            self.out_freq_hz = if diff.abs() <= max_change {
                target
            } else {
                self.out_freq_hz + max_change * diff.signum()
            };
            self.motor.set_volts(self.out_freq_hz);
            self.motor.advance(step);
        }
    }

    /// Output frequency, Hz, signed by direction.
    pub fn output_frequency_hz(&self) -> f64 {
        self.out_freq_hz
    }

    /// Spindle speed, rpm, signed by direction.
    pub fn rpm(&self) -> f64 {
        self.motor.velocity() * 60.0
    }

    /// Whether the output is live.
    pub fn running(&self) -> bool {
        self.out_freq_hz != 0.0
    }

    /// Whether the drive is ramping down.
    pub fn braking(&self) -> bool {
        self.braking
    }

    /// Output voltage, V: volts per hertz up to the base frequency.
    pub fn output_volts(&self) -> f64 {
        let p = &self.params;
        let base = p.base_freq_hz.max(1.0);
        p.rated_volts * (self.out_freq_hz.abs() / base).min(1.0)
    }

    /// Output current, A: magnetising current while running plus a part
    /// that grows with the slip (the motor lagging the frequency).
    pub fn output_amps(&self) -> f64 {
        if !self.running() {
            return 0.0;
        }
        let p = &self.params;
        let synchronous_rpm = self.out_freq_hz / p.max_freq_hz.max(1.0) * p.rpm_at_max_freq;
        let slip = ((synchronous_rpm - self.rpm()).abs() / p.rpm_at_max_freq.max(1.0)).min(1.0);
        p.rated_amps * (0.25 + 0.75 * (slip * 10.0).min(1.0))
    }

    /// Output power, W.
    pub fn output_watts(&self) -> f64 {
        self.output_volts() * self.output_amps() * 3f64.sqrt() * 0.8
    }

    /// DC bus voltage, V.
    pub fn dc_bus_volts(&self) -> f64 {
        self.params.dc_bus_volts
    }
}

fn motor_params(p: &VfdParams) -> DcMotorParams {
    DcMotorParams {
        // Revolutions per second per hertz of drive.
        speed_per_volt: p.rpm_at_max_freq / 60.0 / p.max_freq_hz.max(1.0),
        time_constant: MOTOR_TAU_S,
        friction: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramps_to_speed_and_back() {
        let mut m = VfdModel::new(VfdParams::default());
        m.set_frequency(200.0);
        m.set_command(RunCommand::Forward);
        m.advance(250_000_000);
        assert!(
            (m.output_frequency_hz() - 100.0).abs() < 1e-6,
            "half way up the ramp"
        );
        m.advance(2_000_000_000);
        assert_eq!(m.output_frequency_hz(), 200.0);
        assert!((m.rpm() - 12_000.0).abs() < 1.0, "{}", m.rpm());
        assert!(m.output_amps() > 0.0 && m.output_volts() == 110.0);
        m.set_command(RunCommand::Reverse);
        m.advance(100_000_000);
        assert!(m.braking());
        m.advance(3_000_000_000);
        assert_eq!(m.output_frequency_hz(), -200.0);
        assert!(m.rpm() < -11_999.0);
        m.set_command(RunCommand::Stop);
        m.advance(3_000_000_000);
        assert!(!m.running() && m.rpm().abs() < 1.0);
    }

    #[test]
    fn runs_no_slower_than_the_floor_and_trips() {
        let mut m = VfdModel::new(VfdParams::default());
        m.set_frequency(10.0);
        m.set_command(RunCommand::Forward);
        m.advance(1_000_000_000);
        assert_eq!(m.output_frequency_hz(), 120.0);
        m.trip(7);
        assert_eq!((m.fault(), m.output_frequency_hz()), (7, 0.0));
        m.set_command(RunCommand::Forward);
        assert_eq!(
            m.command(),
            RunCommand::Stop,
            "a faulted drive does not start"
        );
        m.reset_fault();
        m.set_command(RunCommand::Forward);
        assert_eq!(m.command(), RunCommand::Forward);
    }

    #[test]
    fn new_constants_keep_the_speed() {
        let mut m = VfdModel::new(VfdParams::default());
        m.set_frequency(400.0);
        m.set_command(RunCommand::Forward);
        m.advance(3_000_000_000);
        let rpm = m.rpm();
        let p = VfdParams {
            max_freq_hz: 500.0,
            ..*m.params()
        };
        m.set_params(p);
        assert!((m.rpm() - rpm).abs() < 1.0, "{} vs {rpm}", m.rpm());
    }
}
