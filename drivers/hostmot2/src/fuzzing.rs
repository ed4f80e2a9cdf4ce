//! Fuzz bodies for the parsers of outside bytes in this crate: register
//! images through the IDROM loader, config strings, replies from the
//! network to hm2_eth's cycle requests, request datagrams to the
//! simulated Ethernet board, Smart Serial cards' records, whole
//! hostile cards through discovery, and a parallel port's reads under
//! the EPP transport. The workspace's fuzz crate
//! (`hal-fuzz`) can call them as its targets; until it has them, this
//! crate's tests run them (100,000 generated cases each, fewer for the
//! whole-card one, which runs discovery per case).
//!
//! A body panics on a finding: a panic in the code under test, or an
//! accepted board that breaks what the driver relies on, or a refusal
//! that does not say why.

use crate::config;
use crate::firmware::{self, Debug};
use crate::image::{ImageTransport, WINDOW_WORDS};
use crate::llio::Llio;
use crate::log::MessageLog;
use crate::md;
use crate::pins::PinOwner;
use crate::sim::boards;
use crate::test_patterns;

/// The board an IDROM fuzz input starts from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IdromCase {
    /// The llio the image is loaded for.
    pub llio: Llio,
    /// The register image.
    pub image: Vec<u32>,
    /// The config string.
    pub config: String,
}

/// Decodes fuzz bytes into a board: byte 0 picks the starting image (a
/// simulated board's, an hm2_test pattern, or raw bytes); byte 1 may
/// change the llio's connectors and pins per connector; the rest are
/// edits (a word index near the identification and IDROM area, then a
/// value) or, for a raw image, the image itself from 0x0100.
pub fn decode(data: &[u8]) -> IdromCase {
    let pick = data.first().copied().unwrap_or(0);
    let tweak = data.get(1).copied().unwrap_or(0);
    let rest = data.get(2..).unwrap_or(&[]);
    let presets = boards::PRESETS;
    let (mut llio, mut image) = match pick % 8 {
        k @ 0..=3 => {
            let spec = boards::preset(presets[k as usize % presets.len()]).expect("preset");
            (spec.llio(0), spec.image())
        }
        4 | 5 => test_patterns::pattern(pick as u32 % 15).expect("pattern"),
        _ => {
            let spec = boards::preset("5i25").expect("preset");
            let mut img = vec![0u32; WINDOW_WORDS];
            for (i, w) in rest.chunks(4).enumerate() {
                let mut b = [0u8; 4];
                b[..w.len()].copy_from_slice(w);
                if let Some(slot) = img.get_mut(0x40 + i) {
                    *slot = u32::from_le_bytes(b);
                }
            }
            return IdromCase {
                llio: spec.llio(0),
                image: img,
                config: String::new(),
            };
        }
    };
    if tweak & 0x80 != 0 {
        llio.connectors
            .truncate(1 + (tweak as usize & 0x7) % llio.connectors.len().max(1));
        llio.pins_per_connector = match tweak >> 3 & 0xF {
            0 => llio.pins_per_connector,
            k => [0, 1, 5, 17, 24, 29, 32, 33, 37, 64][k as usize % 10],
        };
    }
    for edit in rest.chunks(6) {
        if edit.len() < 6 {
            break;
        }
        // Mostly the identification and IDROM area (0x0100..0x0900).
        let at = 0x40 + (u16::from_le_bytes([edit[0], edit[1]]) as usize % 0x200);
        let v = u32::from_le_bytes([edit[2], edit[3], edit[4], edit[5]]);
        let value = match edit[2] % 8 {
            0 => 0,
            1 => u32::MAX,
            2 => image[at] ^ (1 << (edit[3] % 32)),
            3 => image[at].wrapping_add(edit[4] as u32) & 0xFF,
            4 => v & 0xFFFF,
            _ => v,
        };
        image[at] = value;
    }
    IdromCase {
        llio,
        image,
        config: String::new(),
    }
}

