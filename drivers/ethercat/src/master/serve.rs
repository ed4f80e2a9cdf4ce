//! The helper's cycles after bring-up: each `write` of the realtime
//! side sends one frame (the process data, the states, the reference
//! clock's time to the others); its answer is published for the next
//! `read`; then the clocks' extra work ([`super::dc::DcCycle`]). A fault
//! reset brings slaves that left OP back to it.

use std::future::Future;
use std::pin::pin;
use std::sync::atomic::Ordering::*;
use std::task::Poll;
use std::time::{Duration, Instant};

use ethercrab::{MainDevice, SubDeviceState};

use super::dc::DcCycle;
use super::emcy::MailboxPoll;
use super::io::Io;
use super::recover::Recovery;
use super::{Group, MasterConfig, Shared, SlaveInfo, LOST_LIMIT, MAX_SLAVES};
use crate::regs::{self, al};

/// What the helper does after each cycle's frame besides the frame.
#[derive(Debug, Default)]
pub(super) struct Extras {
    /// The distributed clocks.
    pub(super) clocks: DcCycle,
    /// The mailboxes polled for emergencies.
    pub(super) mailboxes: MailboxPoll,
    /// Slaves that lost their configuration, brought back.
    pub(super) recovery: Recovery,
}

pub(super) fn serve(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    group: &Group,
    shared: &Shared,
    slaves: &[SlaveInfo],
    cfg: &MasterConfig,
    extras: &mut Extras,
) {
    let mut out = vec![0u8; shared.outputs.len()];
    let mut inp = vec![0u8; shared.inputs.len()];
    let mut last_writes = 0;
    let mut lost_run = 0u32;
    let period = Duration::from_nanos(cfg.period_ns.max(1000));
    let timeout = cfg.frame_timeout.unwrap_or(period);
    let mut waiting = NextWrite::new(cfg.period_ns.max(1000));
    while !shared.stop.load(Acquire) {
        if shared.reset.swap(false, AcqRel) {
            reset_slaves(md, io, group, shared, &extras.recovery);
        }
        let writes = shared.outputs.writes();
        if writes == last_writes {
            waiting.wait(shared.written_at.load(Relaxed));
            continue;
        }
        if writes > last_writes + 1 {
            shared
                .counters
                .skipped
                .fetch_add(writes - last_writes - 1, Relaxed);
        }
        last_writes = writes;
        waiting.saw(shared.written_at.load(Relaxed));
        let Some(tag) = shared.outputs.read(&mut out) else {
            continue;
        };
        for (s, sd) in slaves.iter().zip(group.iter(md)) {
            let mut raw = sd.io_raw_mut();
            let o = raw.outputs();
            if let Some(src) = out.get(s.outputs.clone()) {
                if o.len() == src.len() {
                    o.copy_from_slice(src);
                }
            }
        }
        // The carrier alone does not make the link up: while frames are
        // still being lost (LOST_LIMIT in a row) it stays down, so the
        // pins do not flicker back to up before each frame when the
        // carrier is there (or cannot be read, as in another network
        // namespace) but nothing answers.
        let carrier = io.link.is_up();
        shared
            .link_up
            .store(carrier && lost_run < LOST_LIMIT, Relaxed);
        let started = Instant::now();
        let has_reference = extras.clocks.reference.is_some();
        let deadline = started + timeout;
        if exchange(
            md,
            io,
            group,
            has_reference,
            deadline,
            shared,
            slaves,
            &mut inp,
        ) {
            lost_run = 0;
            shared.link_up.store(carrier, Relaxed);
            shared.frame_ns.store(
                started.elapsed().as_nanos().min(u128::from(u32::MAX)) as u32,
                Relaxed,
            );
            shared.inputs.write(&inp, tag);
            extras.recovery.step(md, io, group, shared, slaves, cfg);
        } else {
            shared.counters.lost.fetch_add(1, Relaxed);
            lost_run += 1;
            if lost_run >= LOST_LIMIT {
                // No frames back: as far as the slaves go, the link is
                // down.
                shared.wkc.store(0, Release);
                shared.link_up.store(false, Relaxed);
            }
        }
        let monitor = shared.clocks.monitor.load(Relaxed);
        let clocks = &mut extras.clocks;
        if let Some(diff) = clocks.after_frame(md, io, shared.clocks.base, monitor, timeout) {
            shared.clocks.diff.store(diff, Relaxed);
        }
        extras.mailboxes.poll(md, io, &shared.emergencies, timeout);
    }
}

