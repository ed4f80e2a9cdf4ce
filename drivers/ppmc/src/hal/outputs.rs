//! The output blocks of the boards, with LinuxCNC's names: the DAC
//! board's four DACs, the USC's step generators, the UPC's PWM
//! generators and the extra port. Each fills the board's write cache;
//! nothing here touches the bus.

use canonical::{usable_scale, ChannelNames, DigOut, Pwm};
use hal_core::{HalHost, HostParam, HostPin, In, PinFactory, Result, Ro, Rw};

use crate::regs::{self, ctrl, dac, pwm, stepgen, uxc, SPAN};

/// One DAC channel: LinuxCNC's `value` pin and `scale` param (volts =
/// value / scale).
pub struct DacChannel<H: HalHost> {
    value: H::Pin<f64, In>,
    scale: H::Param<f64, Rw>,
}

impl<H: HalHost> DacChannel<H> {
    fn export(c: &impl PinFactory<H>, prefix: &str) -> Result<Self> {
        Ok(DacChannel {
            value: c.pin(&format!("{prefix}.value"))?,
            scale: c.param(&format!("{prefix}.scale"), 1.0)?,
        })
    }

    #[inline]
    fn volts(&self) -> f64 {
        self.value.get() / usable_scale(&self.scale)
    }
}

/// The DAC board's four 16-bit DACs (`ppmc.<bus>.DAC.<n>`).
pub struct Dacs<H: HalHost>(Vec<DacChannel<H>>);

impl<H: HalHost> Dacs<H> {
    /// Exports DACs `first..first + 4`.
    pub fn export(c: &impl PinFactory<H>, bus: usize, first: usize) -> Result<Self> {
        (first..first + 4)
            .map(|n| DacChannel::export(c, &format!("ppmc.{bus}.DAC.{n:02}")))
            .collect::<Result<Vec<_>>>()
            .map(Dacs)
    }

    /// Fills the DAC codes.
    pub fn write(&self, wr: &mut [u8; SPAN]) {
        for (n, d) in self.0.iter().enumerate() {
            let code = regs::dac16_code(d.volts());
            regs::put_le(wr, dac::DAC0 + 2 * n as u8, code as u32, 2);
        }
    }

    /// The codes of 0 V.
    pub fn safe(wr: &mut [u8; SPAN]) {
        for n in 0..4u8 {
            regs::put_le(wr, dac::DAC0 + 2 * n, dac::ZERO as u32, 2);
        }
    }
}

/// One step generator's pins and params.
struct StepChannel<H: HalHost> {
    enable: H::Pin<bool, In>,
    velocity: H::Pin<f64, In>,
    scale: H::Param<f64, Rw>,
    max_vel: H::Param<f64, Rw>,
    freq: H::Param<f64, Ro>,
}

/// The USC's four step generators (`ppmc.<bus>.stepgen.<n>`), with the
/// group's timing params (`ppmc.<bus>.stepgen.<n>-<n+3>.*-ns`).
pub struct Stepgens<H: HalHost> {
    ch: Vec<StepChannel<H>>,
    setup_ns: H::Param<u32, Rw>,
    width_ns: H::Param<u32, Rw>,
    space_ns: H::Param<u32, Rw>,
}

/// Shortest step timings the hardware can make, in ns.
const MIN_WIDTH_NS: u32 = 200;
const MIN_SPACE_NS: u32 = 300;
const MIN_SETUP_NS: u32 = 200;
/// Longest, in ns.
const MAX_TIMING_NS: u32 = 25_400;

/// A timing param in 100 ns ticks within `min_ns..=25.4 us`; the param is
/// set to the time the ticks make.
fn ticks(p: &impl HostParam<u32, Rw>, min_ns: u32) -> u32 {
    let ns = p.get().clamp(min_ns, MAX_TIMING_NS);
    let t = ns / 100;
    p.set(t * 100);
    t
}

