//! Connecting the captured pins to a sampler channel, and undoing it.
//!
//! With `--pins` halscope loads a `sampler` of its own (one channel, one
//! column per name), links each column to the name's signal (an output
//! pin without a signal gets a new signal of halscope's), adds the
//! sampler's function at the end of the thread, and on drop removes all
//! of it again. With `--channel` it only reads a channel the HAL file
//! made.

use hal_components::infra::columns::pin_name;
use hal_core::{HalType, Instance, PinDir};
use hal_lang::protocol::Client;

use super::ScopeError;

/// Depth of the FIFO halscope's own sampler gets: records the reader may
/// fall behind by before samples are lost (about 0.2 s of a 25 µs thread).
pub const OWN_FIFO_DEPTH: i64 = 8192;

/// The sampler channel a capture reads, and what to undo at the end.
pub struct Probe {
    instance: String,
    /// The sampler channel.
    pub channel: usize,
    /// A name per column (the pin or signal asked for, or what the
    /// channel's column is linked to).
    pub names: Vec<String>,
    /// The column types.
    pub types: Vec<HalType>,
    /// The thread the sampler runs in.
    pub thread: String,
    /// Its period in ns.
    pub period_ns: i64,
    own: Option<OwnSampler>,
}

/// What halscope added to the instance.
struct OwnSampler {
    /// Signals halscope made, with the pin it linked to each.
    made_signals: Vec<(String, String)>,
    /// The signal each column was linked to.
    linked: Vec<String>,
    funct_added: bool,
}

fn hal(e: hal_core::HalError) -> ScopeError {
    ScopeError::Hal(e)
}

fn cfg_letter(t: HalType) -> char {
    match t {
        HalType::Bit => 'b',
        HalType::Float => 'f',
        HalType::S32 => 's',
        // A port is probed as the size of its buffer.
        HalType::U32 | HalType::Port => 'u',
        HalType::S64 => 'l',
        HalType::U64 => 'k',
    }
}

