//! A register model of the ADS1115 (hardware.md 7.2): the pointer
//! register, 16-bit registers sent most significant byte first,
//! single-shot conversions started by OS with the OS bit reading 0 while
//! converting, continuous mode, and the multiplexer and gain applied to
//! the input voltages the plant sets, clipped to the code range.
//! Conversions take 1 / data rate of simulated time. The comparator is
//! not modelled (its registers hold what is written); the driver turns it
//! off.

use std::any::Any;

use super::ChipModel;
use crate::regs::ads1115::*;

/// The chip.
#[derive(Debug, Clone)]
pub struct Ads1115 {
    pointer: u8,
    /// CONFIG as written (OS as last written; reads report the state).
    config: u16,
    conversion: i16,
    lo_thresh: u16,
    hi_thresh: u16,
    /// AIN0..AIN3, volts.
    inputs: [f64; 4],
    /// Time left of the conversion in progress.
    converting: Option<u64>,
    /// The MUX/PGA of the conversion in progress.
    latched: u16,
    /// Conversions finished.
    pub conversions: u64,
}

impl Default for Ads1115 {
    fn default() -> Self {
        Self::new()
    }
}

impl Ads1115 {
    /// A chip at power-up, every input at 0 V.
    pub fn new() -> Ads1115 {
        Ads1115 {
            pointer: CONVERSION,
            config: CONFIG_RESET,
            conversion: 0,
            lo_thresh: LO_THRESH_RESET,
            hi_thresh: HI_THRESH_RESET,
            inputs: [0.0; 4],
            converting: None,
            latched: CONFIG_RESET,
            conversions: 0,
        }
    }

    /// Sets input AINn to `volts`.
    pub fn set_input(&mut self, n: usize, volts: f64) {
        if n < 4 {
            self.inputs[n] = volts;
        }
    }

    /// CONFIG as last written.
    pub fn config(&self) -> u16 {
        self.config
    }

    /// The conversion register.
    pub fn conversion(&self) -> i16 {
        self.conversion
    }

    /// Whether a conversion is in progress.
    pub fn busy(&self) -> bool {
        self.converting.is_some()
    }

    /// The voltage the multiplexer code `mux` presents.
    fn mux_volts(&self, mux: u16) -> f64 {
        let a = &self.inputs;
        match mux & 7 {
            0 => a[0] - a[1],
            1 => a[0] - a[3],
            2 => a[1] - a[3],
            3 => a[2] - a[3],
            n => a[(n - 4) as usize],
        }
    }

    fn start(&mut self) {
        self.latched = self.config;
        self.converting = Some(conversion_ns((self.config >> DR_SHIFT) & 7));
    }

    fn finish(&mut self) {
        let cfg = self.latched;
        let fs = FULL_SCALE[((cfg >> PGA_SHIFT) & 7) as usize];
        self.conversion = code_for(self.mux_volts(cfg >> MUX_SHIFT), fs);
        self.conversions += 1;
    }

    fn read_reg(&self) -> u16 {
        match self.pointer {
            CONVERSION => self.conversion as u16,
            CONFIG => {
                let idle = self.converting.is_none();
                (self.config & !OS) | if idle { OS } else { 0 }
            }
            LO_THRESH => self.lo_thresh,
            _ => self.hi_thresh,
        }
    }
}

impl ChipModel for Ads1115 {
    fn write(&mut self, bytes: &[u8]) {
        let Some((&p, data)) = bytes.split_first() else {
            return;
        };
        self.pointer = p & 3;
        if data.len() < 2 {
            return;
        }
        let v = (data[0] as u16) << 8 | data[1] as u16;
        match self.pointer {
            CONFIG => {
                self.config = v;
                let single = v & MODE_SINGLE != 0;
                // Single shot starts on OS (a conversion in progress
                // finishes first); continuous restarts with the new
                // settings at once.
                if !single || (v & OS != 0 && self.converting.is_none()) {
                    self.start();
                }
            }
            LO_THRESH => self.lo_thresh = v,
            HI_THRESH => self.hi_thresh = v,
            _ => {} // the conversion register is read-only
        }
    }

    fn read(&mut self, out: &mut [u8]) {
        let v = self.read_reg().to_be_bytes();
        for (i, b) in out.iter_mut().enumerate() {
            *b = if i < 2 { v[i] } else { 0xFF };
        }
    }

    fn advance(&mut self, mut dt_ns: u64) {
        while let Some(left) = self.converting {
            if dt_ns < left {
                self.converting = Some(left - dt_ns);
                return;
            }
            dt_ns -= left;
            self.finish();
            if self.config & MODE_SINGLE != 0 {
                self.converting = None;
            } else {
                self.start();
            }
        }
    }

    fn describe(&self) -> String {
        "simulated ADS1115".into()
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write16(c: &mut Ads1115, reg: u8, v: u16) {
        let b = v.to_be_bytes();
        c.write(&[reg, b[0], b[1]]);
    }

    fn read16(c: &mut Ads1115, reg: u8) -> u16 {
        c.write(&[reg]);
        let mut b = [0u8; 2];
        c.read(&mut b);
        u16::from_be_bytes(b)
    }

    #[test]
    fn single_shot_takes_one_period_and_scales() {
        let mut c = Ads1115::new();
        assert_eq!(read16(&mut c, CONFIG), CONFIG_RESET, "idle: OS reads 1");
        c.set_input(2, 1.5);
        // AIN2 vs GND, ±2.048 V, single shot, 860 SPS, comparator off.
        let cfg =
            OS | (6 << MUX_SHIFT) | (2 << PGA_SHIFT) | MODE_SINGLE | (7 << DR_SHIFT) | COMP_QUE_OFF;
        write16(&mut c, CONFIG, cfg);
        assert_eq!(read16(&mut c, CONFIG) & OS, 0, "converting");
        c.advance(conversion_ns(7) - 1);
        assert!(c.busy());
        c.advance(1);
        assert_eq!(read16(&mut c, CONFIG) & OS, OS);
        assert_eq!(read16(&mut c, CONVERSION) as i16, code_for(1.5, 2.048));
        assert_eq!(c.conversions, 1);
        c.advance(10 * conversion_ns(7));
        assert_eq!(c.conversions, 1, "single shot powers down");
    }

    #[test]
    fn differential_clipping_and_continuous() {
        let mut c = Ads1115::new();
        c.set_input(0, 0.1);
        c.set_input(1, 0.5);
        let cfg = (MUX_DIFF_0_1 << MUX_SHIFT) | (4 << PGA_SHIFT) | (7 << DR_SHIFT) | COMP_QUE_OFF;
        write16(&mut c, CONFIG, cfg);
        c.advance(conversion_ns(7));
        assert_eq!(c.conversion(), code_for(-0.4, 0.512));
        c.set_input(1, -1.0);
        c.advance(3 * conversion_ns(7));
        assert_eq!(c.conversion(), 32767, "clipped");
        assert_eq!(c.conversions, 4);
        assert_eq!(
            read16(&mut c, CONFIG) & OS,
            0,
            "continuous: always converting"
        );
        write16(&mut c, HI_THRESH, 0x1234);
        assert_eq!(read16(&mut c, HI_THRESH), 0x1234);
        let mut three = [0u8; 3];
        c.write(&[HI_THRESH]);
        c.read(&mut three);
        assert_eq!(three, [0x12, 0x34, 0xFF]);
    }
}
