//! Fuzz bodies for hm2_modbus's two inputs from outside: `.mbccb`
//! command files (the `hm2_mbccb` target, seeded by [`seed_mbccbs`]) and
//! mesambccc's XML sources (`hm2_mbccs`). Re-exported by the crate's
//! `fuzzing` module beside the other targets' bodies.

/// Sample `.mbccb` files for the `hm2_mbccb` target: a file with init
/// packets, a delay, a communication change, and every function.
pub fn seed_mbccbs() -> Vec<Vec<u8>> {
    use crate::modbus::encode::encode;
    use crate::modbus::mbccb::{Command, HalType, Init, Mbccb, ModbusType, PinSpec};
    let pin = |name: &str, htype, mtype, flags, regofs| PinSpec {
        name: name.into(),
        htype,
        mtype: ModbusType(mtype),
        flags,
        regofs,
    };
    let cmd = |func, regcnt, pins| Command {
        mbid: 1,
        func,
        flags: 0,
        addr: 0x10,
        regcnt,
        interval_us: 0,
        timeout_us: 20_000,
        pins,
    };
    let m = Mbccb {
        baudrate: 19_200,
        format: 1,
        txdelay: 0,
        rxdelay: 0,
        drvdelay: 0,
        icdelay: 0,
        inits: vec![
            Init::Packet {
                mbid: 1,
                func: 6,
                flags: 0,
                timeout_us: 10_000,
                pdu: vec![1, 6, 0, 1, 0, 2],
            },
            Init::Delay { us: 1000 },
            Init::Comms {
                baud: 9600,
                flags: 0x0100,
                rxdelay: 0,
                txdelay: 0,
                drvdelay: 0,
                icdelay: 0,
            },
        ],
        commands: vec![
            cmd(
                1,
                0,
                vec![
                    pin("a.c-00", HalType::Bit, 0, 0, 0),
                    pin("a.c-01", HalType::Bit, 0, 0, 0),
                ],
            ),
            cmd(
                3,
                6,
                vec![
                    pin("a.f", HalType::Float, 0x22, 3, 0),
                    pin("a.s", HalType::S64, 0x16, 1, 2),
                ],
            ),
            cmd(
                16,
                3,
                vec![
                    pin("a.w", HalType::S32, 0x13, 3, 0),
                    pin("a.h", HalType::Float, 0x20, 2, 2),
                ],
            ),
            cmd(6, 1, vec![pin("a.one", HalType::U32, 0x0e, 0, 0)]),
            cmd(5, 0, vec![pin("a.coil", HalType::Bit, 0, 0, 0)]),
            Command {
                mbid: 0,
                func: 0,
                flags: 0,
                addr: 0,
                regcnt: 0,
                interval_us: 0,
                timeout_us: 500,
                pins: vec![],
            },
        ],
        warnings: Vec::new(),
    };
    vec![encode(&m)]
}

/// An `.mbccb` file (hm2_modbus) through the parser: no panic; a refusal
/// names an offset inside the file (or its end); an accepted file written
/// again parses to the same contents; an engine running it against a line
/// that answers with the rest of the input's bytes never panics and keeps
/// its pins' types.
pub fn mbccb_file(data: &[u8]) {
    use crate::modbus::{encode::encode, engine, line::Versions, mbccb};
    let file = match mbccb::parse(data) {
        Ok(f) => f,
        Err(e) => {
            if let crate::Hm2Error::Mbccb { offset, .. } = &e {
                assert!(*offset <= data.len(), "{e}");
            }
            assert!(!e.to_string().trim().is_empty());
            return;
        }
    };
    let again = mbccb::parse(&encode(&file)).expect("a re-encoded file parses");
    assert_eq!(again.commands, file.commands);
    assert_eq!(again.inits, file.inits);
    let mut e = engine::Engine::new(file, Versions { rx: 3, tx: 3 });
    let types: Vec<_> = e
        .pins
        .iter()
        .map(|p| std::mem::discriminant(&p.value))
        .collect();
    let mut port = FuzzPort {
        bytes: data,
        at: 0,
        fetching: false,
    };
    for _ in 0..64 {
        e.process(&mut port, 5_000_000);
    }
    for (p, t) in e.pins.iter().zip(types) {
        assert_eq!(std::mem::discriminant(&p.value), t);
    }
}

