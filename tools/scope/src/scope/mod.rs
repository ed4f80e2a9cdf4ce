//! `halscope`, headless: captures pins at the full rate of a HAL thread
//! through a `sampler` FIFO, with an oscilloscope's trigger (level, edge,
//! pre-trigger), and writes the record as a PNG plot, a CSV table or a
//! VCD for waveform viewers.
//!
//! When the configuration loaded `scope_rt` (LinuxCNC's realtime half of
//! halscope) and added `scope.sample` to a thread, pins are captured
//! through it instead ([`rt`]).
//!
//! Modules: [`args`] (the command line), [`wiring`] (the sampler channel
//! and its links, undone at the end), [`capture`] (trigger and record),
//! [`rt`] (capture through scope_rt), [`output`] (CSV and VCD), [`plot`]
//! (the PNG).

pub mod args;
pub mod capture;
pub mod output;
pub mod plot;
pub mod rt;
pub mod wiring;

use std::time::{Duration, Instant};

use hal_core::Instance;

use crate::error::Cause;
pub use crate::error::ScopeError;

use args::{Format, Request, Source};
use capture::{Capture, Trigger};
use output::Record;
use rt::RtProbe;
use wiring::Probe;

/// The shortest sleep of the reader between looks at the FIFO.
const POLL_MIN: Duration = Duration::from_millis(1);

/// The longest: how late the reader may see an interruption, the
/// trigger's timeout or lost samples.
const POLL_MAX: Duration = Duration::from_millis(20);

/// How often the reader asks whether the host still runs: each ask opens
/// and locks the host's lock file and checks the runtime directory (its
/// group's lookup reads the group database), too dear for every poll.
const ALIVE_EVERY: Duration = Duration::from_millis(500);

/// How often the reader looks at the sampler's overrun count while the
/// record fills (each look is a lookup by name under the HAL's lock); it
/// always looks once more before it takes a record as complete.
const OVERRUNS_EVERY: Duration = Duration::from_millis(10);

/// The trigger of `req` on the columns of `probe`: the name is a column's
/// name or its number.
fn trigger_of(req: &Request, probe: &Probe) -> Result<Option<Trigger>, ScopeError> {
    let Some(spec) = &req.trigger else {
        return Ok(None);
    };
    let column = probe
        .names
        .iter()
        .position(|n| *n == spec.name)
        .or_else(|| {
            spec.name
                .parse::<usize>()
                .ok()
                .filter(|c| *c < probe.names.len())
        })
        .ok_or_else(|| {
            ScopeError::Usage(format!(
                "the trigger '{}' is not a captured name (captured: {})",
                spec.name,
                probe.names.join(", ")
            ))
        })?;
    Ok(Some(Trigger {
        column,
        hal_type: probe.types[column],
        edge: spec.edge,
        level: spec.level,
    }))
}

/// Captures one record on `inst` as `req` asks; `interrupted` ends the
/// wait early. What the capture added to the instance is removed again.
pub fn capture(
    inst: &Instance,
    req: &Request,
    interrupted: &dyn Fn() -> bool,
) -> Result<Record, ScopeError> {
    let mut session = Session::open(inst, &req.source)?;
    let record = session.record(inst, req, interrupted)?;
    session.close()?;
    Ok(record)
}

/// A sampler channel (or scope_rt) made ready for records, kept between
/// them: a client that asks for record after record of the same pins (a
/// scope in normal mode) loads and links its sampler once, not once per
/// record. Dropping it removes what it added.
pub struct Session {
    via: Via,
    /// Whether a record was taken: samples since then are stale.
    used: bool,
}

/// What a session records through.
enum Via {
    /// A sampler channel, halscope's own or the configuration's.
    Sampler(Probe),
    /// The configuration's scope_rt.
    ScopeRt(RtProbe),
}

