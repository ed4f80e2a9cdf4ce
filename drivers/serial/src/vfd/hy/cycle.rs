//! What `hy_vfd` does each cycle: the set-up reads and writes once
//! enabled, then the status reads and the frequency and control writes.

use std::io::Write as _;
use std::time::Duration;

use hal_core::Component;

use super::options::HyOptions;
use super::pins::HyPins;
use crate::error::{Result, SerialError};
use crate::line::SerialLine;
use crate::modbus::Master;
use crate::regs::hy;
use crate::vfd::{Cycle, Link};

/// Consecutive good reads and writes after which `hycomm-ok` rises
/// (LinuxCNC: more than 10).
const HYCOMM_MIN_OK: u32 = 10;

/// The component: options, pins, the master, the link's health.
pub struct HyVfd<L: SerialLine> {
    opts: HyOptions,
    pins: HyPins,
    link: Link,
    master: Master<L>,
    setup_done: bool,
    was_enabled: bool,
    /// The frequency the drive last confirmed, 0.01 Hz; None sends it
    /// again (at start and after the drive was lost).
    sent_freq: Option<u16>,
    good_phases: u32,
    /// This cycle's failure code for `retval`.
    cycle_code: i32,
}

impl<L: SerialLine> HyVfd<L> {
    /// Exports the pins on `comp` and takes the line. The set-up pins
    /// start with the command-line values, as in LinuxCNC.
    pub fn new(comp: &Component, opts: HyOptions, line: L) -> hal_core::Result<HyVfd<L>> {
        let pins = HyPins::new(comp, &opts.name)?;
        let link = Link::new(comp, &opts.name)?;
        pins.max_freq.set(opts.max_freq);
        pins.base_freq.set(opts.base_freq);
        pins.freq_lower_limit.set(opts.min_freq);
        pins.rated_motor_voltage.set(opts.motor_voltage);
        pins.rated_motor_current.set(opts.motor_current);
        pins.rated_motor_rev.set(opts.motor_speed);
        pins.motor_poles.set(opts.motor_poles);
        let master = Master::new(line, opts.serial.master);
        Ok(HyVfd {
            opts,
            pins,
            link,
            master,
            setup_done: false,
            was_enabled: false,
            sent_freq: None,
            good_phases: 0,
            cycle_code: 0,
        })
    }

    /// The master (tests reach the line through it).
    pub fn master_mut(&mut self) -> &mut Master<L> {
        &mut self.master
    }

    /// Whether the set-up parameters have been read.
    pub fn setup_done(&self) -> bool {
        self.setup_done
    }

    fn slave(&self) -> u8 {
        self.opts.serial.slave
    }

    /// Counts a failed transaction and reports it.
    fn failed(&mut self, e: &SerialError) {
        self.cycle_code = e.code();
        let n = self.pins.error_count.get();
        self.pins.error_count.set(n.wrapping_add(1));
        self.link.failed(e);
    }

    /// Writes PDn = `value` when `value` is given (non-zero), then reads
    /// PDn back.
    fn setup_parameter(&mut self, n: u8, value: Option<u16>) -> Result<u16> {
        let slave = self.slave();
        if let Some(v) = value {
            self.master.hy_write_parameter(slave, n, v)?;
        }
        self.master.hy_read_parameter(slave, n)
    }

    /// Prints PD001..PD183 (`-y`).
    fn regdump(&mut self) {
        // Written without print!, which panics when stdout has gone.
        let mut out = std::io::stdout();
        let _ = writeln!(out, "Current Register values list");
        let slave = self.slave();
        for n in 1..=hy::PD_LAST {
            let _ = match self.master.hy_read_parameter(slave, n) {
                Ok(v) => writeln!(out, "PD{n:03} = {v}"),
                Err(_) => writeln!(out, "PD{n:03} = INVALID"),
            };
        }
    }

