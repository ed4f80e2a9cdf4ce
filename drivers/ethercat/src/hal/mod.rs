//! The HAL binding: `loadrt lcec config=ethercat-conf.xml
//! [backend=raw|sim] [iface=eth0,...]`, with linuxcnc-ethercat's names;
//! or, as with linuxcnc-ethercat, `loadusr -W lcec_conf
//! ethercat-conf.xml` then `loadrt lcec` ([`crate::lcec::handoff`]).
//! The driver is one [`DriverModule`] ([`Lcec`]) for our host and for
//! LinuxCNC (`lcec.so`); inside LinuxCNC only `config=` gives the
//! configuration, as the hand-over lives in our host's instance.
//!
//! One realtime component `lcec`. For each `<master>` of the
//! configuration (pins `lcec.<m>.`, `<m>` its name or index) a master
//! on EtherCrab ([`crate::master`]) over the interface `iface=` gives
//! for it (masters in file order; default `eth0`), or with `backend=sim`
//! over a simulated segment of exactly the configured slaves, in
//! process. Pins and parameters are lcec's ([`crate::lcec::pins`]):
//!
//! * `lcec.slaves-responding`, `lcec.state-{init,preop,safeop,op}`,
//!   `lcec.link-up`, `lcec.all-op` for all masters together, and the
//!   same per master plus `wkc`, `wkc-state`, `wkc-min`,
//!   `wkc-change-count`, `wkc-reset`, `dc-sync-diff`,
//!   `dc-sync-converged`, `dc-sync-max`, `app-time-*`, `mono-time-*`
//!   and, for `syncToRefClock`, the PLL ([`crate::master::pll`]:
//!   `pll-err`, `pll-out`, `pll-reset-count`, `pll-step`,
//!   `pll-max-err`);
//! * per slave `lcec.<m>.<slave>.slave-online`, `slave-oper`,
//!   `slave-state-{init,preop,safeop,op}` and the pins of its type.
//!
//! Functions: `lcec.read-all` and `lcec.write-all` (every master), and
//! `lcec.<m>.read`, `lcec.<m>.write`. `read` takes the inputs of the
//! last frame and never waits for one; `write` fills the outputs and
//! hands the frame to the master's helper thread ([`crate::master`] says
//! what each costs at worst). A slave that is not in OP, or whose data
//! missed the working counter, gets its safe outputs that period, per
//! slave and per meaning (digital outputs off, analog outputs 0 V, the
//! EL7041 disabled, a drive's controlword from the CiA 402 layer with
//! its latch tripped: disable voltage), and its output pins
//! (`srv-cia-controlword`, `aout-N-curr-dc`, `srv-curr-dc`, ...) show
//! what went on the wire; a drive enables again only after
//! `srv-fault-reset` and a new rising `srv-enable`, the EL7041 after a
//! new rising `srv-enable`. A rising
//! `srv-fault-reset` brings slaves back to OP. At unload, exit or after
//! a panic every slave's outputs go to their safe values (zeros; drives:
//! disable voltage) in one last frame.
//!
//! With `backend=sim` the segment is published for tests as
//! `lcec.<m>` ([`hal_driver::sim::find`] with
//! [`crate::link::SharedSegment`]) to inject faults.

mod any_pin;
mod drive;
mod encoder;
mod field;
mod setup;
mod slave;
mod stepper;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{FunctCtx, HalError, HalHost, Host, Instance, PinFactory, Result};
use hal_driver::fault::SafeState;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::params::{BackendTokens, Params};
use hal_driver::rt_cell::RtCell;
use hal_driver::{ForModule, LogSink};

use any_pin::AnyPin;
use slave::SlaveRt;

use crate::lcec::pins::{self, MODULE as NAME};
use crate::lcec::{conf, handoff};
use crate::link::{InProcess, Link, RawSocket};
use crate::master::dc::NOT_HEARD;
use crate::master::pll::{self, Pll};
use crate::master::{Cyclic, Master};
use crate::regs::al;