impl Session {
    /// Prepares `source`: pins through scope_rt when the configuration
    /// loaded it; otherwise loads and links a sampler of its own for
    /// pins, or finds the configuration's channel.
    pub fn open(inst: &Instance, source: &Source) -> Result<Session, ScopeError> {
        let via = match source {
            Source::Own { names, thread } if rt::loaded(inst)? => {
                Via::ScopeRt(RtProbe::open(inst, names, thread.as_deref())?)
            }
            Source::Own { names, thread } => {
                let thread = thread.as_deref().ok_or_else(|| {
                    ScopeError::Usage(
                        "give --thread: no scope_rt is loaded to sample in, so halscope \
                         loads a sampler of its own in that thread"
                            .into(),
                    )
                })?;
                Via::Sampler(Probe::own(inst, names, thread)?)
            }
            Source::Channel(c) => Via::Sampler(Probe::channel(inst, *c)?),
        };
        Ok(Session { via, used: false })
    }

    /// Whether this session records `source`.
    pub fn serves(&self, source: &Source) -> bool {
        match (&self.via, source) {
            (Via::ScopeRt(p), Source::Own { names, thread }) => {
                p.names == *names && thread.as_ref().is_none_or(|t| *t == p.thread)
            }
            (Via::Sampler(p), Source::Own { names, thread }) => {
                p.is_own() && p.names == *names && thread.as_ref() == Some(&p.thread)
            }
            (Via::Sampler(p), Source::Channel(c)) => !p.is_own() && p.channel == *c,
            (Via::ScopeRt(_), Source::Channel(_)) => false,
        }
    }

    /// Takes one record as `req` asks (its source must be this session's).
    pub fn record(
        &mut self,
        inst: &Instance,
        req: &Request,
        interrupted: &dyn Fn() -> bool,
    ) -> Result<Record, ScopeError> {
        let probe = match &mut self.via {
            Via::ScopeRt(p) => return p.record(inst, req, interrupted),
            Via::Sampler(p) => p,
        };
        if req.mult != 1 {
            return Err(ScopeError::Usage(
                "--mult: only scope_rt samples at a multiple of the period; load it \
                 (loadrt scope_rt, addf scope.sample THREAD)"
                    .into(),
            ));
        }
        if self.used {
            // Someone may have changed the HAL since the last record.
            probe.check_wiring(inst)?;
        }
        let trigger = trigger_of(req, probe)?;
        probe.check_running(inst)?;
        let (mut ring, _) = crate::fifo::open_sampler(inst, probe.channel)
            .map_err(|e| ScopeError::Sampler(Box::new(e)))?;
        let mut record = vec![0u64; probe.types.len() + 1];
        if self.used || !probe.is_own() {
            // What the channel holds already was sampled before we came.
            while ring.pop(&mut record) {}
        }
        self.used = true;
        let cap = Capture::new(req.samples, req.pre, trigger);
        let (rows, trigger_index) = fill(inst, probe, &mut ring, cap, req, interrupted)?;
        Ok(Record {
            names: probe.names.clone(),
            types: probe.types.clone(),
            rows,
            trigger_index,
            period_ns: probe.period_ns,
        })
    }

    /// Removes what the session added, and says whether that worked.
    pub fn close(self) -> Result<(), ScopeError> {
        match self.via {
            Via::Sampler(mut p) => p.remove(),
            Via::ScopeRt(_) => Ok(()),
        }
    }
}