/// How the helper waits for the realtime side's next `write` without
/// the realtime side waking it (a futex wake is a system call, and on a
/// virtual machine an interrupt to another CPU: more than the rest of
/// `write`): it sleeps until shortly before the writes' interval after
/// the last write, then looks every [`NextWrite::step`] ns until the
/// write is there. A frame goes out at most a step (plus the helper's
/// own wake-up) after its `write`. The interval is the configured period
/// until the writes show theirs: the shortest gap of the last 16 (a
/// thread faster than `appTimePeriod` is followed from its first short
/// gap). With no write for four periods (the thread stopped) it sleeps a
/// period at a time, or until unparked.
#[derive(Debug)]
pub(super) struct NextWrite {
    period: u64,
    step: u64,
    /// The expected gap between writes.
    interval: u64,
    /// The shortest gap of the current window, and its gaps so far.
    window_min: u64,
    window_len: u32,
    /// The time of the last write seen.
    prev: u64,
}

impl NextWrite {
    /// The waits for a servo thread of `period` ns: steps of 1/40 of
    /// it, 5 to 25 µs.
    pub(super) fn new(period: u64) -> NextWrite {
        NextWrite {
            period,
            step: (period / 40).clamp(5_000, 25_000),
            interval: period,
            window_min: u64::MAX,
            window_len: 0,
            prev: 0,
        }
    }

    /// A write made at `written_at` was seen.
    pub(super) fn saw(&mut self, written_at: u64) {
        if self.prev != 0 && written_at > self.prev {
            let gap = written_at - self.prev;
            let (lo, hi) = (2 * self.step, 4 * self.period);
            if gap < self.interval {
                self.interval = gap.clamp(lo, hi);
            }
            self.window_min = self.window_min.min(gap);
            self.window_len += 1;
            if self.window_len >= 16 {
                self.interval = self.window_min.clamp(lo, hi);
                self.window_min = u64::MAX;
                self.window_len = 0;
            }
        }
        self.prev = written_at;
    }

    /// When to look again (CLOCK_MONOTONIC ns) for a write after the one
    /// made at `written_at`, it being `now`; None: idle, park.
    pub(super) fn next_look(&self, written_at: u64, now: u64) -> Option<u64> {
        if written_at == 0 || now > written_at.saturating_add(4 * self.period) {
            return None;
        }
        let expected = written_at + self.interval;
        Some(if now + self.step < expected {
            expected - self.step
        } else {
            now + self.step
        })
    }

    /// Sleeps until the next look.
    fn wait(&mut self, written_at: u64) {
        let now = hal_core::clock::monotonic_ns();
        match self.next_look(written_at, now) {
            Some(t) => hal_core::clock::sleep_until(t),
            None => std::thread::park_timeout(Duration::from_nanos(self.period)),
        }
    }
}

/// One cycle's frame, back by `deadline` (true) or not: with a
/// reference clock it carries the clock's time to the others (EtherCrab's
/// `tx_rx_sync_system_time`, which must not be called without one: its
/// fallback takes the process image's lock twice and spins forever).
#[allow(clippy::too_many_arguments, reason = "the helper's state, passed down")]
fn exchange(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    group: &Group,
    has_reference: bool,
    deadline: Instant,
    shared: &Shared,
    slaves: &[SlaveInfo],
    inp: &mut [u8],
) -> bool {
    if has_reference {
        match io.block_on(with_deadline(group.tx_rx_sync_system_time(md), deadline)) {
            Some(Ok(resp)) => {
                if let Some(t) = resp.extra {
                    shared.clocks.reference.store(t, Relaxed);
                }
                received(md, group, shared, slaves, &resp, inp);
                true
            }
            _ => false,
        }
    } else {
        match io.block_on(with_deadline(group.tx_rx(md), deadline)) {
            Some(Ok(resp)) => {
                received(md, group, shared, slaves, &resp, inp);
                true
            }
            _ => false,
        }
    }
}