/// The IDROM loader on the board `data` decodes to: no panic; an accepted
/// board's pins, instances and registers are what the driver relies on;
/// a refusal says why.
pub fn idrom_image(data: &[u8]) {
    let case = decode(data);
    let config = config::parse(&case.config).unwrap_or_default();
    let mut t = ImageTransport::new(case.image, "fuzz");
    let mut log = MessageLog::default();
    match firmware::load(&case.llio, &config, Debug::default(), &mut t, &mut log) {
        Ok(fw) => {
            assert_eq!(fw.pins.len() as u32, fw.idrom.io_width);
            assert_eq!(fw.idrom.port_width, case.llio.pins_per_connector);
            assert_eq!(fw.idrom.io_ports as usize, case.llio.connectors.len());
            for p in &fw.pins {
                assert!((p.port as usize) < case.llio.connectors.len() && p.bit < 32);
                if let PinOwner::Module { gtag, .. } = p.owner {
                    assert!([4, 5, 6, 0xC1].contains(&gtag), "pin {p:?}");
                }
            }
            for m in [
                Some(fw.ioport),
                fw.watchdog,
                fw.encoder,
                fw.stepgen,
                fw.pwmgen,
                fw.led,
            ]
            .into_iter()
            .flatten()
            {
                assert!(m.instances >= 1);
                if m.md.gtag != crate::regs::gtag::LED {
                    assert!(m.instances <= m.md.instances as u32);
                }
                assert!(md::check_window(&m.md).is_ok());
            }
        }
        Err(e) => {
            let text = e.to_string();
            assert!(!text.trim().is_empty(), "a refusal without a reason: {e:?}");
            assert!(text.lines().all(|l| !l.trim().is_empty()), "{text:?}");
        }
    }
}

/// The config string parser on `text`: no panic; a refusal says why and
/// names the token it refused (`sserial_port` excepted, whose message is
/// LinuxCNC's fixed text).
pub fn config_string(text: &str) {
    match config::parse(text) {
        Ok(c) => {
            assert!(c.num_encoders >= -1 && c.num_stepgens >= -1 && c.num_pwmgens >= -1);
            assert!((0..=8).contains(&c.stepgen_width));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.trim().is_empty());
            let named = text
                .split_ascii_whitespace()
                .any(|t| msg.contains(t) || msg.contains(t.split('=').nth(1).unwrap_or(t)));
            assert!(named || msg.contains("sserial_port"), "{msg} for {text:?}");
        }
    }
}

/// A datagram that came while hm2_eth waited for a cycle's reply, as
/// `data` decodes it (words read, the cycle's tags, how the datagram was
/// made: raw bytes, the right length with random tags, the right tags
/// and random data, the right tags with a bad write tag, or one byte
/// short or long of a right one): only a datagram of exactly the
/// expected length echoing this cycle's read tag is taken, and its lost
/// write is told exactly when its write tag differs.
pub fn eth_reply(data: &[u8]) {
    use crate::eth::transport::{classify, copy_words, reply_len, Reply};
    let byte = |i: usize| data.get(i).copied().unwrap_or(0);
    let words = byte(0) as usize % 80;
    let read_tag = u32::from_le_bytes([byte(1), byte(2), byte(3), byte(4)]);
    let write_tag =
        (byte(5) & 1 == 1).then(|| u32::from_le_bytes([byte(6), byte(7), byte(8), byte(9)]));
    let rest = data.get(11..).unwrap_or(&[]);
    let n = reply_len(words);
    let shaped = |tag_ok: bool, write_ok: bool| {
        let mut r: Vec<u8> = rest.iter().copied().cycle().take(n).collect();
        r.resize(n, 0);
        if tag_ok {
            r[n - 8..n - 4].copy_from_slice(&read_tag.to_le_bytes());
        }
        if let (true, Some(w)) = (write_ok, write_tag) {
            r[n - 4..].copy_from_slice(&w.to_le_bytes());
        }
        r
    };
    let reply = match byte(10) % 6 {
        0 => rest.to_vec(),
        1 => shaped(false, false),
        2 => shaped(true, true),
        3 => shaped(true, false),
        4 => {
            let mut r = shaped(true, true);
            r.pop();
            r
        }
        _ => {
            let mut r = shaped(true, true);
            r.push(byte(11));
            r
        }
    };
    let verdict = classify(&reply, words, read_tag, write_tag);
    let ours = reply.len() == n && reply[n - 8..n - 4] == read_tag.to_le_bytes();
    match verdict {
        Reply::Ours { lost_write } => {
            assert!(ours, "a foreign datagram taken for the reply");
            let differs = write_tag.is_some_and(|w| reply[n - 4..] != w.to_le_bytes());
            assert_eq!(lost_write, differs);
            let mut out = vec![0u32; words];
            copy_words(&reply, &mut out);
            for (i, w) in out.iter().enumerate() {
                assert_eq!(w.to_le_bytes(), reply[4 * i..4 * i + 4]);
            }
        }
        Reply::Foreign => assert!(!ours, "the cycle's reply refused"),
    }
}

