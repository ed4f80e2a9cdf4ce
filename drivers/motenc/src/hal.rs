//! The HAL binding: `loadrt hal_motenc`.
//!
//! One realtime component `hal_motenc` with, per board `<id>` (its HAL
//! board ID, [`crate::open::assign_ids`]), LinuxCNC's pins, params and
//! functions (hardware.md §4.4) and this driver's additions, as the crate
//! documentation lists them. Canonical interfaces carry every io-type:
//! [`Encoder`] (LinuxCNC's `enc-NN-*` names), [`DacOut`], [`AdcIn`] (its
//! `scale` is LinuxCNC's `gain`), [`DigIn`] and [`DigOut`].
//!
//! Faults go through each board's [`FaultLatch`]; the first one puts the
//! board in its safe state in the function that found it, says which
//! board and why in the realtime log, and shows on `motenc.<id>.fault`
//! and `.fault-code`.

use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use canonical::{AdcIn, ChannelNames, DacOut, DigIn, DigOut, Encoder};
use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::{FunctCtx, HalHost, Host, HostParam, HostPin, Io, Out, PinFactory, Result, Rw};
use hal_driver::bus::ALL_ONES;
use hal_driver::fault::{ErrorWatch, Fault, FaultLatch, SafeState};
use hal_driver::module::{self, CompId, DriverHost, DriverModule, Exporter, LoadEnv};
use hal_driver::pci::{EnableGuard, PciMatch, Sysfs};
use hal_driver::sim::SimBoard;
use hal_driver::ForModule;

use crate::board::Motenc;
use crate::open::{self, Opened, Source};
use crate::regs;
use crate::sim::MotencModel;

/// The module's name.
pub const NAME: &str = "hal_motenc";

/// hal_motenc's module parameters: the one table both hosts read.
/// LinuxCNC's driver has none; these select a backend and describe
/// simulated boards.
#[macro_export]
macro_rules! hal_motenc_params {
    ($($then:tt)*) => { $($then)*! {
        backend: Str = "pci (default: every MOTENC on the PCI bus) or sim (simulated boards)",
        sim_boards: StrArray($crate::open::MAX_BOARDS) =
            "with backend=sim: one item per board, 100 or lite (default: one 100)",
        sim_ids: IntArray($crate::open::MAX_BOARDS) =
            "with backend=sim: each board's ID jumpers, 0..3 (default: 0, 1, 2, 3)",
    } };
}

/// The module's parameters.
pub const PARAMS: &[ParamDecl] = hal_motenc_params!(hal_driver::param_table);

/// The `hal_motenc` driver, declared once for both hosts.
#[derive(Debug)]
pub struct HalMotenc;

/// The `hal_motenc` module of our host.
pub static MODULE: ModuleDef = module::module_def::<HalMotenc>();

impl DriverModule for HalMotenc {
    const NAME: &'static str = NAME;
    const HELP: &'static str =
        "Vital Systems MOTENC-100 / MOTENC-Lite PCI servo cards (or simulated ones)";
    const PARAMS: &'static [ParamDecl] = PARAMS;
    type Opened = Vec<Opened>;

    fn open(args: &ModuleArgs, _env: &LoadEnv) -> Result<Vec<Opened>> {
        open_from(args, &Sysfs::system(), regs::PCI_TABLE)
    }

    fn export<H: DriverHost>(boards: Vec<Opened>, ex: &mut Exporter<'_, H>) -> Result<()> {
        let ids: Vec<_> = boards.iter().map(|b| b.drv.identity()).collect();
        let locations: Vec<_> = boards.iter().map(|b| b.location.clone()).collect();
        let (hal_ids, warnings) = open::assign_ids(&ids, &locations);
        for w in &warnings {
            ex.log().warn(format_args!("{w}"));
        }
        let comp = ex.component(NAME)?;
        let mut shared = Vec::with_capacity(boards.len());
        for (opened, id) in boards.into_iter().zip(hal_ids) {
            if let Some(s) = &opened.sim {
                ex.publish_sim(&format!("motenc.{id}"), s);
            }
            shared.push(export_board(ex, comp, opened, id)?);
        }
        ex.safe_state(comp, shared);
        Ok(())
    }
}

