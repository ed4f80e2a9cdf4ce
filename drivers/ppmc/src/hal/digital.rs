//! Digital inputs and outputs of the USC, the UPC and the PPMC digital
//! I/O board, as the canonical digital interfaces with LinuxCNC's names:
//! `ppmc.<bus>.din.<n>.in` / `.in-not`, `ppmc.<bus>.dout.<n>.out`; the
//! inversion param is `dout.<n>-invert` on a USC/UPC and `dout.<n>.invert`
//! on a DIO board, as LinuxCNC names them. The first DIO board on a bus
//! also has the estop circuit: `din.estop.in`, `din.fault.in` (and their
//! `-not`), `dout.Estop.out` and `dout.Estop.invert`. On a USC/UPC the
//! estop input is input 15 and the estop output is output 7.

use canonical::{ChannelNames, DigIn, DigOut};
use hal_core::{HalHost, PinFactory, Result};

use crate::epp::block;
use crate::regs::{dio, uxc, SPAN};

/// A board's digital inputs.
pub struct Dins<H: HalHost> {
    pins: Vec<DigIn<H>>,
    /// DIO estop master: the estop and fault inputs.
    estop: Option<[DigIn<H>; 2]>,
    uxc: bool,
}

fn din_names(bus: usize) -> ChannelNames {
    ChannelNames::custom(move |n, item| format!("ppmc.{bus}.din.{n:02}.{item}"))
}

impl<H: HalHost> Dins<H> {
    /// A USC/UPC's 16 inputs, numbered from `first`.
    pub fn uxc(c: &impl PinFactory<H>, bus: usize, first: usize) -> Result<Self> {
        let names = din_names(bus);
        Ok(Dins {
            pins: (first..first + 16)
                .map(|n| DigIn::export(c, &names, n))
                .collect::<Result<_>>()?,
            estop: None,
            uxc: true,
        })
    }

    /// A DIO board's 16 inputs from `first`, and the estop inputs when it
    /// is the bus's estop master.
    pub fn dio(c: &impl PinFactory<H>, bus: usize, first: usize, master: bool) -> Result<Self> {
        let names = din_names(bus);
        let named = |what: &'static str| {
            ChannelNames::custom(move |_, item| format!("ppmc.{bus}.din.{what}.{item}"))
        };
        Ok(Dins {
            pins: (first..first + 16)
                .map(|n| DigIn::export(c, &names, n))
                .collect::<Result<_>>()?,
            estop: if master {
                Some([
                    DigIn::export(c, &named("estop"), 0)?,
                    DigIn::export(c, &named("fault"), 0)?,
                ])
            } else {
                None
            },
            uxc: false,
        })
    }

    /// The registers to read.
    pub fn read_map(&self) -> u32 {
        match (self.uxc, self.estop.is_some()) {
            (true, _) => block(uxc::DIN_A, uxc::DIN_B),
            (false, true) => block(dio::DIN_A, dio::ESTOP_IN),
            (false, false) => block(dio::DIN_A, dio::DIN_B),
        }
    }

    /// Publishes the lines read.
    pub fn read(&self, rd: &[u8; SPAN]) {
        let (a, b) = if self.uxc {
            (uxc::DIN_A, uxc::DIN_B)
        } else {
            (dio::DIN_A, dio::DIN_B)
        };
        let lines = rd[a as usize] as u16 | (rd[b as usize] as u16) << 8;
        for (i, p) in self.pins.iter().enumerate() {
            p.update(lines & (1 << i) != 0);
        }
        if let Some(e) = &self.estop {
            let v = rd[dio::ESTOP_IN as usize];
            e[0].update(v & 1 != 0);
            e[1].update(v & 2 != 0);
        }
    }
}

/// A board's digital outputs.
pub struct Douts<H: HalHost> {
    pins: Vec<DigOut<H>>,
    /// DIO estop master: `dout.Estop`.
    estop: Option<DigOut<H>>,
    uxc: bool,
}

impl<H: HalHost> Douts<H> {
    /// A USC/UPC's 8 outputs, numbered from `first`.
    pub fn uxc(c: &impl PinFactory<H>, bus: usize, first: usize) -> Result<Self> {
        let names = ChannelNames::custom(move |n, item| match item {
            "invert" => format!("ppmc.{bus}.dout.{n:02}-invert"),
            _ => format!("ppmc.{bus}.dout.{n:02}.{item}"),
        });
        Ok(Douts {
            pins: (first..first + 8)
                .map(|n| DigOut::export(c, &names, n))
                .collect::<Result<_>>()?,
            estop: None,
            uxc: true,
        })
    }

    /// A DIO board's 8 outputs from `first`, and `dout.Estop` when it is
    /// the bus's estop master.
    pub fn dio(c: &impl PinFactory<H>, bus: usize, first: usize, master: bool) -> Result<Self> {
        let names = ChannelNames::custom(move |n, item| format!("ppmc.{bus}.dout.{n:02}.{item}"));
        let estop_names =
            ChannelNames::custom(move |_, item| format!("ppmc.{bus}.dout.Estop.{item}"));
        Ok(Douts {
            pins: (first..first + 8)
                .map(|n| DigOut::export(c, &names, n))
                .collect::<Result<_>>()?,
            estop: if master {
                Some(DigOut::export(c, &estop_names, 0)?)
            } else {
                None
            },
            uxc: false,
        })
    }

    /// The registers to write.
    pub fn write_map(&self) -> u32 {
        match (self.uxc, self.estop.is_some()) {
            (true, _) => block(uxc::DOUT, uxc::DOUT),
            (false, true) => block(dio::DOUT, dio::ESTOP_OUT),
            (false, false) => block(dio::DOUT, dio::DOUT),
        }
    }

    /// Fills the output registers: `out XOR invert` on each line.
    pub fn write(&self, wr: &mut [u8; SPAN]) {
        let at = if self.uxc { uxc::DOUT } else { dio::DOUT };
        wr[at as usize] = DigOut::pack(&self.pins, DigOut::level) as u8;
        if let Some(e) = &self.estop {
            wr[dio::ESTOP_OUT as usize] = u8::from(e.level());
        }
    }
}
