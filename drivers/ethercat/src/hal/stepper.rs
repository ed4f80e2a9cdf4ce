//! The EL7041's motor in velocity mode as lcec drives it (`srv-*`): the
//! command `srv-cmd` (absolute with `srv-absmode`) becomes a duty cycle
//! `cmd / srv-scale + srv-offset` limited to `srv-min-dc..srv-max-dc`
//! (each within -1..1), shown in `srv-curr-dc`, and the 16-bit velocity
//! `32767 × duty` in `srv-raw-cmd` and on the wire, 0 while `srv-enable`
//! is off. `srv-fault` is the terminal's error bit; `srv-fault-reset` or
//! `srv-reset` set the terminal's reset bit, and an enable's rising edge
//! while in error pulses it once (one cycle on, one off) with `srv-fault`
//! held low meanwhile. After the terminal's safe state (its link or
//! slave lost) the motor stays off, its enable bit 0, until `srv-enable`
//! falls and rises again.

use hal_core::HalHost;

use super::field::Field;
use super::slave::Named;
use crate::master::Layout;

/// The motor's pins (indices into the slave's pins) and its entries.
pub(crate) struct StepperPins {
    scale: Option<usize>,
    offset: Option<usize>,
    min_dc: Option<usize>,
    max_dc: Option<usize>,
    curr_dc: Option<usize>,
    enable: Option<usize>,
    absmode: Option<usize>,
    cmd: Option<usize>,
    raw_cmd: Option<usize>,
    reset: Option<usize>,
    error: Option<usize>,
    fault: Option<usize>,
    fault_reset: Option<usize>,
    /// The velocity (0x7010:21) in the outputs.
    velocity: Option<Field>,
    /// The reset bit (0x7010:02) in the outputs.
    reset_bit: Option<Field>,
    /// The enable bit (0x7010:01) in the outputs.
    enable_bit: Option<Field>,
}

impl StepperPins {
    /// The EL7041's motor pins in `p`, its entries in `layout`.
    pub(crate) fn new<H: HalHost>(p: &Named<'_, H>, layout: &Layout) -> StepperPins {
        let output = |sub: u8| {
            layout.find(0x7010, sub, true).map(|m| Field {
                bit: m.bit,
                bits: m.bits,
            })
        };
        StepperPins {
            scale: p.index("srv-scale"),
            offset: p.index("srv-offset"),
            min_dc: p.index("srv-min-dc"),
            max_dc: p.index("srv-max-dc"),
            curr_dc: p.index("srv-curr-dc"),
            enable: p.index("srv-enable"),
            absmode: p.index("srv-absmode"),
            cmd: p.index("srv-cmd"),
            raw_cmd: p.index("srv-raw-cmd"),
            reset: p.index("srv-reset"),
            error: p.index("srv-error"),
            fault: p.index("srv-fault"),
            fault_reset: p.index("srv-fault-reset"),
            velocity: output(0x21),
            reset_bit: output(0x02),
            enable_bit: output(0x01),
        }
    }
}

/// What the motor keeps between cycles.
#[derive(Default)]
pub(crate) struct Stepper {
    last_enable: bool,
    /// The terminal's error bit at the last read.
    in_error: bool,
    /// An automatic reset in progress (after an enable edge in error).
    retry: bool,
    /// Its reset bit this cycle.
    pulse_on: bool,
    /// Held off since its safe state, until `srv-enable` falls.
    held: bool,
    /// Cycles the pulse has been in its current half.
    pulse_cycles: u8,
}

impl Stepper {
    /// After reception: `srv-fault` from the terminal's error bit, held
    /// low while an automatic reset runs.
    pub(crate) fn read<H: HalHost>(&mut self, at: &StepperPins, p: &Named<'_, H>) {
        self.in_error = p.at(at.error).is_some_and(|x| x.is_set());
        if !self.in_error {
            self.retry = false;
        }
        if self.retry {
            self.pulse_cycles += 1;
            if self.pulse_cycles > 1 {
                self.pulse_cycles = 0;
                self.pulse_on = !self.pulse_on;
                // One on-half and one off-half: the retry is spent.
                if self.pulse_on {
                    self.retry = false;
                }
            }
        }
        if let Some(f) = p.at(at.fault) {
            f.set(f64::from(u8::from(self.in_error && !self.retry)));
        }
    }

    /// Before transmission: the velocity and the reset bit.
    pub(crate) fn write<H: HalHost>(&mut self, out: &mut [u8], at: &StepperPins, p: &Named<'_, H>) {
        let get = |i| p.at(i).map_or(0.0, |x| x.get());
        let set = |i, v: f64| {
            if let Some(x) = p.at(i) {
                x.set(v);
            }
        };
        // After its safe state (the link or the slave lost) the motor
        // stays off until `srv-enable` falls and rises again: it never
        // powers up by itself when the link returns.
        let asked = get(at.enable) != 0.0;
        if !asked {
            self.held = false;
        }
        let enable = asked && !self.held;
        if let (true, Some(f)) = (self.held, at.enable_bit) {
            f.write(out, 0);
        }
        if enable && !self.last_enable && self.in_error {
            self.retry = true;
            self.pulse_on = true;
            self.pulse_cycles = 0;
        }
        self.last_enable = enable;
        let (hi0, lo0) = (get(at.max_dc), get(at.min_dc));
        let hi = hi0.min(1.0);
        let lo = lo0.min(hi).max(-1.0);
        let hi = hi.max(lo);
        // Written back only when limited (a write is a store to the
        // HAL's shared memory each period).
        if hi.to_bits() != hi0.to_bits() {
            set(at.max_dc, hi);
        }
        if lo.to_bits() != lo0.to_bits() {
            set(at.min_dc, lo);
        }
        let mut scale = get(at.scale);
        if !scale.is_finite() || scale.abs() < 1e-20 {
            scale = 1.0;
            set(at.scale, 1.0);
        }
        let mut cmd = get(at.cmd);
        if get(at.absmode) != 0.0 {
            cmd = cmd.abs();
        }
        let dc = (cmd / scale + get(at.offset)).clamp(lo, hi);
        let dc = if dc.is_finite() { dc } else { 0.0 };
        let (raw, curr) = if enable {
            ((32767.0 * dc).clamp(-32767.0, 32767.0), dc)
        } else {
            (0.0, 0.0)
        };
        let raw = raw as i32;
        set(at.curr_dc, curr);
        set(at.raw_cmd, f64::from(raw));
        if let Some(f) = at.velocity {
            f.write(out, raw as i16 as u16 as u64);
        }
        let reset =
            get(at.reset) != 0.0 || get(at.fault_reset) != 0.0 || (self.retry && self.pulse_on);
        if let Some(f) = at.reset_bit {
            f.write(out, u64::from(reset));
        }
    }

    /// The safe state's pins (the terminal disabled, its velocity 0 on
    /// the wire): `srv-curr-dc` and `srv-raw-cmd` show 0; the motor is
    /// held off until a new rising `srv-enable`.
    pub(crate) fn safe<H: HalHost>(&mut self, at: &StepperPins, p: &Named<'_, H>) {
        self.held = true;
        self.last_enable = false;
        for i in [at.curr_dc, at.raw_cmd] {
            if let Some(x) = p.at(i) {
                x.set(0.0);
            }
        }
    }
}