/// Board gone: the version register no longer reads back.
pub static BOARD_GONE: Fault = Fault::new(
    1,
    "board stopped answering (boardVersion no longer reads back): DACs set to 0 V, outputs off; \
     reload the driver once the board is back",
);
/// The counters could not be read: a bus access failed.
pub static READBACK_FAILED: Fault = Fault::new(
    2,
    "encoder counters could not be read back (a bus access failed): DACs set to 0 V, outputs off",
);
/// The watchdog bit.
pub static WATCHDOG_BIT: Fault = Fault::new(
    3,
    "watchdog bit (no DAC write or watchdog-reset within its timeout): DACs at 0 V, outputs \
     off; set watchdog-reset to restart",
);

/// Opens and identifies every board `args` asks for, looking for PCI
/// boards of `table` under `sysfs`, before anything is exported.
fn open_from(args: &ModuleArgs, sysfs: &Sysfs, table: &[PciMatch]) -> Result<Vec<Opened>> {
    let source = open::parse_source(args).for_module(NAME)?;
    match &source {
        Source::Pci => open::open_pci(sysfs, table),
        Source::Sim(specs) => open::open_sim(specs),
    }
    .map_err(|e| e.into_hal(NAME))
}

/// Loads the driver for `args` into our host, looking for PCI boards of
/// `table` under `sysfs`. `loadrt` uses the system's sysfs and the
/// MOTENC's IDs; tests pass a fake tree, the VM rig its ivshmem device.
pub fn load_from(host: &Host, args: &ModuleArgs, sysfs: &Sysfs, table: &[PciMatch]) -> Result<()> {
    load_opened(host, open_from(args, sysfs, table)?)
}

/// Exports boards already opened and identified into our host (what
/// [`load_from`] does after opening them; tests give boards on buses of
/// their own).
pub fn load_opened(host: &Host, boards: Vec<Opened>) -> Result<()> {
    module::load_opened::<HalMotenc>(host, boards)
}

/// What a board's functions and its safe-state hook share.
struct Shared<H: HalHost> {
    drv: Motenc,
    latch: FaultLatch<H>,
    /// The board stopped answering: its inputs are no longer read.
    lost: AtomicBool,
    outputs: Vec<DigOut<H>>,
    /// The watchdog control value last written.
    watchdog_control: AtomicU32,
    /// When the watchdog was last restarted (board time).
    last_kick_ns: AtomicU64,
    /// Failed bus accesses.
    bus_errors: ErrorWatch,
    sim: Option<Arc<SimBoard<MotencModel>>>,
    _guard: Option<EnableGuard>,
}

impl<H: HalHost> Shared<H> {
    /// The board's time: the simulator's, or the HAL thread's.
    #[inline]
    fn now(&self, ctx: &FunctCtx) -> u64 {
        self.sim.as_ref().map_or(ctx.now_ns(), |s| s.now_ns())
    }

    /// Trips the latch; the first trip puts the board in its safe state.
    #[inline]
    fn fail(&self, f: &'static Fault) {
        self.latch.trip_into(f, self);
    }

    /// The bits of FPGA `fpga`'s outputs from `level`.
    #[inline]
    fn output_bits(&self, fpga: usize, level: impl Fn(&DigOut<H>) -> bool) -> u16 {
        let first = fpga * regs::OUTPUTS_PER_FPGA;
        DigOut::pack(&self.outputs[first..first + regs::OUTPUTS_PER_FPGA], level) as u16
    }
}

impl<H: HalHost> SafeState for Shared<H> {
    /// Every DAC at 0 V, every output at the level of `out` FALSE.
    fn go_safe(&self) {
        self.drv.zero_dacs();
        for fpga in 0..self.drv.identity().kind.fpgas() {
            self.drv
                .write_outputs(fpga, self.output_bits(fpga, DigOut::safe_level));
        }
    }
}

/// Names `motenc.<id>.<item>` where items are named `<kind>-NN-<name>`.
fn names(id: u8, kind: &'static str) -> ChannelNames {
    ChannelNames::custom(move |c, item| format!("motenc.{id}.{kind}-{c:02}-{item}"))
}

