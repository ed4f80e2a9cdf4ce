//! A segment: slaves in a line, a frame passing each in order (every
//! datagram through each slave, auto-increment addresses counting down
//! the line, working counters adding up), and the last slave closing the
//! loop. Faults are injected here: the link down (frames lost), a slave
//! lost (the line ends before it), a slave reset (power cycle), an AL
//! error, a drive fault.

use super::device::Device;
use super::esc::{Access, Esc};
use crate::wire::frame::{datagram_spans, Command, DATAGRAM_HEADER_LEN};

/// How long a frame takes through one slave (ns): processing plus cable.
pub const HOP_NS: u64 = 600;

/// The segment.
#[derive(Debug, Default)]
pub struct Segment {
    slaves: Vec<Esc>,
    link_up: bool,
    /// Slaves from this position on are cut off.
    cut_at: Option<usize>,
    frames: u64,
    dropped: u64,
}

/// What happened to a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// It went round and comes back.
    Returned,
    /// It did not come back (link down, or not an EtherCAT frame a slave
    /// would process: a real ESC drops it).
    Lost,
}

impl Segment {
    /// A segment of `devices` in this order, link up.
    pub fn new(devices: Vec<Device>) -> Segment {
        let slaves = devices
            .into_iter()
            .enumerate()
            .map(|(i, d)| Esc::new(d, i as u16))
            .collect();
        let mut s = Segment {
            slaves,
            link_up: true,
            ..Segment::default()
        };
        s.update_links();
        s
    }

    fn reachable(&self) -> usize {
        self.cut_at
            .unwrap_or(self.slaves.len())
            .min(self.slaves.len())
    }

    fn update_links(&mut self) {
        let n = self.reachable();
        for (i, s) in self.slaves.iter_mut().enumerate().take(n) {
            s.set_links(i + 1 < n);
            let downstream = 2 * (n - i - 1) as u64 * HOP_NS;
            s.set_downstream_ns(downstream as i64);
        }
    }

    /// The slaves.
    pub fn slaves(&self) -> &[Esc] {
        &self.slaves
    }

    /// A slave, mutable (to turn shafts, set inputs, inject faults).
    pub fn slave_mut(&mut self, position: usize) -> Option<&mut Esc> {
        self.slaves.get_mut(position)
    }

    /// Frames processed and frames dropped so far.
    pub fn counters(&self) -> (u64, u64) {
        (self.frames, self.dropped)
    }

    /// Pulls the cable at the master (true) or plugs it back.
    pub fn set_link_down(&mut self, down: bool) {
        self.link_up = !down;
    }

    /// Cuts the line before `position` (the slave and those after it are
    /// lost), or reconnects (None).
    pub fn cut_before(&mut self, position: Option<usize>) {
        self.cut_at = position;
        self.update_links();
    }

    /// Power-cycles a slave: it comes back in INIT with no address.
    pub fn reset_slave(&mut self, position: usize) {
        if let Some(s) = self.slaves.get_mut(position) {
            s.power_on();
        }
        self.update_links();
    }

    /// Processes one Ethernet frame in place at simulated time `now_ns`.
    pub fn process(&mut self, frame: &mut [u8], now_ns: u64) -> Outcome {
        if !self.link_up {
            self.dropped += 1;
            return Outcome::Lost;
        }
        let Ok(spans) = datagram_spans(frame) else {
            self.dropped += 1;
            return Outcome::Lost;
        };
        self.frames += 1;
        let n = self.reachable();
        for (i, esc) in self.slaves.iter_mut().enumerate().take(n) {
            esc.begin_frame(now_ns + i as u64 * HOP_NS);
            for s in &spans {
                process_datagram(esc, frame, s.header, s.data, s.len, s.wkc);
            }
        }
        // The first slave marks the source address as locally
        // administered, which tells a master its own frames from replies.
        if frame.len() > 6 {
            frame[6] |= 0x02;
        }
        Outcome::Returned
    }
}

fn bump_wkc(frame: &mut [u8], at: usize, by: u16) {
    let w = u16::from_le_bytes([frame[at], frame[at + 1]]).wrapping_add(by);
    frame[at..at + 2].copy_from_slice(&w.to_le_bytes());
}

