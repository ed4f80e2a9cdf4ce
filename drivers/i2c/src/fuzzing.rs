//! The fuzz body for what the chip drivers take from outside: replies
//! on the I2C bus. [`random_replies`] runs each chip (set-up, cycles,
//! failures, retries, fault resets) against a bus whose every reply, and
//! whether each transfer fails, comes from the fuzz bytes. It must never
//! panic, and it checks what must hold whatever the bus says:
//!
//! * the driver writes only the registers its set-up and cycles name
//!   (never the PCA9685's test mode register, never another MCP23017
//!   register), with block writes whole channels long;
//! * the MCP23017's directions are only ever written as configured, so
//!   no reply can turn an input into a driven output;
//! * while a chip's fault is latched, every output it writes is the safe
//!   one;
//! * every step with a failed transfer (or a chip that answers nonsense)
//!   counts an error and latches the fault.
//!
//! Until the workspace has its `fuzz/` crate this runs from the crate's
//! proptest (`tests/fuzz_replies.rs`, 100 000 cases); a fuzz target can
//! call it as it is.

use std::sync::Mutex;

use hal_core::RtLog;

use crate::bus::{BusError, I2cBus, BLOCK_MAX};
use crate::chips::{AdcSettings, Ads1115Chip, Chip, DioCmd, Mcp23017Chip, Pca9685Chip, PwmCmd};
use crate::regs::{mcp23017 as mcp, pca9685 as pca};
use crate::worker::{ChipRunner, Task, RETRY_NS};

/// What a transfer did, for the checks.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Written {
    reg: u8,
    data: Vec<u8>,
    /// Whether the chip's fault was latched when the cycle started.
    latched: bool,
}

struct Script {
    bytes: Vec<u8>,
    pos: usize,
    writes: Vec<Written>,
    failures: u32,
    latched: bool,
}

/// A bus answering from a script of bytes.
struct ScriptedBus {
    s: Mutex<Script>,
}

impl ScriptedBus {
    fn new(bytes: &[u8]) -> ScriptedBus {
        ScriptedBus {
            s: Mutex::new(Script {
                bytes: bytes.to_vec(),
                pos: 0,
                writes: Vec::new(),
                failures: 0,
                latched: false,
            }),
        }
    }

    fn next(s: &mut Script) -> u8 {
        if s.bytes.is_empty() {
            return 0;
        }
        let b = s.bytes[s.pos % s.bytes.len()];
        s.pos += 1;
        b
    }

    /// Whether this transfer fails, and with what.
    fn outcome(&self) -> Result<(), BusError> {
        let mut s = self.s.lock().unwrap_or_else(|e| e.into_inner());
        let b = Self::next(&mut s);
        if b % 7 == 0 {
            s.failures += 1;
            const ERRNOS: [i32; 5] = [
                libc::ENXIO,
                libc::EIO,
                libc::EREMOTEIO,
                libc::ETIMEDOUT,
                libc::EAGAIN,
            ];
            return Err(BusError(ERRNOS[(b / 7) as usize % ERRNOS.len()]));
        }
        Ok(())
    }

    fn write(&self, reg: u8, data: &[u8]) -> Result<(), BusError> {
        self.outcome()?;
        let mut s = self.s.lock().unwrap_or_else(|e| e.into_inner());
        let latched = s.latched;
        s.writes.push(Written {
            reg,
            data: data.to_vec(),
            latched,
        });
        Ok(())
    }

    fn read(&self, out: &mut [u8]) -> Result<(), BusError> {
        self.outcome()?;
        let mut s = self.s.lock().unwrap_or_else(|e| e.into_inner());
        for b in out {
            *b = Self::next(&mut s);
        }
        Ok(())
    }

    fn take_writes(&self) -> Vec<Written> {
        std::mem::take(&mut self.s.lock().unwrap_or_else(|e| e.into_inner()).writes)
    }

