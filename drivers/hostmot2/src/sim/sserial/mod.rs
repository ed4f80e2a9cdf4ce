//! The simulated Smart Serial module (SSLBP, hostmot2-more.md 2.2, 2.3):
//! per port a command and a data register, per channel a control/status
//! register and three interface registers whose reads and writes are
//! different things, the processor's local parameters, and the remote
//! cards on the channels ([`remote`]).
//!
//! A command executes when written and the register reads 0 afterwards
//! (the firmware takes microseconds; the driver polls, and over the
//! network its next read comes later anyway). A channel reaches its card
//! only while the board drives the channel's TX pin (the IOPort gives the
//! pin to the module and makes it an output) and the card is connected:
//! a watchdog bite or a pulled cable cuts it off, and a transfer on it
//! fails with a timeout in the channel's status.

pub mod eight_i20;
pub mod flash;
pub mod remote;

use crate::sserial::{cmd, lbp, local, status, MAX_CHANNELS};
pub use remote::{RemoteKind, RemoteSpec, SimRemote};

/// Where the per-channel blocks of the local parameters start, and
/// their size.
const CHANNEL_START: u16 = 0x10;
const CHANNEL_STRIDE: u16 = 0x40;

/// What a channel is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Chan {
    Stopped,
    Setup,
    Normal,
}

/// One port of the module.
#[derive(Debug, Clone)]
pub struct SimPort {
    channels: usize,
    data: u32,
    cs_written: [u32; MAX_CHANNELS],
    cs_status: [u32; MAX_CHANNELS],
    iface_out: [[u32; 3]; MAX_CHANNELS],
    iface_in: [[u32; 3]; MAX_CHANNELS],
    state: [Chan; MAX_CHANNELS],
    local: Vec<u8>,
    /// The card on each channel.
    pub remotes: [Option<SimRemote>; MAX_CHANNELS],
    /// Commands executed.
    pub commands: u64,
    /// The processor hangs: commands are not executed and the command
    /// register keeps reading the last one (tests of the host's waits).
    pub stuck: bool,
    busy: u32,
}

impl SimPort {
    fn new(channels: usize) -> SimPort {
        let mut local = vec![0u8; 0x240];
        local[local::INTERFACE_TYPE as usize] = 0x12;
        local[local::INTERFACE_WIDTH as usize] = channels as u8;
        local[local::MAJOR_REV as usize] = 0;
        local[local::MINOR_REV as usize] = 43;
        local[local::CHANNEL_START as usize] = CHANNEL_START as u8;
        local[local::CHANNEL_STRIDE as usize] = CHANNEL_STRIDE as u8;
        local[local::PROCESSOR_TYPE as usize] = 0x0D;
        local[local::CHANNELS as usize] = channels as u8;
        // Every channel starts at the rate the cards ship with
        // (remote::DEFAULT_BAUD_INDEX), in its block's baud-rate word.
        let baud = crate::sserial::BAUD_RATES[remote::DEFAULT_BAUD_INDEX as usize].to_le_bytes();
        for c in 0..MAX_CHANNELS {
            let at = (CHANNEL_START + c as u16 * CHANNEL_STRIDE + local::BAUD_RATE) as usize;
            local[at..at + 4].copy_from_slice(&baud);
        }
        let clock = 100_000_000u32.to_le_bytes();
        local[local::CLOCK as usize..local::CLOCK as usize + 4].copy_from_slice(&clock);
        SimPort {
            channels,
            data: 0,
            cs_written: [0; MAX_CHANNELS],
            cs_status: [0; MAX_CHANNELS],
            iface_out: [[0; 3]; MAX_CHANNELS],
            iface_in: [[0; 3]; MAX_CHANNELS],
            state: [Chan::Stopped; MAX_CHANNELS],
            local,
            remotes: Default::default(),
            commands: 0,
            stuck: false,
            busy: 0,
        }
    }

    /// The card on `channel`, if one is plugged in and reachable.
    fn card(&mut self, c: usize, reachable: u8) -> Option<&mut SimRemote> {
        if reachable & (1 << c) == 0 {
            return None;
        }
        self.remotes[c].as_mut().filter(|r| r.connected)
    }

    fn channel_mask(&self, m: u32) -> u32 {
        let all = (1u32 << self.channels) - 1;
        if m & 0xFF == 0 {
            all
        } else {
            m & all
        }
    }

    fn fail(&mut self, c: usize, why: u32) {
        self.data |= 1 << c;
        self.cs_status[c] = why;
    }

    /// Sets local parameter byte `at` (tests: an older processor).
    pub fn set_local(&mut self, at: u16, v: u8) {
        if let Some(b) = self.local.get_mut(at as usize) {
            *b = v;
        }
    }