/// One datagram through one slave.
fn process_datagram(
    esc: &mut Esc,
    frame: &mut [u8],
    header: usize,
    data: usize,
    len: usize,
    wkc: usize,
) {
    let Some(cmd) = Command::from_u8(frame[header]) else {
        return;
    };
    let adp = u16::from_le_bytes([frame[header + 2], frame[header + 3]]);
    let ado = u16::from_le_bytes([frame[header + 4], frame[header + 5]]);
    let address = u32::from(adp) | u32::from(ado) << 16;
    debug_assert!(data == header + DATAGRAM_HEADER_LEN);
    let set_adp =
        |frame: &mut [u8], v: u16| frame[header + 2..header + 4].copy_from_slice(&v.to_le_bytes());
    let body = data..data + len;
    use Command::*;
    let inc = match cmd {
        Nop => 0,
        Aprd | Apwr | Aprw | Armw => {
            let mine = adp == 0;
            set_adp(frame, adp.wrapping_add(1));
            let access = match cmd {
                Aprd => Access::Read,
                Apwr => Access::Write,
                Aprw => Access::ReadWrite,
                _ if mine => Access::Read,
                _ => Access::Write,
            };
            if mine || cmd == Armw {
                esc.physical(ado, &mut frame[body], access)
            } else {
                0
            }
        }
        Fprd | Fpwr | Fprw | Frmw => {
            let mine = adp == esc.station_address();
            let access = match cmd {
                Fprd => Access::Read,
                Fpwr => Access::Write,
                Fprw => Access::ReadWrite,
                _ if mine => Access::Read,
                _ => Access::Write,
            };
            if mine || cmd == Frmw {
                esc.physical(ado, &mut frame[body], access)
            } else {
                0
            }
        }
        Brd => {
            // Broadcast read: the data is OR-ed over the slaves.
            set_adp(frame, adp.wrapping_add(1));
            let mut mine = vec![0u8; len];
            let w = esc.physical(ado, &mut mine, Access::Read);
            for (d, m) in frame[body].iter_mut().zip(mine) {
                *d |= m;
            }
            w
        }
        Bwr => {
            set_adp(frame, adp.wrapping_add(1));
            esc.physical(ado, &mut frame[body], Access::Write)
        }
        Brw => {
            set_adp(frame, adp.wrapping_add(1));
            let mut mine = frame[body.clone()].to_vec();
            let w = esc.physical(ado, &mut mine, Access::ReadWrite);
            for (d, m) in frame[body].iter_mut().zip(mine) {
                *d |= m;
            }
            w
        }
        Lrd => esc.logical(address, &mut frame[body], true, false),
        Lwr => esc.logical(address, &mut frame[body], false, true),
        Lrw => esc.logical(address, &mut frame[body], true, true),
    };
    if inc > 0 {
        bump_wkc(frame, wkc, inc);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regs;
    use crate::sim::catalog;
    use crate::wire::frame::{Frame, FrameBuilder};

    fn run(seg: &mut Segment, b: FrameBuilder) -> Vec<u8> {
        let mut bytes = b.finish();
        assert_eq!(seg.process(&mut bytes, 1_000), Outcome::Returned);
        bytes
    }

    #[test]
    fn counting_and_addressing() {
        let mut seg = Segment::new(vec![
            catalog::ek1100(1),
            catalog::el1008(2),
            catalog::el2008(3),
        ]);
        // BRD of the type register: every slave answers.
        let mut b = FrameBuilder::new([0x10; 6]);
        b.push_physical(Command::Brd, 0, 0, regs::TYPE, &[0])
            .unwrap();
        let bytes = run(&mut seg, b);
        let f = Frame::parse(&bytes).unwrap();
        assert_eq!(f.datagrams[0].wkc, 3);
        assert_eq!(f.source[0] & 0x02, 0x02);
        // APWR station addresses, then FPRD one back.
        let mut b = FrameBuilder::new([0x10; 6]);
        for p in 0..3u16 {
            b.push_physical(
                Command::Apwr,
                p as u8,
                0u16.wrapping_sub(p),
                regs::STATION_ADDRESS,
                &(0x1000 + p).to_le_bytes(),
            )
            .unwrap();
        }
        b.push_physical(Command::Fprd, 9, 0x1002, regs::STATION_ADDRESS, &[0, 0])
            .unwrap();
        let bytes = run(&mut seg, b);
        let f = Frame::parse(&bytes).unwrap();
        assert!(f.datagrams[..3].iter().all(|d| d.wkc == 1));
        assert_eq!(
            (f.datagrams[3].data, f.datagrams[3].wkc),
            (&[0x02, 0x10][..], 1)
        );
        // A cut line: only the slaves before the cut answer.
        seg.cut_before(Some(1));
        let mut b = FrameBuilder::new([0x10; 6]);
        b.push_physical(Command::Brd, 0, 0, regs::TYPE, &[0])
            .unwrap();
        let f_bytes = run(&mut seg, b);
        assert_eq!(Frame::parse(&f_bytes).unwrap().datagrams[0].wkc, 1);
        seg.set_link_down(true);
        let mut lost = FrameBuilder::new([0; 6]).finish();
        assert_eq!(seg.process(&mut lost, 0), Outcome::Lost);
        // Garbage is dropped, never a panic.
        let mut junk = vec![0xFF; 70];
        seg.set_link_down(false);
        assert_eq!(seg.process(&mut junk, 0), Outcome::Lost);
    }
}
