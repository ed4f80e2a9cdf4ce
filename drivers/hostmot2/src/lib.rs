//! `hostmot2`: Mesa Anything I/O FPGA cards running HostMot2 firmware,
//! compatible with LinuxCNC's `hostmot2`, `hm2_pci` and `hm2_test`
//! drivers, with a simulator of the firmware.
//!
//! ```text
//! loadrt hostmot2
//! loadrt hm2_pci config="num_encoders=3 num_pwmgens=3 num_stepgens=0"
//! addf hm2_5i25.0.read servo-thread
//! addf hm2_5i25.0.write servo-thread
//! ```
//!
//! # Loading
//!
//! `loadrt hostmot2` first (params `debug_idrom`, `debug_module_descriptors`,
//! `debug_pin_descriptors`, `debug_modules`, and for Smart Serial
//! `use_serial_numbers` and `sserial_baudrate`), then a board driver:
//!
//! * `hm2_pci config="<board 0>,<board 1>,..."`: every Mesa PCI board
//!   LinuxCNC knows (5i20 ... 3x20, 5i24, 5i25, 6i25 and their T
//!   variants; [`pci::BOARDS`]), found through sysfs in bus-address order,
//!   enabled, its FPGA window's BAR mapped (the shared driver layer,
//!   `hal_driver::pci`). Access without root: the udev rules in `udev/`.
//! * `hm2_eth board_ip=... config=...`: Mesa's Ethernet boards (7I76E,
//!   7I96S, 7I92, 7I95, 7I97, ...) over LBP16 on UDP, with LinuxCNC's
//!   `read-request` function and packet-error pins and params
//!   ([`eth`]); the host's ARP table and firewall are never changed (the
//!   setup steps are in [`eth`]).
//! * `hm2_7i43 ioaddr=... config=...`, `hm2_7i90 ...`: the 7I43 and
//!   7I90 on a PC parallel port in EPP mode, with LinuxCNC's `ioaddr`,
//!   `ioaddr_hi`, `epp_wide` and `debug_epp` ([`epp`]); `sim=7i43` or
//!   `sim=7i90` puts a simulated board behind a simulated port.
//! * `hm2_spi spidev_path=... config=...`, `hm2_rpspi spi_probe=...`:
//!   the 7I90 (SPI mode), 7C80 and 7C81 over Linux's spidev with Mesa's
//!   SPI frames ([`spi`]); `sim=7i90`, `sim=7c80`, `sim=7c81` put a
//!   simulated board behind a simulated SPI link.
//! * `hm2_test test_pattern=N`: LinuxCNC's test driver, a board serving
//!   one of the broken register images 0..14 ([`test_patterns`]); each
//!   load fails with LinuxCNC's message.
//!
//! The config string is LinuxCNC's ([`config`]): `num_encoders`,
//! `num_stepgens`, `num_pwmgens`, `num_leds`, `stepgen_width`,
//! `sserial_port_N`, `enable_raw`, and the tokens of modules not
//! supported yet (`ssi_chan_N`, `num_3pwmgens`, ...: accepted and
//! checked, their modules ignored so their pins stay GPIO).
//!
//! # FPGA firmware: `firmware=`
//!
//! The PLX-bridged cards (5i20, 4i65 on a PLX 9030; 5i21, 5i22, 5i23,
//! 4i68, 4i69, 3x20 on a PLX 9054/9056) have no flash: as in LinuxCNC,
//! `config="firmware=hm2/5i20/SVST8_4.BIT ..."` loads the bitfile of that
//! name under `/lib/firmware` (or under `hm2_pci firmware_dir=DIR`) into
//! the FPGA at every load: the Xilinx header is parsed and its part
//! checked against the card's, the bitstream clocked in through the
//! bridge's /PROGRAM, /INIT, DONE and data lines ([`fpga`],
//! [`pci_fpga`]). The 7I43 on EPP is loaded the same way through its
//! CPLD, which also says whether it carries the 200k- or 400k-gate part
//! ([`epp::cpld`], [`epp::load`]). Boards with flash ignore `firmware=`
//! (use mesaflash).
//!
//! # Smart Serial
//!
//! Remote cards on the FPGA's Smart Serial ports (7I76, 7I77, ...) are
//! found at load and their process data become HAL pins and params under
//! LinuxCNC's names (`hm2_7i76e.0.7i76.0.0.input-05`, `output-03`,
//! `spinout`, `analogin0`; [`modules::sserial`]); the 8I20 drive and the
//! 7I64, which do not describe themselves, by LinuxCNC's built-in tables
//! (`hm2_5i20.0.8i20.0.0.current`, `bus-voltage`, `fault.overtemp`); the
//! shared protocol pieces are in [`sserial`].
//!
//! `loadrt hostmot2 sserial_baudrate=115200` puts discovery in setup
//! mode (any Mesa remote is found and named, none gets pins or is
//! started), for `loadrt setsserial cmd="flash <remote> <file>.BIN"`;
//! `setsserial cmd="set <remote>.<parameter> <value>"` writes a remote's
//! EEPROM parameter ([`setsserial`]). Both reach the loaded board
//! through a registry of the boards of each HAL.
//!
//! # The simulator: `hm2_pci sim=...`
//!
//! `loadrt hm2_pci config="..." sim=5i25` (or `sim=6i25`, `sim=5i24`,
//! `sim=5i25-7i77` with a simulated 7I77 on Smart Serial, a PLX card
//! such as `sim=5i20` or `sim=5i22` whose simulated FPGA is loaded
//! through its simulated bridge with the firmware `firmware=` names and
//! then runs it ([`sim::plx_boards`]), a list for
//! several boards) registers simulated boards instead of
//! scanning the PCI bus. The choice of a parameter of `hm2_pci` rather
//! than a module `hm2_sim`: a LinuxCNC configuration then runs without
//! the card by adding one word to its `loadrt hm2_pci` line, and every
//! HAL name (`hm2_5i25.0.*`), the config string, the functions and the
//! registration path are those of the real board: the driver cannot tell
//! the difference, since the simulator is a `RegWindow` like a mapped BAR.
//! The boards' firmwares are in [`sim::boards`]; the machine at their
//! connectors (motors, encoders, steppers, switches from
//! `hal_driver::plant`) in [`sim::machine::preset`]. Simulated time moves
//! one thread period per `read`, so a configuration runs the same way
//! every time whatever the host's load. Tests and tools in the host's
//! process reach a loaded simulated board with
//! `hal_driver::sim::find::<sim::SimHm2>(instance, "hm2_5i25.0")`.
//!
//! # The Ethernet simulator: `hm2-eth-sim`
//!
//! The firmware simulator's Ethernet face ([`sim::eth`],
//! [`sim::eth_server`]) answers LBP16 on a UDP socket; the `hm2-eth-sim`
//! tool runs it as a process of its own with a 7I96S or 7I76E
//! personality (each with a simulated 7I76 on Smart Serial) and options
//! to drop, delay or duplicate packets, so `loadrt hm2_eth
//! board_ip=127.0.0.1` runs a configuration without the card. Simulated
//! time moves one period per cycle's read request.
//!
//! # HAL names
//!
//! LinuxCNC's, as its code exports them (`hm2_<board>.<n>.<module>.<NN>.<pin>`,
//! GPIO `gpio.NNN` with `in`, `in_not`, `out`, `is_output`,
//! `is_opendrain`, `invert_output`, module output aliases such as
//! `stepgen.00.step.invert_output`; functions `read`, `write`,
//! `read_gpio`, `write_gpio`; params `io_error`,
//! `watchdog.timeout_ns`, ...). The modules' details are in
//! `modules`; encoders, step generators, PWM generators and digital
//! I/O use the canonical interfaces' arithmetic and pin sets under these
//! names.
//!
//! Differences from LinuxCNC, each deliberate: a board without an IOPort
//! module (hm2_test pattern 12) is refused after LinuxCNC's messages
//! instead of registering with no pins; a module whose registers reach
//! past the 64 KiB window is refused; a config number that is not a
//! number is refused instead of read as 0; step timing registers hold the
//! time rounded up minus one clock (the firmware adds one), so steps are
//! never shorter than asked nor a clock longer; the safe state (after a
//! fault, at unload, at exit) disables PWM, zeroes step rates, makes the
//! watchdog bite and releases every pin at once.
//!
//! # Crate layout
//!
//! The bus-independent core: [`regs`] (register map), [`llio`] (what a
//! low-level driver says about its board), [`transport`] (the
//! low-level transport trait: read, write, queued reads and writes, so a
//! network transport sends one packet per direction per cycle),
//! [`idrom`], [`md`], [`pins`] and [`firmware`] (reading and checking the
//! firmware's description), `tram` (the per-cycle batched transfers),
//! `modules` and [`board`] (the modules and the cycle functions),
//! `error` and [`log`] (LinuxCNC's words and prefixes).
//! Transports: [`window`] (a `RegWindow`: a PCI BAR or the simulator),
//! [`eth::EthTransport`] (LBP16 over UDP, [`lbp16`]) and
//! [`image::ImageTransport`] (a fixed image: hm2_test). The simulator:
//! [`image`] (firmware descriptions and register images) and [`sim`]. The
//! HAL binding: [`hal`], [`pci`] and [`eth`]. Also [`readhmid`] (the
//! `mesaflash --readhmid` listing the board tool prints), [`board_tool`]
//! with [`ToolError`] (`hal-board` and `hm2-eth-sim`'s errors) and
//! `fuzzing` (feature `fuzzing`).

#![forbid(unsafe_code)]

pub mod board;
pub mod board_args;
pub mod board_tool;
pub mod config;
pub mod epp;
mod error;
pub mod eth;
pub mod eth_sim_args;
pub mod firmware;
pub mod fpga;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod hal;
pub mod idrom;
pub mod image;
pub mod lbp16;
pub mod llio;
pub mod log;
pub mod md;
pub mod mesambccc_args;
pub mod modbus;
mod modules;
pub mod pci;
pub mod pci_fpga;
pub mod pins;
pub mod pktuart;
pub mod readhmid;
mod registry;
pub mod regs;
pub mod setsserial;
mod shared_board;
pub mod sim;
pub mod spi;
pub mod sserial;
pub mod test_patterns;
mod tool_error;
mod tram;
pub mod transport;
pub mod window;

pub use error::{Hm2Error, MbccbProblem, ModbusParamProblem, PinNameProblem, Result};
pub use eth::hal::HM2_ETH_MODULE;
pub use hal::{modules, HM2_PCI_MODULE, HM2_TEST_MODULE, HOSTMOT2_MODULE};
pub use setsserial::SETSSERIAL_MODULE;
pub use tool_error::ToolError;