    /// Executes a command.
    fn command(&mut self, v: u32, reachable: u8) {
        if v & cmd::NOTHING != 0 {
            return;
        }
        if self.stuck {
            self.busy = v;
            return;
        }
        self.busy = 0;
        self.commands += 1;
        let v = v & 0xFFFF;
        if v & 0xE000 == cmd::WRITE_LOCAL {
            if let Some(b) = self.local.get_mut((v & 0x7FF) as usize) {
                *b = self.data as u8;
            }
        } else if v & 0xE000 == cmd::READ_LOCAL {
            self.data = self.local.get((v & 0x7FF) as usize).copied().unwrap_or(0) as u32;
        } else if v & cmd::RESET != 0 {
            self.data = 0;
            for c in 0..MAX_CHANNELS {
                self.state[c] = Chan::Stopped;
                if let Some(r) = &mut self.remotes[c] {
                    r.stop();
                }
            }
        } else if v & cmd::DOIT != 0 {
            self.data = 0;
            let mask = self.channel_mask(v);
            for c in (0..self.channels).filter(|c| mask & (1 << c) != 0) {
                self.doit(c, reachable);
            }
        } else {
            let mask = self.channel_mask(v);
            self.data = 0;
            for c in (0..self.channels).filter(|c| mask & (1 << c) != 0) {
                match v & 0x0F00 {
                    cmd::STOP => {
                        self.state[c] = Chan::Stopped;
                        if let Some(r) = &mut self.remotes[c] {
                            r.stop();
                        }
                    }
                    cmd::START_SETUP => self.start(c, reachable, true),
                    cmd::START_NORMAL => self.start(c, reachable, false),
                    _ => {}
                }
            }
        }
    }

    fn start(&mut self, c: usize, reachable: u8, setup: bool) {
        let mode = (self.cs_written[c] >> 24) as u8;
        let Some(card) = self.card(c, reachable) else {
            self.iface_in[c] = [0; 3];
            self.state[c] = Chan::Stopped;
            self.fail(c, status::NO_ID | status::TIMEOUT);
            return;
        };
        let ok = if setup {
            card.identify(mode).map(|ids| (ids, Chan::Setup))
        } else {
            card.start(mode).then_some(([0; 3], Chan::Normal))
        };
        match ok {
            Some((ids, state)) => {
                if setup {
                    self.iface_in[c] = ids;
                }
                self.state[c] = state;
                self.cs_status[c] = 0;
            }
            None => {
                self.state[c] = Chan::Stopped;
                self.fail(c, status::REMOTE_FAULT | status::ILLEGAL_MODE);
            }
        }
    }

    fn doit(&mut self, c: usize, reachable: u8) {
        let state = self.state[c];
        let cs = self.cs_written[c];
        let out = self.iface_out[c];
        let mut back = self.iface_in[c];
        let Some(card) = self.card(c, reachable) else {
            self.fail(c, status::TIMEOUT | status::COMM_ERROR);
            return;
        };
        match state {
            Chan::Stopped => {
                self.fail(c, status::NOT_READY);
                return;
            }
            Chan::Normal => {
                card.transfer(&out, &mut back);
                let st = card.status();
                self.iface_in[c] = back;
                self.cs_status[c] = st;
                return;
            }
            Chan::Setup => {}
        }
        let op = (cs >> 24) as u8;
        let addr = cs as u16;
        let size = 1usize << (op & 3);
        match op & !3 {
            lbp::READ => {
                let v = card.read_memory(addr, size);
                back = [v as u32, (v >> 32) as u32, 0];
            }
            _ if op == lbp::READ_BYTE => {
                back = [card.read_memory(addr, 1) as u32, 0, 0];
            }
            lbp::WRITE => {
                card.write_memory(addr, size, out[0] as u64 | (out[1] as u64) << 32);
            }
            _ if op == lbp::NONVOLATILE => card.set_nonvolatile(out[0]),
            _ if op == lbp::COOKIE => back = [card.flash.cookie() as u32, 0, 0],
            _ => {
                self.fail(c, status::REMOTE_FAULT | status::LBPCOM);
                return;
            }
        }
        self.iface_in[c] = back;
        self.cs_status[c] = 0;
    }
}

/// The Smart Serial module of a simulated board.
#[derive(Debug, Clone, Default)]
pub struct SimSserial {
    /// Its ports.
    pub ports: Vec<SimPort>,
}

impl SimSserial {
    /// A module of ports with the given numbers of channels.
    pub fn new(channels: &[usize]) -> SimSserial {
        SimSserial {
            ports: channels
                .iter()
                .map(|&n| SimPort::new(n.min(MAX_CHANNELS)))
                .collect(),
        }
    }

