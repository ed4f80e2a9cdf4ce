//! The threads' integrator switches: per-function timing, the missed-deadline
//! policy and CPU placement (halcmd `setthread`).

use std::sync::atomic::Ordering::*;

use crate::error::{HalError, Result};
use crate::exec::realtime;
use crate::exec::thread::ThreadCtl;
use crate::exec::MissedDeadline;
use crate::shm::{ThreadRec, THREAD_CATCH_UP, THREAD_NO_FUNCT_TIMING};

use super::{lock, thread_index, Host};

impl Host {
    /// Turns per-function timing (`<funct>.time`, `.tmax`) on or off for
    /// every thread, and for threads created later; a thread's own `time`
    /// is always measured.
    pub fn set_function_timing(&self, on: bool) {
        let mut st = lock(&self.state);
        st.timing_default = on;
        for t in &st.threads {
            // A thread's record only goes away with the thread.
            let _ = self.set_option(&t.ctl, THREAD_NO_FUNCT_TIMING, !on);
        }
    }

    /// Turns per-function timing on or off for one thread (halcmd
    /// `setthread THREAD timing=on|off`). Off, the thread's functions'
    /// `.time`, `.tmax` and `.tmax-increased` keep their last values and
    /// the thread reads the clock twice per cycle instead of once per
    /// function.
    pub fn set_thread_timing(&self, thread: &str, on: bool) -> Result<()> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        self.set_option(&st.threads[ti].ctl, THREAD_NO_FUNCT_TIMING, !on)
    }

    /// Chooses what a thread does with missed deadlines (halcmd
    /// `setthread THREAD missed=skip|catch-up`); see [`MissedDeadline`].
    pub fn set_missed_deadline(&self, thread: &str, policy: MissedDeadline) -> Result<()> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let catch_up = policy == MissedDeadline::CatchUp;
        self.set_option(&st.threads[ti].ctl, THREAD_CATCH_UP, catch_up)
    }

    pub(super) fn set_option(&self, ctl: &ThreadCtl, bit: u64, set: bool) -> Result<()> {
        if set {
            ctl.options.fetch_or(bit, Relaxed);
        } else {
            ctl.options.fetch_and(!bit, Relaxed);
        }
        self.publish_options(ctl)
    }

    /// Copies a thread's switch bits into its segment record, where other
    /// processes read them.
    pub(super) fn publish_options(&self, ctl: &ThreadCtl) -> Result<()> {
        self.inst.tx(|tx| {
            let rec: &ThreadRec = tx.rec(ctl.rec_off)?;
            tx.set(&rec.options, ctl.options.load(Relaxed))
        })
    }

    /// A thread's integrator switches: whether its functions are timed,
    /// and what it does with missed deadlines.
    pub fn thread_options(&self, thread: &str) -> Result<(bool, MissedDeadline)> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let bits = st.threads[ti].ctl.options.load(Relaxed);
        let policy = if bits & THREAD_CATCH_UP != 0 {
            MissedDeadline::CatchUp
        } else {
            MissedDeadline::Skip
        };
        Ok((bits & THREAD_NO_FUNCT_TIMING == 0, policy))
    }

    /// Puts a thread on `cpu`, or back on the default placement for `None`
    /// (halcmd `setthread THREAD cpu=N|default`); takes effect at once,
    /// running or not. Two threads on different CPUs under realtime can
    /// run at the same time: HAL files that rely on the faster thread
    /// preempting the slower one must keep them on one CPU.
    pub fn set_thread_cpu(&self, thread: &str, cpu: Option<usize>) -> Result<()> {
        if let Some(c) = cpu {
            if !self.allowed_cpus.contains(&c) {
                return Err(HalError::BadValue {
                    what: format!("CPU of thread '{thread}'"),
                    reason: format!(
                        "CPU {c} is not one this process may use ({})",
                        realtime::cpu_list(&self.allowed_cpus)
                    ),
                });
            }
        }
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let ctl = &st.threads[ti].ctl;
        self.inst.tx(|tx| {
            let rec: &ThreadRec = tx.rec(ctl.rec_off)?;
            tx.set(&rec.cpu, cpu.map_or(0, |c| c as u64 + 1))
        })?;
        let mut p = lock(&ctl.placement);
        p.cpu = cpu.or(self.default_cpu);
        match p.tid {
            Some(tid) => realtime::place_thread(tid, p.cpu, &self.allowed_cpus).map_err(|e| {
                HalError::BadSetting {
                    what: format!("CPU of thread '{thread}'"),
                    source: Box::new(e),
                }
            }),
            None => Ok(()),
        }
    }

    /// The CPUs a thread's OS thread may run on, as the kernel reports
    /// them (`sched_getaffinity`); `None` before its OS thread has started.
    pub fn thread_affinity(&self, thread: &str) -> Result<Option<Vec<usize>>> {
        let st = lock(&self.state);
        let ti = thread_index(&st, thread)?;
        let tid = lock(&st.threads[ti].ctl.placement).tid;
        tid.map(|tid| {
            realtime::thread_affinity(tid).map_err(|e| HalError::BadSetting {
                what: format!("thread '{thread}'"),
                source: Box::new(e),
            })
        })
        .transpose()
    }
}
