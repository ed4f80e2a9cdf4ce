//! The HAL binding: `loadrt hal_stg`.
//!
//! One realtime component `hal_stg` with LinuxCNC's pins, params and
//! functions (hardware.md §3.9) and this driver's additions, as the crate
//! documentation lists them. Canonical interfaces carry every io-type:
//! [`Encoder`] (`stg.N.counts`, `.position-scale`), [`DacOut`],
//! [`AdcIn`] (its `scale` is LinuxCNC's `adc-gain`), [`DigIn`] and
//! [`DigOut`].

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;

use canonical::{AdcIn, ChannelNames, DacOut, DigIn, DigOut, Encoder};
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{FunctCtx, HalHost, Host, HostPin, In, Out, PinFactory, Result};
use hal_driver::fault::{ErrorWatch, Fault, FaultLatch, SafeState};
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::sim::SimBoard;
use hal_driver::ForModule;

use crate::detect::Model;
use crate::dio::{Dio, LINES};
use crate::driver::Stg;
use crate::open::{self, Opened};
use crate::regs;
use crate::sim::StgModel;

/// The module's name.
pub const NAME: &str = "hal_stg";

/// hal_stg's module parameters, the one table both hosts read:
/// LinuxCNC's four, and the backend.
#[macro_export]
macro_rules! hal_stg_params {
    ($($then:tt)*) => { $($then)*! {
        base: Int = "base address (0x200, 0x220, ... 0x3e0); 0 (default) searches them",
        model: Int = "1 or 2 forces Model I or II; 0 (default) detects it",
        num_chan: Int = "channels to export, 1..8 (default 8)",
        dio: Str = "directions of ports A B C D, I or O each (default IIOO)",
        backend: Str = "ioperm (default; needs CAP_SYS_RAWIO) or sim (a simulated board)",
    } };
}

/// The module's parameters.
pub const PARAMS: &[ParamDecl] = hal_stg_params!(hal_driver::param_table);

/// The `hal_stg` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalStg;

/// The `hal_stg` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalStg>();

/// Board gone: the board test register lost the signature.
pub static BOARD_GONE: Fault = Fault::new(
    1,
    "board stopped answering (its board test register lost the Servo-To-Go signature): DACs \
     set to 0 V, outputs off; reload the driver once the board is back",
);
/// The counters could not be read: a port access failed.
pub static READBACK_FAILED: Fault = Fault::new(
    2,
    "encoder counters could not be read back (a port access failed): DACs set to 0 V, outputs off",
);

/// How often `read-adcs` checks for the end of a conversion before
/// leaving it for the next call (LinuxCNC polled up to 1000 times).
pub const ADC_POLLS: usize = 3;

impl DriverModule for HalStg {
    const NAME: &'static str = NAME;
    const HELP: &'static str = "Servo-To-Go ISA servo card, Model I or II (or a simulated one)";
    const PARAMS: &'static [ParamDecl] = PARAMS;
    /// The board and how many channels to export.
    type Opened = (Opened, usize);

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<(Opened, usize)> {
        let cfg = open::parse(args).for_module(NAME)?;
        let opened = open::open(&cfg).map_err(|e| e.into_hal(NAME))?;
        Ok((opened, cfg.num_chan))
    }

    fn export<H: DriverHost>(o: (Opened, usize), ex: &mut Exporter<'_, H>) -> Result<()> {
        export_board(o.0, o.1, ex)
    }
}

/// Exports a board already opened and initialised into our host, with
/// `num_chan` channels (what `loadrt` does after opening it; tests give
/// boards on buses of their own).
pub fn load_opened(host: &Host, opened: Opened, num_chan: usize) -> Result<()> {
    module::load_opened::<HalStg>(host, (opened, num_chan))
}