    /// Plugs a card in.
    pub fn attach(&mut self, spec: &RemoteSpec) {
        if let Some(p) = self.ports.get_mut(spec.port as usize) {
            if let Some(slot) = p.remotes.get_mut(spec.channel as usize) {
                *slot = Some(SimRemote::new(spec.kind, spec.unit));
            }
        }
    }

    /// Register `reg` (0 command, 1 data, 2 CS, 3..5 interfaces) of
    /// `port`, channel `chan`.
    pub fn read(&self, reg: u8, port: u8, chan: u8) -> u32 {
        let Some(p) = self.ports.get(port as usize) else {
            return 0;
        };
        let c = chan as usize % MAX_CHANNELS;
        match reg {
            0 => p.busy,
            1 => p.data,
            2 => p.cs_status[c],
            3..=5 => p.iface_in[c][reg as usize - 3],
            _ => 0,
        }
    }

    /// A register write; a command executes, reaching the channels whose
    /// bit is set in `reachable`.
    pub fn write(&mut self, reg: u8, port: u8, chan: u8, v: u32, reachable: u8) {
        let Some(p) = self.ports.get_mut(port as usize) else {
            return;
        };
        let c = chan as usize % MAX_CHANNELS;
        match reg {
            0 => p.command(v, reachable),
            1 => p.data = v,
            2 => p.cs_written[c] = v,
            3..=5 => p.iface_out[c][reg as usize - 3] = v,
            _ => {}
        }
    }

    /// Lets `dt_ns` pass for every card.
    pub fn advance(&mut self, dt_ns: u64) {
        for p in &mut self.ports {
            for r in p.remotes.iter_mut().flatten() {
                r.advance(dt_ns);
            }
        }
    }

    /// The card on `port`, `channel`.
    pub fn remote(&mut self, port: usize, channel: usize) -> Option<&mut SimRemote> {
        self.ports.get_mut(port)?.remotes.get_mut(channel)?.as_mut()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discovery_and_a_transfer() {
        let mut s = SimSserial::new(&[2]);
        s.attach(&RemoteSpec {
            port: 0,
            channel: 0,
            kind: RemoteKind::SevenI76,
            unit: 7,
        });
        // The processor's revision.
        s.write(0, 0, 0, cmd::READ_LOCAL | local::MINOR_REV as u32, 3);
        assert_eq!(s.read(1, 0, 0), 43);
        // Setup start on both channels: only 0 has a card.
        s.write(2, 0, 0, 0, 3);
        s.write(2, 0, 1, 0, 3);
        s.write(0, 0, 0, cmd::START_SETUP | 3, 3);
        assert_eq!(s.read(1, 0, 0), 0b10);
        assert_eq!(s.read(3, 0, 0), 0x1000_0007);
        assert_eq!(&s.read(4, 0, 0).to_le_bytes(), b"7I76");
        // A byte of its memory.
        let ptoc = s.read(5, 0, 0) & 0xFFFF;
        s.write(2, 0, 0, (lbp::READ_BYTE as u32) << 24 | ptoc, 3);
        s.write(0, 0, 0, cmd::DOIT | 1, 3);
        assert_eq!(s.read(1, 0, 0), 0);
        assert_ne!(s.read(3, 0, 0), 0);
        // Normal mode: data through.
        s.write(0, 0, 0, cmd::STOP, 3);
        s.write(2, 0, 0, 0, 3);
        s.write(0, 0, 0, cmd::START_NORMAL | 1, 3);
        assert_eq!(s.read(1, 0, 0), 0);
        s.remote(0, 0).unwrap().set_value("Input", 5.0);
        s.write(3, 0, 0, 0xFFFF, 3);
        s.write(0, 0, 0, cmd::DOIT | 1, 3);
        assert_eq!(s.read(3, 0, 0), 5);
        assert_eq!(s.remote(0, 0).unwrap().value("Output"), Some(65535.0));
        // Unreachable: a timeout in the status, the data bit set.
        s.write(0, 0, 0, cmd::DOIT | 1, 0);
        assert_eq!(s.read(1, 0, 0), 1);
        assert_eq!(s.read(2, 0, 0) & status::TIMEOUT, status::TIMEOUT);
        // A mode the card lacks.
        s.write(2, 0, 0, 7 << 24, 3);
        s.write(0, 0, 0, cmd::START_NORMAL | 1, 3);
        assert_eq!(s.read(2, 0, 0) & status::ILLEGAL_MODE, status::ILLEGAL_MODE);
    }
}