/// Reads `ring` into `cap` until the record is complete, the trigger's
/// wait times out, the host exits or `interrupted` says so.
fn fill(
    inst: &Instance,
    probe: &Probe,
    ring: &mut hal_core::RingReader,
    mut cap: Capture,
    req: &Request,
    interrupted: &dyn Fn() -> bool,
) -> Result<(Vec<Vec<u64>>, usize), ScopeError> {
    let overruns_pin = format!("sampler.{}.overruns", probe.channel);
    let overruns = || inst.pin_value(&overruns_pin).ok();
    let mut record = vec![0u64; probe.types.len() + 1];
    let mut seen_overruns = overruns();
    // The timeout is for the trigger: the record itself takes its time.
    let record_time =
        Duration::from_nanos((req.samples as u64).saturating_mul(probe.period_ns.max(0) as u64));
    let end = Instant::now() + req.timeout + record_time;
    let mut alive_asked = Instant::now();
    let mut overruns_asked = Instant::now();
    loop {
        let mut got = false;
        while !cap.done() && ring.pop(&mut record) {
            cap.push(&record);
            got = true;
        }
        // The sampler counts only records it wrote: a full FIFO shows in
        // its overrun pin, not in the sample numbers.
        if cap.done() || overruns_asked.elapsed() >= OVERRUNS_EVERY {
            overruns_asked = Instant::now();
            let now_overruns = overruns();
            if now_overruns != seen_overruns {
                seen_overruns = now_overruns;
                cap.restart();
                continue;
            }
        }
        if cap.done() {
            break;
        }
        if interrupted() {
            return Err(ScopeError::Interrupted);
        }
        if alive_asked.elapsed() >= ALIVE_EVERY {
            if !inst.host_alive() {
                return Err(ScopeError::HostExited);
            }
            alive_asked = Instant::now();
        }
        if Instant::now() > end {
            return Err(ScopeError::Timeout(format!(
                "no complete record after {:.1} s ({})",
                req.timeout.as_secs_f64(),
                if cap.triggered() {
                    "triggered, samples still missing"
                } else {
                    "no trigger"
                }
            )));
        }
        if !got {
            std::thread::sleep(next_look(ring.depth(), probe.period_ns, cap.missing()));
        }
    }
    Ok(cap.into_record())
}

/// How long the reader sleeps with the FIFO drained: until about a
/// quarter of a FIFO of `depth` has filled at one sample each
/// `period_ns`, or until the `missing` samples of a triggered record have
/// come, whichever is sooner; within [`POLL_MIN`] and [`POLL_MAX`]. (Each
/// look costs a wake-up: at 1 ms, a 10 kHz record of 1000 samples took a
/// hundred of them.)
fn next_look(depth: usize, period_ns: i64, missing: Option<usize>) -> Duration {
    let samples = (depth / 4).min(missing.unwrap_or(usize::MAX)) as u64;
    let period = u64::try_from(period_ns).unwrap_or(0);
    Duration::from_nanos(samples.saturating_mul(period)).clamp(POLL_MIN, POLL_MAX)
}

/// Writes `r` to every output of `req`.
pub fn write_outputs(r: &Record, req: &Request, thread_title: &str) -> Result<(), ScopeError> {
    for (path, format) in &req.outputs {
        let shown = path.display().to_string();
        let written = match format {
            Format::Csv => std::fs::write(path, output::csv(r)).map_err(Cause::from),
            Format::Vcd => std::fs::write(path, output::vcd(r)).map_err(Cause::from),
            Format::Png => plot::draw(r, thread_title, &shown).map_err(Cause::from),
        };
        written.map_err(|source| ScopeError::Output {
            path: shown.clone(),
            source,
        })?;
    }
    Ok(())
}

/// The title of a capture's plot.
pub fn title(r: &Record, req: &Request) -> String {
    let trig = match &req.trigger {
        Some(t) => format!(
            "TRIGGER {} {} {}",
            t.name.to_uppercase(),
            match t.edge {
                capture::Edge::Rising => "RISING",
                capture::Edge::Falling => "FALLING",
            },
            t.level
        ),
        None => "NO TRIGGER".into(),
    };
    format!(
        "HALSCOPE: {} SAMPLES EVERY {} US, {trig}",
        r.rows.len(),
        r.period_ns as f64 / 1000.0
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reader_sleeps_for_a_quarter_fifo_or_the_missing_samples() {
        let ms = Duration::from_millis;
        // 10 kHz into 8192 records: a quarter is 205 ms, past the bound.
        assert_eq!(next_look(8192, 100_000, None), POLL_MAX);
        // A small FIFO: a quarter of 40 records of 1 ms.
        assert_eq!(next_look(40, 1_000_000, None), ms(10));
        // A triggered record wants 50 more samples of 100 us.
        assert_eq!(next_look(8192, 100_000, Some(50)), ms(5));
        // Never busier than the floor, even with one sample missing or
        // no period known.
        assert_eq!(next_look(8192, 25_000, Some(1)), POLL_MIN);
        assert_eq!(next_look(8192, -1, None), POLL_MIN);
        assert_eq!(next_look(0, 100_000, None), POLL_MIN);
    }
}
