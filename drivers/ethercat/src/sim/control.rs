//! Running a simulated segment behind a [`Link`] (what `ethercat-sim`
//! does on one end of a veth pair), and the commands that inject faults
//! into it while it runs (`ethercat-sim` reads them on its standard
//! input, one per line):
//!
//! | command | fault |
//! |---|---|
//! | `link down`, `link up` | the cable at the master pulled or plugged: frames are lost |
//! | `cut N`, `cut none` | the line ends before slave N (N and those after it lost), or is whole again |
//! | `reset N` | slave N power-cycles: back in INIT without an address |
//! | `al-error N CODE` | slave N drops to SAFE-OP with AL status code CODE |
//! | `drive-fault N CODE` | the drive at N faults with error code CODE (and sends an EMCY); a stepper terminal raises its error bit |
//! | `shaft N COUNTS_PER_S` | the encoder at N turns at that rate |
//! | `drift N PPM` | the DC clock of slave N runs PPM parts per million fast (negative: slow) against the host |
//! | `clock-step N NS` | the DC clock of slave N jumps by NS (negative: back) |
//! | `show N INDEX:SUB` | no fault: prints object INDEX:SUB of slave N (hexadecimal), e.g. an output the master wrote |
//!
//! Numbers are decimal or `0x` hexadecimal.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::catalog::{Encoder, Stepper};
use super::servo::Servo;
use super::{Outcome, Segment};
use crate::error::{Error, Result};
use crate::link::{Link, SharedSegment};

/// One fault-injection command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// The link at the master: down (true) or up.
    LinkDown(bool),
    /// The line cut before a slave, or whole (None).
    Cut(Option<usize>),
    /// A slave power-cycled.
    Reset(usize),
    /// An AL error with its status code.
    AlError(usize, u16),
    /// A drive fault with its error code.
    DriveFault(usize, u16),
    /// An encoder's shaft speed (counts per second).
    Shaft(usize, f64),
    /// A slave's DC clock rate against the host (ppm).
    Drift(usize, i64),
    /// A slave's DC clock jumps (ns).
    ClockStep(usize, i64),
    /// No fault: the value of a slave's object (index, subindex).
    Show(usize, u16, u8),
}

/// The largest drift `drift` takes (ppm): a tenth of a percent.
pub const MAX_DRIFT_PPM: u64 = 1000;
/// The largest jump `clock-step` takes (ns): an hour.
pub const MAX_CLOCK_STEP_NS: u64 = 3_600_000_000_000;

fn bad(line: &str, reason: impl Into<String>) -> Error {
    Error::malformed(format!("command '{line}'"), reason)
}

fn num(line: &str, word: Option<&str>, what: &str) -> Result<u64> {
    let w = word.ok_or_else(|| bad(line, format!("{what} is missing")))?;
    let v = match w.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16),
        None => w.parse(),
    };
    v.map_err(|_| bad(line, format!("{what} '{w}' is not a number")))
}

impl Control {
    /// Parses one command line (see the module's table).
    pub fn parse(line: &str) -> Result<Control> {
        let mut w = line.split_whitespace();
        let cmd = w.next().unwrap_or("");
        let position = |w: Option<&str>| num(line, w, "slave position").map(|n| n as usize);
        let code = |w: Option<&str>| {
            num(line, w, "code")
                .and_then(|c| u16::try_from(c).map_err(|_| bad(line, "code over 0xffff")))
        };
        let c = match cmd {
            "link" => match w.next() {
                Some("down") => Control::LinkDown(true),
                Some("up") => Control::LinkDown(false),
                _ => return Err(bad(line, "say 'link down' or 'link up'")),
            },
            "cut" => match w.next() {
                Some("none") => Control::Cut(None),
                p => Control::Cut(Some(position(p)?)),
            },
            "reset" => Control::Reset(position(w.next())?),
            "al-error" => Control::AlError(position(w.next())?, code(w.next())?),
            "drive-fault" => Control::DriveFault(position(w.next())?, code(w.next())?),
            "shaft" => {
                let p = position(w.next())?;
                let v = w.next().and_then(|s| s.parse::<f64>().ok()).filter(|v| v.is_finite());
                Control::Shaft(p, v.ok_or_else(|| bad(line, "speed is not a number"))?)
            }
            "show" => {
                let p = position(w.next())?;
                let at = w.next().ok_or_else(|| bad(line, "INDEX:SUB is missing"))?;
                let (i, sub) = at
                    .split_once(':')
                    .ok_or_else(|| bad(line, format!("'{at}' is not INDEX:SUB")))?;
                let hex = |t: &str, max: u64| {
                    u64::from_str_radix(t, 16)
                        .ok()
                        .filter(|v| *v <= max)
                        .ok_or_else(|| bad(line, format!("'{t}' in '{at}' is not a hexadecimal {}", if max > 0xff { "index" } else { "subindex" })))
                };
                Control::Show(p, hex(i, 0xffff)? as u16, hex(sub, 0xff)? as u8)
            }
            "drift" | "clock-step" => {
                let p = position(w.next())?;
                let v = w
                    .next()
                    .and_then(|s| s.parse::<i64>().ok())
                    .ok_or_else(|| bad(line, "the amount is not a whole number"))?;
                match cmd {
                    "drift" if v.unsigned_abs() <= MAX_DRIFT_PPM => Control::Drift(p, v),
                    "drift" => {
                        return Err(bad(
                            line,
                            format!("a drift past ±{MAX_DRIFT_PPM} ppm is no quartz"),
                        ))
                    }
                    _ if v.unsigned_abs() <= MAX_CLOCK_STEP_NS => Control::ClockStep(p, v),
                    _ => {
                        return Err(bad(
                            line,
                            format!("a clock step past ±{MAX_CLOCK_STEP_NS} ns (an hour)"),
                        ))
                    }
                }
            }
            _ => {
                return Err(bad(
                    line,
                    "unknown; commands: link down|up, cut N|none, reset N, al-error N CODE, drive-fault N CODE, shaft N COUNTS_PER_S, drift N PPM, clock-step N NS, show N INDEX:SUB",
                ))
            }
        };
        if w.next().is_some() {
            return Err(bad(line, "too many words"));
        }
        Ok(c)
    }

