//! The Servo-To-Go register map (hardware.md §3.2), offsets from the
//! board's base address, and the chips' command bytes.
//!
//! Two 32-port windows: `base + 0x000..0x01F` (counters, DACs) and
//! `base + 0x400..0x41F` (digital I/O, board test, interrupt or index
//! registers, ADC). Accesses are 8 bits wide except DAC writes and ADC
//! reads/writes (16 bits).

/// Ports in each window.
pub const WINDOW_LEN: u16 = 0x20;
/// Offset of the upper window.
pub const HIGH_WINDOW: u16 = 0x400;
/// Base addresses the board's jumpers select, searched from the top as
/// LinuxCNC does.
pub const CANDIDATE_BASES: [u16; 16] = {
    let mut b = [0u16; 16];
    let mut i = 0;
    while i < 16 {
        b[i] = 0x3E0 - 0x20 * i as u16;
        i += 1;
    }
    b
};

/// Channels (encoders, DACs, ADCs) on a full board.
pub const CHANNELS: usize = 8;

/// LS7166 data port of counter `n`.
pub const fn counter_data(n: usize) -> u16 {
    (2 * n - (n % 2)) as u16
}
/// LS7166 control port of counter `n`.
pub const fn counter_control(n: usize) -> u16 {
    (2 * (n + 1) - (n % 2)) as u16
}
/// DAC `n` (16-bit write).
pub const fn dac(n: usize) -> u16 {
    0x10 + 2 * n as u16
}
/// ADC `n` (16-bit).
pub const fn adc(n: usize) -> u16 {
    0x410 + 2 * n as u16
}

/// 8255 #1 port A: digital I/O port A.
pub const PORT_A: u16 = 0x400;
/// Model I: digital I/O port D (8255 #2 port A). Model II: CNTRL0.
pub const PORT_D_OR_CNTRL0: u16 = 0x401;
/// 8255 #1 port B: digital I/O port B.
pub const PORT_B: u16 = 0x402;
/// Board test register (read): the signature bits. Model I: reading
/// clears the even axis's index latch. Model II: bit 3 = ADC busy.
pub const BRDTST: u16 = 0x403;
/// 8255 #1 port C: digital I/O port C.
pub const PORT_C: u16 = 0x404;
/// Model I: INTC (8255 #2 port C). Model II: digital I/O port D.
pub const INTC_OR_PORT_D: u16 = 0x405;
/// 8255 #1 control word (ports A, B, C).
pub const ABC_DIR: u16 = 0x406;
/// 8255 #2 control word (write). Model I read: ODDRST, clears the odd
/// axis's index latch.
pub const D_DIR: u16 = 0x407;
/// Model I: 8259 ICW1/OCW2/OCW3 (write), IRR or ISR (read). Model II:
/// IDLEN, bit n enables the index of axis n.
pub const IRR_OR_IDLEN: u16 = 0x409;
/// Model I: 8259 ICW2/OCW1 (write), IMR (read). Model II: SELDI, bit n
/// = 0 lets the index latch axis n.
pub const IMR_OR_SELDI: u16 = 0x40B;
/// Model II: IDL, latched index flags (read); writing 0 clears them all.
pub const IDL: u16 = 0x40D;
/// Model II: CNTRL1.
pub const CNTRL1: u16 = 0x40F;
/// Model I: 8254 timer registers (unused by the driver).
pub const TIMER: [u16; 4] = [0x408, 0x40A, 0x40C, 0x40E];

/// The digital I/O ports' registers, A B C D, per model.
pub const fn dio_ports(model2: bool) -> [u16; 4] {
    [
        PORT_A,
        PORT_B,
        PORT_C,
        if model2 {
            INTC_OR_PORT_D
        } else {
            PORT_D_OR_CNTRL0
        },
    ]
}

/// Board signature of a Model I.
pub const SIGNATURE_MODEL1: u8 = 0x75;
/// Board signature of a Model II.
pub const SIGNATURE_MODEL2: u8 = 0x74;
/// BRDTST: the signature bit of this read.
pub const BRDTST_SER: u8 = 0x80;
/// BRDTST: shift of the signature bit's position (3 bits).
pub const BRDTST_Q_SHIFT: u8 = 4;
/// Model II BRDTST: the ADC is converting.
pub const BRDTST_ADC_BUSY: u8 = 0x08;