/// A request datagram from anyone on the network to the simulated
/// Ethernet board: executed or refused, never a panic; a refused one is
/// counted and answered with nothing, an answered one has exactly the
/// bytes its reads ask for.
pub fn lbp16_request(data: &[u8]) {
    use crate::lbp16::{addr, parse};
    use crate::sim::eth::{EthBoard, EthIdentity};
    thread_local! {
        // One board for every case: what a case writes stays, as it
        // would on a board on the network.
        static BOARD: std::cell::RefCell<EthBoard> = std::cell::RefCell::new({
            let spec = boards::preset("7i96s").expect("preset");
            EthBoard::new(crate::sim::Hm2Model::new(spec), EthIdentity::new("7I96S"))
                .with_period(1_000_000)
        });
    }
    BOARD.with(|b| lbp16_request_on(&mut b.borrow_mut(), data));
    fn lbp16_request_on(b: &mut EthBoard, data: &[u8]) {
        let mut reply = Vec::new();
        let errors_before = b.counter(addr::CTRL_PARSE_ERRORS);
        let parsed: Vec<_> = parse(data).collect();
        let well_formed = parsed.iter().all(Result::is_ok);
        let answered = b.handle(data, &mut reply);
        if well_formed {
            let want: usize = parsed
                .iter()
                .flatten()
                .filter(|p| !p.cmd.write)
                .map(|p| p.cmd.data_len())
                .sum();
            assert_eq!(reply.len(), want);
            assert_eq!(answered, want > 0);
        } else {
            assert!(!answered && reply.is_empty());
            assert_eq!(
                b.counter(addr::CTRL_PARSE_ERRORS),
                errors_before.wrapping_add(1)
            );
        }
    }
}

/// A card's memory as the driver reads its tables and records: a
/// record or a refusal with a reason, never a panic or an endless read.
pub fn sserial_records(data: &[u8]) {
    use crate::sserial::records::{read_record, read_table, Record, RecordError};
    let mut reads = 0usize;
    let mut byte = |a: u16| -> Result<u8, RecordError> {
        reads += 1;
        Ok(data.get(a as usize).copied().unwrap_or(0))
    };
    let start = u16::from_le_bytes([
        data.first().copied().unwrap_or(0),
        data.get(1).copied().unwrap_or(0),
    ]) % (data.len().max(1) as u16);
    if let Ok(table) = read_table(start, &mut byte) {
        assert!(table.len() <= crate::sserial::records::MAX_TABLE);
        for at in table {
            match read_record(at, &mut byte) {
                Ok(Record::Data(d)) => {
                    assert!(!d.name.is_empty() && d.name.len() <= 48);
                    assert!(d.name.bytes().all(|b| b.is_ascii_graphic()));
                }
                Ok(Record::Mode(m)) => assert!(m.name.len() <= 48),
                Err(e) => assert!(!e.to_string().is_empty()),
            }
        }
    }
    assert!(reads <= 3 * 66 + 64 * 120, "bounded reads: {reads}");
}

