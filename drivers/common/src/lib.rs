//! The shared driver layer: what every HAL driver crate (parport,
//! hostmot2, motenc, stg, canservo, gpio, i2c, serial) builds on, so the
//! drivers come out alike and nothing here is written twice.
//!
//! # A driver author's guide
//!
//! A driver crate has four parts (DESIGN.md "Drivers"): `regs` (the
//! register map as named constants), the bus it talks through, `sim` (a
//! register-level model of the board), and the HAL binding (`loadrt`
//! parameters, probing, canonical exports, `read`/`write` functions),
//! declared once as a [`DriverModule`] that loads in two hosts: ours, and
//! LinuxCNC's `rtapi_app` (§8). This crate supplies the bus, the
//! simulator harness, PCI discovery, the parameter helpers, the fault
//! machinery and the load sequence of both hosts; the driver supplies
//! only what is particular to its board.
//!
//! ## 1. Talk through a bus trait
//!
//! Write the driver against [`bus::RegWindow`] (32-bit registers in a
//! memory window: PCI boards) or [`bus::PortBus`] (x86 I/O ports by
//! absolute address: ISA cards, parallel ports), usually as
//! `Arc<dyn RegWindow>` or a generic parameter. The driver never knows
//! which backend it has:
//!
//! | hardware | backend |
//! |---|---|
//! | PCI memory BAR | [`pci::PciDevice::map_bar`] → [`bus::MmapWindow`] |
//! | PCI I/O BAR | [`pci::PciDevice::io_bar`] → [`bus::SysfsIoBar`] |
//! | legacy I/O ports | [`bus::IopermPorts`] (needs `CAP_SYS_RAWIO`), [`bus::DevPortPorts`] |
//! | the simulator | [`sim::SimBoard`] around your model |
//!
//! Accessors take `&self`, never fail visibly and never panic: a failed
//! access reads all ones and is counted in `errors()`. A realtime
//! function that sees all ones where the board cannot return them (an ID
//! register, a cookie) has lost the board: it trips its fault latch (§4).
//! Batch register traffic with `read_burst`/`write_burst`. Call
//! `bus.tick(ctx.now_ns())` once at the start of the `read` function:
//! hardware ignores it, a simulated board takes its time from it.
//!
//! A board type that is neither (a CAN socket, a gpio chip, a tty) keeps
//! its own small bus trait in the same shape: `&self` accessors, an
//! `errors()` count, a real and a simulated backend.
//!
//! ## 2. Find the hardware
//!
//! PCI boards: an ID table of [`pci::PciMatch`] and [`pci::find`] over
//! [`pci::Sysfs::system`] (tests: `pci::fake::FakeSysfs`, feature `testing`); then
//! [`pci::PciDevice::enable`] (keep the guard as long as the driver
//! lives) and `map_bar`/`map_bar_window`/`io_bar`. Missing boards,
//! permissions (naming the udev rule and the `hal` group), kernel
//! lockdown and wrong or small BARs come back as [`DriverError`]s that
//! say what and where. Port boards: [`bus::IopermPorts::open`] with the
//! [`bus::PortRange`]s the board occupies, nothing wider.
//!
//! ## 3. Give it a simulator, selectable from `loadrt`
//!
//! Model the board as a [`sim::MemModel`] or [`sim::PortModel`] (plus
//! [`sim::BoardModel::advance`]: counters count, watchdogs bite, only as
//! simulated time passes) and drive the outside world through
//! [`plant`] models (motors, steppers, encoders, switches), never a copy
//! of your own. Wrap it in a [`sim::SimBoard`], which is a `RegWindow` or
//! `PortBus`.
//!
//! The backend is a `loadrt` choice parsed one way everywhere:
//! [`params::BackendTokens`] (`sim` always exists; variants start with
//! `sim`). Under `loadrt` give the board a
//! [`sim::SimClock::following_thread`] so it advances by the HAL
//! thread's time, and publish it with [`Exporter::publish_sim`] (our host
//! publishes it once the load succeeded), so tests and tools in the
//! process can [`sim::find`] it and turn its shafts. In unit tests leave the board on its explicit clock and move
//! time with [`sim::SimBoard::advance`]; check what the driver did in its
//! [`sim::AccessLog`].
//!
//! ## 4. Faults and safe state
//!
//! Implement [`fault::SafeState`] (outputs off, DACs to 0 V, enables
//! off, watchdog allowed to bite) and register it with
//! [`Exporter::safe_state`]: the host calls it after a panic in any
//! realtime function, at unload and at exit. When a realtime function
//! finds the hardware gone it trips a [`fault::FaultLatch`] with a static
//! [`fault::Fault`]; the first trip returns true, so the function goes
//! safe once and the latch says why once through the host's message path
//! ([`Exporter::log`], a [`LogSink`]: our host's realtime log, or
//! LinuxCNC's `rtapi_print_msg`; no allocation, lock or system call in
//! the function).
//!
//! ## 5. Parameters and errors
//!
//! Declare the module parameters once, in a table macro named
//! `<module>_params` that hands its list to whatever macro it is given:
//! [`param_table!`] makes [`DriverModule::PARAMS`] from it, and the
//! LinuxCNC adapter LinuxCNC's parameter symbols (§8). Read `loadrt`
//! arguments through [`params::Params`]: defaults, ranges, per-board
//! arrays with count checks, and messages naming module, parameter and
//! item. Addresses: [`params::parse_hex`],
//! [`params::parse_number`]. Turn layer errors into `loadrt` errors with
//! [`ForModule::for_module`]. Open and check everything in
//! [`DriverModule::open`], before [`DriverModule::export`] makes
//! anything, so a failed `loadrt` leaves nothing behind.
//!
//! ## 6. Tests
//!
//! Mock-register tests run the driver on a `SimBoard` and assert on the
//! access log; PCI tests run on a `FakeSysfs`; real-device tests go in
//! one test binary per crate that the VM rig runs (`vmrig`, feature `testing`: its
//! ivshmem BAR and a host-side peer), skipping cleanly outside it.
//!
//! Test files are named `<kind>_<subject>.rs` after what they run on:
//! `sim_hal.rs` (the HAL binding on the simulator), `fake_pci.rs` (a
//! fake sysfs), `fuzz_parsers.rs` (the crate's `fuzzing` bodies),
//! `real_device.rs` (kernel devices, in the VM rig), `vmrig.rs`; a test
//! of one subject without a backend of its own is named after the subject
//! (`idrom.rs`, `master.rs`).
//!
//! ## 7. A real one to read
//!
//! `drivers/parport` (hal_parport) is built this way: its raw backend is
//! an [`bus::IopermPorts`] opened for the port's two register windows,
//! its simulator a [`sim::PortModel`] on a [`sim::SimBoard`] whose
//! writes-only [`sim::AccessLog`] its tests read, its backend tokens a
//! [`params::BackendTokens`], and its outputs go to their inactive levels
//! through [`Exporter::safe_state`]. Its `HalParport` is the
//! [`DriverModule`]; `OpenedPorts` what `open` claimed. (Its ppdev
//! backend keeps a bus trait of its own, `PortIo`: ppdev is an ioctl per
//! register, not a port address.)
//!
//! ## 8. One definition, two hosts
//!
//! [`DriverModule::open`] turns the parsed parameters into opened
//! backends; [`DriverModule::export`] is generic over the host
//! (`H: DriverHost`) and builds through an [`Exporter`]:
//! [`component`](Exporter::component) (most drivers one, named after the
//! module), its [`pins`](Exporter::pins) (a [`hal_core::PinFactory`]),
//! [`funct`](Exporter::funct), [`safe_state`](Exporter::safe_state),
//! [`keep`](Exporter::keep) for what must live as long as the module
//! (helper threads, PCI enable guards), [`log`](Exporter::log) and
//! [`publish_sim`](Exporter::publish_sim). The driver's pin structs hold
//! `H::Pin<T, D>` and `H::Param<T, A>` and the canonical interfaces take
//! the host as a parameter (`DigOut<H>`), so its realtime functions are
//! monomorphised per host. [`module_def`] makes our host's
//! [`hal_core::ModuleDef`]; the shared sequence (open, create, export,
//! safe state, ready, publish; undo on error) lives in [`module`] once
//! per host, and a driver's own load code is only what differs.
//!
//! For LinuxCNC (feature `linuxcnc`), add a crate under
//! `linuxcnc-modules/<module>/`: a `cdylib` whose lib.rs is
//! `hal_driver::linuxcnc_module!(my_crate::MyDriver, my_crate::my_module_params);`
//! and whose build script is `../nodelete.rs`. The macro turns the
//! parameter table into LinuxCNC's `rtapi_info_*` symbols and adds
//! `rtapi_app_main`/`rtapi_app_exit`, which run the same `open` and
//! `export` against LinuxCNC's HAL (`linuxcnc` module docs). Then add
//! the module to `linuxcnc-modules/tests`, which loads it in LinuxCNC's
//! own halrun and compares it with our host.
//!
//! # Worked example
//!
//! A one-channel counter card: an ID register, a count register fed by
//! an encoder on a shaft, and an output-enable register. The driver
//! loads with `backend=sim` (or finds the card on the PCI bus), exports a
//! count pin, and goes safe when the card stops answering. Written once,
//! it loads in our host (below) and, through the LinuxCNC adapter, in
//! LinuxCNC's.
//!
//! ```
//! use std::sync::Arc;
//! use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
//! use hal_core::{HalHost, HostPin, Host, HostConfig, In, Out, PinFactory};
//! use hal_driver::bus::{RegWindow, ALL_ONES};
//! use hal_driver::fault::{Fault, FaultLatch, SafeState};
//! use hal_driver::params::{Backend, BackendTokens, Params};
//! use hal_driver::pci::{self, PciMatch, Sysfs};
//! use hal_driver::plant::QuadEncoder;
//! use hal_driver::sim::{self, BoardModel, MemModel, SimBoard, SimClock};
//! use hal_driver::{DriverHost, DriverModule, Exporter, ForModule, LoadEnv};
//!
//! // regs
//! const ID: usize = 0x0;
//! const COUNT: usize = 0x4;
//! const ENABLE: usize = 0x8;
//! const CARD_ID: u32 = 0xC0DE_0001;
//!
//! // sim: the card's registers over a plant encoder.
//! struct CardModel { encoder: QuadEncoder, enabled: bool }
//! impl BoardModel for CardModel {}
//! impl MemModel for CardModel {
//!     fn len(&self) -> usize { 0x10 }
//!     fn read32(&mut self, offset: usize) -> u32 {
//!         match offset { ID => CARD_ID, COUNT => self.encoder.count() as u32, ENABLE => self.enabled as u32, _ => 0 }
//!     }
//!     fn write32(&mut self, offset: usize, value: u32) {
//!         if offset == ENABLE { self.enabled = value & 1 != 0 }
//!     }
//! }
//!
//! // The driver, on any RegWindow, with its pins in any host H.
//! static CARD_GONE: Fault = Fault::new(1, "card reads all ones, output disabled");
//! struct Card<H: HalHost> {
//!     bus: Arc<dyn RegWindow>,
//!     count: H::Pin<i32, Out>,
//!     enable: H::Pin<bool, In>,
//!     latch: FaultLatch<H>,
//! }
//! impl<H: HalHost> Card<H> {
//!     fn read(&self, now_ns: u64) {
//!         self.bus.tick(now_ns);
//!         if self.bus.read32(ID) == ALL_ONES {
//!             if self.latch.trip(&CARD_GONE) { self.go_safe(); }
//!             return;
//!         }
//!         self.count.set(self.bus.read32(COUNT) as i32);
//!     }
//!     fn write(&self) {
//!         if !self.latch.is_tripped() { self.bus.write32(ENABLE, self.enable.get() as u32) }
//!     }
//! }
//! impl<H: HalHost> SafeState for Card<H> {
//!     fn go_safe(&self) { self.bus.write32(ENABLE, 0) }
//! }
//!
//! // The parameters, written once: both hosts read this table.
//! macro_rules! counter_params {
//!     ($($then:tt)*) => { $($then)*! { backend: Str = "pci|sim" } };
//! }
//!
//! // The HAL binding: open everything, then export it in host H.
//! const NAME: &str = "counter";
//! const BACKENDS: BackendTokens = BackendTokens::new(&["pci"], &[]);
//! const TABLE: &[PciMatch] = &[PciMatch::new(0x1234, 0x5678, "counter card")];
//!
//! struct Counter;
//! struct Opened { bus: Arc<dyn RegWindow>, sim: Option<Arc<SimBoard<CardModel>>> }
//!
//! impl DriverModule for Counter {
//!     const NAME: &'static str = NAME;
//!     const HELP: &'static str = "a counter card";
//!     const PARAMS: &'static [ParamDecl] = counter_params!(hal_driver::param_table);
//!     type Opened = Opened;
//!
//!     fn open(args: &ModuleArgs, _env: &LoadEnv) -> hal_core::Result<Opened> {
//!         let p = Params::new(NAME, args);
//!         let token = p.str_or("backend", "pci");
//!         let backend = BACKENDS.parse(token).ok_or_else(|| {
//!             p.error("backend", format!("'{token}' is not one of {}", BACKENDS.list()))
//!         }).for_module(NAME)?;
//!         Ok(match backend {
//!             Backend::Sim(_) => {
//!                 let model = CardModel { encoder: QuadEncoder::new(2000), enabled: false };
//!                 let board = Arc::new(SimBoard::new(model).with_clock(Arc::new(SimClock::following_thread())));
//!                 Opened { bus: board.clone(), sim: Some(board) }
//!             }
//!             Backend::Real(_) => {
//!                 let dev = pci::find(&Sysfs::system(), TABLE).for_module(NAME)?.remove(0);
//!                 // (a real driver keeps the enable guard: `ex.keep(comp, guard)`)
//!                 Opened { bus: Arc::new(dev.map_bar_window(0, 0x10).for_module(NAME)?), sim: None }
//!             }
//!         })
//!     }
//!
//!     fn export<H: DriverHost>(o: Opened, ex: &mut Exporter<'_, H>) -> hal_core::Result<()> {
//!         let comp = ex.component(NAME)?;
//!         let c = ex.pins(comp);
//!         let card = Arc::new(Card::<H> {
//!             bus: o.bus,
//!             count: c.pin("counter.0.count")?,
//!             enable: c.pin("counter.0.enable")?,
//!             latch: FaultLatch::named("counter.0").with_log(ex.log()).with_pin(c.pin("counter.0.fault")?),
//!         });
//!         let k = card.clone();
//!         ex.funct(comp, "counter.0.read", false, move |ctx| k.read(ctx.now_ns()))?;
//!         let k = card.clone();
//!         ex.funct(comp, "counter.0.write", false, move |_| k.write())?;
//!         ex.safe_state(comp, card);
//!         if let Some(board) = &o.sim {
//!             ex.publish_sim("counter.0", board);
//!         }
//!         Ok(())
//!     }
//! }
//!
//! // Our host's registry entry.
//! static MODULE: ModuleDef = hal_driver::module_def::<Counter>();
//!
//! # fn main() -> hal_core::Result<()> {
//! // Use: load on the simulator, turn the shaft, watch the pin.
//! let host = Host::create(HostConfig::for_tests("counter-doc"))?;
//! assert!(host.loadrt(&MODULE, &["backend=bogus"]).unwrap_err().to_string()
//!     .contains("'bogus' is not one of pci|sim"));
//! host.loadrt(&MODULE, &["backend=sim"])?;
//! let board = sim::find::<SimBoard<CardModel>>(host.instance().name(), "counter.0").unwrap();
//! board.with(|m| m.encoder.set_revs(1.5));
//! host.instance().set_pin("counter.0.enable", hal_core::Value::Bit(true))?;
//! host.create_thread("servo", 1_000_000, false, None)?;
//! host.addf("counter.0.read", "servo", -1)?;
//! host.addf("counter.0.write", "servo", -1)?;
//! host.start()?;
//! let count = || host.instance().pin_value("counter.0.count").unwrap();
//! let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
//! while count() != hal_core::Value::S32(3000) || !board.with(|m| m.enabled) {
//!     assert!(std::time::Instant::now() < end, "count or enable never arrived");
//!     std::thread::sleep(std::time::Duration::from_millis(1));
//! }
//! host.stop();
//! host.unloadrt(NAME)?; // the safe-state hook disables the output
//! assert!(!board.with(|m| m.enabled));
//! # Ok(()) }
//! ```
//!
//! # Modules
//!
//! * [`bus`]: the bus traits and the real backends.
//! * [`pci`]: sysfs discovery, enable, BARs; `pci::fake` for tests (feature `testing`).
//! * [`sim`]: the board-model harness, simulated time, the access log.
//! * [`plant`]: motors, steppers, encoders, switches.
//! * [`params`]: `loadrt` parameter helpers and backend tokens.
//! * [`fault`]: safe state and the fault latch.
//! * [`module`]: [`DriverModule`], the [`Exporter`] and our host's load
//!   sequence.
//! * `linuxcnc` (feature `linuxcnc`): LinuxCNC's `rtapi_app` as the
//!   host, and `linuxcnc_module!` for a driver's `<module>.so`.
//! * `log` (private): [`LogSink`], a host's realtime-safe message path.
//! * `error` (private): the error type, [`DriverError`], at the crate root.
//! * `lockdown` (private): telling kernel lockdown from a missing permission.
//! * `testing` (feature `testing`): helpers for drivers' HAL tests, behind a
//!   feature so test doubles stay out of the normal API.
//! * `vmrig` (feature `testing`): for tests in the VM rig.
//! * `bench` (feature `testing`): per-call timing for benchmark binaries.
//! * `fuzzing` (feature `fuzzing`): fuzz-target bodies for the parsers of
//!   sysfs files and address tokens.
//!
//! # Where this differs from the first sketch
//!
//! * Both bus traits have `describe()` (messages name the device) and
//!   `tick(now_ns)` (the simulator's time source under `loadrt`; a no-op
//!   on hardware), because a simulated board behind the trait must get
//!   the thread's time without the driver knowing it is simulated.
//! * `map_bar_window(n, len)` beside `map_bar(n)`: drivers map the window
//!   they use and get `BarTooSmall` when the BAR is shorter.
//! * `FaultLatch::trip` takes a `&'static Fault` (code and reason
//!   declared together as a static), so a trip is one atomic pointer
//!   store and the pair can never tear.
//! * `SimClock` is one type for simulated time: explicit (tests, with an
//!   optional step per reading so busy-waits end) or following the HAL
//!   thread (`loadrt`).

#[cfg(any(test, feature = "testing"))]
pub mod bench;
pub mod bus;
mod error;
pub mod fault;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
#[cfg(feature = "linuxcnc")]
pub mod linuxcnc;
mod lockdown;
mod log;
pub mod module;
pub mod params;
pub mod pci;
pub mod plant;
pub mod sim;
#[cfg(any(test, feature = "testing"))]
pub mod testing;
#[cfg(any(test, feature = "testing"))]
pub mod vmrig;

pub use bus::{PortBus, RegWindow};
pub use error::{DriverError, ForModule, Result};
pub use fault::{FaultLatch, SafeState};
pub use log::LogSink;
pub use module::{module_def, CompId, DriverHost, DriverModule, Exporter, LoadEnv};
pub use params::Params;

/// What this crate's macros expand to; not for direct use.
#[doc(hidden)]
pub mod __private {
    pub use hal_core::module::{ParamDecl, ParamKind};
}
