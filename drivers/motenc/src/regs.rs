//! The MOTENC register map (hardware.md §4.2) and its conversions.
//!
//! All registers are 32 bits wide in BAR 2. Two identical FPGA blocks
//! hold the encoders, digital I/O and status: FPGA 0 at 0x00, FPGA 1 at
//! 0x20 (absent on the MOTENC-Lite). The timer, watchdog, DACs and ADC
//! sit above them, once per board.

use hal_driver::pci::PciMatch;

/// PLX vendor ID (the card's PCI bridge).
pub const PCI_VENDOR: u16 = 0x10B5;
/// The MOTENC's device ID. LinuxCNC matches vendor and device only.
pub const PCI_DEVICE: u16 = 0x3001;
/// The board on the PCI bus.
pub const PCI_TABLE: &[PciMatch] = &[PciMatch::new(PCI_VENDOR, PCI_DEVICE, "MOTENC")];
/// The BAR holding the registers.
pub const BAR: usize = 2;
/// The bytes of the BAR the driver uses (up to the ADC start register).
pub const WINDOW_LEN: usize = ADC_START + 4;
/// The window the simulated board decodes (LinuxCNC's
/// `MOTENC_PCI_MEM_LEN`); offsets it does not list read 0.
pub const SIM_WINDOW_LEN: usize = 0x200;

/// Distance between the two FPGA blocks.
pub const FPGA_STRIDE: usize = 0x20;
/// Encoders per FPGA block.
pub const ENCODERS_PER_FPGA: usize = 4;
/// Digital outputs per FPGA block.
pub const OUTPUTS_PER_FPGA: usize = 16;

/// encoderCount[j] of FPGA `fpga`: reads the count; writing 1 arms
/// "clear on the next index", 0 disarms.
pub const fn encoder_count(fpga: usize, j: usize) -> usize {
    fpga * FPGA_STRIDE + 4 * j
}
/// digitalIo of FPGA `fpga`: bits 31..16 read 16 inputs, bits 15..0
/// write 16 outputs; both active low.
pub const fn digital_io(fpga: usize) -> usize {
    fpga * FPGA_STRIDE + 0x10
}
/// statusControl of FPGA `fpga`: see the `STATUS_*` bits; writing bit j
/// resets counter j of the block.
pub const fn status_control(fpga: usize) -> usize {
    fpga * FPGA_STRIDE + 0x14
}
/// boardVersion (FPGA 0's is the one that counts).
pub const BOARD_VERSION: usize = 0x1C;

/// Timer interrupt compare (unused).
pub const TIMER_COMPARE: usize = 0x40;
/// Writing 1 disables the timer interrupt.
pub const TIMER_IRQ_DISABLE: usize = 0x44;
/// Timer interrupt enable (unused).
pub const TIMER_IRQ_ENABLE: usize = 0x48;
/// Watchdog control: the `WATCHDOG_*` bits.
pub const WATCHDOG_CONTROL: usize = 0x4C;
/// Writing [`WATCHDOG_KICK`] restarts the watchdog.
pub const WATCHDOG_RESET: usize = 0x50;
/// DAC n (0..8): 13-bit code, [`DAC_ZERO`] = 0 V, higher = lower voltage.
pub const fn dac(n: usize) -> usize {
    0x60 + 4 * n
}
/// ADC: writing selects a conversion list (the `ADC_CMD_*`), reading
/// takes the next result.
pub const ADC_DATA_COMMAND: usize = 0x80;
/// ADC: writing 1 starts the conversions the last command selected.
pub const ADC_START: usize = 0xA0;

/// boardVersion of a MOTENC-100.
pub const VERSION_100: u32 = 0;
/// boardVersion of a MOTENC-Lite.
pub const VERSION_LITE: u32 = 1;

/// statusControl: 16 digital inputs, active low.
pub const STATUS_INPUTS: u32 = 0xFFFF;
/// statusControl of FPGA 0: shift of the 2-bit board ID (jumpers).
pub const STATUS_ID_SHIFT: u32 = 16;
/// statusControl of FPGA 0: the ADC is converting (LinuxCNC calls it
/// `ADC_DONE`, but treats a set bit as "not done").
pub const STATUS_ADC_BUSY: u32 = 1 << 18;
/// statusControl of FPGA 0: the E-stop input.
pub const STATUS_ESTOP: u32 = 1 << 19;
/// statusControl of FPGA 1: four more digital inputs at bits 19..16.
pub const STATUS_FPGA1_EXTRA_INPUTS: u32 = 0xF << 16;
/// statusControl: shift of the live index inputs of the block's encoders.
pub const STATUS_INDEX_SHIFT: u32 = 20;
/// statusControl: shift of the index-latched flags of the block's
/// encoders.
pub const STATUS_LATCH_SHIFT: u32 = 24;
/// statusControl write: reset all four counters of the block.
pub const RESET_ALL_COUNTERS: u32 = 0x0F;

/// Watchdog control: 16 ms timeout (else 8 ms).
pub const WATCHDOG_16MS: u32 = 1 << 0;
/// Watchdog control: enabled.
pub const WATCHDOG_ENABLE: u32 = 1 << 2;
/// Watchdog control: DAC writes restart it.
pub const WATCHDOG_DAC_RESETS: u32 = 1 << 4;
/// Written to [`WATCHDOG_RESET`] to restart the watchdog.
pub const WATCHDOG_KICK: u32 = 0x5A;