/// The board's component, pins, functions and safe state.
fn export_board<H: DriverHost>(
    opened: Opened,
    num_chan: usize,
    ex: &mut Exporter<'_, H>,
) -> Result<()> {
    if let Some(w) = &opened.warning {
        ex.log().warn(format_args!("{w}"));
    }
    let drv = opened.drv;
    let model = drv.model();
    let comp = ex.component(NAME)?;
    let c = ex.pins(comp);
    let mut channels = export_channels(c, model, num_chan)?;
    let (dacs, adcs) = export_analog(c, num_chan)?;
    let (inputs, outputs) = export_dio(c, &drv.dio())?;
    let place = if opened.sim.is_some() {
        ", simulated"
    } else {
        ""
    };
    let latch = FaultLatch::named(format!("stg ({model} at {:#x}{place})", drv.base()))
        .with_log(ex.log())
        .with_pin(c.pin("stg.fault")?)
        .with_code_pin(c.pin("stg.fault-code")?);

    // The first reading defines each encoder's zero: take it now, right
    // after the counters were reset, so that no count made before the
    // first capture is lost.
    let now0 = opened
        .sim
        .as_ref()
        .map_or_else(hal_core::clock::monotonic_ns, |s| s.now_ns());
    for (k, ch) in channels.iter_mut().enumerate() {
        ch.enc.update(drv.latch_count(k) as u64, None, now0);
    }
    let bus_errors = ErrorWatch::new(drv.bus().errors());
    let sh = Arc::new(Shared::<H> {
        drv,
        latch,
        lost: AtomicBool::new(false),
        outputs,
        bus_errors,
        sim: opened.sim,
    });
    let s = sh.clone();
    let mut capture = Capture { channels, pair: 0 };
    ex.funct(comp, "stg.capture-position", true, move |ctx| {
        capture.run(&s, ctx)
    })?;
    let s = sh.clone();
    ex.funct(comp, "stg.write-dacs", true, move |_| write_dacs(&s, &dacs))?;
    let s = sh.clone();
    let mut adc = AdcReader {
        adcs,
        converting: None,
    };
    ex.funct(comp, "stg.read-adcs", true, move |_| adc.read(&s))?;
    let s = sh.clone();
    ex.funct(comp, "stg.di-read", false, move |_| di_read(&s, &inputs))?;
    let s = sh.clone();
    ex.funct(comp, "stg.do-write", false, move |_| do_write(&s))?;
    ex.safe_state(comp, sh.clone());
    if let Some(s) = &sh.sim {
        ex.publish_sim("stg", s);
    }
    Ok(())
}

/// The encoder channels' pins (LinuxCNC's names).
fn export_channels<H: HalHost>(
    c: &impl PinFactory<H>,
    model: Model,
    num_chan: usize,
) -> Result<Vec<Channel<H>>> {
    let enc_names = ChannelNames::custom(|k, item| {
        let item = match item {
            "count" => "counts",
            "scale" => "position-scale",
            other => other,
        };
        format!("stg.{k}.{item}")
    });
    (0..num_chan)
        .map(|k| {
            Ok(Channel {
                enc: Encoder::export(c, &enc_names, k, regs::COUNTER_BITS)?,
                index_latch: c.pin(&enc_names.item(k, "index-latch"))?,
                polarity: match model {
                    Model::One => Some(c.pin_init(&enc_names.item(k, "index-polarity"), true)?),
                    Model::Two => None,
                },
            })
        })
        .collect::<Result<Vec<_>>>()
}

/// The DAC and ADC channels' pins and params (LinuxCNC's names).
/// The DAC and ADC channels of a board.
type Analog<H> = (Vec<DacOut<H>>, Vec<AdcIn<H>>);

fn export_analog<H: HalHost>(c: &impl PinFactory<H>, num_chan: usize) -> Result<Analog<H>> {
    let dac_names = ChannelNames::custom(|k, item| format!("stg.{k}.dac-{item}"));
    let dacs = (0..num_chan)
        .map(|k| DacOut::export(c, &dac_names, k))
        .collect::<Result<Vec<_>>>()?;
    let adc_names = ChannelNames::custom(|k, item| {
        let item = if item == "scale" { "gain" } else { item };
        format!("stg.{k}.adc-{item}")
    });
    let adcs = (0..num_chan)
        .map(|k| AdcIn::export(c, &adc_names, k, regs::ADC_VOLTS_PER_COUNT, 0.0))
        .collect::<Result<Vec<_>>>()?;
    Ok((dacs, adcs))
}

/// Pins by digital port: the port's index and its eight pins.
type PortPins<T> = Vec<(usize, Vec<T>)>;

/// The digital ports' pins: inputs and outputs as the `dio` parameter
/// makes them.
/// The digital input and output ports of a board.
type DigitalPorts<H> = (PortPins<DigIn<H>>, PortPins<DigOut<H>>);