/// A cycle's answer: the slaves' states, the working counter, the inputs.
fn received<T>(
    md: &MainDevice<'_>,
    group: &Group,
    shared: &Shared,
    slaves: &[SlaveInfo],
    resp: &ethercrab::TxRxResponse<MAX_SLAVES, T>,
    inp: &mut [u8],
) {
    for (i, st) in resp.subdevice_states.iter().enumerate() {
        if let Some(a) = shared.states.get(i) {
            a.store(state_byte(*st), Relaxed);
        }
    }
    if resp.working_counter < shared.expected_wkc {
        shared.counters.wkc_short.fetch_add(1, Relaxed);
    }
    shared.wkc.store(resp.working_counter, Release);
    for (s, sd) in slaves.iter().zip(group.iter(md)) {
        let raw = sd.io_raw();
        if let Some(dst) = inp.get_mut(s.inputs.clone()) {
            if raw.inputs().len() == dst.len() {
                dst.copy_from_slice(raw.inputs());
            }
        }
    }
}

/// The future's output, or None once `deadline` passes.
pub(super) async fn with_deadline<F: Future>(fut: F, deadline: Instant) -> Option<F::Output> {
    let mut fut = pin!(fut);
    std::future::poll_fn(|cx| {
        if let Poll::Ready(v) = fut.as_mut().poll(cx) {
            return Poll::Ready(Some(v));
        }
        if Instant::now() >= deadline {
            return Poll::Ready(None);
        }
        Poll::Pending
    })
    .await
}

fn state_byte(s: SubDeviceState) -> u8 {
    match s {
        SubDeviceState::Init => al::INIT,
        SubDeviceState::PreOp => al::PREOP,
        SubDeviceState::Bootstrap => al::BOOT,
        SubDeviceState::SafeOp => al::SAFEOP,
        SubDeviceState::Op => al::OP,
        SubDeviceState::Other(b) => b,
        SubDeviceState::None => 0,
    }
}

/// Slaves in SAFE-OP or PRE-OP (an AL error, a lost and found slave)
/// are asked back to OP with the error acknowledged.
/// Slaves being brought back after they lost their configuration are
/// left to that.
fn reset_slaves(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    group: &Group,
    shared: &Shared,
    recovery: &Recovery,
) {
    for (i, sd) in group.iter(md).enumerate() {
        if recovery.busy(i) {
            continue;
        }
        let state = shared.states.get(i).map_or(0, |s| s.load(Relaxed)) & al::STATE_MASK;
        let steps: &[u8] = match state {
            al::OP => &[],
            al::SAFEOP => &[al::OP],
            al::PREOP => &[al::SAFEOP, al::OP],
            _ => &[],
        };
        for &to in steps {
            let request = u16::from(to | al::ERROR);
            let _ = io.block_on(sd.register_write(regs::AL_CONTROL, request));
            let deadline = Instant::now() + Duration::from_millis(500);
            while Instant::now() < deadline {
                match io.block_on(sd.register_read::<u16>(regs::AL_STATUS)) {
                    Ok(s) if s as u8 & al::STATE_MASK == to => break,
                    _ => std::thread::sleep(Duration::from_millis(1)),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::NextWrite;

    #[test]
    fn the_helper_looks_just_before_a_period_after_the_last_write() {
        let w = NextWrite::new(1_000_000);
        assert_eq!(w.step, 25_000);
        // Right after a write: sleep until a step before the next.
        assert_eq!(w.next_look(10_000_000, 10_050_000), Some(10_975_000));
        // Around the expected time, and when it is late: every step.
        assert_eq!(w.next_look(10_000_000, 10_990_000), Some(11_015_000));
        assert_eq!(w.next_look(10_000_000, 12_000_000), Some(12_025_000));
        // No write for four periods, or none yet: park.
        assert_eq!(w.next_look(10_000_000, 14_000_001), None);
        assert_eq!(w.next_look(0, 5), None);
        assert_eq!(NextWrite::new(50_000).step, 5_000);
    }

    #[test]
    fn the_interval_follows_the_writes() {
        let mut w = NextWrite::new(1_000_000);
        // A thread four times faster than configured: followed at once.
        w.saw(10_000_000);
        w.saw(10_250_000);
        assert_eq!(w.next_look(10_250_000, 10_260_000), Some(10_475_000));
        // A slower one (2 ms): once a whole window of 16 gaps is of it.
        let mut t = 10_250_000;
        for _ in 0..32 {
            t += 2_000_000;
            w.saw(t);
        }
        assert_eq!(w.interval, 2_000_000);
        assert_eq!(w.next_look(t, t + 10_000), Some(t + 1_975_000));
    }
}
