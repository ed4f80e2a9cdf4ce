//! The simulated devices: the coupler EK1100, digital inputs EL1008 and
//! EL1018, digital outputs EL2008 and EL2088, analog input EL3102,
//! analog output EL4102, encoder EL5101, stepper EL7041, and a generic
//! slave whose PDO entries the segment file names (inputs mirror the
//! outputs of the same size, so a loop-back shows data went both ways).
//! The CiA 402 servo drive is [`super::servo`].
//!
//! Identities and PDO layouts are those of the real terminals (vendor 2,
//! product codes by type number), so a configuration written for the
//! hardware finds them.

use std::any::Any;

use super::device::{dictionary, Application, Device, PdoSpec, INPUTS_AT, OUTPUTS_AT};
use super::od::{dtype, Dictionary};
use crate::wire::sii::Identity;

/// Beckhoff's vendor id.
pub const BECKHOFF: u32 = 0x0000_0002;

/// An application that does nothing: the world sets inputs in the
/// dictionary and reads outputs from it.
struct Passive;

impl Application for Passive {
    fn cycle(&mut self, _: &mut Dictionary, _: bool, _: u64, _: u64) {}
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// Outputs go to 0 while the slave is not in OP (a terminal's safe
/// state): what the world reads of an output terminal.
struct SafeOutputs {
    objects: Vec<(u16, u8)>,
}

impl Application for SafeOutputs {
    fn cycle(&mut self, od: &mut Dictionary, outputs_valid: bool, _: u64, _: u64) {
        if !outputs_valid {
            for (i, s) in &self.objects {
                od.set(*i, *s, 0);
            }
        }
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

fn identity(product: u32, serial: u32) -> Identity {
    Identity {
        vendor: BECKHOFF,
        product,
        revision: 0x0011_0000,
        serial,
    }
}

fn device(
    kind: &str,
    id: Identity,
    order: &str,
    group: &str,
    mailbox: bool,
    od: Dictionary,
    app: Box<dyn Application>,
) -> Device {
    Device {
        kind: kind.to_string(),
        identity: id,
        name: order.to_string(),
        order: kind.to_string(),
        group: group.to_string(),
        mailbox,
        dc: false,
        needs_sync0: false,
        od,
        outputs_at: if mailbox { OUTPUTS_AT } else { 0x0F00 },
        inputs_at: if mailbox { INPUTS_AT } else { 0x1000 },
        app,
    }
}

/// A device whose ESC has distributed clocks (a reference clock, and
/// SYNC0/SYNC1 for those that use them).
fn with_dc(
    kind: &str,
    id: Identity,
    order: &str,
    group: &str,
    mailbox: bool,
    od: Dictionary,
    app: Box<dyn Application>,
) -> Device {
    Device {
        dc: true,
        ..device(kind, id, order, group, mailbox, od, app)
    }
}

/// EK1100 EtherCAT coupler: no process data.
pub fn ek1100(serial: u32) -> Device {
    let id = identity(0x044C_2C52, serial);
    let od = dictionary(id, "EK1100", &[], &[], &[], &[]);
    with_dc(
        "EK1100",
        id,
        "EK1100 EtherCAT-Koppler (2A E-Bus)",
        "Coupler",
        false,
        od,
        Box::new(Passive),
    )
}

fn digital_inputs(kind: &str, product: u32, serial: u32) -> Device {
    let id = identity(product, serial);
    let names: Vec<String> = (0..8).map(|i| format!("Channel {}", i + 1)).collect();
    let pdos: Vec<PdoSpec<'_>> = (0..8u16)
        .map(|i| PdoSpec {
            index: 0x1A00 + i,
            name: &names[usize::from(i)],
            entries: vec![(0x6000 + 0x10 * i, 1, "Input", dtype::BOOL, 1)],
        })
        .collect();
    let assigned: Vec<u16> = (0..8).map(|i| 0x1A00 + i).collect();
    let od = dictionary(id, kind, &[], &pdos, &[], &assigned);
    device(
        kind,
        id,
        &format!("{kind} 8K. Dig. Eingang 24V"),
        "DigIn",
        false,
        od,
        Box::new(Passive),
    )
}

/// EL1008: 8 digital inputs, 3 ms filter.
pub fn el1008(serial: u32) -> Device {
    digital_inputs("EL1008", 0x03F0_3052, serial)
}

/// EL1018: 8 digital inputs, 10 µs filter.
pub fn el1018(serial: u32) -> Device {
    digital_inputs("EL1018", 0x03FA_3052, serial)
}

fn digital_outputs(kind: &str, product: u32, serial: u32) -> Device {
    let id = identity(product, serial);
    let names: Vec<String> = (0..8).map(|i| format!("Channel {}", i + 1)).collect();
    let pdos: Vec<PdoSpec<'_>> = (0..8u16)
        .map(|i| PdoSpec {
            index: 0x1600 + i,
            name: &names[usize::from(i)],
            entries: vec![(0x7000 + 0x10 * i, 1, "Output", dtype::BOOL, 1)],
        })
        .collect();
    let assigned: Vec<u16> = (0..8).map(|i| 0x1600 + i).collect();
    let od = dictionary(id, kind, &pdos, &[], &assigned, &[]);
    let objects = (0..8).map(|i| (0x7000 + 0x10 * i, 1)).collect();
    device(
        kind,
        id,
        &format!("{kind} 8K. Dig. Ausgang 24V"),
        "DigOut",
        false,
        od,
        Box::new(SafeOutputs { objects }),
    )
}

/// EL2008: 8 digital outputs, 0.5 A.
pub fn el2008(serial: u32) -> Device {
    digital_outputs("EL2008", 0x07D8_3052, serial)
}

/// EL2088: 8 digital outputs, switching to ground.
pub fn el2088(serial: u32) -> Device {
    digital_outputs("EL2088", 0x0828_3052, serial)
}

/// EL3102: 2 analog inputs ±10 V, 16 bit (status byte and value per
/// channel in 0x3101/0x3102, as the terminal's compact PDOs).
pub fn el3102(serial: u32) -> Device {
    let id = identity(0x0C1E_3052, serial);
    let pdos = [
        PdoSpec {
            index: 0x1A00,
            name: "AI Inputs Ch.1",
            entries: vec![
                (0x3101, 1, "Status", dtype::U8, 8),
                (0x3101, 2, "Value", dtype::I16, 16),
            ],
        },
        PdoSpec {
            index: 0x1A01,
            name: "AI Inputs Ch.2",
            entries: vec![
                (0x3102, 1, "Status", dtype::U8, 8),
                (0x3102, 2, "Value", dtype::I16, 16),
            ],
        },
    ];
    let od = dictionary(id, "EL3102", &[], &pdos, &[], &[0x1A00, 0x1A01]);
    device(
        "EL3102",
        id,
        "EL3102 2K. Ana. Eingang +/-10V, DIFF",
        "AnaIn",
        true,
        od,
        Box::new(Passive),
    )
}

/// EL4102: 2 analog outputs 0..10 V, 16 bit.
pub fn el4102(serial: u32) -> Device {
    let id = identity(0x1006_3052, serial);
    let pdos = [
        PdoSpec {
            index: 0x1600,
            name: "AO Output Ch.1",
            entries: vec![(0x3001, 1, "Output", dtype::I16, 16)],
        },
        PdoSpec {
            index: 0x1601,
            name: "AO Output Ch.2",
            entries: vec![(0x3002, 1, "Output", dtype::I16, 16)],
        },
    ];
    let od = dictionary(id, "EL4102", &pdos, &[], &[0x1600, 0x1601], &[]);
    device(
        "EL4102",
        id,
        "EL4102 2K. Ana. Ausgang 0-10V, 16bit",
        "AnaOut",
        true,
        od,
        Box::new(SafeOutputs {
            objects: vec![(0x3001, 1), (0x3002, 1)],
        }),
    )
}

/// The EL5101's counter, driven by a shaft the test turns.
#[derive(Debug, Default)]
pub struct Encoder {
    /// Counts per second the shaft turns at.
    pub counts_per_s: f64,
    /// Where the index pulse is (counts, modulo `index_every`).
    pub index_every: i64,
    position: f64,
    /// The count latched at an index pulse while latch C was enabled;
    /// it stays (and "latch C valid" with it) until the enable drops.
    latched: Option<i64>,
}

impl Application for Encoder {
    fn cycle(&mut self, od: &mut Dictionary, outputs_valid: bool, _: u64, dt_ns: u64) {
        let before = self.position;
        self.position += self.counts_per_s * dt_ns as f64 * 1e-9;
        let count = self.position.floor() as i64;
        let ctrl = if outputs_valid {
            od.get(0x7000, 1) as u8
        } else {
            0
        };
        let mut status = 0u8;
        if ctrl & 0x04 != 0 {
            // Set counter.
            let v = od.get_signed(0x7000, 2);
            self.position = v as f64;
            status |= 0x04;
        }
        if ctrl & 0x01 == 0 {
            self.latched = None;
        } else if self.latched.is_none() && self.index_every > 0 {
            let a = before.floor().div_euclid(self.index_every as f64);
            let b = (count as f64).div_euclid(self.index_every as f64);
            if a != b {
                // The pulse between the two: the multiple passed.
                let at = a.max(b) as i64 * self.index_every;
                self.latched = Some(at);
                od.set(0x6000, 3, at as u64);
            }
        }
        if self.latched.is_some() {
            status |= 0x01;
        }
        od.set(0x6000, 1, u64::from(status));
        od.set(0x6000, 2, self.position.floor() as i64 as u64);
        let hz = self.counts_per_s.abs() / 4.0;
        od.set(0x6000, 4, (hz * 100.0) as u64);
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// EL5101: incremental encoder interface, 16-bit counter.
pub fn el5101(serial: u32) -> Device {
    let id = identity(0x13ED_3052, serial);
    let outs = [PdoSpec {
        index: 0x1600,
        name: "Outputs",
        entries: vec![
            (0x7000, 1, "Ctrl", dtype::U8, 8),
            (0x7000, 2, "Value", dtype::U16, 16),
        ],
    }];
    let ins = [
        PdoSpec {
            index: 0x1A00,
            name: "Inputs",
            entries: vec![
                (0x6000, 1, "Status", dtype::U8, 8),
                (0x6000, 2, "Value", dtype::U16, 16),
                (0x6000, 3, "Latch", dtype::U16, 16),
            ],
        },
        PdoSpec {
            index: 0x1A02,
            name: "Period",
            entries: vec![
                (0x6000, 4, "Frequency", dtype::U32, 32),
                (0x6000, 5, "Period", dtype::U16, 16),
                (0x6000, 6, "Window", dtype::U16, 16),
            ],
        },
    ];
    let od = dictionary(id, "EL5101", &outs, &ins, &[0x1600], &[0x1A00, 0x1A02]);
    with_dc(
        "EL5101",
        id,
        "EL5101 1K. Inc. Encoder 5V",
        "Encoder",
        true,
        od,
        Box::new(Encoder {
            index_every: 4000,
            ..Encoder::default()
        }),
    )
}

/// The EL7041's stepper in velocity mode with its encoder, as lcec
/// configures it: while enabled the motor turns at the commanded share
/// of `max_speed` (16-bit velocity, ±32767 full speed), and the encoder
/// counts its steps. The encoder's C track pulses every `index_every`
/// counts (`Status of input C` in the cycle it passes); with latch C
/// enabled (0x7000:01) the first pulse's count is latched into
/// 0x6000:12 and `Latch C valid` (0x6000:01) set, both held until the
/// enable drops, as the terminal does.
#[derive(Debug)]
pub struct Stepper {
    /// Steps per second at full command.
    pub max_speed: f64,
    /// Where the motor is (steps).
    pub position: f64,
    /// An error the test raised (cleared by the reset bit).
    pub error: bool,
    /// Counts between the encoder's index pulses (0: none).
    pub index_every: i64,
    /// The count latched at an index pulse while latch C was enabled.
    latched: Option<i64>,
    toggle: bool,
}

impl Stepper {
    /// The index pulse passed between counts `before` and `after`, if
    /// one did: the multiple of `index_every` crossed.
    fn index_between(&self, before: f64, after: f64) -> Option<i64> {
        if self.index_every <= 0 {
            return None;
        }
        let every = self.index_every as f64;
        let (a, b) = (
            before.floor().div_euclid(every),
            after.floor().div_euclid(every),
        );
        (a != b).then(|| a.max(b) as i64 * self.index_every)
    }
}

impl Application for Stepper {
    fn cycle(&mut self, od: &mut Dictionary, outputs_valid: bool, _: u64, dt_ns: u64) {
        let bit = |od: &Dictionary, i, s| outputs_valid && od.get(i, s) != 0;
        let enable = bit(od, 0x7010, 1);
        if bit(od, 0x7010, 2) {
            self.error = false;
        }
        let mut status = 0;
        if bit(od, 0x7000, 3) {
            self.position = od.get(0x7000, 0x11) as u16 as i16 as f64;
            status = 1;
        }
        let velocity = if outputs_valid {
            od.get_signed(0x7010, 0x21) as f64 / 32767.0 * self.max_speed
        } else {
            0.0
        };
        let mut moving = 0.0;
        let before = self.position;
        if enable && !self.error {
            moving = velocity * dt_ns as f64 * 1e-9;
            self.position += moving;
        }
        let index = self.index_between(before, self.position);
        if !bit(od, 0x7000, 1) {
            self.latched = None;
        } else if let (None, Some(at)) = (self.latched, index) {
            self.latched = Some(at);
            od.set(0x6000, 0x12, u64::from(at as u16));
        }
        self.toggle = !self.toggle;
        od.set(0x6000, 1, u64::from(self.latched.is_some()));
        od.set(0x6000, 0x0B, u64::from(index.is_some()));
        od.set(0x6000, 3, status);
        od.set(0x6000, 0x10, u64::from(self.toggle));
        od.set(0x6000, 0x11, u64::from(self.position.floor() as i64 as u16));
        od.set(0x6010, 1, u64::from(!self.error));
        od.set(0x6010, 2, u64::from(enable && !self.error));
        od.set(0x6010, 4, u64::from(self.error));
        od.set(0x6010, 5, u64::from(moving > 0.0));
        od.set(0x6010, 6, u64::from(moving < 0.0));
        od.set(0x6010, 0x10, u64::from(self.toggle));
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// EL7041: stepper terminal, 5 A, with the PDOs lcec assigns (encoder
/// control and status, stepper control and status, velocity).
pub fn el7041(serial: u32) -> Device {
    let id = identity(0x1B81_3052, serial);
    let bool_entry = |i, s, n| (i, s, n, dtype::BOOL, 1);
    let gap = |bits| (0, 0, "", 0, bits);
    let outs = [
        PdoSpec {
            index: 0x1600,
            name: "ENC RxPDO-Map Control compact",
            entries: vec![
                bool_entry(0x7000, 1, "Enable latch C"),
                bool_entry(0x7000, 2, "Enable latch extern on positive edge"),
                bool_entry(0x7000, 3, "Set counter"),
                bool_entry(0x7000, 4, "Enable latch extern on negative edge"),
                gap(4),
                gap(8),
                (0x7000, 0x11, "Set counter value", dtype::U16, 16),
            ],
        },
        PdoSpec {
            index: 0x1602,
            name: "STM RxPDO-Map Control",
            entries: vec![
                bool_entry(0x7010, 1, "Enable"),
                bool_entry(0x7010, 2, "Reset"),
                bool_entry(0x7010, 3, "Reduce torque"),
                gap(5),
                gap(8),
            ],
        },
        PdoSpec {
            index: 0x1604,
            name: "STM RxPDO-Map Velocity",
            entries: vec![(0x7010, 0x21, "Velocity", dtype::I16, 16)],
        },
    ];
    let ins = [
        PdoSpec {
            index: 0x1A00,
            name: "ENC TxPDO-Map Status compact",
            entries: vec![
                bool_entry(0x6000, 1, "Latch C valid"),
                bool_entry(0x6000, 2, "Latch extern valid"),
                bool_entry(0x6000, 3, "Set counter done"),
                bool_entry(0x6000, 4, "Counter underflow"),
                bool_entry(0x6000, 5, "Counter overflow"),
                gap(2),
                bool_entry(0x6000, 8, "Extrapolation stall"),
                bool_entry(0x6000, 9, "Status of input A"),
                bool_entry(0x6000, 0x0A, "Status of input B"),
                bool_entry(0x6000, 0x0B, "Status of input C"),
                gap(1),
                bool_entry(0x6000, 0x0D, "Status of extern latch"),
                bool_entry(0x6000, 0x0E, "Sync error"),
                gap(1),
                bool_entry(0x6000, 0x10, "TxPDO Toggle"),
                (0x6000, 0x11, "Counter value", dtype::U16, 16),
                (0x6000, 0x12, "Latch value", dtype::U16, 16),
            ],
        },
        PdoSpec {
            index: 0x1A03,
            name: "STM TxPDO-Map Status",
            entries: vec![
                bool_entry(0x6010, 1, "Ready to enable"),
                bool_entry(0x6010, 2, "Ready"),
                bool_entry(0x6010, 3, "Warning"),
                bool_entry(0x6010, 4, "Error"),
                bool_entry(0x6010, 5, "Moving positive"),
                bool_entry(0x6010, 6, "Moving negative"),
                bool_entry(0x6010, 7, "Torque reduced"),
                gap(4),
                bool_entry(0x6010, 0x0C, "Digital input 1"),
                bool_entry(0x6010, 0x0D, "Digital input 2"),
                bool_entry(0x6010, 0x0E, "Sync error"),
                gap(1),
                bool_entry(0x6010, 0x10, "TxPDO Toggle"),
            ],
        },
    ];
    let mut od = dictionary(
        id,
        "EL7041",
        &outs,
        &ins,
        &[0x1600, 0x1602, 0x1604],
        &[0x1A00, 0x1A03],
    );
    use super::od::Access;
    od.add(
        0x8010,
        1,
        "Maximal current",
        (dtype::U16, 16),
        Access::Rw,
        5000,
    );
    od.add(
        0x8010,
        2,
        "Reduced current",
        (dtype::U16, 16),
        Access::Rw,
        2500,
    );
    od.add(
        0x8010,
        3,
        "Nominal voltage",
        (dtype::U16, 16),
        Access::Rw,
        5000,
    );
    od.add(
        0x8010,
        4,
        "Motor coil resistance",
        (dtype::U16, 16),
        Access::Rw,
        100,
    );
    od.add(0x8010, 5, "Motor EMF", (dtype::U16, 16), Access::Rw, 0);
    od.add(0x8012, 1, "Operation mode", (dtype::U8, 8), Access::Rw, 0);
    with_dc(
        "EL7041",
        id,
        "EL7041 1K. Schrittmotor-Endstufe (50V, 5A)",
        "DriveAxisTerminals",
        true,
        od,
        Box::new(Stepper {
            max_speed: 20_000.0,
            position: 0.0,
            error: false,
            index_every: 1000,
            latched: None,
            toggle: false,
        }),
    )
}

/// A generic slave's process entry: index, sub-index, bit length.
pub type GenericEntry = (u16, u8, u8);

/// A loop-back for generic slaves: every input takes the value of the
/// output of the same position in the list (0 where there is none).
struct Loopback {
    pairs: Vec<((u16, u8), (u16, u8))>,
}

impl Application for Loopback {
    fn cycle(&mut self, od: &mut Dictionary, outputs_valid: bool, _: u64, _: u64) {
        for (o, i) in &self.pairs {
            let v = if outputs_valid { od.get(o.0, o.1) } else { 0 };
            od.set(i.0, i.1, v);
        }
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// A generic slave with CoE: one RxPDO per output entry (0x1600 + n) and
/// one TxPDO per input entry (0x1A00 + n).
pub fn generic(
    vendor: u32,
    product: u32,
    serial: u32,
    outputs: &[GenericEntry],
    inputs: &[GenericEntry],
) -> Device {
    let id = Identity {
        vendor,
        product,
        revision: 1,
        serial,
    };
    let dt = |bits: u8| match bits {
        1 => dtype::BOOL,
        8 => dtype::U8,
        16 => dtype::U16,
        _ => dtype::U32,
    };
    let spec = |base: u16, list: &[GenericEntry]| -> Vec<PdoSpec<'static>> {
        list.iter()
            .enumerate()
            .map(|(n, (i, s, b))| PdoSpec {
                index: base + n as u16,
                name: "Generic",
                entries: vec![(*i, *s, "Value", dt(*b), *b)],
            })
            .collect()
    };
    let outs = spec(0x1600, outputs);
    let ins = spec(0x1A00, inputs);
    let ao: Vec<u16> = (0..outs.len() as u16).map(|n| 0x1600 + n).collect();
    let ai: Vec<u16> = (0..ins.len() as u16).map(|n| 0x1A00 + n).collect();
    let od = dictionary(id, "Generic", &outs, &ins, &ao, &ai);
    let pairs = outputs
        .iter()
        .zip(inputs)
        .filter(|(o, i)| o.2 == i.2)
        .map(|(o, i)| ((o.0, o.1), (i.0, i.1)))
        .collect();
    device(
        "generic",
        id,
        "Generic simulated slave",
        "Generic",
        true,
        od,
        Box::new(Loopback { pairs }),
    )
}
