//! Threads and their function lists: exported functions, `loadrt threads`,
//! `addf`, `initf`, `delf`, and the executor lists they publish.

use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, Ordering::*};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use crate::error::{HalError, Result};
use crate::exec::funct::{ExecList, FunctCode, TimingOut};
use crate::exec::thread::{self, Placement, ThreadCtl};
use crate::handles::{Param, Pin};
use crate::objects::funct::{
    add_entry_tx, delete_thread_tx, new_funct_tx, new_thread_tx, position_to_index,
    remove_entry_tx, NewThread,
};
use crate::objects::Component;
use crate::shm::{FunctRec, ThreadRec, THREAD_NO_FUNCT_TIMING};

use super::{lock, thread_index, wait_for_boundary, FunctSlot, Host, HostState, HostThread};

impl Host {
    pub(super) fn export_funct(
        &self,
        comp: &Component,
        name: &str,
        uses_fp: bool,
        code: FunctCode,
        reentrant: bool,
    ) -> Result<usize> {
        let mut st = lock(&self.state);
        // A slot freed by an unload is taken again, so that a host that
        // loads and unloads for months does not grow its table; never the
        // slot of a function whose fault still stands (`fault` names it).
        let faulted = self.shared.fault.load(Acquire);
        let reuse = st.free_functs.iter().rposition(|&i| i != faulted);
        let code_id = reuse.map_or(st.functs.len(), |p| st.free_functs[p]);
        let rec_off = self
            .inst
            .tx(|tx| new_funct_tx(tx, comp.offset(), name, code_id as u64, uses_fp, reentrant))?;
        let slot = Some(FunctSlot {
            name: name.to_string(),
            rec_off,
            code: Arc::new(code),
            reentrant,
            threads: Vec::new(),
        });
        match reuse {
            Some(p) => {
                st.free_functs.swap_remove(p);
                st.functs[code_id] = slot;
            }
            None => st.functs.push(slot),
        }
        st.by_name.insert(name.to_string(), code_id);
        Ok(code_id)
    }

    /// Removes functions of a component that never became ready, taking
    /// them out of any thread first.
    pub(super) fn drop_functs(&self, ids: &[usize]) {
        let mut st = lock(&self.state);
        for id in ids {
            for ti in 0..st.threads.len() {
                while st.threads[ti].holds(*id) {
                    if self.remove_from_thread(&mut st, ti, *id).is_err() {
                        break;
                    }
                }
            }
        }
        for &id in ids {
            st.release_funct(id);
        }
    }

