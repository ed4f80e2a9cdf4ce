//! Consistent snapshots of the instance's objects, for show, list and save.

use std::sync::atomic::Ordering::*;

use super::component::ComponentKind;
use super::funct::entries;
use super::list;
use super::param::{param_dir, param_type};
use super::pin::{pin_dir, pin_type};
use super::signal::sig_type;
use super::Instance;
use crate::error::Result;
use crate::shm::*;
use crate::types::{HalType, ParamDir, PinDir, Value};

/// A component as `show comp` needs it.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentInfo {
    /// The component's name (`loadrt` name or the name a user-space component chose).
    pub name: String,
    /// Its id, which `show` prints and owner ids refer to.
    pub id: i32,
    /// User-space, realtime or the core's own.
    pub kind: ComponentKind,
    /// Whether it has called `ready`; `waitusr` and `loadusr -W` wait on it.
    pub ready: bool,
    /// The process that created it.
    pub pid: i32,
    /// The `loadrt` arguments, if recorded.
    pub loadrt_args: Option<String>,
}

/// A pin as `show pin` needs it.
#[derive(Debug, Clone, PartialEq)]
pub struct PinInfo {
    /// The pin's name (its alias, if aliased).
    pub name: String,
    /// The name before `alias`, if aliased.
    pub orig_name: Option<String>,
    /// Id of the component that owns it.
    pub owner_id: i32,
    /// Name of the component that owns it.
    pub owner: String,
    /// Its HAL type.
    pub hal_type: HalType,
    /// In, out or io.
    pub dir: PinDir,
    /// The value it reads now: its signal's, or its own when unlinked.
    pub value: Value,
    /// The signal it is linked to, if any.
    pub signal: Option<String>,
}

/// A param as `show param` needs it.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamInfo {
    /// The param's name (its alias, if aliased).
    pub name: String,
    /// The name before `alias`, if aliased.
    pub orig_name: Option<String>,
    /// Id of the component that owns it.
    pub owner_id: i32,
    /// Name of the component that owns it.
    pub owner: String,
    /// Its HAL type.
    pub hal_type: HalType,
    /// Read-only or read-write.
    pub dir: ParamDir,
    /// Its current value.
    pub value: Value,
}

/// A signal with the pins linked to it, in pin-name order.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalInfo {
    /// The signal's name.
    pub name: String,
    /// Its HAL type.
    pub hal_type: HalType,
    /// Its current value.
    pub value: Value,
    /// Output pins linked to it (0 or 1).
    pub writers: u32,
    /// I/O pins linked to it.
    pub bidirs: u32,
    /// Input pins linked to it.
    pub readers: u32,
    /// Every linked pin with its direction.
    pub pins: Vec<(String, PinDir)>,
}

/// A function's metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct FunctInfo {
    /// The function's name, as `addf` takes it.
    pub name: String,
    /// Id of the component that exported it.
    pub owner_id: i32,
    /// Name of the component that exported it.
    pub owner: String,
    /// Whether it was declared to use floating point.
    pub uses_fp: bool,
    /// Whether several threads may run it (else `addf` refuses a second thread).
    pub reentrant: bool,
    /// How many threads call it.
    pub users: u32,
    /// Execution time of the last run, in ns (its `.time` pin).
    pub time_ns: i32,
    /// Longest execution time seen, in ns (its `.tmax` param).
    pub tmax_ns: i32,
}

/// A thread with its function list and statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct ThreadInfo {
    /// The thread's name.
    pub name: String,
    /// Its period in ns.
    pub period: i64,
    /// Its SCHED_FIFO priority (faster threads get higher ones).
    pub priority: i32,
    /// Whether it may run floating-point functions.
    pub uses_fp: bool,
    /// The CPU it is pinned to, or `None` for the default placement.
    pub cpu: Option<usize>,
    /// Whether its functions' `.time`/`.tmax` are measured (`timing=1`).
    pub functs_timed: bool,
    /// What it does with missed deadlines.
    pub missed: crate::MissedDeadline,
    /// Functions it runs each cycle, in order.
    pub functs: Vec<String>,
    /// Functions run once on the first cycle after start (`initf`).
    pub init_functs: Vec<String>,
    /// Whether it is running (`start`) or stopped.
    pub running: bool,
    /// Execution time of the last cycle, in ns (its `.time` pin).
    pub time_ns: i32,
    /// Longest cycle seen, in ns (its `.tmax` param).
    pub tmax_ns: i32,
    /// Cycles that ended after the next one was due.
    pub overruns: u64,
    /// Cycles run since start.
    pub cycles: u64,
    /// Wake-up latency minimum (ns); `None` before the first cycle.
    pub latency_min_ns: Option<u64>,
    /// Wake-up latency maximum (ns); `None` before the first cycle.
    pub latency_max_ns: Option<u64>,
    /// Wake-up latency histogram; see [`crate::latency_bucket`].
    pub latency_histogram: Vec<u64>,
}