pub use drive::SLAVE_LOST;

/// Masters `iface=` names at most.
pub const MAX_MASTERS: usize = 8;

/// Backends: raw sockets, or the simulated segment.
pub const BACKENDS: BackendTokens = BackendTokens::new(&["raw"], &[]);

/// lcec's module parameters: the one table both hosts read (our host
/// through [`MODULE`], LinuxCNC through `lcec.so`'s symbols).
#[macro_export]
macro_rules! lcec_params {
    ($($then:tt)*) => { $($then)*! {
        config: Str =
            "linuxcnc-ethercat's configuration file (default: the one lcec_conf keeps)",
        backend: Str =
            "raw (default): raw sockets | sim: the configured slaves simulated in process",
        iface: StrArray($crate::hal::MAX_MASTERS) =
            "per master, in file order: its network interface (default eth0)",
    } };
}

const PARAMS: &[ParamDecl] = lcec_params!(hal_driver::param_table);

/// The `lcec` driver, declared once for both hosts. In LinuxCNC the
/// configuration is always `config=`: `lcec_conf`'s hand-over lives in
/// our host's instance.
#[derive(Debug)]
pub struct Lcec;

/// The `lcec` module of our host, which also takes the configuration
/// `loadusr -W lcec_conf FILE` keeps in the instance.
pub static MODULE: ModuleDef = ModuleDef {
    name: NAME,
    params: PARAMS,
    help: Lcec::HELP,
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let opened = open(args, Some(host.instance()))?;
    module::load_opened::<Lcec>(host, opened)
}

impl DriverModule for Lcec {
    const NAME: &'static str = NAME;
    const HELP: &'static str =
        "EtherCAT masters on EtherCrab with linuxcnc-ethercat's configuration and pins";
    const PARAMS: &'static [ParamDecl] = PARAMS;
    type Opened = Opened;

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<Opened> {
        open(args, None)
    }

    fn export<H: DriverHost>(o: Opened, ex: &mut Exporter<'_, H>) -> Result<()> {
        export(o, ex)
    }
}

/// One master, bound.
struct MasterRt<H: HalHost> {
    cyclic: Cyclic,
    slaves: Vec<SlaveRt<H>>,
    pins: Vec<AnyPin<H>>,
    wkc: WkcStats,
    /// `syncToRefClock`: the application time follows the reference
    /// clock.
    pll: Option<Pll>,
    /// The last `read` had the inputs of the last `write`'s frame.
    fresh: bool,
    /// `read`s so far: every [`REWRITE_EVERY`] one slave's output pins
    /// (or the master's) are written whole again.
    reads: u32,
}

/// Every this many `read`s the next slave's output pins (in turn, the
/// master's after the last slave's) are written whether changed or not.
const REWRITE_EVERY: u32 = 64;

/// The working counter's statistics: from the first complete exchange
/// on (bring-up's ramp does not count), until `wkc-reset`.
#[derive(Default)]
struct WkcStats {
    armed: bool,
    min: u16,
    last: u16,
    changes: u32,
}

/// Indices into a master's pins, in [`pins::master_pins`] order.
mod mp {
    pub const RESPONDING: usize = 0;
    pub const STATES: usize = 1;
    pub const LINK_UP: usize = 5;
    pub const ALL_OP: usize = 6;
    pub const WKC: usize = 7;
    pub const WKC_STATE: usize = 8;
    pub const WKC_MIN: usize = 9;
    pub const WKC_CHANGES: usize = 10;
    pub const WKC_RESET: usize = 11;
    pub const DC_DIFF: usize = 12;
    pub const DC_CONVERGED: usize = 13;
    pub const DC_MAX: usize = 14;
    pub const DC_MONITOR: usize = 15;
    pub const APP_TIME: usize = 16;
    pub const MONO_TIME: usize = 18;
    pub const PLL_ERR: usize = 20;
    pub const PLL_OUT: usize = 21;
    pub const PLL_RESETS: usize = 22;
    pub const PLL_STEP: usize = 23;
    pub const PLL_MAX_ERR: usize = 24;
}