    /// Applies the command to `seg`, with what it has to say (`show`'s
    /// value); an error says which slave is not there or cannot take it.
    pub fn apply(self, seg: &mut Segment) -> Result<Option<String>> {
        let n = seg.slaves().len();
        let missing =
            |p: usize| Error::malformed("command", format!("no slave {p} (the segment has {n})"));
        match self {
            Control::LinkDown(d) => seg.set_link_down(d),
            Control::Cut(p) => seg.cut_before(p),
            Control::Reset(p) if p < n => seg.reset_slave(p),
            Control::AlError(p, code) => seg
                .slave_mut(p)
                .ok_or_else(|| missing(p))?
                .raise_al_error(code),
            Control::DriveFault(p, code) => {
                let esc = seg.slave_mut(p).ok_or_else(|| missing(p))?;
                let kind = esc.device.kind.clone();
                let app = esc.device.app.as_any_mut();
                if let Some(s) = app.downcast_mut::<Servo>() {
                    s.inject_fault(code);
                } else if let Some(s) = app.downcast_mut::<Stepper>() {
                    s.error = true;
                } else {
                    return Err(Error::malformed(
                        "command",
                        format!("slave {p} ({kind}) is not a drive"),
                    ));
                }
            }
            Control::Shaft(p, v) => {
                let esc = seg.slave_mut(p).ok_or_else(|| missing(p))?;
                let kind = esc.device.kind.clone();
                match esc.device.app.as_any_mut().downcast_mut::<Encoder>() {
                    Some(e) => e.counts_per_s = v,
                    None => {
                        return Err(Error::malformed(
                            "command",
                            format!("slave {p} ({kind}) is not an encoder"),
                        ))
                    }
                }
            }
            Control::Drift(p, ppm) => seg
                .slave_mut(p)
                .ok_or_else(|| missing(p))?
                .set_clock_ppm(ppm),
            Control::ClockStep(p, ns) => seg.slave_mut(p).ok_or_else(|| missing(p))?.step_clock(ns),
            Control::Show(p, index, sub) => {
                let v = seg
                    .slaves()
                    .get(p)
                    .ok_or_else(|| missing(p))?
                    .device
                    .od
                    .get(index, sub);
                return Ok(Some(format!("slave {p} {index:04x}:{sub:02x} = {v:#x}")));
            }
            Control::Reset(p) => return Err(missing(p)),
        }
        Ok(None)
    }
}

/// How long [`serve`] waits before it listens again on an interface that
/// is down.
const CABLE_OUT_PAUSE: Duration = Duration::from_millis(10);

/// Whether `e` says the interface is down (`ip link set ... down`, the
/// cable out): the slaves wait for it to come back, as real ones do.
fn cable_out(e: &std::io::Error) -> bool {
    // The link's errors keep the kind but not always the OS number.
    e.kind() == std::io::ErrorKind::NetworkDown || e.raw_os_error() == Some(libc::ENETDOWN)
}

/// The most frames [`drop_stale`] throws away: more than a socket's
/// queue holds, and a bound on the loop.
const MAX_STALE: usize = 4096;

/// Throws away the frames that were waiting when the interface went
/// down (the kernel reports the error before them): they were sent
/// before the cable was pulled, and a real slave never sees those after
/// it is plugged in again. Answering them late would hand the master
/// stale replies and apply old outputs.
fn drop_stale(link: &mut dyn Link, buf: &mut [u8]) {
    for _ in 0..MAX_STALE {
        if !matches!(link.recv(buf, Duration::ZERO), Ok(Some(_))) {
            break;
        }
    }
}