/// Digital input names: `in-NN` and `in-NN-not`.
fn input_names(id: u8) -> ChannelNames {
    ChannelNames::custom(move |c, item| match item.strip_prefix("in") {
        Some(rest) => format!("motenc.{id}.in-{c:02}{rest}"),
        None => format!("motenc.{id}.in-{c:02}-{item}"),
    })
}

/// Digital output names: `out-NN` and `out-NN-invert`.
fn output_names(id: u8) -> ChannelNames {
    ChannelNames::custom(move |c, item| match item {
        "out" => format!("motenc.{id}.out-{c:02}"),
        other => format!("motenc.{id}.out-{c:02}-{other}"),
    })
}

/// ADC names: LinuxCNC's `gain` is the canonical `scale`.
fn adc_names(id: u8) -> ChannelNames {
    ChannelNames::custom(move |c, item| {
        let item = if item == "scale" { "gain" } else { item };
        format!("motenc.{id}.adc-{c:02}-{item}")
    })
}

/// One encoder channel.
struct EncChannel<H: HalHost> {
    enc: Encoder<H>,
    index: H::Pin<bool, Out>,
    /// What was last written to the channel's arm register.
    armed: bool,
    /// The hardware count is `fed - base` (mod 2^32): the board clears
    /// its counter at an index, the encoder interface sees one count.
    base: u32,
    fed: u32,
}