/// What one master's `read` found, for the global pins.
#[derive(Default, Clone, Copy)]
struct Summary {
    responding: u32,
    states: [bool; 4],
    link_up: bool,
    all_op: bool,
}

impl<H: HalHost> MasterRt<H> {
    fn read(&mut self, log: Option<&LogSink>) -> Summary {
        let st = self.cyclic.read();
        self.fresh = st.fresh;
        self.reads = self.reads.wrapping_add(1);
        if self.reads % REWRITE_EVERY == 0 {
            let turn = (self.reads / REWRITE_EVERY) as usize % (self.slaves.len() + 1);
            match self.slaves.get_mut(turn) {
                Some(s) => s.rewrite_outputs(),
                None => self.pins.iter().for_each(AnyPin::forget),
            }
        }
        let mut sum = Summary {
            link_up: st.link_up,
            all_op: st.all_op,
            ..Summary::default()
        };
        // With the link down no slave answers: its state is unknown (0),
        // as IgH reports a slave it lost, not the last one it read, so
        // `slave-online` and `slave-state-*` go false with `link-up`.
        let link_up = st.link_up;
        let al_state = |cyclic: &Cyclic, i: usize| if link_up { cyclic.al_state(i) } else { 0 };
        for s in &mut self.slaves {
            let state = al_state(&self.cyclic, s.index);
            let healthy = self.cyclic.healthy(s.index);
            let emcy = self.cyclic.take_emergency(s.index);
            let expected = self
                .cyclic
                .slaves()
                .get(s.index)
                .map_or((0, 0), |i| (i.identity.0, i.identity.1));
            s.show_refused(self.cyclic.refused(s.index), expected, log);
            s.show_failure(self.cyclic.recovery_failure(s.index), log);
            s.read(
                self.cyclic.inputs(s.index),
                (state, healthy),
                emcy,
                &st,
                log,
            );
        }
        for i in 0..self.cyclic.slaves().len() {
            let state = al_state(&self.cyclic, i);
            if state != 0 {
                sum.responding += 1;
            }
            for (k, want) in [al::INIT, al::PREOP, al::SAFEOP, al::OP].iter().enumerate() {
                sum.states[k] |= state & al::STATE_MASK == *want;
            }
        }
        publish(&self.pins, &sum);
        self.wkc(st.wkc, st.expected_wkc);
        self.clocks();
        sum
    }

    fn wkc(&mut self, wkc: u16, expected: u16) {
        let p = &self.pins;
        let w = &mut self.wkc;
        if p[mp::WKC_RESET].is_set() {
            *w = WkcStats::default();
            p[mp::WKC_RESET].set(0.0);
        }
        if !w.armed && wkc >= expected {
            *w = WkcStats {
                armed: true,
                min: wkc,
                last: wkc,
                changes: 0,
            };
        }
        if w.armed {
            if wkc != w.last {
                w.changes = w.changes.wrapping_add(1);
                w.last = wkc;
            }
            w.min = w.min.min(wkc);
        }
        p[mp::WKC].set(f64::from(wkc));
        p[mp::WKC_STATE].set(match wkc {
            0 => 0.0,
            w if w < expected => 1.0,
            _ => 2.0,
        });
        p[mp::WKC_MIN].set(f64::from(w.min));
        p[mp::WKC_CHANGES].set(f64::from(w.changes));
    }