fn period_of(inst: &Instance, thread: &str) -> Result<i64, ScopeError> {
    let threads = inst.threads().map_err(hal)?;
    match threads.iter().find(|t| t.name == thread) {
        Some(t) => Ok(t.period),
        None => Err(ScopeError::Usage(format!(
            "thread '{thread}' does not exist (threads: {})",
            if threads.is_empty() {
                "none".to_string()
            } else {
                threads
                    .iter()
                    .map(|t| t.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        ))),
    }
}

impl Probe {
    /// Uses channel `channel` of the sampler the configuration loaded.
    pub fn channel(inst: &Instance, channel: usize) -> Result<Probe, ScopeError> {
        let types = crate::fifo::columns(inst, "sampler", channel)
            .map_err(|e| ScopeError::Sampler(Box::new(e)))?;
        let mut names = Vec::new();
        for m in 0..types.len() {
            let pin = pin_name("sampler", channel, m);
            let info = inst.pin(&pin).map_err(hal)?;
            names.push(info.and_then(|p| p.signal).unwrap_or(pin));
        }
        let funct = format!("sampler.{channel}");
        let thread = inst
            .threads()
            .map_err(hal)?
            .into_iter()
            .find(|t| t.functs.contains(&funct))
            .ok_or_else(|| {
                ScopeError::Usage(format!(
                    "function {funct} is in no thread: nothing samples channel {channel}"
                ))
            })?;
        Ok(Probe {
            instance: inst.name().to_string(),
            channel,
            names,
            types,
            period_ns: thread.period,
            thread: thread.name,
            own: None,
        })
    }

    /// Loads a sampler of halscope's own for `names` (pins or signals)
    /// in `thread`. On error nothing stays behind.
    pub fn own(inst: &Instance, names: &[String], thread: &str) -> Result<Probe, ScopeError> {
        if names.len() > hal_components::infra::columns::MAX_COLUMNS {
            return Err(ScopeError::Usage(format!(
                "{} names: a capture takes at most {}",
                names.len(),
                hal_components::infra::columns::MAX_COLUMNS
            )));
        }
        if inst.component("sampler").map_err(hal)?.is_some() {
            return Err(ScopeError::Usage(
                "a sampler is already loaded on this instance: capture through one of its \
                 channels with --channel N"
                    .into(),
            ));
        }
        let period_ns = period_of(inst, thread)?;
        // Resolve every name before touching anything.
        let mut plan = Vec::new();
        for name in names {
            plan.push(resolve(inst, name)?);
        }
        let mut probe = Probe {
            instance: inst.name().to_string(),
            channel: 0,
            names: names.to_vec(),
            types: plan.iter().map(|(t, _)| *t).collect(),
            thread: thread.to_string(),
            period_ns,
            own: Some(OwnSampler {
                made_signals: Vec::new(),
                linked: Vec::new(),
                funct_added: false,
            }),
        };
        // From here on, dropping `probe` undoes what was done.
        let cfg: String = probe.types.iter().map(|t| cfg_letter(*t)).collect();
        probe.call(&[
            "loadrt",
            "sampler",
            &format!("cfg={cfg}"),
            &format!("depth={OWN_FIFO_DEPTH}"),
        ])?;
        let pid = std::process::id();
        for (m, (t, link)) in plan.into_iter().enumerate() {
            let signal = match link {
                Link::Signal(s) => s,
                Link::NewSignalFor(pin) => {
                    let s = format!("halscope-{pid}-{m}");
                    inst.newsig(&s, t).map_err(hal)?;
                    if let Some(own) = probe.own.as_mut() {
                        own.made_signals.push((s.clone(), pin.clone()));
                    }
                    inst.link(&pin, &s).map_err(hal)?;
                    s
                }
            };
            inst.link(&pin_name("sampler", 0, m), &signal)
                .map_err(hal)?;
            if let Some(own) = probe.own.as_mut() {
                own.linked.push(signal);
            }
        }
        probe.call(&["addf", "sampler.0", thread])?;
        if let Some(own) = probe.own.as_mut() {
            own.funct_added = true;
        }
        Ok(probe)
    }

    fn call(&self, words: &[&str]) -> Result<(), ScopeError> {
        let words: Vec<String> = words.iter().map(|w| w.to_string()).collect();
        Client::connect(&self.instance)
            .and_then(|mut c| c.call(&words))
            .map_err(|source| ScopeError::Request {
                command: words.join(" "),
                source,
            })
    }

    /// Removes what halscope added; a second call does nothing.
    pub fn remove(&mut self) -> Result<(), ScopeError> {
        let Some(own) = self.own.take() else {
            return Ok(());
        };
        let mut first_error = None;
        let mut note = |r: Result<(), ScopeError>| {
            if let Err(e) = r {
                first_error.get_or_insert(e);
            }
        };
        if own.funct_added {
            note(self.call(&["delf", "sampler.0", &self.thread]));
        }
        note(self.call(&["unloadrt", "sampler"]));
        if let Ok(inst) = Instance::attach(&self.instance) {
            for (signal, pin) in &own.made_signals {
                note(inst.unlink(pin).map_err(hal));
                note(inst.delsig(signal).map_err(hal));
            }
        }
        first_error.map_or(Ok(()), Err)
    }

    /// Whether the sampler is halscope's own (loaded for this probe).
    pub fn is_own(&self) -> bool {
        self.own.is_some()
    }

    /// Checks that the channel still records what it did when the probe
    /// was made: the same column types and, for an own sampler, each
    /// column on the signal it was linked to and the function in its
    /// thread. Between records a kept probe leaves the HAL open to
    /// anyone's changes.
    pub fn check_wiring(&self, inst: &Instance) -> Result<(), ScopeError> {
        let changed = |what: String| {
            Err(ScopeError::Usage(format!(
                "the sampler channel {} changed since the last record: {what}",
                self.channel
            )))
        };
        let types = crate::fifo::columns(inst, "sampler", self.channel)
            .map_err(|e| ScopeError::Sampler(Box::new(e)))?;
        if types != self.types {
            return changed("its columns have other types".into());
        }
        let Some(own) = &self.own else {
            return Ok(());
        };
        for (m, want) in own.linked.iter().enumerate() {
            let pin = pin_name("sampler", self.channel, m);
            let now = inst.pin(&pin).map_err(hal)?.and_then(|p| p.signal);
            if now.as_deref() != Some(want.as_str()) {
                return changed(format!("{pin} is no longer on signal {want}"));
            }
        }
        let funct = format!("sampler.{}", self.channel);
        let in_thread = inst
            .threads()
            .map_err(hal)?
            .iter()
            .any(|t| t.name == self.thread && t.functs.contains(&funct));
        if !in_thread {
            return changed(format!("{funct} is no longer in {}", self.thread));
        }
        Ok(())
    }

    /// Checks that the thread runs (a stopped thread samples nothing).
    pub fn check_running(&self, inst: &Instance) -> Result<(), ScopeError> {
        let running = inst
            .threads()
            .map_err(hal)?
            .iter()
            .any(|t| t.name == self.thread && t.running);
        if running {
            Ok(())
        } else {
            Err(ScopeError::Usage(format!(
                "thread '{}' is stopped: start it first",
                self.thread
            )))
        }
    }
}

impl Drop for Probe {
    fn drop(&mut self) {
        let _ = self.remove();
    }
}

/// How a captured name reaches a sampler column.
enum Link {
    /// Link the column to this signal.
    Signal(String),
    /// Make a signal and link this output pin to it first.
    NewSignalFor(String),
}

fn resolve(inst: &Instance, name: &str) -> Result<(HalType, Link), ScopeError> {
    if let Some(p) = inst.pin(name).map_err(hal)? {
        return match (p.signal, p.dir) {
            (Some(s), _) => Ok((p.hal_type, Link::Signal(s))),
            (None, PinDir::Out) => Ok((p.hal_type, Link::NewSignalFor(p.name))),
            (None, _) => Err(ScopeError::Usage(format!(
                "pin '{name}' is an input on no signal: its value is its own (setp); \
                 linking it would change it, so halscope does not capture it"
            ))),
        };
    }
    if let Some(s) = inst.signal(name).map_err(hal)? {
        return Ok((s.hal_type, Link::Signal(s.name)));
    }
    Err(ScopeError::Usage(format!(
        "'{name}' is neither a pin nor a signal"
    )))
}