fn export_board<H: DriverHost>(
    ex: &mut Exporter<'_, H>,
    comp: CompId,
    opened: Opened,
    id: u8,
) -> Result<Arc<Shared<H>>> {
    let kind = opened.drv.identity().kind;
    let c = ex.pins(comp);
    let p = |s: &str| format!("motenc.{id}.{s}");
    let enc_names = names(id, "enc");
    let mut encoders = (0..kind.encoders())
        .map(|k| {
            Ok(EncChannel {
                enc: Encoder::export(c, &enc_names, k, 32)?,
                index: c.pin(&enc_names.item(k, "index"))?,
                armed: false,
                base: 0,
                fed: 0,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let dac_names = names(id, "dac");
    let dacs = (0..regs::DACS)
        .map(|n| DacOut::export(c, &dac_names, n))
        .collect::<Result<Vec<_>>>()?;
    let adc_names = adc_names(id);
    let adcs = (0..regs::ADCS)
        .map(|n| AdcIn::export(c, &adc_names, n, regs::ADC_VOLTS_PER_COUNT, 0.0))
        .collect::<Result<Vec<_>>>()?;
    let in_names = input_names(id);
    let inputs = (0..kind.inputs())
        .map(|n| DigIn::export(c, &in_names, n))
        .collect::<Result<Vec<_>>>()?;
    let out_names = output_names(id);
    let outputs = (0..kind.outputs())
        .map(|n| DigOut::export(c, &out_names, n))
        .collect::<Result<Vec<_>>>()?;
    let estop_names = ChannelNames::custom(move |_, item| match item {
        "in" => format!("motenc.{id}.estop-in"),
        _ => format!("motenc.{id}.estop-{item}"),
    });
    let estop = DigIn::export(c, &estop_names, 0)?;
    let watchdog_reset: H::Pin<bool, Io> = c.pin(&p("watchdog-reset"))?;
    let watchdog_control: H::Param<u32, Rw> = c.param(&p("watchdog-control"), 0)?;
    let label = format!("motenc.{id} ({} {})", kind, opened.location);
    let latch = FaultLatch::named(label)
        .with_log(ex.log())
        .with_pin(c.pin(&p("fault"))?)
        .with_code_pin(c.pin(&p("fault-code"))?);

    opened.drv.init();
    // The first reading defines each encoder's zero: take it now, right
    // after the counters were reset, so that no count made before the
    // first encoder-read is lost.
    let now0 = opened
        .sim
        .as_ref()
        .map_or_else(hal_core::clock::monotonic_ns, |s| s.now_ns());
    for (k, ch) in encoders.iter_mut().enumerate() {
        ch.fed = opened.drv.count(k);
        ch.enc.update(ch.fed as u64, None, now0);
    }
    let bus_errors = ErrorWatch::new(opened.drv.bus().errors());
    let sh = Arc::new(Shared {
        drv: opened.drv,
        latch,
        lost: AtomicBool::new(false),
        outputs,
        watchdog_control: AtomicU32::new(0),
        last_kick_ns: AtomicU64::new(0),
        bus_errors,
        sim: opened.sim,
        _guard: opened.guard,
    });

    let s = sh.clone();
    ex.funct(comp, &p("encoder-read"), true, move |ctx| {
        encoder_read(&s, &mut encoders, ctx)
    })?;
    let s = sh.clone();
    ex.funct(comp, &p("dac-write"), true, move |ctx| {
        dac_write(&s, &dacs, ctx)
    })?;
    let s = sh.clone();
    let mut adc = AdcReader {
        adcs,
        state: AdcState::Idle,
    };
    ex.funct(comp, &p("adc-read"), true, move |_| adc.read(&s))?;
    let s = sh.clone();
    ex.funct(comp, &p("digital-in-read"), false, move |_| {
        digital_in_read(&s, &inputs)
    })?;
    let s = sh.clone();
    ex.funct(comp, &p("digital-out-write"), false, move |_| {
        digital_out_write(&s)
    })?;
    let s = sh.clone();
    ex.funct(comp, &p("misc-update"), false, move |ctx| {
        misc_update(&s, &watchdog_control, &watchdog_reset, &estop, ctx)
    })?;
    Ok(sh)
}

/// `motenc.<id>.encoder-read`: moves a simulated board one period, checks
/// that the board answers, reads the counters and index flags, and
/// checks the watchdog.
fn encoder_read<H: HalHost>(sh: &Shared<H>, encoders: &mut [EncChannel<H>], ctx: &FunctCtx) {
    if let Some(s) = &sh.sim {
        // Simulated time moves one thread period per read: every run of
        // a configuration computes the same thing.
        s.advance(ctx.period().max(0) as u64);
    }
    sh.drv.bus().tick(ctx.now_ns());
    if sh.lost.load(Relaxed) {
        return;
    }
    let now = sh.now(ctx);
    let fpgas = sh.drv.identity().kind.fpgas();
    let mut status = [0u32; 2];
    for (f, st) in status.iter_mut().enumerate().take(fpgas) {
        *st = sh.drv.status(f);
    }
    if status[0] == ALL_ONES && !sh.drv.answers() {
        sh.lost.store(true, Relaxed);
        sh.fail(&BOARD_GONE);
        return;
    }
    for (k, ch) in encoders.iter_mut().enumerate() {
        let (fpga, j) = (k / regs::ENCODERS_PER_FPGA, k % regs::ENCODERS_PER_FPGA);
        let st = status[fpga];
        let hw = sh.drv.count(k);
        ch.index
            .set(st & 1 << (regs::STATUS_INDEX_SHIFT + j as u32) != 0);
        let latched = st & 1 << (regs::STATUS_LATCH_SHIFT + j as u32) != 0;
        // The board cleared its counter at the index and keeps no count
        // of where that was: the last count read stands for it.
        let index_hw = if latched && ch.armed {
            ch.base = ch.fed;
            Some(ch.fed as u64)
        } else {
            None
        };
        ch.fed = ch.base.wrapping_add(hw);
        ch.enc.update(ch.fed as u64, index_hw, now);
        let arm = ch.enc.index_armed();
        if arm != ch.armed {
            sh.drv.arm_index(k, arm);
            ch.armed = arm;
        }
    }
    if sh.bus_errors.failed_since(sh.drv.bus().errors()) {
        sh.lost.store(true, Relaxed);
        sh.fail(&READBACK_FAILED);
        return;
    }
    let control = sh.watchdog_control.load(Relaxed);
    if control & regs::WATCHDOG_ENABLE != 0
        && now.saturating_sub(sh.last_kick_ns.load(Relaxed)) > regs::watchdog_timeout_ns(control)
    {
        sh.fail(&WATCHDOG_BIT);
    }
}

/// `motenc.<id>.dac-write`: every DAC's code; restarts the watchdog
/// when its control says DAC writes do.
fn dac_write<H: HalHost>(sh: &Shared<H>, dacs: &[DacOut<H>], ctx: &FunctCtx) {
    if sh.latch.is_tripped() {
        return;
    }
    for (n, dac) in dacs.iter().enumerate() {
        let v = dac.volts(-regs::DAC_MAX_VOLTS, regs::DAC_MAX_VOLTS);
        sh.drv.write_dac(n, regs::dac_code(v));
    }
    if sh.watchdog_control.load(Relaxed) & regs::WATCHDOG_DAC_RESETS != 0 {
        sh.last_kick_ns.store(sh.now(ctx), Relaxed);
    }
}

/// Where the ADC sequence stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AdcState {
    /// Nothing started yet.
    Idle,
    /// Channels 0..3 are converting.
    Low,
    /// Channels 4..7 are converting.
    High,
}

/// `motenc.<id>.adc-read`: LinuxCNC's sequence. Channels 0..3 and 4..7
/// convert in turn; a call whose conversion is done reads its four
/// results and starts the other four, so each channel updates every
/// second call at best.
struct AdcReader<H: HalHost> {
    adcs: Vec<AdcIn<H>>,
    state: AdcState,
}

impl<H: HalHost> AdcReader<H> {
    fn read(&mut self, sh: &Shared<H>) {
        if sh.lost.load(Relaxed) {
            return;
        }
        let (first, next) = match self.state {
            AdcState::Idle => {
                sh.drv.adc_start(regs::ADC_CMD_CH0_3);
                self.state = AdcState::Low;
                return;
            }
            AdcState::Low => (0, (regs::ADC_CMD_CH4_7, AdcState::High)),
            AdcState::High => (4, (regs::ADC_CMD_CH0_3, AdcState::Low)),
        };
        if sh.drv.status(0) & regs::STATUS_ADC_BUSY != 0 {
            return;
        }
        for adc in &self.adcs[first..first + 4] {
            adc.update_counts(sh.drv.adc_result() as i64);
        }
        sh.drv.adc_start(next.0);
        self.state = next.1;
    }
}

/// `motenc.<id>.digital-in-read`: per FPGA, 16 inputs from digitalIo
/// and 16 (FPGA 1: 20) from statusControl, all active low.
fn digital_in_read<H: HalHost>(sh: &Shared<H>, inputs: &[DigIn<H>]) {
    if sh.lost.load(Relaxed) {
        return;
    }
    // FPGA 0: in-00..31; FPGA 1: in-32..67.
    let (fpga0, fpga1) = inputs.split_at(inputs.len().min(32));
    for (fpga, pins) in [fpga0, fpga1]
        .into_iter()
        .enumerate()
        .filter(|(_, p)| !p.is_empty())
    {
        let io = sh.drv.digital_io(fpga) >> 16;
        let st = sh.drv.status(fpga);
        for (i, pin) in pins.iter().enumerate() {
            let word = if i < 16 { io >> i } else { st >> (i - 16) };
            pin.update(word & 1 == 0);
        }
    }
}

/// `motenc.<id>.digital-out-write`: per FPGA, `out XOR invert` of its 16
/// outputs, active low. Nothing while the board is faulted.
fn digital_out_write<H: HalHost>(sh: &Shared<H>) {
    if sh.latch.is_tripped() {
        return;
    }
    for fpga in 0..sh.drv.identity().kind.fpgas() {
        sh.drv
            .write_outputs(fpga, sh.output_bits(fpga, DigOut::level));
    }
}

/// `motenc.<id>.misc-update`: watchdog control and restart, E-stop
/// input. A watchdog-reset also clears a watchdog fault.
fn misc_update<H: HalHost>(
    sh: &Shared<H>,
    control: &H::Param<u32, Rw>,
    reset: &H::Pin<bool, Io>,
    estop: &DigIn<H>,
    ctx: &FunctCtx,
) {
    if sh.lost.load(Relaxed) {
        return;
    }
    let now = sh.now(ctx);
    let c = control.get();
    if c != sh.watchdog_control.load(Relaxed) {
        sh.drv.set_watchdog(c);
        sh.watchdog_control.store(c, Relaxed);
        sh.last_kick_ns.store(now, Relaxed);
    }
    if reset.get() {
        reset.set(false);
        sh.drv.kick_watchdog();
        sh.last_kick_ns.store(now, Relaxed);
        if sh.latch.fault() == Some(&WATCHDOG_BIT) {
            sh.latch.reset();
        }
    }
    estop.update(sh.drv.status(0) & regs::STATUS_ESTOP != 0);
}