    /// `dc-sync-diff` and `dc-sync-converged` from the helper's monitor
    /// (0 and false while no slave uses SYNC).
    fn clocks(&mut self) {
        let p = &self.pins;
        let monitor = p[mp::DC_MONITOR].is_set();
        self.cyclic.set_dc_monitor(monitor);
        let dc = self.cyclic.dc_status();
        if !dc.in_use || !monitor {
            p[mp::DC_CONVERGED].set(0.0);
            return;
        }
        let converged = dc.diff != NOT_HEARD && f64::from(dc.diff) < p[mp::DC_MAX].get();
        p[mp::DC_DIFF].set(f64::from(dc.diff));
        p[mp::DC_CONVERGED].set(f64::from(u8::from(converged)));
    }

    /// The cycle's time pair (`app-time-*`, `mono-time-*`): the
    /// application time on the host's clock, or with `syncToRefClock`
    /// as the PLL makes it follow the reference clock.
    fn times(&mut self, ctx: &FunctCtx) {
        let now_ns = ctx.now_ns();
        let app = match &mut self.pll {
            None => self.cyclic.app_time(now_ns),
            Some(pll) => {
                let p = &self.pins;
                let dc = self.cyclic.dc_status();
                let reference = (self.fresh && dc.reference_time != 0).then_some(dc.reference_time);
                let c = pll.cycle(
                    self.cyclic.app_time(ctx.deadline_ns()),
                    now_ns,
                    ctx.deadline_ns(),
                    ctx.period().max(1) as u64,
                    reference,
                    p[mp::PLL_STEP].get() as u32,
                    p[mp::PLL_MAX_ERR].get() as u32,
                );
                p[mp::PLL_ERR].set(f64::from(c.err));
                p[mp::PLL_OUT].set(f64::from(c.out));
                p[mp::PLL_RESETS].set(f64::from(pll.resets()));
                c.app_time
            }
        };
        for (at, v) in [(mp::APP_TIME, app), (mp::MONO_TIME, now_ns)] {
            self.pins[at].set(f64::from(v as u32));
            self.pins[at + 1].set(f64::from((v >> 32) as u32));
        }
    }

    fn write(&mut self, ctx: &FunctCtx) {
        let now_ns = ctx.now_ns();
        self.times(ctx);
        let mut reset = false;
        for s in &mut self.slaves {
            let healthy = self.cyclic.healthy(s.index);
            s.write(self.cyclic.outputs_mut(s.index), now_ns, healthy);
            reset |= s.wants_reset();
        }
        if reset {
            self.cyclic.fault_reset();
        }
        self.cyclic.write();
    }

    /// Safe outputs in two last frames (a slave may apply outputs a
    /// frame late), each waited for up to 100 ms: this runs at unload or
    /// exit, never in a realtime function.
    fn go_safe(&mut self) {
        use std::sync::atomic::Ordering::Relaxed;
        for s in &mut self.slaves {
            s.safe(self.cyclic.outputs_mut(s.index));
        }
        for _ in 0..2 {
            let lost = self.cyclic.counters().lost.load(Relaxed);
            self.cyclic.write();
            for _ in 0..50 {
                std::thread::sleep(std::time::Duration::from_millis(2));
                let now_lost = self.cyclic.counters().lost.load(Relaxed);
                if self.cyclic.read().fresh || now_lost != lost {
                    break;
                }
            }
        }
    }
}

/// Sets the state pins `pins` (master or global order) from `sum`.
fn publish<H: HalHost>(pins: &[AnyPin<H>], sum: &Summary) {
    pins[mp::RESPONDING].set(f64::from(sum.responding));
    for (k, on) in sum.states.iter().enumerate() {
        pins[mp::STATES + k].set(f64::from(u8::from(*on)));
    }
    pins[mp::LINK_UP].set(f64::from(u8::from(sum.link_up)));
    pins[mp::ALL_OP].set(f64::from(u8::from(sum.all_op)));
}

/// The masters, for the safe-state hook; dropping it stops their
/// helper threads.
struct SafeMasters<H: HalHost> {
    cells: Vec<Arc<RtCell<MasterRt<H>>>>,
    _masters: Vec<Master>,
}