    /// Writes what the command line gives and reads the drive's set-up
    /// into the pins, in LinuxCNC's order.
    fn setup(&mut self) -> Result<()> {
        let given = |v: f64, scale: f64| (v > 0.0).then(|| (v * scale).round().min(65535.0) as u16);
        let o = self.opts.clone();
        let max = self.setup_parameter(hy::PD_MAX_FREQUENCY, given(o.max_freq, 100.0))?;
        let max_freq = f64::from(max) * 0.01;
        self.pins.max_freq.set(max_freq);
        let base = self.setup_parameter(hy::PD_BASE_FREQUENCY, given(o.base_freq, 100.0))?;
        self.pins.base_freq.set(f64::from(base) * 0.01);
        let min = self.setup_parameter(hy::PD_MIN_FREQUENCY, given(o.min_freq, 100.0))?;
        self.pins.freq_lower_limit.set(f64::from(min) * 0.01);
        let v = self.setup_parameter(hy::PD_MOTOR_VOLTAGE, given(o.motor_voltage, 10.0))?;
        self.pins.rated_motor_voltage.set(f64::from(v) * 0.1);
        let a = self.setup_parameter(hy::PD_MOTOR_CURRENT, given(o.motor_current, 10.0))?;
        self.pins.rated_motor_current.set(f64::from(a) * 0.1);
        let poles = (o.motor_poles > 0).then_some(o.motor_poles as u16);
        let poles = self.setup_parameter(hy::PD_MOTOR_POLES, poles)?;
        self.pins.motor_poles.set(u32::from(poles));
        // -S is the speed at the maximum frequency; PD144 holds the speed
        // at 50 Hz.
        let rpm_at_50 = (o.motor_speed > 0.0 && max_freq > 0.0)
            .then(|| (o.motor_speed / max_freq * 50.0).round().min(65535.0) as u16);
        let rpm_at_50 = self.setup_parameter(hy::PD_MOTOR_RPM_AT_50HZ, rpm_at_50)?;
        self.pins
            .rated_motor_rev
            .set(f64::from(rpm_at_50) / 50.0 * max_freq);
        let slave = self.slave();
        for &(n, value) in &o.registers {
            self.master.hy_write_parameter(slave, n, value)?;
            self.master.hy_read_parameter(slave, n)?;
            if self.opts.serial.master.debug {
                println!("Register {n} successfully set to {value}");
            }
        }
        Ok(())
    }

    /// Reads the eight status values; speed feedback and at-speed
    /// follow the output frequency.
    fn read_data(&mut self) -> Result<()> {
        let slave = self.slave();
        let scale = [0.01, 0.01, 0.1, 1.0, 1.0, 1.0, 1.0, 1.0];
        for index in 0..hy::STATUS_COUNT {
            let v = self.master.hy_read_status(slave, index)?;
            self.pins.status[usize::from(index)].set(f64::from(v) * scale[usize::from(index)]);
            if index == hy::STATUS_OUT_F {
                self.update_feedback();
            }
        }
        Ok(())
    }

    /// Speed feedback from OutF while the spindle runs on a command;
    /// at-speed when it is within the tolerance of the command.
    fn update_feedback(&self) {
        let p = &self.pins;
        let cmd = p.speed_command.get().abs();
        let set_f = p.status[usize::from(hy::STATUS_SET_F)].get();
        let max = p.max_freq.get();
        if p.spindle_on.get() && cmd > 0.0 && set_f > 0.0 && max > 0.0 {
            let out_f = p.status[usize::from(hy::STATUS_OUT_F)].get();
            let fb = out_f / max * p.rated_motor_rev.get();
            p.speed_fb.set(fb);
            p.speed_fb_rps.set(fb / 60.0);
            p.at_speed
                .set((1.0 - fb / cmd).abs() < p.at_speed_tolerance.get());
        } else {
            p.speed_fb.set(0.0);
            p.speed_fb_rps.set(0.0);
            p.at_speed.set(false);
        }
    }