/// The watchdog's timeout for a control value, in ns.
pub const fn watchdog_timeout_ns(control: u32) -> u64 {
    if control & WATCHDOG_16MS != 0 {
        16_000_000
    } else {
        8_000_000
    }
}

/// ADC command: convert channels 0..3.
pub const ADC_CMD_CH0_3: u32 = 3;
/// ADC command: convert channels 4..7.
pub const ADC_CMD_CH4_7: u32 = 7;
/// ADC command: power down.
pub const ADC_CMD_POWER_DOWN: u32 = 8;

/// The channels an ADC command converts, in the order their results come
/// out; empty for power-down and unknown commands.
pub fn adc_command_channels(cmd: u32) -> std::ops::Range<usize> {
    match cmd {
        0..=3 => 0..cmd as usize + 1,
        4..=7 => 4..cmd as usize + 1,
        _ => 0..0,
    }
}

/// DACs per board.
pub const DACS: usize = 8;
/// ADC channels per board.
pub const ADCS: usize = 8;
/// The DAC code of 0 V.
pub const DAC_ZERO: u32 = 0x1000;
/// The DAC's range in volts.
pub const DAC_MAX_VOLTS: f64 = 10.0;

/// The DAC code for `volts`, as LinuxCNC computes it: clamped to ±10 V,
/// then `volts * -8191 / 20 + 4096` truncated: +10 V is 0, 0 V is 0x1000,
/// -10 V is 0x1FFF.
#[inline]
pub fn dac_code(volts: f64) -> u32 {
    let v = if volts.is_nan() { 0.0 } else { volts };
    let v = v.clamp(-DAC_MAX_VOLTS, DAC_MAX_VOLTS);
    (v * -8191.0 / 20.0 + 4096.0) as u32
}

/// The voltage a DAC outputs for `code` (the inverse of [`dac_code`],
/// for the simulator): the low 13 bits count, 0 V at 0x1000.
pub fn dac_volts(code: u32) -> f64 {
    (4096.0 - (code & 0x1FFF) as f64) * 20.0 / 8191.0
}

/// Volts per ADC count: 14-bit results over ±5 V.
pub const ADC_VOLTS_PER_COUNT: f64 = 10.0 / 16384.0;

/// An ADC result register as a signed count: 14-bit two's complement.
#[inline]
pub fn adc_count(raw: u32) -> i32 {
    if raw & 0x2000 != 0 {
        (raw | 0xFFFF_C000) as i32
    } else {
        (raw & 0x3FFF) as i32
    }
}

/// The ADC result register for `volts` (for the simulator): rounded,
/// clamped to the 14-bit range.
pub fn adc_raw(volts: f64) -> u32 {
    let counts = (volts / ADC_VOLTS_PER_COUNT).round();
    let counts = if counts.is_nan() { 0.0 } else { counts };
    (counts.clamp(-8192.0, 8191.0) as i32 as u32) & 0x3FFF
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dac_codes_at_both_ends_and_zero() {
        assert_eq!(dac_code(10.0), 0);
        assert_eq!(dac_code(-10.0), 0x1FFF);
        assert_eq!(dac_code(0.0), DAC_ZERO);
        assert_eq!(dac_code(25.0), 0, "clamped");
        assert_eq!(dac_code(-1e9), 0x1FFF, "clamped");
        assert_eq!(dac_code(f64::NAN), DAC_ZERO);
        assert_eq!(dac_code(5.0), 2048, "5 * -409.55 + 4096 = 2048.25");
        assert!((dac_volts(dac_code(-3.3)) + 3.3).abs() < 20.0 / 8191.0);
        assert_eq!(dac_volts(DAC_ZERO), 0.0);
    }

    #[test]
    fn adc_results_are_14_bit_signed() {
        assert_eq!(adc_count(0x1FFF), 8191);
        assert_eq!(adc_count(0x2000), -8192);
        assert_eq!(adc_count(0x3FFF), -1);
        assert_eq!(
            adc_count(0xFFFF_0005),
            5,
            "bits above 13 ignored when positive"
        );
        for v in [-5.0, -2.5, -0.001, 0.0, 1.25, 4.999] {
            let back = adc_count(adc_raw(v)) as f64 * ADC_VOLTS_PER_COUNT;
            assert!((back - v).abs() <= ADC_VOLTS_PER_COUNT / 2.0, "{v} {back}");
        }
        assert_eq!(adc_count(adc_raw(9.0)), 8191, "clamped");
    }

    #[test]
    fn adc_commands_select_lists() {
        assert_eq!(adc_command_channels(ADC_CMD_CH0_3), 0..4);
        assert_eq!(adc_command_channels(ADC_CMD_CH4_7), 4..8);
        assert_eq!(adc_command_channels(0), 0..1);
        assert_eq!(adc_command_channels(5), 4..6);
        assert!(adc_command_channels(ADC_CMD_POWER_DOWN).is_empty());
    }

    #[test]
    fn fpga_blocks() {
        assert_eq!(encoder_count(1, 3), 0x2C);
        assert_eq!(digital_io(1), 0x30);
        assert_eq!(status_control(0), 0x14);
        assert_eq!(dac(7), 0x7C);
        assert_eq!(WINDOW_LEN, 0xA4);
    }
}