/// A named memory region.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionInfo {
    /// The region's name.
    pub name: String,
    /// Id of the component that allocated it.
    pub owner_id: i32,
    /// Its size in bytes.
    pub size: u64,
}

fn owner(seg: &Segment, off: u64) -> (i32, String) {
    seg.rec::<CompRec>(off)
        .map(|c| (c.id.load(Relaxed) as i32, c.name.get()))
        .unwrap_or((0, String::new()))
}

fn opt_name(n: &Name) -> Option<String> {
    (!n.is_empty()).then(|| n.get())
}

fn value_at(seg: &Segment, off: u64, t: HalType) -> Result<Value> {
    Ok(Value::from_bits(t, seg.word(off)?.load(Relaxed)))
}

fn component_info(seg: &Segment, c: &CompRec) -> Result<ComponentInfo> {
    let loadrt_args = match c.args.load(Relaxed) {
        0 => None,
        b => {
            let blob: &BlobRec = seg.rec(b)?;
            let len = blob.len.load(Relaxed) as usize;
            // Only the words the text fills: a reused blob may be far
            // larger than the text it holds.
            let mut bytes: Vec<u8> = blob_words_of(seg, b)?
                .iter()
                .take(len.div_ceil(8))
                .flat_map(|w| w.load(Relaxed).to_le_bytes())
                .collect();
            bytes.truncate(len);
            Some(String::from_utf8_lossy(&bytes).into_owned())
        }
    };
    Ok(ComponentInfo {
        name: c.name.get(),
        id: c.id.load(Relaxed) as i32,
        kind: ComponentKind::from_code(c.kind.load(Relaxed)),
        ready: c.ready.load(Relaxed) != 0,
        pid: c.pid.load(Relaxed) as i32,
        loadrt_args,
    })
}

fn pin_info(seg: &Segment, p: &PinRec) -> Result<PinInfo> {
    let t = pin_type(seg, p)?;
    let (owner_id, owner) = owner(seg, p.owner.load(Relaxed));
    let sig = p.signal.load(Relaxed);
    Ok(PinInfo {
        name: p.name.get(),
        orig_name: opt_name(&p.orig_name),
        owner_id,
        owner,
        hal_type: t,
        dir: pin_dir(seg, p)?,
        value: value_at(seg, p.words(seg)?.first.load(Relaxed), t)?,
        signal: if sig == 0 {
            None
        } else {
            Some(seg.rec::<SigRec>(sig)?.name.get())
        },
    })
}

fn param_info(seg: &Segment, p: &ParamRec) -> Result<ParamInfo> {
    let t = param_type(seg, p)?;
    let (owner_id, owner) = owner(seg, p.owner.load(Relaxed));
    Ok(ParamInfo {
        name: p.name.get(),
        orig_name: opt_name(&p.orig_name),
        owner_id,
        owner,
        hal_type: t,
        dir: param_dir(p),
        value: Value::from_bits(t, p.words(seg)?.first.load(Relaxed)),
    })
}

fn signal_info(seg: &Segment, off: u64, s: &SigRec) -> Result<SignalInfo> {
    let t = sig_type(seg, s)?;
    let cell: &CellRec = seg.rec(s.cell.load(Relaxed))?;
    Ok(SignalInfo {
        name: s.name.get(),
        hal_type: t,
        value: Value::from_bits(t, cell.value.load(Relaxed)),
        writers: s.writers.load(Relaxed) as u32,
        bidirs: s.bidirs.load(Relaxed) as u32,
        readers: s.readers.load(Relaxed) as u32,
        pins: super::signal::pins_of(seg, off)?,
    })
}