/// A hostile card on Smart Serial port 0 channel 0 of a simulated 7i96S
/// (its identity words and memory from `data`), through the driver's
/// discovery: the board loads with the card's objects checked, or the
/// load is refused saying which port and channel and why.
pub fn sserial_card(data: &[u8]) {
    use crate::sim::sserial::SimRemote;
    use crate::window::WindowTransport;
    let word = |i: usize| {
        let b = |k| data.get(i + k).copied().unwrap_or(0);
        u32::from_le_bytes([b(0), b(1), b(2), b(3)])
    };
    let mut ids = [word(0), word(4), word(8)];
    // Mostly tables inside the memory the card has.
    let len = data.len().saturating_sub(12).max(1) as u32;
    if ids[2] & 0x8000_0000 == 0 {
        ids[2] = (((ids[2] >> 16) % len) << 16) | ((ids[2] & 0xFFFF) % len);
    }
    let memory = data.get(12..).unwrap_or(&[]).to_vec();
    let mut spec = boards::preset("7i96s").expect("preset");
    spec.remotes.clear();
    let mut model = crate::sim::Hm2Model::new(spec.clone());
    model.sserial().ports[0].remotes[0] = Some(SimRemote::hostile(ids, memory));
    let board = std::sync::Arc::new(hal_driver::sim::SimBoard::new(model));
    let mut t = WindowTransport::new(board);
    let mut log = MessageLog::default();
    let llio = spec.llio(0);
    match firmware::load(
        &llio,
        &config::Config::default(),
        Debug::default(),
        &mut t,
        &mut log,
    ) {
        Ok(fw) => {
            let s = fw.sserial.expect("the 7i96s has Smart Serial");
            for r in s.ports.iter().flat_map(|p| &p.remotes) {
                let (i, o) = r.widths();
                assert!(i <= 96 && o <= 96, "{i} / {o} bits");
                for p in &r.process {
                    assert!(!p.name.is_empty());
                    assert!(!crate::sserial::records::data_type::is_nonvolatile(
                        p.data_type
                    ));
                }
            }
        }
        Err(e) => {
            let text = e.to_string();
            assert!(
                text.starts_with("Smart Serial port 0 channel 0: "),
                "{text}"
            );
        }
    }
}

/// Seeds of the bitfile target: the simulator's bitfiles of a 5i20 and
/// a 5i22 firmware.
pub fn seed_bitfiles() -> Vec<Vec<u8>> {
    vec![
        crate::sim::plx::bitfile("SVST8_4", "2s200pq208"),
        crate::sim::plx::bitfile("SV16", "3s1000fg320"),
    ]
}

/// A bitfile through the header parser, and an accepted one's bitstream
/// through the loader into simulated 5i20 and 5i22 bridges: no panic; a
/// refusal says why; an accepted file written again parses to the same
/// fields; its bitstream lies inside the input; the load ends with DONE
/// high exactly when the simulated FPGA runs a design, and a load that
/// fails names its step.
pub fn bitfile(data: &[u8]) {
    use crate::fpga::{self, bitfile, Bridge, FpgaError};
    use crate::sim::plx::SimPlxBridge;
    let file = match bitfile::parse(data) {
        Ok(f) => f,
        Err(e) => {
            assert!(!e.to_string().trim().is_empty());
            return;
        }
    };
    assert!(file.bitstream.len() < data.len());
    let again = bitfile::build(
        &file.design,
        &file.part,
        &file.date,
        &file.time,
        &file.bitstream,
    );
    let back = bitfile::parse(&again).expect("a parsed bitfile written again parses");
    assert_eq!(back, file);
    for (bridge, part) in [
        (Bridge::Plx9030, "2s200pq208"),
        (Bridge::Plx9054, "3s1000fg320"),
    ] {
        if fpga::check_part(&file, part).is_err() {
            continue;
        }
        let sim = SimPlxBridge::new(bridge, part);
        match fpga::plx::program(&sim.ports(), &file.bitstream) {
            Ok(()) => assert!(sim.design().is_some(), "DONE without a design"),
            Err(FpgaError::Program { reason, .. }) => {
                assert!(!reason.is_empty());
                assert!(sim.design().is_none(), "a failed load left a design");
            }
            Err(e) => panic!("a load failed outside a step: {e}"),
        }
    }
}