fn export_dio<H: HalHost>(c: &impl PinFactory<H>, dio: &Dio) -> Result<DigitalPorts<H>> {
    let in_names = ChannelNames::custom(|n, item| match item.strip_prefix("in") {
        Some(rest) => format!("stg.in-{n:02}{rest}"),
        None => format!("stg.in-{n:02}-{item}"),
    });
    let inputs = dio
        .input_ports()
        .enumerate()
        .map(|(i, port)| {
            let pins = (0..LINES)
                .map(|b| DigIn::export(c, &in_names, i * LINES + b))
                .collect::<Result<Vec<_>>>()?;
            Ok((port, pins))
        })
        .collect::<Result<Vec<_>>>()?;
    let out_names = ChannelNames::custom(|n, item| match item {
        "out" => format!("stg.out-{n:02}"),
        other => format!("stg.out-{n:02}-{other}"),
    });
    let outputs = dio
        .output_ports()
        .enumerate()
        .map(|(i, port)| {
            let pins = (0..LINES)
                .map(|b| DigOut::export(c, &out_names, i * LINES + b))
                .collect::<Result<Vec<_>>>()?;
            Ok((port, pins))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((inputs, outputs))
}

/// What the functions and the safe-state hook share.
struct Shared<H: HalHost> {
    drv: Stg,
    latch: FaultLatch<H>,
    /// The board stopped answering: nothing is read from it any more.
    lost: AtomicBool,
    /// Output ports and their pins.
    outputs: PortPins<DigOut<H>>,
    bus_errors: ErrorWatch,
    sim: Option<Arc<SimBoard<StgModel>>>,
}

impl<H: HalHost> Shared<H> {
    /// The board is lost: trips the latch; the first trip puts the board
    /// in its safe state.
    #[inline]
    fn fail(&self, f: &'static Fault) {
        self.lost.store(true, Relaxed);
        self.latch.trip_into(f, self);
    }
}

impl<H: HalHost> SafeState for Shared<H> {
    /// Every DAC at 0 V, every output at the level of `out` FALSE.
    fn go_safe(&self) {
        self.drv.zero_dacs();
        for (port, pins) in &self.outputs {
            self.drv
                .write_port(*port, DigOut::pack(pins, DigOut::safe_level) as u8);
        }
    }
}

/// One encoder channel's pins.
struct Channel<H: HalHost> {
    enc: Encoder<H>,
    index_latch: H::Pin<bool, Out>,
    /// Model I only: TRUE = the index is active high.
    polarity: Option<H::Pin<bool, In>>,
}

/// `stg.capture-position`.
struct Capture<H: HalHost> {
    channels: Vec<Channel<H>>,
    /// Model I: the axis pair whose index INTC watches.
    pair: usize,
}

impl<H: HalHost> Capture<H> {
    fn run(&mut self, sh: &Shared<H>, ctx: &FunctCtx) {
        if let Some(s) = &sh.sim {
            // Simulated time moves one thread period per capture: every
            // run of a configuration computes the same thing.
            s.advance(ctx.period().max(0) as u64);
        }
        sh.drv.bus().tick(ctx.now_ns());
        if sh.lost.load(Relaxed) {
            return;
        }
        let now = sh.sim.as_ref().map_or(ctx.now_ns(), |s| s.now_ns());
        let model = sh.drv.model();
        let mut index_at = [None; regs::CHANNELS];
        let alive = match model {
            Model::Two => self.index_model2(sh, &mut index_at),
            Model::One => self.index_model1(sh, &mut index_at),
        };
        if !alive {
            sh.fail(&BOARD_GONE);
            return;
        }
        for (k, ch) in self.channels.iter_mut().enumerate() {
            let hw = sh.drv.latch_count(k);
            ch.enc.update(hw as u64, index_at[k], now);
        }
        if sh.bus_errors.failed_since(sh.drv.bus().errors()) {
            sh.fail(&READBACK_FAILED);
        }
    }

    /// Model II: enable the armed axes' index, take the latched ones'
    /// counts. Whether the board answered.
    fn index_model2(&mut self, sh: &Shared<H>, index_at: &mut [Option<u64>]) -> bool {
        let d = &sh.drv;
        if !Model::Two.brdtst_ok(d.brdtst()) {
            return false;
        }
        let armed = self.channels.iter().enumerate().fold(0u8, |m, (k, ch)| {
            if ch.enc.index_armed() {
                m | 1 << k
            } else {
                m
            }
        });
        d.set_index_enables(armed);
        let flags = d.index_flags();
        if flags != 0 {
            // At once: an index latched between the read and the clear
            // would be lost.
            d.clear_index_flags();
        }
        for (k, ch) in self.channels.iter().enumerate() {
            let hit = flags & (1 << k) != 0;
            ch.index_latch.set(hit);
            if hit && armed & (1 << k) != 0 {
                index_at[k] = Some(d.index_count(k) as u64);
            }
        }
        true
    }

    /// Model I: INTC watches one axis pair at a time. Read its latches
    /// (set since the last clear), move the watch to a pair with an axis
    /// still waiting for its index, clear the latches, take the hit
    /// axes' counts. Whether the board answered.
    fn index_model1(&mut self, sh: &Shared<H>, index_at: &mut [Option<u64>]) -> bool {
        let d = &sh.drv;
        let irr = d.irr();
        let hit = |k: usize| {
            let (even, odd) = (2 * self.pair, 2 * self.pair + 1);
            (k == even && irr & regs::IRR_LIXEVN != 0) || (k == odd && irr & regs::IRR_LIXODD != 0)
        };
        let mut waiting = [false; regs::CHANNELS];
        for (k, ch) in self.channels.iter().enumerate() {
            ch.index_latch.set(hit(k));
            waiting[k] = ch.enc.index_armed() && !hit(k);
        }
        let hits: [bool; regs::CHANNELS] = std::array::from_fn(hit);
        // The first axis still waiting, from the watched pair on; with
        // none, the watch stays as it is.
        let waiting_axis = (0..regs::CHANNELS)
            .map(|i| (2 * self.pair + i) % regs::CHANNELS)
            .find(|&k| waiting[k]);
        if let Some(k) = waiting_axis {
            let active_high = self.channels[k].polarity.as_ref().is_none_or(HostPin::get);
            d.select_index_pair(k / 2, active_high);
            self.pair = k / 2;
        }
        if !Model::One.brdtst_ok(d.clear_index_latches()) {
            return false;
        }
        for (k, ch) in self.channels.iter().enumerate() {
            if hits[k] && ch.enc.index_armed() {
                index_at[k] = Some(d.index_count(k) as u64);
            }
        }
        true
    }
}

/// `stg.write-dacs`: every channel's DAC. Nothing while faulted.
fn write_dacs<H: HalHost>(sh: &Shared<H>, dacs: &[DacOut<H>]) {
    if sh.latch.is_tripped() {
        return;
    }
    for (n, dac) in dacs.iter().enumerate() {
        let v = dac.volts(-regs::DAC_MAX_VOLTS, regs::DAC_MAX_VOLTS);
        sh.drv.write_dac(n, regs::dac_code(v));
    }
}

/// `stg.read-adcs`: one channel per call, round robin over the exported
/// channels: read the conversion the previous call started, start the
/// next channel's. (LinuxCNC's driver also started one on the channel
/// past the last and threw it away, so a sweep took one call more.)
struct AdcReader<H: HalHost> {
    adcs: Vec<AdcIn<H>>,
    converting: Option<usize>,
}

impl<H: HalHost> AdcReader<H> {
    fn read(&mut self, sh: &Shared<H>) {
        if sh.lost.load(Relaxed) {
            return;
        }
        let d = &sh.drv;
        if let Some(i) = self.converting {
            if !(0..ADC_POLLS).any(|_| d.adc_done()) {
                return; // not yet: try again next call
            }
            self.adcs[i].update_counts(d.adc_result(i) as i64);
        }
        let next = self.converting.map_or(0, |i| (i + 1) % self.adcs.len());
        d.adc_start(next);
        self.converting = Some(next);
    }
}

/// `stg.di-read`: every input port. A line that reads 1 is FALSE on
/// `in-NN` (LinuxCNC's documentation says the opposite; its code, and
/// this driver, do this).
fn di_read<H: HalHost>(sh: &Shared<H>, inputs: &[(usize, Vec<DigIn<H>>)]) {
    if sh.lost.load(Relaxed) {
        return;
    }
    for (port, pins) in inputs {
        let v = sh.drv.read_port(*port);
        for (b, pin) in pins.iter().enumerate() {
            pin.update(v & (1 << b) == 0);
        }
    }
}

/// `stg.do-write`: every output port, `out XOR invert` on each line.
/// Nothing while faulted.
fn do_write<H: HalHost>(sh: &Shared<H>) {
    if sh.latch.is_tripped() {
        return;
    }
    for (port, pins) in &sh.outputs {
        sh.drv
            .write_port(*port, DigOut::pack(pins, DigOut::level) as u8);
    }
}