    /// Creates a thread (as `loadrt threads` does) with LinuxCNC's rules:
    /// the first thread fixes the base period, later ones are rounded to a
    /// multiple of it and must not be faster than any earlier one. Returns
    /// the period in use. `cpu` pins this thread to a CPU explicitly.
    pub fn create_thread(
        &self,
        name: &str,
        period_ns: i64,
        uses_fp: bool,
        cpu: Option<usize>,
    ) -> Result<i64> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "create_thread")?;
        let mut st = lock(&self.state);
        let (off, period) = self.inst.tx(|tx| {
            new_thread_tx(
                tx,
                &NewThread {
                    name,
                    period: period_ns,
                    uses_fp,
                    cpu,
                },
            )
        })?;
        let seg = &self.inst.seg;
        let built = (|| -> Result<(i32, Arc<ThreadCtl>)> {
            let rec: &ThreadRec = seg.rec(off)?;
            let priority = rec.priority.load(Relaxed) as i32;
            let ctl = Arc::new(ThreadCtl {
                name: name.to_string(),
                task_id: st.threads.len(),
                period,
                priority,
                placement: Mutex::new(Placement {
                    cpu: cpu.or(self.default_cpu),
                    tid: None,
                }),
                rec_off: off,
                options: AtomicU64::new(if st.timing_default {
                    0
                } else {
                    THREAD_NO_FUNCT_TIMING
                }),
                list: AtomicPtr::new(Box::into_raw(Box::new(ExecList::new(seg)))),
                epoch: AtomicU64::new(0),
                idle: AtomicBool::new(true),
                exit: AtomicBool::new(false),
                init_done: AtomicBool::new(false),
                time: Pin::new(seg, rec.time_pin.load(Relaxed))?,
                tmax: Param::new(seg, rec.tmax_param.load(Relaxed))?,
                beat: Pin::new(seg, rec.beat_pin.load(Relaxed))?,
                done_deadline: AtomicU64::new(0),

                faster: st.threads.iter().map(|t| t.ctl.clone()).collect(),
            });
            Ok((priority, ctl))
        })();
        let built = built.and_then(|b| self.publish_options(&b.1).map(|()| b));
        let (_, ctl) = match built {
            Ok(b) => b,
            Err(e) => {
                let _ = self.inst.tx(|tx| delete_thread_tx(tx, off));
                return Err(e);
            }
        };
        let join = {
            let ctl = ctl.clone();
            let shared = self.shared.clone();
            let allowed = self.allowed_cpus.clone();
            std::thread::Builder::new()
                .name(format!("hal-{name}"))
                .spawn(move || thread::run(ctl, shared, allowed))
        };
        let join = match join {
            Ok(j) => j,
            Err(e) => {
                let _ = self.inst.tx(|tx| delete_thread_tx(tx, off));
                // SAFETY: the list was never shared with a running executor.
                drop(unsafe { Box::from_raw(ctl.list.load(SeqCst)) });
                return Err(HalError::io("starting thread", "", e));
            }
        };
        // A thread made while others run starts at once: shown running,
        // as `start` shows the others. Under the state lock, like `start`.
        if let Ok(rec) = seg.rec::<ThreadRec>(off) {
            rec.running
                .store(u64::from(self.shared.running.load(SeqCst)), SeqCst);
        }
        st.threads.push(HostThread {
            ctl,
            join: Some(join),
            functs: Vec::new(),
            init: Vec::new(),
            stale: false,
        });
        drop(st);
        // Set-up notes matter once threads exist; say them once.
        if !self.notes_printed.swap(true, SeqCst) {
            for note in lock(&self.notes).iter() {
                eprintln!("HAL: note: {note}");
            }
        }
        Ok(period)
    }

    /// Deletes a thread; its functions stay loaded.
    pub fn delete_thread(&self, name: &str) -> Result<()> {
        let mut st = lock(&self.state);
        let idx = thread_index(&st, name)?;
        let mut t = st.threads.remove(idx);
        t.ctl.exit.store(true, SeqCst);
        self.wake_executors();
        if let Some(j) = t.join.take() {
            let _ = j.join();
        }
        for id in &t.functs {
            if let Some(Some(slot)) = st.functs.get_mut(*id) {
                slot.threads.retain(|n| n != name);
            }
        }
        // SAFETY: the executor has exited; nobody else reads the list.
        drop(unsafe { Box::from_raw(t.ctl.list.swap(std::ptr::null_mut(), SeqCst)) });
        self.inst.tx(|tx| delete_thread_tx(tx, t.ctl.rec_off))
    }

    /// Adds a function to a thread (halcmd `addf`). `position` as halcmd:
    /// -1 appends, 1 puts it first, -2 before the last, and so on.
    pub fn addf(&self, funct: &str, thread: &str, position: i32) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "add_funct_to_thread")?;
        let mut st = lock(&self.state);
        let id = *st.by_name.get(funct).ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        let ti = thread_index(&st, thread)?;
        let slot = st.functs[id].as_ref().ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        if !slot.reentrant && !slot.threads.is_empty() {
            return Err(HalError::FunctInUse {
                funct: funct.to_string(),
                thread: slot.threads[0].clone(),
            });
        }
        let len = st.threads[ti].functs.len();
        let index = position_to_index(position, len).ok_or_else(|| HalError::BadPosition {
            thread: thread.to_string(),
            position,
            len,
        })?;
        let (rec_off, thread_off) = (slot.rec_off, st.threads[ti].ctl.rec_off);
        // Everything that can fail happens before anything changes.
        let list = if self.shared.running.load(SeqCst) {
            let mut functs = st.threads[ti].functs.clone();
            functs.insert(index, id);
            Some(self.build_list(&st, &functs, &st.threads[ti].init)?)
        } else {
            None
        };
        self.inst
            .tx(|tx| add_entry_tx(tx, thread_off, rec_off, index, index == len))?;
        st.threads[ti].functs.insert(index, id);
        self.publish(&mut st, ti, list);
        if let Some(slot) = st.functs[id].as_mut() {
            slot.threads.push(thread.to_string());
        }
        Ok(())
    }

    /// Registers a function for the init cycle of a thread (halcmd
    /// `initf`): it runs once, on the thread's first cycle after `start`,
    /// instead of the function list. Refused once that cycle has run.
    pub fn initf(&self, funct: &str, thread: &str) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "add_funct_to_thread")?;
        let mut st = lock(&self.state);
        let id = *st.by_name.get(funct).ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        let ti = thread_index(&st, thread)?;
        if st.threads[ti].ctl.init_done.load(SeqCst) {
            return Err(HalError::BadValue {
                what: format!("initf {funct} {thread}"),
                reason: format!("thread '{thread}' has already run its init cycle"),
            });
        }
        let slot = st.functs[id].as_ref().ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        if !slot.reentrant && slot.threads.iter().any(|t| t != thread) {
            return Err(HalError::FunctInUse {
                funct: funct.to_string(),
                thread: slot.threads[0].clone(),
            });
        }
        let (rec_off, thread_off) = (slot.rec_off, st.threads[ti].ctl.rec_off);
        let list = if self.shared.running.load(SeqCst) {
            let mut init = st.threads[ti].init.clone();
            init.push(id);
            Some(self.build_list(&st, &st.threads[ti].functs, &init)?)
        } else {
            None
        };
        self.inst
            .tx(|tx| crate::objects::funct::add_init_entry_tx(tx, thread_off, rec_off))?;
        st.threads[ti].init.push(id);
        self.publish(&mut st, ti, list);
        if let Some(slot) = st.functs[id].as_mut() {
            slot.threads.push(thread.to_string());
        }
        Ok(())
    }

    /// Removes a function from a thread (halcmd `delf`); with no thread,
    /// from every thread it is in.
    pub fn delf(&self, funct: &str, thread: Option<&str>) -> Result<()> {
        self.inst
            .check_unlocked(crate::lock_bits::CONFIG, "del_funct_from_thread")?;
        let mut st = lock(&self.state);
        let id = *st.by_name.get(funct).ok_or_else(|| HalError::NotFound {
            kind: "function",
            name: funct.to_string(),
        })?;
        let targets: Vec<usize> = match thread {
            Some(t) => {
                let ti = thread_index(&st, t)?;
                if !st.threads[ti].holds(id) {
                    return Err(HalError::FunctNotInThread {
                        funct: funct.to_string(),
                        thread: t.to_string(),
                    });
                }
                vec![ti]
            }
            None => (0..st.threads.len())
                .filter(|&i| st.threads[i].holds(id))
                .collect(),
        };
        for ti in targets {
            self.remove_from_thread(&mut st, ti, id)?;
        }
        Ok(())
    }

    pub(super) fn remove_from_thread(
        &self,
        st: &mut HostState,
        ti: usize,
        id: usize,
    ) -> Result<()> {
        let Some(slot) = st.functs.get(id).and_then(Option::as_ref) else {
            return Ok(());
        };
        let (rec_off, thread_off) = (slot.rec_off, st.threads[ti].ctl.rec_off);
        // One entry per call, an init entry before a cyclic one, as
        // remove_entry_tx takes it off the thread's lists.
        let t = &st.threads[ti];
        let (in_init, pos) = match t.init.iter().position(|&f| f == id) {
            Some(pos) => (true, Some(pos)),
            None => (false, t.functs.iter().position(|&f| f == id)),
        };
        let take = |v: &mut Vec<usize>, on: bool| {
            if let (true, Some(p)) = (on, pos) {
                v.remove(p);
            }
        };
        let list = if self.shared.running.load(SeqCst) {
            let (mut functs, mut init) = (t.functs.clone(), t.init.clone());
            take(&mut init, in_init);
            take(&mut functs, !in_init);
            Some(self.build_list(st, &functs, &init)?)
        } else {
            None
        };
        self.inst
            .tx(|tx| remove_entry_tx(tx, thread_off, rec_off).map(|_| ()))?;
        take(&mut st.threads[ti].init, in_init);
        take(&mut st.threads[ti].functs, !in_init);
        self.publish(st, ti, list);
        let tname = st.threads[ti].ctl.name.clone();
        if let Some(Some(slot)) = st.functs.get_mut(id) {
            if let Some(p) = slot.threads.iter().position(|n| *n == tname) {
                slot.threads.remove(p);
            }
        }
        Ok(())
    }

    /// Builds an executor list for the code ids `functs`.
    pub(super) fn build_list(
        &self,
        st: &HostState,
        functs: &[usize],
        init: &[usize],
    ) -> Result<ExecList> {
        let seg = &self.inst.seg;
        let mut list = ExecList::new(seg);
        for &id in init {
            if let Some(slot) = st.functs.get(id).and_then(Option::as_ref) {
                list.push_init(slot.code.clone(), id);
            }
        }
        for &id in functs {
            let Some(slot) = st.functs.get(id).and_then(Option::as_ref) else {
                continue;
            };
            let rec: &FunctRec = seg.rec(slot.rec_off)?;
            let timing = TimingOut::new(
                &Pin::new(seg, rec.time_pin.load(Relaxed))?,
                &Param::new(seg, rec.tmax_param.load(Relaxed))?,
                &Param::new(seg, rec.tmax_inc_param.load(Relaxed))?,
            );
            list.push(slot.code.clone(), id, timing);
        }
        Ok(list)
    }

    /// Hands thread `ti` its new function list: `list` when threads run
    /// (built before the change, so that nothing can fail after it), else
    /// an empty list until the next `start` builds the real one
    /// ([`Host::publish_stale`]): building a list costs its length, and a
    /// configuration adds its functions one by one before it starts.
    ///
    /// The executor's list owns the code of every function on it (and so
    /// whatever the closures hold: a module's devices, a simulated bus).
    /// A function taken out while threads are stopped must therefore not
    /// stay on the old list until the next start: the first change after a
    /// stop swaps the old list for an empty one, which drops it. The swap
    /// also waits for an executor that `stop` caught inside a cycle, so
    /// that nothing the change removes is still being run.
    pub(super) fn publish(&self, st: &mut HostState, ti: usize, list: Option<ExecList>) {
        match list {
            Some(list) => self.swap_list(&st.threads[ti].ctl, list),
            None if st.threads[ti].stale => {}
            None => {
                self.swap_list(&st.threads[ti].ctl, ExecList::new(&self.inst.seg));
                st.threads[ti].stale = true;
            }
        }
    }

    /// Builds and hands over the lists changed while threads were stopped.
    pub(super) fn publish_stale(&self, st: &mut HostState) -> Result<()> {
        for ti in 0..st.threads.len() {
            if st.threads[ti].stale {
                let t = &st.threads[ti];
                let list = self.build_list(st, &t.functs, &t.init)?;
                self.swap_list(&st.threads[ti].ctl, list);
                st.threads[ti].stale = false;
            }
        }
        Ok(())
    }

    /// Swaps a thread's list and frees the old one once the executor has
    /// passed a cycle boundary. Never gives up: freeing (or forgetting) a
    /// list the executor may still run would let a non-reentrant function
    /// run on two threads.
    pub(super) fn swap_list(&self, ctl: &ThreadCtl, list: ExecList) {
        let new = Box::into_raw(Box::new(list));
        let old = ctl.list.swap(new, SeqCst);
        let mut warned = false;
        while !wait_for_boundary(ctl, Duration::from_secs(10)) {
            if !warned {
                warned = true;
                self.add_note(format!(
                    "thread '{}' has not reached a cycle boundary for 10 s; still waiting",
                    ctl.name
                ));
            }
        }
        // SAFETY: the executor is idle or has finished a cycle since the
        // swap, so it no longer references `old`.
        drop(unsafe { Box::from_raw(old) });
    }
}