impl<H: HalHost> SafeState for SafeMasters<H> {
    fn go_safe(&self) {
        for c in &self.cells {
            c.try_with(MasterRt::go_safe);
        }
    }
}

fn load_error(e: crate::Error) -> HalError {
    HalError::module_failed(NAME, e)
}

/// Every master of the configuration started on its link: what
/// [`Lcec`]'s `open` opened.
pub struct Opened {
    file: PathBuf,
    started: Vec<Started>,
}

/// A master started on its link, and what the simulator publishes.
struct Started {
    conf: conf::Master,
    master: Master,
    cyclic: Cyclic,
    sim: Option<crate::link::SharedSegment>,
}

fn start(cfg: &conf::Config, file: &Path, sim: bool, ifaces: &[String]) -> Result<Vec<Started>> {
    let mut out = Vec::with_capacity(cfg.masters.len());
    for (i, m) in cfg.masters.iter().enumerate() {
        let (link, seg): (Box<dyn Link>, _) = if sim {
            let seg = setup::sim_segment(m, file).map_err(load_error)?;
            (Box::new(InProcess::new(seg.clone())), Some(seg))
        } else {
            let iface = ifaces.get(i).map_or("eth0", String::as_str);
            let raw = RawSocket::open(iface).map_err(|source| {
                load_error(crate::Error::Interface {
                    iface: iface.to_string(),
                    reason: "cannot open a raw socket (the host needs CAP_NET_RAW: see the README)"
                        .into(),
                    source: Some(source),
                })
            })?;
            (Box::new(raw), None)
        };
        let (master, cyclic) = Master::start(link, setup::plan(m, sim)).map_err(load_error)?;
        out.push(Started {
            conf: m.clone(),
            master,
            cyclic,
            sim: seg,
        });
    }
    Ok(out)
}

fn export_master<H: HalHost>(
    c: &impl PinFactory<H>,
    s: Started,
    file: &Path,
) -> Result<(MasterRt<H>, Master, Option<crate::link::SharedSegment>)> {
    let name = s.conf.name.clone();
    let pins = pins::master_pins(false)
        .iter()
        .map(|p| AnyPin::export(c, &pins::full_name(Some(&name), None, &p.name), p))
        .collect::<Result<Vec<_>>>()?;
    let mut slaves = Vec::with_capacity(s.conf.slaves.len());
    let mut cyclic = s.cyclic;
    for sc in &s.conf.slaves {
        let index = usize::from(sc.index);
        cyclic.caller_makes_safe(index);
        let layout = cyclic
            .slaves()
            .get(index)
            .map(|i| i.layout.clone())
            .unwrap_or_default();
        slaves.push(SlaveRt::export(c, &name, sc, index, &layout, file)?);
    }
    let rt = MasterRt {
        cyclic,
        slaves,
        pins,
        wkc: WkcStats::default(),
        pll: s.conf.sync_to_ref_clock.then(Pll::new),
        fresh: false,
        reads: 0,
    };
    // lcec's default threshold: 4 % of the period.
    rt.pins[mp::DC_MAX].set((s.conf.app_time_period / 25).min(u64::from(u32::MAX)) as f64);
    let period = s.conf.app_time_period;
    rt.pins[mp::PLL_STEP].set(f64::from(pll::default_step(period)));
    rt.pins[mp::PLL_MAX_ERR].set(f64::from(pll::default_max_err(period)));
    Ok((rt, s.master, s.sim))
}