/// A parallel port whose reads are a simulated EPP board's, except the
/// ones the fuzz input replaces: (the n-th read, its value).
struct EditedPort {
    inner: std::sync::Arc<hal_driver::sim::SimBoard<crate::sim::epp::EppPortModel>>,
    edits: Vec<(u32, u32)>,
    reads: std::sync::atomic::AtomicU32,
}

impl EditedPort {
    fn edit(&self, v: u32) -> u32 {
        let n = self
            .reads
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.edits
            .iter()
            .find(|(at, _)| *at == n)
            .map_or(v, |&(_, e)| e)
    }
}

impl hal_driver::bus::PortBus for EditedPort {
    fn inb(&self, port: u16) -> u8 {
        self.edit(self.inner.inb(port) as u32) as u8
    }
    fn outb(&self, port: u16, value: u8) {
        self.inner.outb(port, value)
    }
    fn inw(&self, port: u16) -> u16 {
        self.edit(self.inner.inw(port) as u32) as u16
    }
    fn outw(&self, port: u16, value: u16) {
        self.inner.outw(port, value)
    }
    fn inl(&self, port: u16) -> u32 {
        self.edit(self.inner.inl(port))
    }
    fn outl(&self, port: u16, value: u32) {
        self.inner.outl(port, value)
    }
    fn errors(&self) -> u64 {
        self.inner.errors()
    }
    fn describe(&self) -> String {
        "fuzzed parallel port".into()
    }
}

/// The EPP transport and the IDROM loader on a parallel port whose reads
/// (status, EPP data) the input edits: byte 0 picks the board (bit 0:
/// 7I43 or 7I90) and the access width (bit 1: byte cycles), then groups
/// of three bytes replace one port read (a 16-bit read number, a value
/// spread over the word). No panic; a failed transfer is one of the
/// transport's EPP or bus errors; a refusal says why; an accepted board
/// has the pins its llio says; a board set up once clears a timeout it
/// meets and reads its cookie again once the edits are spent.
pub fn epp_port(data: &[u8]) {
    use crate::epp::hal::{PortPlace, SEVEN_I43, SEVEN_I90};
    use crate::transport::{Transport, TransportError};
    let flags = data.first().copied().unwrap_or(0);
    let kind = if flags & 1 == 0 { SEVEN_I43 } else { SEVEN_I90 };
    let wide = flags & 2 == 0;
    let edits: Vec<(u32, u32)> = data
        .get(1..)
        .unwrap_or(&[])
        .chunks_exact(3)
        .take(64)
        .map(|c| {
            let v = c[2] as u32;
            (
                u16::from_le_bytes([c[0], c[1]]) as u32 % 4096,
                v * 0x0101_0101,
            )
        })
        .collect();
    let place = PortPlace {
        base: 0x378,
        base_hi: Some(0x778),
        wide,
    };
    let (port, _board) = crate::epp::hal::sim_port(kind.board, place).expect("a preset");
    let bus = std::sync::Arc::new(EditedPort {
        inner: port,
        edits,
        reads: std::sync::atomic::AtomicU32::new(0),
    });
    let mut t = crate::epp::EppTransport::new(bus.clone(), place.base, place.base_hi, wide);
    let epp_error = |e: &TransportError| {
        assert!(
            matches!(
                e,
                TransportError::EppTimeout { .. }
                    | TransportError::EppRange { .. }
                    | TransportError::Bus { .. }
            ),
            "{e:?}"
        );
    };
    if let Err(e) = t.set_up() {
        epp_error(&e);
        return;
    }
    let llio = kind.llio(0);
    let mut log = MessageLog::default();
    match firmware::load(
        &llio,
        &config::Config::default(),
        Debug::default(),
        &mut t,
        &mut log,
    ) {
        Ok(fw) => assert_eq!(fw.pins.len() as u32, 24 * llio.connectors.len() as u32),
        Err(e) => {
            let text = e.to_string();
            assert!(!text.trim().is_empty(), "a refusal without a reason: {e:?}");
        }
    }
    // The edits spent, the board answers again.
    bus.reads
        .store(u32::MAX / 2, std::sync::atomic::Ordering::Relaxed);
    let mut w = [0u32; 1];
    if let Err(e) = t.read(0x100, &mut w) {
        epp_error(&e);
        t.read(0x100, &mut w).expect("a cleared timeout");
    }
    assert_eq!(w[0], crate::regs::COOKIE, "the cookie after the edits");
}