impl<H: HalHost> Stepgens<H> {
    /// Exports step generators `first..first + 4`.
    pub fn export(c: &impl PinFactory<H>, bus: usize, first: usize) -> Result<Self> {
        let group = format!("ppmc.{bus}.stepgen.{first:02}-{:02}", first + 3);
        let ch = (first..first + 4)
            .map(|n| {
                let p = format!("ppmc.{bus}.stepgen.{n:02}");
                Ok(StepChannel {
                    enable: c.pin(&format!("{p}.enable"))?,
                    velocity: c.pin(&format!("{p}.velocity"))?,
                    scale: c.param(&format!("{p}.scale"), 1.0)?,
                    max_vel: c.param(&format!("{p}.max-vel"), 0.0)?,
                    freq: c.param(&format!("{p}.freq"), 0.0)?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Stepgens {
            ch,
            setup_ns: c.param(&format!("{group}.setup-time-ns"), 10_000)?,
            width_ns: c.param(&format!("{group}.pulse-width-ns"), 4_000)?,
            space_ns: c.param(&format!("{group}.pulse-space-min-ns"), 4_000)?,
        })
    }

    /// Fills the divisors, the control byte and the timing registers.
    pub fn write(&self, wr: &mut [u8; SPAN]) {
        let width = ticks(&self.width_ns, MIN_WIDTH_NS);
        let space = ticks(&self.space_ns, MIN_SPACE_NS);
        let setup = ticks(&self.setup_ns, MIN_SETUP_NS);
        wr[stepgen::WIDTH as usize] = (256 - width) as u8;
        wr[stepgen::SETUP as usize] = (256 - setup) as u8;
        let board_max = stepgen::CLOCK_HZ / (width + space) as f64;
        let mut control = 0u8;
        for (n, sg) in self.ch.iter().enumerate() {
            let scale = usable_scale(&sg.scale);
            let mut max = board_max;
            let mv = sg.max_vel.get();
            if mv.is_nan() || mv <= 0.0 {
                sg.max_vel.set(0.0);
            } else if mv * scale.abs() > board_max {
                sg.max_vel.set(board_max / scale.abs());
            } else {
                max = mv * scale.abs();
            }
            let cmd = sg.velocity.get() * scale;
            let cmd = if cmd.is_nan() { 0.0 } else { cmd };
            let mut run = sg.enable.get();
            let mut f = cmd.abs();
            let divisor = if f > max {
                f = max;
                (stepgen::CLOCK_HZ / f) as u32
            } else if f < stepgen::CLOCK_HZ / stepgen::MAX_DIVISOR as f64 {
                f = 0.0;
                run = false;
                stepgen::MAX_DIVISOR
            } else {
                let d = (stepgen::CLOCK_HZ / f + 0.5) as u32;
                f = stepgen::CLOCK_HZ / d as f64;
                d
            };
            let forward = cmd >= 0.0;
            sg.freq.set(if forward { f } else { -f });
            let bits = if run { ctrl::RUN } else { 0 } | if forward { ctrl::FORWARD } else { 0 };
            control |= bits << (2 * n);
            let d = divisor.saturating_sub(stepgen::DIVISOR_OFFSET);
            regs::put_le(wr, stepgen::RATE0 + 3 * n as u8, d, 3);
        }
        wr[stepgen::CTRL as usize] = control;
    }
}

/// Where a bootstrap sequence is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Boot {
    Normal,
    Forward,
    Reverse,
}

/// One PWM generator: the canonical PWM (`value`, `enable`, `scale`)
/// and LinuxCNC's additions.
struct PwmChannel<H: HalHost> {
    pwm: Pwm<H>,
    max_dc: H::Param<f64, Rw>,
    min_dc: H::Param<f64, Rw>,
    duty_cycle: H::Param<f64, Ro>,
    bootstrap: H::Param<bool, Rw>,
    boot: Boot,
    was_enabled: bool,
}

/// The UPC's four PWM generators (`ppmc.<bus>.pwm.<n>`) and the group's
/// `freq`.
pub struct Pwms<H: HalHost> {
    ch: Vec<PwmChannel<H>>,
    freq: H::Param<f64, Rw>,
    clock_hz: f64,
    last_freq: f64,
    period: u32,
}

/// The duty cycle a bootstrap pulse gives.
const BOOT_DUTY: f64 = 0.05;

impl<H: HalHost> Pwms<H> {
    /// Exports PWM generators `first..first + 4` of a UPC of revision `rev`
    /// (the PWM clock is 40 MHz from revision 3, 10 MHz before).
    pub fn export(c: &impl PinFactory<H>, bus: usize, first: usize, rev: u8) -> Result<Self> {
        let names = ChannelNames::custom(move |n, item| format!("ppmc.{bus}.pwm.{n:02}.{item}"));
        let ch = (first..first + 4)
            .map(|n| {
                Ok(PwmChannel {
                    pwm: Pwm::export(c, &names, n)?,
                    max_dc: c.param(&names.item(n, "max-dc"), 1.0)?,
                    min_dc: c.param(&names.item(n, "min-dc"), 0.0)?,
                    duty_cycle: c.param(&names.item(n, "duty-cycle"), 0.0)?,
                    bootstrap: c.param(&names.item(n, "bootstrap"), false)?,
                    boot: Boot::Normal,
                    was_enabled: false,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Pwms {
            ch,
            freq: c.param(
                &format!("ppmc.{bus}.pwm.{first:02}-{:02}.freq", first + 3),
                0.0,
            )?,
            clock_hz: if rev >= 3 {
                pwm::CLOCK_HZ
            } else {
                pwm::CLOCK_OLD_HZ
            },
            last_freq: 0.0,
            period: 0,
        })
    }

    /// Fills the period, the stop counts and the control byte. A `freq`
    /// of 0 (the default) turns every generator off.
    pub fn write(&mut self, wr: &mut [u8; SPAN]) {
        let freq = self.freq.get();
        if freq == 0.0 || freq.is_nan() {
            self.last_freq = 0.0;
            wr[pwm::CTRL as usize] = 0;
            return;
        }
        if freq != self.last_freq {
            let f = freq.clamp(self.clock_hz / 65535.0, pwm::MAX_FREQ_HZ);
            self.period = ((self.clock_hz / f + 0.5) as u32).min(65535);
            let actual = self.clock_hz / self.period as f64;
            self.freq.set(actual);
            self.last_freq = actual;
        }
        let period = self.period;
        regs::put_le(wr, pwm::FREQ_LO, 65536 - period, 2);
        let mut control = 0u8;
        for (n, pg) in self.ch.iter_mut().enumerate() {
            let duty = pg.pwm.duty();
            let enabled = duty.is_some();
            let mut dc = duty.unwrap_or(0.0);
            if pg.bootstrap.get() {
                if enabled && !pg.was_enabled {
                    pg.boot = Boot::Forward;
                }
                match pg.boot {
                    Boot::Normal => {}
                    Boot::Forward => {
                        dc = BOOT_DUTY;
                        pg.boot = Boot::Reverse;
                    }
                    Boot::Reverse => {
                        dc = -BOOT_DUTY;
                        pg.boot = Boot::Normal;
                    }
                }
            }
            pg.was_enabled = enabled;
            let (min, max) = limits(&pg.min_dc, &pg.max_dc);
            let abs = dc.abs().clamp(min, max);
            let len = ((abs * period as f64 + 0.5) as u32).min(period);
            let actual = len as f64 / period as f64;
            let forward = dc >= 0.0;
            pg.duty_cycle.set(if forward { actual } else { -actual });
            let bits =
                if enabled { ctrl::RUN } else { 0 } | if forward { ctrl::FORWARD } else { 0 };
            control |= bits << (2 * n);
            regs::put_le(wr, pwm::GEN0 + 2 * n as u8, 65535 - len, 2);
        }
        wr[pwm::CTRL as usize] = control;
    }
}

/// `min-dc` and `max-dc`, reset to 0 and 1 (and the params with them)
/// when out of 0..1 or crossed.
fn limits(min_p: &impl HostParam<f64, Rw>, max_p: &impl HostParam<f64, Rw>) -> (f64, f64) {
    let ok = |v: f64| (0.0..=1.0).contains(&v);
    if !ok(min_p.get()) {
        min_p.set(0.0);
    }
    if !ok(max_p.get()) {
        max_p.set(1.0);
    }
    if min_p.get() >= max_p.get() {
        min_p.set(0.0);
        max_p.set(1.0);
    }
    (min_p.get(), max_p.get())
}

/// What a USC/UPC's extra port drives.
pub enum Extra<H: HalHost> {
    /// The 8-bit spindle DAC (`ppmc.<bus>.DAC8.<n>`).
    Dac(DacChannel<H>),
    /// Eight more digital outputs, numbered after the board's own.
    Douts(Vec<DigOut<H>>),
}

impl<H: HalHost> Extra<H> {
    /// Exports the spindle DAC number `n`.
    pub fn dac(c: &impl PinFactory<H>, bus: usize, n: usize) -> Result<Self> {
        DacChannel::export(c, &format!("ppmc.{bus}.DAC8.{n:02}")).map(Extra::Dac)
    }

    /// Exports outputs `first..first + 8`.
    pub fn douts(c: &impl PinFactory<H>, bus: usize, first: usize) -> Result<Self> {
        let names = ChannelNames::custom(move |n, item| format!("ppmc.{bus}.dout.{n:02}.{item}"));
        (first..first + 8)
            .map(|n| DigOut::export(c, &names, n))
            .collect::<Result<Vec<_>>>()
            .map(Extra::Douts)
    }

    /// Fills the extra port's register.
    pub fn write(&self, wr: &mut [u8; SPAN]) {
        wr[uxc::EXTRA as usize] = match self {
            Extra::Dac(d) => regs::dac8_code(d.volts()),
            Extra::Douts(o) => DigOut::pack(o, DigOut::level) as u8,
        };
    }
}
