//! Capturing through `scope_rt`, the realtime half a configuration
//! loaded (`loadrt scope_rt`, `addf scope.sample THREAD`): halscope
//! writes the channels, the sample rate multiplier, the trigger and the
//! record length into scope_rt's shared region
//! ([`hal_components::infra::scope_rt::layout`]), arms it, waits for the
//! record and reads it back. Nothing is loaded or linked: the channels
//! are read where their values live.

use std::sync::atomic::Ordering::Relaxed;
use std::time::{Duration, Instant};

use hal_components::infra::scope_rt::layout::{
    self, Settings, State, Status, TriggerSetting, MAX_CHANNELS, REGION,
};
use hal_core::{HalType, Instance, Region, ValueKind};

use super::args::Request;
use super::output::Record;
use super::ScopeError;

/// The function scope_rt exports.
pub const FUNCT: &str = "scope.sample";

/// How often the reader looks at the region while it waits.
const POLL: Duration = Duration::from_millis(2);

/// Looks between two asks whether the host still runs (about 0.5 s).
const ALIVE_EVERY: u32 = 250;

fn hal(e: hal_core::HalError) -> ScopeError {
    ScopeError::Hal(e)
}

/// Whether the configuration loaded scope_rt.
pub fn loaded(inst: &Instance) -> Result<bool, ScopeError> {
    Ok(inst.component("scope_rt").map_err(hal)?.is_some())
}

/// scope_rt's region and the names a capture records through it.
pub struct RtProbe {
    region: Region,
    /// Pins, signals or parameters, one per channel.
    pub names: Vec<String>,
    /// The thread `scope.sample` runs in.
    pub thread: String,
    /// Its period in ns.
    pub period_ns: i64,
}

/// A copy of the region's words, checked.
fn status(region: &Region) -> Result<(Vec<u64>, Status), ScopeError> {
    let words: Vec<u64> = region.words().iter().map(|w| w.load(Relaxed)).collect();
    let st = Status::parse(&words)?;
    Ok((words, st))
}

impl RtProbe {
    /// Checks that scope_rt's region is one this halscope reads and that
    /// `scope.sample` is in a thread (`thread`, when given).
    pub fn open(
        inst: &Instance,
        names: &[String],
        thread: Option<&str>,
    ) -> Result<RtProbe, ScopeError> {
        if names.is_empty() || names.len() > MAX_CHANNELS {
            return Err(ScopeError::Usage(format!(
                "{} names: scope_rt records 1 to {MAX_CHANNELS} channels",
                names.len()
            )));
        }
        let region = inst.region(REGION).map_err(hal)?;
        status(&region)?;
        let holder = inst
            .threads()
            .map_err(hal)?
            .into_iter()
            .find(|t| t.functs.iter().any(|f| f == FUNCT))
            .ok_or_else(|| {
                ScopeError::Usage(format!(
                    "scope_rt is loaded but {FUNCT} is in no thread: add it with \
                     'addf {FUNCT} servo-thread'"
                ))
            })?;
        if let Some(t) = thread.filter(|t| *t != holder.name) {
            return Err(ScopeError::Usage(format!(
                "--thread {t}: scope_rt samples in '{}', where the configuration added {FUNCT}",
                holder.name
            )));
        }
        Ok(RtProbe {
            region,
            names: names.to_vec(),
            thread: holder.name,
            period_ns: holder.period,
        })
    }

    /// Each name's value word and type, and the generation they were
    /// found at (all at one).
    fn resolve(&self, inst: &Instance) -> Result<(Vec<(u64, HalType)>, u64), ScopeError> {
        let mut out = Vec::new();
        let mut generation = None;
        for name in &self.names {
            let found = [ValueKind::Pin, ValueKind::Signal, ValueKind::Param]
                .into_iter()
                .find_map(|k| inst.value_word(k, name).transpose())
                .transpose()
                .map_err(hal)?;
            let (off, g, t) = found.ok_or_else(|| {
                ScopeError::Usage(format!("'{name}' is no pin, signal or parameter"))
            })?;
            if generation.is_some_and(|was| was != g) {
                return Err(changed());
            }
            generation = Some(g);
            out.push((off, t));
        }
        Ok((out, generation.unwrap_or(0)))
    }