/// LS7166 command: master reset, CNTR to OL, reset the byte pointer.
pub const LS_RESET: u8 = 0x23;
/// LS7166 ICR: enable A/B inputs, load pin loads OL (the index).
pub const LS_ICR_INDEX_LOADS_OL: u8 = 0x68;
/// LS7166 OCCR: binary count, normal mode.
pub const LS_OCCR_DEFAULT: u8 = 0x80;
/// LS7166 QR: x4 quadrature.
pub const LS_QR_X4: u8 = 0xC3;
/// LS7166 MCR: CNTR to OL and reset the byte pointer.
pub const LS_LATCH: u8 = 0x03;
/// LS7166 MCR: reset the byte pointer only.
pub const LS_RESET_POINTER: u8 = 0x01;
/// LS7166 counters are 24 bits wide.
pub const COUNTER_BITS: u32 = 24;

/// 8255 mode-set control word for ports A, B, C: `inputs` A, B, C.
pub const fn abc_control(a_in: bool, b_in: bool, c_in: bool) -> u8 {
    0x80 | if a_in { 0x10 } else { 0 } | if b_in { 0x02 } else { 0 } | if c_in { 0x09 } else { 0 }
}
/// Model I 8255 #2: port D input (BRDTST input, INTC output).
pub const MODEL1_D_IN: u8 = 0x92;
/// Model I 8255 #2: port D output.
pub const MODEL1_D_OUT: u8 = 0x82;
/// Model II 8255 #2: CNTRL0 output, BRDTST input, port D input.
pub const MODEL2_D_IN: u8 = 0x8B;
/// Model II 8255 #2: port D output.
pub const MODEL2_D_OUT: u8 = 0x82;
/// Model I 8255 #2 bit set: PC7 (INTC AUTOZERO) on.
pub const MODEL1_AUTOZERO_ON: u8 = 0x0F;

/// Model I INTC: ADC auto-zero.
pub const INTC_AUTOZERO: u8 = 0x80;
/// Model I INTC: index active level high.
pub const INTC_IXLVL: u8 = 0x40;
/// Model I INTC: shift of the index axis pair select.
pub const INTC_IXS_SHIFT: u8 = 4;
/// IRQ select code of IRQ5 (the driver selects it, never enables it).
pub const IRQ5: u8 = 4;

/// Model I 8259 ICW1: edge triggered, single, no ICW4.
pub const PIC_ICW1: u8 = 0x1A;
/// Model I 8259 OCW3: the next read of 0x409 returns IRR.
pub const PIC_READ_IRR: u8 = 0x0A;
/// Model I IRR: live index of the selected pair's even axis.
pub const IRR_IXEVN: u8 = 0x80;
/// Model I IRR: live index of the odd axis.
pub const IRR_IXODD: u8 = 0x40;
/// Model I IRR: latched index of the even axis.
pub const IRR_LIXEVN: u8 = 0x20;
/// Model I IRR: latched index of the odd axis.
pub const IRR_LIXODD: u8 = 0x10;
/// Model I IRR: ADC end of conversion.
pub const IRR_EOC: u8 = 0x08;

/// Model II CNTRL0: ADC auto-zero.
pub const CNTRL0_AUTOZERO: u8 = 0x80;
/// Model II CNTRL0: shift of the ADC multiplexer channel.
pub const CNTRL0_MUX_SHIFT: u8 = 4;
/// Model II CNTRL0: CAL (the driver keeps it set).
pub const CNTRL0_CAL: u8 = 0x08;

/// DACs are 13 bits, ±10 V.
pub const DAC_MAX_VOLTS: f64 = 10.0;
/// The DAC code LinuxCNC writes for 0 V at start-up.
pub const DAC_ZERO: u16 = 0x1000;