    fn failures(&self) -> u32 {
        self.s.lock().unwrap_or_else(|e| e.into_inner()).failures
    }

    fn set_latched(&self, latched: bool) {
        self.s.lock().unwrap_or_else(|e| e.into_inner()).latched = latched;
    }
}

impl I2cBus for ScriptedBus {
    fn claim(&self, _addr: u8) -> Result<(), BusError> {
        Ok(())
    }
    fn write_byte_data(&self, _a: u8, reg: u8, value: u8) -> Result<(), BusError> {
        self.write(reg, &[value])
    }
    fn read_byte_data(&self, _a: u8, _reg: u8) -> Result<u8, BusError> {
        let mut b = [0u8; 1];
        self.read(&mut b)?;
        Ok(b[0])
    }
    fn write_word_data(&self, _a: u8, reg: u8, value: u16) -> Result<(), BusError> {
        self.write(reg, &value.to_le_bytes())
    }
    fn read_word_data(&self, _a: u8, _reg: u8) -> Result<u16, BusError> {
        let mut b = [0u8; 2];
        self.read(&mut b)?;
        Ok(u16::from_le_bytes(b))
    }
    fn write_block(&self, _a: u8, reg: u8, data: &[u8]) -> Result<(), BusError> {
        assert!(data.len() <= BLOCK_MAX, "block of {} bytes", data.len());
        self.write(reg, data)
    }
    fn read_block(&self, _a: u8, _reg: u8, out: &mut [u8]) -> Result<(), BusError> {
        self.read(out)
    }
    fn errors(&self) -> u64 {
        self.failures() as u64
    }
    fn describe(&self) -> String {
        "fuzz bus".into()
    }
}

/// Runs `chip` for 24 helper cycles on `bus`, with commands from
/// `cmd(i)`, time stepping 1 ms (and now and then past a retry), and a
/// fault reset now and then; checks every write with `check`.
fn exercise<C: Chip>(
    bus: &ScriptedBus,
    chip: C,
    mut cmd: impl FnMut(usize) -> C::Cmd,
    mut check: impl FnMut(&Written),
) {
    let (runner, mut rt) = ChipRunner::new("fuzz.0", chip, RtLog::new(4));
    let mut now = 0u64;
    let mut failures_before = bus.failures();
    let mut errors_before = 0;
    for i in 0..24 {
        rt.cmd.publish(cmd(i));
        let st = *rt.status.latest();
        // A fault reset asked for in the previous step may clear the
        // latch in this one, and commanded outputs may follow.
        let reset_pending = i > 0 && i % 5 == 0;
        bus.set_latched(st.fault && !reset_pending);
        runner.service(bus, now);
        for w in bus.take_writes() {
            check(&w);
        }
        let st = *rt.status.latest();
        let failures = bus.failures();
        if failures > failures_before {
            assert!(st.errors > errors_before, "a failed transfer is counted");
        }
        if st.errors > errors_before {
            assert!(st.fault, "a failure latches the fault");
        }
        failures_before = failures;
        errors_before = st.errors;
        rt.status.fault_reset(i % 5 == 4);
        now += if i % 9 == 8 { RETRY_NS } else { 1_000_000 };
    }
}