/// A PktUART whose every status and received frame is the next slice of
/// the fuzz input.
struct FuzzPort<'a> {
    bytes: &'a [u8],
    at: usize,
    fetching: bool,
}

impl FuzzPort<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        let end = (self.at + n).min(self.bytes.len());
        let s = &self.bytes[self.at..end];
        self.at = end;
        s
    }
}

impl crate::modbus::engine::Port for FuzzPort<'_> {
    fn configure(
        &mut self,
        _rx: &crate::pktuart::LineConfig,
        _tx: &crate::pktuart::LineConfig,
        _flush: bool,
    ) -> Result<(), crate::transport::TransportError> {
        Ok(())
    }
    fn clear(&mut self) -> Result<(), crate::transport::TransportError> {
        Ok(())
    }
    fn send(&mut self, _frame: &[u8]) -> Result<(), crate::transport::TransportError> {
        Ok(())
    }
    fn take_status(&mut self) -> Option<crate::pktuart::link::Status> {
        use crate::regs::pktuart::{rx, tx};
        let b = self.take(1).first().copied().unwrap_or(0);
        if b & 0x40 != 0 {
            return None;
        }
        Some(crate::pktuart::link::Status {
            tx_mode: if b & 0x80 != 0 { tx::BUSY } else { 0 },
            rx_mode: u32::from(b & 1) << rx::NFRAMES_SHIFT,
        })
    }
    fn fetching(&self) -> bool {
        self.fetching
    }
    fn fetch_frame(
        &mut self,
        out: &mut [u8],
    ) -> Result<Option<(u32, usize)>, crate::transport::TransportError> {
        if !self.fetching {
            self.fetching = true;
            return Ok(None);
        }
        self.fetching = false;
        let count = self
            .take(4)
            .iter()
            .fold(0u32, |a, &b| a << 8 | u32::from(b));
        let want = (count & 0x3FF) as usize;
        let src = self.take(want.min(out.len()));
        let n = src.len();
        out[..n].copy_from_slice(src);
        Ok(Some((count, n)))
    }
}

/// A sample `.mbccs` source for the `hm2_mbccs` target.
pub const SEED_MBCCS: &str = r#"<?xml version="1.0"?>
<mesamodbus baudrate="19200" parity="E" timeout="auto">
  <devices><device address="1" name="dev" /></devices>
  <initlist>
    <command device="dev" function="W_REGISTERS" address="4"><data modbustype="S_ABCD" value="-5" /></command>
    <command delay="100" />
    <command baudrate="9600" parity="N" />
  </initlist>
  <commands>
    <command device="dev" function="R_COILS" address="0" count="3" name="c" />
    <command device="dev" function="R_REGISTERS" address="8" modbustype="F_ABCD" haltype="HAL_FLOAT">
      <pin name="a" /><pin skip="2" /><pin name="b" modbustype="U_AB" haltype="HAL_U32" />
    </command>
    <command device="broadcast" function="W_COILS" address="1" count="2" name="w" />
    <command delay="50" />
  </commands>
</mesamodbus>
"#;

/// An `.mbccs` source through mesambccc's compiler: no panic; a refusal
/// names a line inside the text; an accepted source compiles to a file
/// hm2_modbus's parser takes back unchanged.
pub fn mbccs_source(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match crate::modbus::mbccs::compile(text) {
        Ok((file, _)) => {
            let bytes = crate::modbus::encode::encode(&file);
            let back = crate::modbus::mbccb::parse(&bytes).expect("a compiled source loads");
            assert_eq!(back.commands, file.commands);
            assert_eq!(back.inits, file.inits);
        }
        Err(e) => {
            if let crate::Hm2Error::Mbccs { line, .. } = &e {
                assert!(*line as usize <= text.lines().count() + 1, "{e}");
            }
            assert!(!e.to_string().trim().is_empty());
        }
    }
}