/// A message arriving at an SPI board: the bytes are its words (big
/// endian, as they come off the wire), served by Mesa's SPI framing
/// ([`crate::spi::frame::serve`]) against a register file of the 64 KiB
/// window. Checks: every command word decodes back to itself; a served
/// message leaves only read data in the buffer; a refused one says why,
/// leaves the rest zero and did nothing after the bad frame.
pub fn spi_frames(data: &[u8]) {
    use crate::spi::frame::{serve, Command, Registers};
    struct Regs {
        words: Vec<u32>,
        accesses: usize,
    }
    impl Registers for Regs {
        fn read(&mut self, addr: u32) -> u32 {
            self.accesses += 1;
            self.words[(addr as usize / 4) % self.words.len()]
        }
        fn write(&mut self, addr: u32, value: u32) {
            self.accesses += 1;
            let n = self.words.len();
            self.words[(addr as usize / 4) % n] = value;
        }
    }
    let mut buf: Vec<u32> = data
        .chunks(4)
        .take(2048)
        .map(|c| {
            let mut b = [0u8; 4];
            b[..c.len()].copy_from_slice(c);
            u32::from_be_bytes(b)
        })
        .collect();
    for &w in &buf {
        if let Ok(c) = Command::decode(w, 0) {
            assert_eq!(c.encode(), w, "command 0x{w:08X} does not round-trip");
        }
    }
    let mut regs = Regs {
        words: vec![0; WINDOW_WORDS],
        accesses: 0,
    };
    let sent = buf.clone();
    match serve(&mut buf, &mut regs) {
        Ok(frames) => {
            assert!(frames <= sent.len());
            assert_eq!(
                regs.accesses,
                sent.len() - frames,
                "one access per data word"
            );
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            let at = match e {
                crate::spi::frame::FrameError::NotACommand { at, .. }
                | crate::spi::frame::FrameError::BadCount { at, .. }
                | crate::spi::frame::FrameError::Truncated { at, .. } => at,
            };
            assert!(buf[at..].iter().all(|&w| w == 0), "the rest reads zero");
            assert!(regs.accesses <= at, "nothing done after the bad frame");
        }
    }
}

/// `setsserial`'s `cmd=` string and its numbers: a command of three
/// words or a refusal that says what is wrong, never a panic.
pub fn setsserial_cmd(text: &str) {
    use crate::setsserial::command::{parse, parse_int, Command, MAX_CMD};
    match parse(text) {
        Ok(Command::Set { target, value }) => {
            assert!(text.len() <= MAX_CMD);
            assert!(text.contains(&target) && text.contains(&value));
            if let Some(v) = parse_int(&value) {
                assert!(v.unsigned_abs() <= u128::from(u64::MAX));
            }
        }
        Ok(Command::Flash { remote, file }) => {
            assert!(text.contains(&remote));
            assert!(file.to_ascii_lowercase().ends_with(".bin"));
        }
        Err(e) => assert!(!e.to_string().trim().is_empty()),
    }
}

pub use crate::modbus::fuzzing::{mbccb_file, mbccs_source, seed_mbccbs, SEED_MBCCS};