/// The fuzz body: random I2C replies and failures for every chip.
pub fn random_replies(bytes: &[u8]) {
    let first = |k: usize| bytes.get(k).copied().unwrap_or(0);
    let word = |k: usize| u16::from_le_bytes([first(k), first(k + 1)]);

    // PCA9685.
    let bus = ScriptedBus::new(bytes);
    let mut pca_chip =
        Pca9685Chip::new(0x40, first(0).max(3), first(1) & 1 != 0, first(1) & 2 != 0);
    let _ = pca_chip.init(&bus, &PwmCmd::default());
    let setup_regs = [pca::MODE1, pca::PRE_SCALE, pca::MODE2, pca::ALL_LED_OFF_H];
    let check_pca = |w: &Written| {
        assert_ne!(w.reg, pca::TESTMODE, "test mode written");
        if w.data.len() == 1 {
            assert!(setup_regs.contains(&w.reg), "byte write to {:#04x}", w.reg);
        } else {
            let first_ch = (w.reg.wrapping_sub(pca::LED0_ON_L) / 4) as usize;
            assert!(
                w.reg >= pca::LED0_ON_L && (w.reg - pca::LED0_ON_L) % 4 == 0,
                "block at {:#04x}",
                w.reg
            );
            assert!(w.data.len() % 4 == 0 && first_ch + w.data.len() / 4 <= pca::CHANNELS);
            if w.latched {
                for ch in w.data.chunks(4) {
                    assert_eq!(ch, pca::channel_bytes(0), "latched: every channel off");
                }
            }
        }
    };
    for w in bus.take_writes() {
        check_pca(&w);
    }
    exercise(
        &bus,
        pca_chip,
        |i| {
            let mut c = PwmCmd::default();
            for (ch, v) in c.counts.iter_mut().enumerate() {
                *v = word(2 * (ch + i) % 64) % 4097;
            }
            c
        },
        check_pca,
    );

    // MCP23017.
    let bus = ScriptedBus::new(bytes);
    let dir = word(0);
    let pullup = word(2) & dir;
    let safe = word(4) & !dir;
    let mut mcp_chip = Mcp23017Chip::new(0x20, dir, pullup);
    let _ = mcp_chip.init(&bus, &DioCmd { out: safe, safe });
    let allowed = [
        mcp::IOCON_IN_BANK1,
        mcp::IOCON,
        mcp::GPINTENA,
        mcp::IPOLA,
        mcp::GPPUA,
        mcp::OLATA,
        mcp::IODIRA,
    ];
    let check_mcp = |w: &Written| {
        assert!(allowed.contains(&w.reg), "write to {:#04x}", w.reg);
        let v = u16::from_le_bytes([w.data[0], w.data.get(1).copied().unwrap_or(0)]);
        match w.reg {
            mcp::IODIRA => assert_eq!(v, dir, "directions as configured"),
            mcp::GPPUA => assert_eq!(v, pullup),
            mcp::OLATA if w.latched => assert_eq!(v & !dir, safe, "latched: safe levels"),
            mcp::IOCON | mcp::IOCON_IN_BANK1 | mcp::GPINTENA | mcp::IPOLA => assert_eq!(v, 0),
            _ => {}
        }
    };
    for w in bus.take_writes() {
        check_mcp(&w);
    }
    exercise(
        &bus,
        mcp_chip,
        |i| DioCmd {
            out: word(6 + (i % 8)),
            safe,
        },
        check_mcp,
    );

    // ADS1115.
    let bus = ScriptedBus::new(bytes);
    let settings = AdcSettings {
        channels: 1 + first(0) as usize % 4,
        differential: false,
        pga: (first(1) % 6) as u16,
        dr: (first(2) % 8) as u16,
    };
    let mut ads_chip = Ads1115Chip::new(0x48, settings);
    let _ = ads_chip.init(&bus, &());
    let check_ads = |w: &Written| {
        assert_eq!(
            w.reg,
            crate::regs::ads1115::CONFIG,
            "only CONFIG is written"
        );
        let cfg = u16::from_be_bytes([w.data[0], w.data[1]]);
        assert_eq!(
            cfg & 0x0103,
            0x0103,
            "single shot, comparator off: {cfg:#06x}"
        );
    };
    for w in bus.take_writes() {
        check_ads(&w);
    }
    exercise(&bus, ads_chip, |_| (), check_ads);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_few_scripts() {
        random_replies(&[]);
        random_replies(&[0]);
        random_replies(&[1, 2, 3, 4, 5, 6, 8, 9]);
        random_replies(&[7; 40]);
        random_replies(&(0..=255).collect::<Vec<u8>>());
    }
}