    /// Takes one record as `req` asks; `interrupted` ends the wait early.
    /// The sampling is stopped again whatever happens.
    pub fn record(
        &mut self,
        inst: &Instance,
        req: &Request,
        interrupted: &dyn Fn() -> bool,
    ) -> Result<Record, ScopeError> {
        let (channels, generation) = self.resolve(inst)?;
        let types: Vec<HalType> = channels.iter().map(|(_, t)| *t).collect();
        let trigger = match &req.trigger {
            None => None,
            Some(spec) => Some(TriggerSetting {
                channel: column_of(&self.names, &spec.name)?,
                level: spec.level,
                rising: spec.edge == super::capture::Edge::Rising,
            }),
        };
        let settings = Settings {
            channels,
            rec_len: req.samples,
            pre_trig: req.pre,
            mult: req.mult,
            trigger,
        };
        let (_, st) = status(&self.region)?;
        settings.check(st.buf_len as u64)?;
        self.reset(inst, interrupted)?;
        settings.write(self.region.words())?;
        let armed = Armed(&self.region);
        self.set_state(State::Arm);
        let record_time = Duration::from_nanos(
            (req.samples as u64)
                .saturating_mul(u64::from(req.mult))
                .saturating_mul(self.period_ns.max(0) as u64),
        );
        let end = Instant::now() + req.timeout + record_time;
        let mut looks = 0u32;
        loop {
            let (state, fault) = layout::poll(self.region.words())?;
            match state {
                State::Done => break,
                State::Fault => {
                    return Err(ScopeError::Usage(format!(
                        "scope_rt refused the capture: {}",
                        fault.describe()
                    )))
                }
                State::Idle | State::Reset => {
                    return Err(ScopeError::Usage(
                        "scope_rt was stopped by someone else during the capture".into(),
                    ))
                }
                _ => {}
            }
            looks = looks.wrapping_add(1);
            self.wait(inst, interrupted, end, state, looks)?;
        }
        // The samples are copied once, complete.
        let (words, st) = status(&self.region)?;
        drop(armed);
        if inst.generation() != generation {
            return Err(changed());
        }
        let rows = layout::record(&words, &st)?
            .into_iter()
            .enumerate()
            .map(|(i, r)| {
                let mut row = Vec::with_capacity(r.len() + 1);
                row.push(i as u64 + 1);
                row.extend(r);
                row
            })
            .collect();
        Ok(Record {
            names: self.names.clone(),
            types,
            rows,
            trigger_index: st.trig_pos,
            period_ns: (st.period_ns as i64).saturating_mul(i64::from(req.mult)),
        })
    }

    fn set_state(&self, s: State) {
        if let Some(w) = self.region.words().get(layout::w::STATE) {
            w.store(s as u64, Relaxed);
        }
    }

    /// Stops any sampling and waits for `scope.sample` to say so: it
    /// must run (its thread started).
    fn reset(&self, inst: &Instance, interrupted: &dyn Fn() -> bool) -> Result<(), ScopeError> {
        self.set_state(State::Reset);
        let patience = Duration::from_nanos((self.period_ns.max(0) as u64).saturating_mul(20))
            .max(Duration::from_secs(2));
        let end = Instant::now() + patience;
        loop {
            if layout::poll(self.region.words())?.0 == State::Idle {
                return Ok(());
            }
            if Instant::now() > end {
                return Err(ScopeError::Usage(format!(
                    "{FUNCT} does not run: start the thread '{}' first",
                    self.thread
                )));
            }
            if interrupted() {
                return Err(ScopeError::Interrupted);
            }
            if !inst.host_alive() {
                return Err(ScopeError::HostExited);
            }
            std::thread::sleep(POLL);
        }
    }

    /// One wait for the record: refuses an interruption, an exited host
    /// or the end of the wait.
    fn wait(
        &self,
        inst: &Instance,
        interrupted: &dyn Fn() -> bool,
        end: Instant,
        state: State,
        looks: u32,
    ) -> Result<(), ScopeError> {
        if interrupted() {
            return Err(ScopeError::Interrupted);
        }
        if Instant::now() > end {
            return Err(ScopeError::Timeout(format!(
                "no complete record from scope_rt in time ({})",
                match state {
                    State::PostTrig => "triggered, samples still missing",
                    _ => "no trigger",
                }
            )));
        }
        // Each ask of the host's liveness locks its lock file: not every look.
        if looks % ALIVE_EVERY == 0 && !inst.host_alive() {
            return Err(ScopeError::HostExited);
        }
        std::thread::sleep(POLL);
        Ok(())
    }
}

/// Stops the sampling when dropped (the capture ended, well or not).
struct Armed<'a>(&'a Region);

impl Drop for Armed<'_> {
    fn drop(&mut self) {
        if let Some(w) = self.0.words().get(layout::w::STATE) {
            w.store(State::Reset as u64, Relaxed);
        }
    }
}

fn changed() -> ScopeError {
    ScopeError::Usage(
        "the HAL changed during the capture (a net or unlink moved a value): take it again".into(),
    )
}

/// The channel `name` names: a captured name or its number.
fn column_of(names: &[String], name: &str) -> Result<usize, ScopeError> {
    names
        .iter()
        .position(|n| n == name)
        .or_else(|| name.parse::<usize>().ok().filter(|c| *c < names.len()))
        .ok_or_else(|| {
            ScopeError::Usage(format!(
                "the trigger '{name}' is not a captured name (captured: {})",
                names.join(", ")
            ))
        })
}