/// The configuration: the file `config=` names, else (our host) the one
/// `loadusr -W lcec_conf FILE` keeps in `kept_in`.
fn configuration(
    args: &ModuleArgs,
    p: &Params<'_>,
    kept_in: Option<&Instance>,
) -> Result<(PathBuf, conf::Config)> {
    if let Some(path) = args.str("config") {
        let file = PathBuf::from(path);
        let cfg = conf::read(&file).map_err(load_error)?;
        return Ok((file, cfg));
    }
    let Some(kept) = kept_in.and_then(handoff::take) else {
        let how = if kept_in.is_some() {
            "no configuration: give config=ethercat-conf.xml, or run `loadusr -W lcec_conf ethercat-conf.xml` first"
        } else {
            "no configuration: give config=ethercat-conf.xml"
        };
        return Err(p.error("config", how)).for_module(NAME);
    };
    let (file, text) = kept.map_err(load_error)?;
    let cfg = conf::parse(&text, &file).map_err(load_error)?;
    Ok((file, cfg))
}

/// Reads the parameters and the configuration and starts every master,
/// before any HAL object exists: a failure leaves nothing behind.
fn open(args: &ModuleArgs, kept_in: Option<&Instance>) -> Result<Opened> {
    let p = Params::new(NAME, args);
    let token = p.str_or("backend", "raw");
    let backend = BACKENDS
        .parse(token)
        .ok_or_else(|| {
            p.error(
                "backend",
                format!("'{token}' is not one of {}", BACKENDS.list()),
            )
        })
        .for_module(NAME)?;
    let ifaces = args.str_array("iface").to_vec();
    let (file, cfg) = configuration(args, &p, kept_in)?;
    let started = start(&cfg, &file, backend.is_sim(), &ifaces)?;
    Ok(Opened { file, started })
}

/// Exports the global pins, then each master's pins and functions, then
/// the functions of all masters and their safe state.
fn export<H: DriverHost>(o: Opened, ex: &mut Exporter<'_, H>) -> Result<()> {
    let comp = ex.component(NAME)?;
    let global = pins::master_pins(true)
        .iter()
        .map(|p| AnyPin::export(ex.pins(comp), &pins::full_name(None, None, &p.name), p))
        .collect::<Result<Vec<_>>>()?;
    let mut cells = Vec::new();
    let mut masters = Vec::new();
    for s in o.started {
        let name = s.conf.name.clone();
        let (rt, master, sim) = export_master(ex.pins(comp), s, &o.file)?;
        let cell = Arc::new(RtCell::new(rt));
        let [read, write] = pins::master_functions(&name);
        let (c, log) = (cell.clone(), ex.log());
        ex.funct(comp, &read, false, move |_| {
            c.try_with(|m| m.read(Some(&log)));
        })?;
        let c = cell.clone();
        ex.funct(comp, &write, false, move |ctx| {
            c.try_with(|m| m.write(ctx));
        })?;
        if let Some(seg) = sim {
            ex.publish_sim(&format!("{NAME}.{name}"), &seg);
        }
        cells.push(cell);
        masters.push(master);
    }
    let (all, log) = (cells.clone(), ex.log());
    let mut reads = 0u32;
    ex.funct(comp, pins::FUNCTIONS[0], false, move |_| {
        reads = reads.wrapping_add(1);
        if reads % (REWRITE_EVERY * 16) == 0 {
            global.iter().for_each(AnyPin::forget);
        }
        let mut sum = Summary {
            link_up: true,
            all_op: true,
            ..Summary::default()
        };
        for c in &all {
            if let Some(s) = c.try_with(|m| m.read(Some(&log))) {
                sum.responding += s.responding;
                for k in 0..4 {
                    sum.states[k] |= s.states[k];
                }
                sum.link_up &= s.link_up;
                sum.all_op &= s.all_op;
            }
        }
        publish(&global, &sum);
    })?;
    let all = cells.clone();
    ex.funct(comp, pins::FUNCTIONS[1], false, move |ctx| {
        for c in &all {
            c.try_with(|m| m.write(ctx));
        }
    })?;
    ex.safe_state(
        comp,
        SafeMasters {
            cells,
            _masters: masters,
        },
    );
    Ok(())
}