impl Instance {
    /// All components, by name.
    pub fn components(&self) -> Result<Vec<ComponentInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<CompRec>(seg, &seg.header().comps)
                .map(|r| component_info(seg, r?.1))
                .collect()
        })
    }

    /// One component, found by its name.
    pub fn component(&self, name: &str) -> Result<Option<ComponentInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::find::<CompRec>(seg, &seg.header().comps, name)?
                .map(|(_, c)| component_info(seg, c))
                .transpose()
        })
    }

    /// All pins, by name.
    pub fn pins(&self) -> Result<Vec<PinInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<PinRec>(seg, &seg.header().pins)
                .map(|r| pin_info(seg, r?.1))
                .collect()
        })
    }

    /// One pin, found by its name or its name before aliasing.
    pub fn pin(&self, name: &str) -> Result<Option<PinInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            super::pin::find_pin(seg, name)?
                .map(|(_, p)| pin_info(seg, p))
                .transpose()
        })
    }

    /// One param, found by its name or its name before aliasing.
    pub fn param(&self, name: &str) -> Result<Option<ParamInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            super::param::find_param(seg, name)?
                .map(|(_, p)| param_info(seg, p))
                .transpose()
        })
    }

    /// One signal, with its pins.
    pub fn signal(&self, name: &str) -> Result<Option<SignalInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::find::<SigRec>(seg, &seg.header().signals, name)?
                .map(|(off, s)| signal_info(seg, off, s))
                .transpose()
        })
    }

    /// All params, by name.
    pub fn params(&self) -> Result<Vec<ParamInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<ParamRec>(seg, &seg.header().params)
                .map(|r| param_info(seg, r?.1))
                .collect()
        })
    }

    /// All signals, by name, with their pins.
    pub fn signals(&self) -> Result<Vec<SignalInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<SigRec>(seg, &seg.header().signals)
                .map(|r| {
                    let (off, s) = r?;
                    signal_info(seg, off, s)
                })
                .collect()
        })
    }

    /// All functions, by name.
    pub fn functs(&self) -> Result<Vec<FunctInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<FunctRec>(seg, &seg.header().functs)
                .map(|r| {
                    let (_, f) = r?;
                    let (owner_id, owner) = owner(seg, f.owner.load(Relaxed));
                    Ok(FunctInfo {
                        name: f.name.get(),
                        owner_id,
                        owner,
                        uses_fp: f.uses_fp.load(Relaxed) != 0,
                        reentrant: f.reentrant.load(Relaxed) != 0,
                        users: f.users.load(Relaxed) as u32,
                        time_ns: seg
                            .rec::<PinRec>(f.time_pin.load(Relaxed))
                            .and_then(|p| p.words(seg))
                            .and_then(|w| seg.word(w.first.load(Relaxed)))
                            .map(|w| w.load(Relaxed) as i32)
                            .unwrap_or(0),
                        tmax_ns: seg
                            .rec::<ParamRec>(f.tmax_param.load(Relaxed))
                            .and_then(|p| p.words(seg))
                            .map(|w| w.first.load(Relaxed) as i32)
                            .unwrap_or(0),
                    })
                })
                .collect()
        })
    }

    /// All threads, slowest first (LinuxCNC's order).
    pub fn threads(&self) -> Result<Vec<ThreadInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<ThreadRec>(seg, &seg.header().threads)
                .map(|r| {
                    let (_, t) = r?;
                    let functs = entries(seg, t)?
                        .into_iter()
                        .map(|f| seg.rec::<FunctRec>(f).map(|f| f.name.get()))
                        .collect::<Result<_>>()?;
                    let init_functs = super::funct::init_entries(seg, t)?
                        .into_iter()
                        .map(|f| seg.rec::<FunctRec>(f).map(|f| f.name.get()))
                        .collect::<Result<_>>()?;
                    let lat_min = t.lat_min_ns.load(Relaxed);
                    let cycles = t.cycles.load(Relaxed);
                    let options = t.options.load(Relaxed);
                    Ok(ThreadInfo {
                        name: t.name.get(),
                        period: t.period.load(Relaxed) as i64,
                        priority: t.priority.load(Relaxed) as i32,
                        uses_fp: t.uses_fp.load(Relaxed) != 0,
                        cpu: match t.cpu.load(Relaxed) {
                            0 => None,
                            c => Some(c as usize - 1),
                        },
                        functs_timed: options & THREAD_NO_FUNCT_TIMING == 0,
                        missed: if options & THREAD_CATCH_UP != 0 {
                            crate::MissedDeadline::CatchUp
                        } else {
                            crate::MissedDeadline::Skip
                        },
                        functs,
                        init_functs,
                        running: t.running.load(Relaxed) != 0,
                        time_ns: seg
                            .rec::<PinRec>(t.time_pin.load(Relaxed))
                            .and_then(|p| p.words(seg))
                            .and_then(|w| seg.word(w.first.load(Relaxed)))
                            .map(|w| w.load(Relaxed) as i32)
                            .unwrap_or(0),
                        tmax_ns: seg
                            .rec::<ParamRec>(t.tmax_param.load(Relaxed))
                            .and_then(|p| p.words(seg))
                            .map(|w| w.first.load(Relaxed) as i32)
                            .unwrap_or(0),
                        overruns: t.overruns.load(Relaxed),
                        cycles,
                        latency_min_ns: (lat_min != u64::MAX).then_some(lat_min),
                        latency_max_ns: (cycles > 0).then(|| t.lat_max_ns.load(Relaxed)),
                        latency_histogram: t.hist.iter().map(|h| h.load(Relaxed)).collect(),
                    })
                })
                .collect()
        })
    }

    /// All named regions.
    pub fn regions(&self) -> Result<Vec<RegionInfo>> {
        self.tx(|tx| {
            let seg = tx.seg();
            list::iter::<RegionRec>(seg, &seg.header().regions)
                .map(|r| {
                    let (_, g) = r?;
                    Ok(RegionInfo {
                        name: g.name.get(),
                        owner_id: owner(seg, g.owner.load(Relaxed)).0,
                        size: g.size.load(Relaxed),
                    })
                })
                .collect()
        })
    }
}