/// The DAC word for `volts`, as LinuxCNC computes it: clamped to ±10 V,
/// then `((-10 - volts) * 8191 / 20)` truncated, minus one, as a 16-bit
/// value. In the 13 bits the DAC uses: 0x0000 is +10 V, 0x1000 is 0 V,
/// 0x1FFF is -10 V.
#[inline]
pub fn dac_code(volts: f64) -> u16 {
    let v = if volts.is_nan() { 0.0 } else { volts };
    let v = v.clamp(-DAC_MAX_VOLTS, DAC_MAX_VOLTS);
    (((-10.0 - v) * 8191.0 / 20.0) as i32 - 1) as i16 as u16
}

/// The voltage of a DAC word (for the simulator): its low 13 bits.
pub fn dac_volts(code: u16) -> f64 {
    (4096.0 - (code & 0x1FFF) as f64) * 10.0 / 4096.0
}

/// Volts per ADC count: 13 bits with sign over ±10 V.
pub const ADC_VOLTS_PER_COUNT: f64 = 10.0 / 4096.0;

/// An ADC word as a signed count: bit 12 is the sign.
#[inline]
pub fn adc_count(raw: u16) -> i32 {
    if raw & 0x1000 != 0 {
        (raw | 0xF000) as i16 as i32
    } else {
        (raw & 0x0FFF) as i32
    }
}

/// The ADC word for `volts` (for the simulator).
pub fn adc_raw(volts: f64) -> u16 {
    let c = (volts / ADC_VOLTS_PER_COUNT).round();
    let c = if c.is_nan() { 0.0 } else { c };
    (c.clamp(-4096.0, 4095.0) as i32 as u16) & 0x1FFF
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counter_ports_follow_the_formula() {
        let data: Vec<u16> = (0..8).map(counter_data).collect();
        let ctl: Vec<u16> = (0..8).map(counter_control).collect();
        assert_eq!(data, [0x00, 0x01, 0x04, 0x05, 0x08, 0x09, 0x0C, 0x0D]);
        assert_eq!(ctl, [0x02, 0x03, 0x06, 0x07, 0x0A, 0x0B, 0x0E, 0x0F]);
        assert_eq!(CANDIDATE_BASES[0], 0x3E0);
        assert_eq!(CANDIDATE_BASES[15], 0x200);
    }

    #[test]
    fn dac_codes_at_both_ends_and_zero() {
        assert_eq!(dac_code(10.0) & 0x1FFF, 0x0000);
        assert_eq!(dac_code(-10.0) & 0x1FFF, 0x1FFF);
        assert_eq!(dac_code(0.0) & 0x1FFF, 0x1000);
        assert_eq!(dac_code(0.0), 0xF000, "LinuxCNC's word, sign bits and all");
        assert_eq!(dac_code(1e9), dac_code(10.0));
        assert_eq!(dac_code(f64::NAN), dac_code(0.0));
        for v in [-9.9, -5.0, -0.1, 0.1, 2.5, 9.9] {
            assert!(
                (dac_volts(dac_code(v)) - v).abs() < 2.0 * 10.0 / 4096.0,
                "{v}"
            );
        }
        assert_eq!(dac_volts(DAC_ZERO), 0.0);
    }

    #[test]
    fn adc_words_are_13_bit_signed() {
        assert_eq!(adc_count(0x0FFF), 4095);
        assert_eq!(adc_count(0x1000), -4096);
        assert_eq!(adc_count(0x1FFF), -1);
        assert_eq!(
            adc_count(0xE005),
            5,
            "upper bits of a positive word ignored"
        );
        for v in [-9.5, -0.01, 0.0, 3.3, 9.99] {
            let back = adc_count(adc_raw(v)) as f64 * ADC_VOLTS_PER_COUNT;
            assert!((back - v).abs() <= ADC_VOLTS_PER_COUNT / 2.0, "{v} {back}");
        }
    }

    #[test]
    fn control_words() {
        assert_eq!(abc_control(true, true, false), 0x92);
        assert_eq!(abc_control(false, false, false), 0x80);
        assert_eq!(abc_control(false, true, true), 0x8B);
        assert_eq!(dio_ports(false)[3], 0x401);
        assert_eq!(dio_ports(true)[3], 0x405);
    }
}