/// Answers every frame that arrives on `link` with `segment` until
/// `stop` is set; returns the frames answered. Times are the monotonic
/// clock since the start. While the interface is down the segment waits
/// for it (frames are lost, as with the cable out); any other receive or
/// send error ends the loop with that error.
pub fn serve(link: &mut dyn Link, segment: &SharedSegment, stop: &AtomicBool) -> Result<u64> {
    let epoch = Instant::now();
    let mut buf = vec![0u8; 1600];
    let mut answered = 0;
    while !stop.load(Ordering::Relaxed) {
        let n = match link.recv(&mut buf, Duration::from_millis(50)) {
            Ok(Some(n)) => n,
            Ok(None) => continue,
            Err(e) if cable_out(&e) => {
                drop_stale(link, &mut buf);
                std::thread::sleep(CABLE_OUT_PAUSE);
                continue;
            }
            Err(e) => {
                return Err(Error::Interface {
                    iface: link.describe(),
                    reason: "receiving".into(),
                    source: Some(e),
                })
            }
        };
        let now = u64::try_from(epoch.elapsed().as_nanos()).unwrap_or(u64::MAX);
        let frame = &mut buf[..n];
        let outcome = match segment.lock() {
            Ok(mut s) => s.process(frame, now),
            Err(p) => p.into_inner().process(frame, now),
        };
        if outcome == Outcome::Returned {
            if let Err(e) = link
                .send(frame)
                .or_else(|e| if cable_out(&e) { Ok(()) } else { Err(e) })
            {
                return Err(Error::Interface {
                    iface: link.describe(),
                    reason: "sending".into(),
                    source: Some(e),
                });
            }
            answered += 1;
        }
    }
    Ok(answered)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::device_by_name;

    #[test]
    fn commands_parse_and_apply() {
        let mut seg = Segment::new(
            ["EK1100", "EL5101", "servo"]
                .iter()
                .filter_map(|k| device_by_name(k, 1))
                .collect(),
        );
        for line in [
            "link down",
            "link up",
            "cut 2",
            "cut none",
            "reset 1",
            "al-error 1 0x1b",
            "drive-fault 2 0x2310",
            "shaft 1 1000.5",
            "drift 0 -300",
            "clock-step 2 5000000",
            "show 1 6000:01",
        ] {
            Control::parse(line).unwrap().apply(&mut seg).unwrap();
        }
        let mut e = |l: &str| match Control::parse(l) {
            Ok(c) => c.apply(&mut seg).unwrap_err().to_string(),
            Err(e) => e.to_string(),
        };
        assert!(e("reset 9").contains("no slave 9 (the segment has 3)"));
        assert!(e("drive-fault 0 1").contains("EK1100) is not a drive"));
        assert!(e("shaft 2 5").contains("is not an encoder"));
        assert!(e("fly 1").contains("unknown; commands"));
        assert!(e("al-error 1").contains("code is missing"));
        assert!(e("al-error 1 0x10000").contains("over 0xffff"));
        assert!(e("link down now").contains("too many words"));
        assert!(e("drift 0 5000").contains("no quartz"));
        assert!(e("drift 0 fast").contains("not a whole number"));
        assert!(e("clock-step 0 -9223372036854775808").contains("an hour"));
        assert!(e("clock-step 7 1").contains("no slave 7"));
        assert!(e("show 7 6000:01").contains("no slave 7"));
        assert!(e("show 1 6000").contains("is not INDEX:SUB"));
        assert!(e("show 1 6000:100").contains("not a hexadecimal subindex"));
        assert!(e("show 1 10000:1").contains("not a hexadecimal index"));
        assert_eq!(
            Control::parse("show 0 1018:01")
                .unwrap()
                .apply(&mut seg)
                .unwrap()
                .as_deref(),
            Some("slave 0 1018:01 = 0x2")
        );
    }

    #[test]
    fn a_drift_changes_the_rate_not_the_time() {
        let mut seg = Segment::new(vec![device_by_name("EK1100", 1).unwrap()]);
        let frame = |seg: &mut Segment, now: u64| {
            let mut b = crate::wire::frame::FrameBuilder::new([2, 0, 0, 0, 0, 1]);
            b.push(crate::wire::frame::Command::Brd, 0, 0, &[0; 2])
                .unwrap();
            let mut f = b.finish();
            seg.process(&mut f, now);
            seg.slaves()[0].system_time()
        };
        let t0 = frame(&mut seg, 5_000_000_000);
        assert_eq!(Control::Drift(0, 500).apply(&mut seg).unwrap(), None);
        assert_eq!(frame(&mut seg, 5_000_000_000), t0, "no jump");
        let t1 = frame(&mut seg, 6_000_000_000);
        // One second at 500 ppm (the EK1100's own -20 ppm replaced).
        assert_eq!(t1 - t0, 1_000_500_000);
        Control::ClockStep(0, -7).apply(&mut seg).unwrap();
        assert_eq!(frame(&mut seg, 6_000_000_000), t1 - 7);
    }
}