    /// The control word for the pins: forward or reverse when exactly
    /// one of them is set and the spindle is on.
    fn cntr(&self) -> u8 {
        let p = &self.pins;
        let (fwd, rev, on) = (
            p.spindle_forward.get(),
            p.spindle_reverse.get(),
            p.spindle_on.get(),
        );
        match (on, fwd, rev) {
            (true, true, false) => hy::CNTR_RUN_FORWARD,
            (true, false, true) => hy::CNTR_RUN_REVERSE,
            _ => hy::CNTR_STOP,
        }
    }

    /// The frequency for `speed-command`, 0.01 Hz, within PD011..PD005.
    fn frequency(&self) -> u16 {
        let p = &self.pins;
        let (max, min, rev) = (
            p.max_freq.get(),
            p.freq_lower_limit.get(),
            p.rated_motor_rev.get(),
        );
        let hz_per_rpm = if rev > 0.0 { max / rev } else { 0.0 };
        let f = (p.speed_command.get().abs() * hz_per_rpm * 100.0).round();
        let f = f.min(max * 100.0).max(min * 100.0);
        if f.is_finite() {
            f.clamp(0.0, 65535.0) as u16
        } else {
            0
        }
    }

    /// Sends the frequency when it changed, then the control word; shows
    /// the status byte the drive answers.
    fn write_data(&mut self) -> Result<()> {
        let slave = self.slave();
        let freq = self.frequency();
        if self.sent_freq != Some(freq) {
            self.master.hy_write_frequency(slave, freq)?;
            self.sent_freq = Some(freq);
            self.pins.frequency_command.set(f64::from(freq));
        }
        let cntr = self.cntr();
        let cnst = self.master.hy_write_control(slave, cntr)?;
        self.pins.cntr.set(f64::from(cntr));
        self.show_cnst(cnst);
        Ok(())
    }

    fn show_cnst(&self, cnst: u8) {
        self.pins.cnst.set(f64::from(cnst));
        for (bit, pin) in self.pins.cnst_bits.iter().enumerate() {
            pin.set(cnst & (1 << bit) != 0);
        }
    }

    /// Counts a read or write phase for `hycomm-ok`.
    fn phase(&mut self, r: Result<()>) {
        match r {
            Ok(()) => self.good_phases = self.good_phases.saturating_add(1),
            Err(e) => {
                self.good_phases = 0;
                self.failed(&e);
            }
        }
    }

    /// Tells the drive to stop (enable fell, or the program ends).
    fn stop(&mut self) {
        let slave = self.slave();
        match self.master.hy_write_control(slave, hy::CNTR_STOP) {
            Ok(cnst) => {
                self.pins.cntr.set(f64::from(hy::CNTR_STOP));
                self.show_cnst(cnst);
            }
            Err(e) => self.failed(&e),
        }
    }
}

impl<L: SerialLine> Cycle for HyVfd<L> {
    fn cycle(&mut self) {
        if !self.pins.enable.get() {
            if self.was_enabled {
                // LinuxCNC leaves the spindle as it was; stop it.
                self.was_enabled = false;
                if self.setup_done {
                    self.stop();
                }
            }
            return;
        }
        self.was_enabled = true;
        self.cycle_code = 0;
        self.link.begin_cycle();
        if !self.setup_done {
            if self.opts.regdump {
                self.regdump();
            }
            match self.setup() {
                Ok(()) => self.setup_done = true,
                Err(e) => {
                    eprintln!("{}: error reading setup from VFD, retrying", self.opts.name);
                    self.failed(&e);
                }
            }
        }
        if self.setup_done {
            let r = self.read_data();
            self.phase(r);
            if !self.link.lost() {
                let r = self.write_data();
                self.phase(r);
            }
        }
        if self.link.lost() {
            // Outputs safe before the fault pin says why.
            self.sent_freq = None;
            self.pins.at_speed.set(false);
        }
        self.link.end_cycle(0);
        self.pins.hycomm_ok.set(self.good_phases > HYCOMM_MIN_OK);
        self.pins.retval.set(self.cycle_code as u32);
    }

    fn period(&self) -> Duration {
        self.opts.period
    }

    fn shutdown(&mut self) {
        if self.was_enabled && self.setup_done {
            self.stop();
        }
    }
}
