//! `hy_vfd`'s pins, named as LinuxCNC's program names them.

use hal_core::{Component, In, Io, Out, Pin};

/// Every pin of the component (besides the link pins of [`crate::vfd::Link`]).
pub struct HyPins {
    /// `enable`: talk to the drive at all.
    pub enable: Pin<bool, In>,
    /// `spindle-forward`.
    pub spindle_forward: Pin<bool, In>,
    /// `spindle-reverse`.
    pub spindle_reverse: Pin<bool, In>,
    /// `spindle-on`.
    pub spindle_on: Pin<bool, In>,
    /// `speed-command`, rpm.
    pub speed_command: Pin<f64, In>,
    /// `spindle-at-speed-tolerance` (default 0.02).
    pub at_speed_tolerance: Pin<f64, In>,

    /// The status values: `SetF`, `OutF`, `OutA`, `Rott`, `DCV`, `ACV`,
    /// `Cont`, `Tmp`, in status-index order.
    pub status: Vec<Pin<f64, Out>>,
    /// `CNTR`: the control word sent.
    pub cntr: Pin<f64, Out>,
    /// `CNST`: the status byte received.
    pub cnst: Pin<f64, Out>,
    /// The CNST bits: `CNST-run`, `-jog`, `-command-rf`, `-running`,
    /// `-jogging`, `-running-rf`, `-bracking`, `-track-start`, bit 0 first.
    pub cnst_bits: Vec<Pin<bool, Out>>,
    /// `frequency-command`, in 0.01 Hz as LinuxCNC shows it.
    pub frequency_command: Pin<f64, Out>,
    /// `spindle-speed-fb`, rpm.
    pub speed_fb: Pin<f64, Out>,
    /// `spindle-speed-fb-rps`.
    pub speed_fb_rps: Pin<f64, Out>,
    /// `spindle-at-speed`.
    pub at_speed: Pin<bool, Out>,
    /// `max-freq`, Hz (PD005).
    pub max_freq: Pin<f64, Out>,
    /// `base-freq`, Hz (PD004).
    pub base_freq: Pin<f64, Out>,
    /// `freq-lower-limit`, Hz (PD011).
    pub freq_lower_limit: Pin<f64, Out>,
    /// `rated-motor-voltage`, V (PD141).
    pub rated_motor_voltage: Pin<f64, Out>,
    /// `rated-motor-current`, A (PD142).
    pub rated_motor_current: Pin<f64, Out>,
    /// `rated-motor-rev`: the motor's speed at `max-freq`, rpm.
    pub rated_motor_rev: Pin<f64, Out>,
    /// `motor-poles` (PD143).
    pub motor_poles: Pin<u32, Out>,
    /// `hycomm-ok`: more than ten reads and writes in a row succeeded.
    pub hycomm_ok: Pin<bool, Out>,
    /// `error-count`: failed transactions.
    pub error_count: Pin<i32, Io>,
    /// `retval`: the last cycle's result code (0, or LinuxCNC's negative
    /// code as an unsigned number).
    pub retval: Pin<u32, Io>,
}

/// Names of the status pins, in status-index order.
pub const STATUS_PINS: [&str; 8] = ["SetF", "OutF", "OutA", "Rott", "DCV", "ACV", "Cont", "Tmp"];
/// Names of the CNST bit pins, bit 0 first.
pub const CNST_PINS: [&str; 8] = [
    "CNST-run",
    "CNST-jog",
    "CNST-command-rf",
    "CNST-running",
    "CNST-jogging",
    "CNST-running-rf",
    "CNST-bracking",
    "CNST-track-start",
];

impl HyPins {
    /// Creates the pins `<prefix>.*` on `comp`.
    pub fn new(comp: &Component, prefix: &str) -> hal_core::Result<HyPins> {
        let p = |n: &str| format!("{prefix}.{n}");
        let status = STATUS_PINS
            .iter()
            .map(|n| comp.pin(&p(n)))
            .collect::<hal_core::Result<Vec<_>>>()?;
        let cnst_bits = CNST_PINS
            .iter()
            .map(|n| comp.pin(&p(n)))
            .collect::<hal_core::Result<Vec<_>>>()?;
        Ok(HyPins {
            enable: comp.pin(&p("enable"))?,
            spindle_forward: comp.pin(&p("spindle-forward"))?,
            spindle_reverse: comp.pin(&p("spindle-reverse"))?,
            spindle_on: comp.pin(&p("spindle-on"))?,
            speed_command: comp.pin(&p("speed-command"))?,
            at_speed_tolerance: comp.pin_init(&p("spindle-at-speed-tolerance"), 0.02)?,
            status,
            cntr: comp.pin(&p("CNTR"))?,
            cnst: comp.pin(&p("CNST"))?,
            cnst_bits,
            frequency_command: comp.pin(&p("frequency-command"))?,
            speed_fb: comp.pin(&p("spindle-speed-fb"))?,
            speed_fb_rps: comp.pin(&p("spindle-speed-fb-rps"))?,
            at_speed: comp.pin(&p("spindle-at-speed"))?,
            max_freq: comp.pin(&p("max-freq"))?,
            base_freq: comp.pin(&p("base-freq"))?,
            freq_lower_limit: comp.pin(&p("freq-lower-limit"))?,
            rated_motor_voltage: comp.pin(&p("rated-motor-voltage"))?,
            rated_motor_current: comp.pin(&p("rated-motor-current"))?,
            rated_motor_rev: comp.pin(&p("rated-motor-rev"))?,
            motor_poles: comp.pin(&p("motor-poles"))?,
            hycomm_ok: comp.pin(&p("hycomm-ok"))?,
            error_count: comp.pin(&p("error-count"))?,
            retval: comp.pin(&p("retval"))?,
        })
    }
}
