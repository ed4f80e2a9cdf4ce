//! A HostMot2 board on an SPI link (`hm2_spi sim=7i90`, `hm2_rpspi
//! sim=7c80`): the board's side of Mesa's SPI frames
//! ([`crate::spi::frame`]) in front of a simulated board, and the
//! firmwares of the SPI boards.
//!
//! | `sim=` | board | connectors | modules |
//! |---|---|---|---|
//! | `7i90` | 7I90HD (as for EPP, [`super::epp`]) | P1, P2, P3 × 24 | 5 stepgens, 4 encoders, 4 PWM |
//! | `7c80` | 7C80 (Raspberry Pi hat) | P1, P2 × 27 | 6 stepgens, 1 encoder, 1 PWM |
//! | `7c81` | 7C81 (Raspberry Pi hat) | P1, P2, P7 × 19 | 5 stepgens, 1 encoder, 1 PWM |
//!
//! The 7C80's and 7C81's pin-outs are this simulator's: step generators
//! from the first pin (step, direction), then the encoder (A, B, index)
//! and the PWM generator (PWM, direction, /enable), the rest GPIO.

use std::sync::Arc;

use hal_driver::bus::RegWindow;
use hal_driver::sim::{BoardModel, SpiModel};

use super::boards::{firmware, Identity};
use super::SimHm2;
use crate::image::{gpio, pd, FirmwareSpec, ModuleSpec};
use crate::regs::gtag;
use crate::spi::frame::{self, FrameError, Registers};

/// The SPI board presets `sim=` takes.
pub const SPI_PRESETS: &[&str] = &["7i90", "7c80", "7c81"];

/// The board end of an SPI link.
pub struct SpiBoardModel {
    board: Arc<SimHm2>,
    /// Messages served.
    pub messages: u64,
    /// Messages refused, and the last reason.
    pub frame_errors: u64,
    /// Why the last refused message was.
    pub last_error: Option<FrameError>,
}

impl SpiBoardModel {
    /// The link to `board`.
    pub fn new(board: Arc<SimHm2>) -> SpiBoardModel {
        SpiBoardModel {
            board,
            messages: 0,
            frame_errors: 0,
            last_error: None,
        }
    }

    /// The board behind the link.
    pub fn board(&self) -> &Arc<SimHm2> {
        &self.board
    }
}

/// The board's registers as frames reach them.
struct Window<'a>(&'a SimHm2);

impl Registers for Window<'_> {
    fn read(&mut self, addr: u32) -> u32 {
        self.0.read32(addr as usize)
    }
    fn write(&mut self, addr: u32, value: u32) {
        self.0.write32(addr as usize, value)
    }
}

/// Time belongs to the board behind the link (the driver's `read`
/// advances it).
impl BoardModel for SpiBoardModel {
    fn describe(&self) -> String {
        format!("simulated SPI link to {}", self.board.describe())
    }
}

impl SpiModel for SpiBoardModel {
    fn exchange(&mut self, buf: &mut [u32]) {
        self.messages += 1;
        if let Err(e) = frame::serve(buf, &mut Window(&self.board)) {
            self.frame_errors += 1;
            self.last_error = Some(e);
        }
    }
}

/// The firmware of a simulated SPI board, by name ([`SPI_PRESETS`]).
pub fn preset(name: &str) -> Option<FirmwareSpec> {
    match name {
        "7i90" => super::epp::preset("7i90"),
        "7c80" => Some(raspberry_hat("7c80", "MESA7C80", &["P1", "P2"], 27, 6)),
        "7c81" => Some(raspberry_hat(
            "7c81",
            "MESA7C81",
            &["P1", "P2", "P7"],
            19,
            5,
        )),
        _ => None,
    }
}

/// A 7C80/7C81: `steppers` step generators, an encoder and a PWM
/// generator from the first pin, the rest GPIO.
fn raspberry_hat(
    board: &'static str,
    idrom_name: &'static str,
    connectors: &'static [&'static str],
    width: u32,
    steppers: u8,
) -> FirmwareSpec {
    let mut pins = Vec::new();
    for k in 0..steppers {
        pins.push(pd(gtag::STEPGEN, k, 0x81));
        pins.push(pd(gtag::STEPGEN, k, 0x82));
    }
    pins.extend((1..=3).map(|f| pd(gtag::ENCODER, 0, f)));
    pins.extend((0x81..=0x83).map(|f| pd(gtag::PWMGEN, 0, f)));
    pins.resize(connectors.len() * width as usize, gpio());
    firmware(
        Identity {
            board,
            idrom_name,
            fpga_part: "6slx9tq144",
            fpga_size: 9,
            fpga_pins: 144,
            connectors,
            port_width: width,
            clock_low: 100_000_000,
        },
        vec![
            ModuleSpec::standard(gtag::WATCHDOG, 0, 1),
            ModuleSpec::standard(gtag::IOPORT, 0, connectors.len() as u8),
            ModuleSpec::standard(gtag::ENCODER, 2, 1),
            ModuleSpec::standard(gtag::STEPGEN, 2, steppers),
            ModuleSpec::standard(gtag::PWMGEN, 1, 1),
            ModuleSpec::standard(gtag::LED, 0, 1),
        ],
        pins,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spi::frame::Command;

    #[test]
    fn the_link_serves_frames_and_counts_bad_ones() {
        for name in SPI_PRESETS {
            let spec = preset(name).unwrap();
            let (board, _) = crate::sim::board(spec, Box::new(super::super::machine::preset(name)));
            let mut link = SpiBoardModel::new(board);
            let mut buf = [Command::read(0x100, 3).encode(), 0, 0, 0];
            link.exchange(&mut buf);
            assert_eq!(buf[1], 0x55AA_CAFE, "{name}: the cookie");
            assert_eq!(&buf[2].to_le_bytes(), b"HOST");
            let mut bad = [0x0100_C840, 0];
            link.exchange(&mut bad);
            assert_eq!(link.frame_errors, 1);
            assert!(matches!(
                link.last_error,
                Some(FrameError::NotACommand { .. })
            ));
            assert_eq!(link.messages, 2);
        }
        assert!(preset("7i43").is_none());
    }
}
