//! The crate's error type. Each variant's text is LinuxCNC's message for
//! the same failure (hardware.md 5.7, hostmot2-more.md 4), so logs read
//! as users of LinuxCNC know them; multi-line messages are separated by
//! `\n` and every line is printed with the board's prefix
//! (`hm2/hm2_5i25.0: `).

use thiserror::Error;

use crate::transport::TransportError;

/// Everything that can make a board fail to register or a module
/// parameter be refused.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum Hm2Error {
    /// The low-level driver described itself wrongly (a bug in the caller).
    #[error("invalid llio: {reason}")]
    BadLlio {
        /// What is wrong.
        reason: String,
    },
    /// A config string token the driver does not know.
    #[error("invalid token in config string: \"{token}\"")]
    InvalidToken {
        /// The token.
        token: String,
    },
    /// A config string number that is not one.
    #[error("invalid value in config string: \"{token}\": {reason}")]
    BadConfigValue {
        /// The token.
        token: String,
        /// Why.
        reason: String,
    },
    /// `firmware=` could not be loaded into the board's FPGA.
    #[error("firmware=\"{file}\": {source}")]
    FpgaLoad {
        /// The requested file.
        file: String,
        /// Why.
        #[source]
        source: crate::fpga::FpgaError,
    },
    /// A simulated card without flash was given no `firmware=`.
    #[error(
        "no firmware specified in config modparam!  the board had better have firmware \
         configured already, or this won't work: the simulated {board} has no flash; name \
         its firmware in the config string, e.g. firmware=hm2/{board}/SVST8_4.BIT"
    )]
    SimNoFirmware {
        /// The card (`5i20`).
        board: String,
    },
    /// The simulator has no firmware of this name.
    #[error(
        "the simulator does not know the firmware '{design}' (it has Mesa's SV<n> and \
         SVST<n>_<m> servo/stepper firmwares: SVST8_4, SV12, ..., SVST2_4_7I47, and Smithy's \
         Smart Serial SSSVST<s>_<n>_<m>[_V<k>])"
    )]
    SimUnknownFirmware {
        /// The design name (`SVST8_4`).
        design: String,
    },
    /// The firmware's modules do not fit the simulated card's connectors.
    #[error("the firmware '{design}' does not fit a {board}: {why}")]
    SimFirmwareUnfit {
        /// The design name.
        design: String,
        /// The card.
        board: String,
        /// What does not fit.
        why: crate::sim::plx_boards::Unfit,
    },
    /// A simulated PLX card was used before its FPGA was loaded, or its
    /// FPGA raised DONE without running a design.
    #[error("the simulated FPGA {what}")]
    SimFpgaNotRunning {
        /// "was not loaded", "raised DONE but runs no design".
        what: &'static str,
    },
    /// `sserial_port_N=` with N outside 0..3.
    #[error(
        "sserial_port tag must be in the form \"sserial_port_N=0123xx23\" where N may be 0 to 3"
    )]
    BadSserialTag,
    /// The cookie is wrong: no (or no running) HostMot2 firmware.
    #[error(
        "invalid cookie, got 0x{found:08X}, expected 0x55AACAFE\n\
         FPGA failed to initialize, or unexpected firmware?"
    )]
    BadCookie {
        /// The word read at 0x0100.
        found: u32,
    },
    /// The configuration name is not `HOSTMOT2`.
    #[error("invalid config name, got '{found}', expected 'HOSTMOT2'")]
    BadConfigName {
        /// The 8 bytes, non-printables shown as `?`.
        found: String,
    },
    /// The IDROM type is not 2 or 3.
    #[error("invalid IDROM type {}, expected 2 or 3, aborting load", *.found as i32)]
    BadIdromType {
        /// The type word.
        found: u32,
    },
    /// IDROM PortWidth differs from the board's pins per connector.
    #[error(
        "invalid IDROM PortWidth {}, this board has {expected} pins per connector, aborting load",
        *.found as i32
    )]
    BadPortWidth {
        /// PortWidth in the IDROM.
        found: u32,
        /// The board's pins per connector.
        expected: u32,
    },
    /// IOWidth is not IOPorts × PortWidth.
    #[error(
        "IDROM IOWidth is {}, but IDROM IOPorts is {} and IDROM PortWidth is {} \
         (inconsistent firmware), aborting driver load",
        *.io_width as i32, *.io_ports as i32, *.port_width as i32
    )]
    InconsistentIoWidth {
        /// IOWidth.
        io_width: u32,
        /// IOPorts.
        io_ports: u32,
        /// PortWidth.
        port_width: u32,
    },
    /// IOPorts differs from the board's connector count.
    #[error(
        "IDROM IOPorts is {} but llio num_ioport_connectors is {expected}, \
         driver and firmware are inconsistent, aborting driver load",
        *.found as i32
    )]
    BadIoPorts {
        /// IOPorts in the IDROM.
        found: u32,
        /// The board's connectors.
        expected: u32,
    },
    /// More I/O pins than the driver handles.
    #[error("IDROM IOWidth is {} but max is 1000", *.found as i32)]
    TooManyPins {
        /// IOWidth.
        found: u32,
    },
    /// ClockLow below 1 MHz.
    #[error("IDROM ClockLow is {}, that's too low, aborting driver load", *.found as i32)]
    ClockLowTooLow {
        /// ClockLow in Hz.
        found: u32,
    },
    /// ClockHigh below 1 MHz.
    #[error("IDROM ClockHigh is {}, that's too low, aborting driver load", *.found as i32)]
    ClockHighTooLow {
        /// ClockHigh in Hz.
        found: u32,
    },
    /// A pin descriptor list shorter than IOWidth.
    #[error("pin {pin} primary tag is 0 (end-of-list sentinel), expected {expected} pins!")]
    PinListEnds {
        /// The pin whose descriptor is the sentinel.
        pin: u32,
        /// IOWidth.
        expected: u32,
    },
    /// A pin whose primary function is not IOPort.
    #[error("pin {pin} primary tag is {tag} ({name}), not IOPort!")]
    PinNotIoPort {
        /// The pin.
        pin: u32,
        /// Its primary tag.
        tag: u8,
        /// The tag's name.
        name: String,
    },
    /// A pin outside the connectors.
    #[error("pin {pin}: Calculated port number ({port}) is invalid")]
    BadPinPort {
        /// The pin.
        pin: u32,
        /// The computed connector.
        port: u32,
    },
    /// A pin past bit 31 of its port.
    #[error("pin {pin}: Calculated bit number ({bit}) is invalid")]
    BadPinBit {
        /// The pin.
        pin: u32,
        /// The computed bit.
        bit: u32,
    },
    /// A module descriptor's ClockTag is neither 1 nor 2.
    #[error("Module Descriptor {index} (at 0x{addr:04x}) has invalid ClockTag {tag}")]
    BadClockTag {
        /// The descriptor's index.
        index: usize,
        /// Its address.
        addr: u32,
        /// The ClockTag.
        tag: u8,
    },
    /// A register stride selector other than 0 or 1.
    #[error("Module Descriptor {index} (at 0x{addr:04x}) has invalid RegisterStride {selector}")]
    BadRegisterStride {
        /// The descriptor's index.
        index: usize,
        /// Its address.
        addr: u32,
        /// The selector.
        selector: u8,
    },
    /// An instance stride selector other than 0 or 1.
    #[error("Module Descriptor {index} (at 0x{addr:04x}) has invalid InstanceStride {selector}")]
    BadInstanceStride {
        /// The descriptor's index.
        index: usize,
        /// Its address.
        addr: u32,
        /// The selector.
        selector: u8,
    },
    /// A module descriptor whose shape the driver does not know.
    #[error(
        "{headline}\n    Version = {version}, NumRegisters = {num_registers}, \
         InstanceStride = 0x{instance_stride:08X}, MultipleRegisters = 0x{multiple_registers:08X}"
    )]
    InconsistentMd {
        /// LinuxCNC's message for this module.
        headline: String,
        /// The descriptor's version.
        version: u8,
        /// Its NumRegisters.
        num_registers: u8,
        /// Its resolved instance stride.
        instance_stride: u32,
        /// Its MultipleRegisters bitmap.
        multiple_registers: u32,
    },
    /// A module whose registers reach past the register window.
    #[error(
        "Module Descriptor {index} (at 0x{addr:04x}) for {name} puts its registers up to \
         0x{end:X}, past the 64 KiB register window, not loading driver"
    )]
    MdOutsideWindow {
        /// The descriptor's index.
        index: usize,
        /// Its address.
        addr: u32,
        /// The module.
        name: String,
        /// The end of its last register.
        end: u64,
    },
    /// A second descriptor for a module that may appear once.
    #[error(
        "found duplicate Module Descriptor for {name} (inconsistent firmware), not loading driver"
    )]
    DuplicateMd {
        /// The module.
        name: &'static str,
    },
    /// IOPort instances differ from IOPorts.
    #[error(
        "IDROM IOPorts is {idrom} but MD IOPort NumInstances is {md}, \
         inconsistent firmware, aborting driver load"
    )]
    IoPortInstances {
        /// IOPorts in the IDROM.
        idrom: u32,
        /// NumInstances of the IOPort descriptor.
        md: u8,
    },
    /// No IOPort module: no pin could be driven.
    #[error(
        "the firmware has no IOPort Module Descriptor, so none of its {pins} pins can be \
         used, not loading driver"
    )]
    NoIoPort {
        /// IOWidth.
        pins: u32,
    },
    /// A `num_<module>s=N` asking for more instances than the firmware has.
    #[error("config.{key}={requested}, but only {available} are available, not loading driver")]
    TooManyRequested {
        /// The config key.
        key: &'static str,
        /// N.
        requested: i32,
        /// Instances in the firmware.
        available: u32,
    },
    /// A register transfer failed while registering.
    #[error("{op}: {source}")]
    Transport {
        /// What was being done, in LinuxCNC's words ("error reading hm2 cookie").
        op: String,
        /// What went wrong.
        source: TransportError,
    },
    /// Smart Serial discovery failed or a remote card is unusable.
    #[error("Smart Serial port {port}{}: {reason}", channel.map(|c| format!(" channel {c}")).unwrap_or_default())]
    Sserial {
        /// The port.
        port: u8,
        /// The channel, when it is about one.
        channel: Option<u8>,
        /// What is wrong.
        reason: String,
    },
    /// A card's process data has split encoder counters.
    #[error("record {record}: split encoder counters are not supported")]
    SplitEncoder {
        /// The record's name.
        record: String,
    },
    /// A card lists a non-volatile record among its process data.
    #[error("Non-Volatile data type found in PTOC (record {record}), the card's firmware is inconsistent")]
    NonVolatileInPtoc {
        /// The record's name.
        record: String,
    },
    /// A process record has a data type this driver does not know.
    #[error("record {record}: unknown data type 0x{data_type:02X}")]
    UnknownDataType {
        /// The record's name.
        record: String,
        /// Its data type.
        data_type: u8,
    },
    /// A process record's width does not suit its type.
    #[error("record {record}: {bits} bits is not a width its type can have")]
    BadRecordWidth {
        /// The record's name.
        record: String,
        /// Its width.
        bits: u8,
    },
    /// A card's process data do not fit the module's registers.
    #[error("Data width, {inputs} in / {outputs} out bits, exceeds the supported number of smart-serial 32-bit registers ({registers})")]
    ProcessTooWide {
        /// Input bits.
        inputs: usize,
        /// Output bits.
        outputs: usize,
        /// The registers there are.
        registers: usize,
    },
    /// A `board_ip` item is not an address.
    #[error("not an IP address (a.b.c.d, optionally :port)")]
    NotAnAddress,
    /// A `board_ip` item names the board an earlier item named: loading
    /// it twice would give two HAL boards driving one card's outputs.
    #[error("the same board as item {first} ({peer}): list each board once")]
    SameBoardTwice {
        /// The earlier item's index.
        first: usize,
        /// The address both items name.
        peer: std::net::SocketAddr,
    },
    /// The first reads and writes after configuration failed.
    #[error("comm errors while initializing firmware!")]
    CommErrors,
    /// A board failed to register: LinuxCNC's line naming the board, and
    /// why (its lines joined by "; ").
    #[error("{fails}: {}", source.to_string().replace('\n', "; "))]
    Registration {
        /// "hm2_pci: board at 0000:01:00.0 fails HM2 registration".
        fails: String,
        /// Why.
        source: Box<Hm2Error>,
    },
    /// A board driver was loaded before the hostmot2 core.
    #[error("the hostmot2 driver is not loaded (loadrt hostmot2 first)")]
    CoreNotLoaded,
    /// No card on the PCI bus: what was looked for, where, and how to try
    /// the driver without one.
    #[error(
        "no {wanted} found on the PCI bus (searched {}); to try the driver without \
         a card, load a simulated one with sim=BOARD ({})",
        searched.display(),
        crate::sim::boards::pci_sim_names()
    )]
    NoPciCard {
        /// The boards looked for, by name and IDs.
        wanted: String,
        /// The sysfs directory listed.
        searched: std::path::PathBuf,
    },
    /// More boards than one load drives.
    #[error("{found} boards found; one hm2_pci load drives at most {max}")]
    TooManyBoards {
        /// Boards found.
        found: usize,
        /// The most one load drives.
        max: usize,
    },
    /// `hm2_test` was given a pattern it does not have.
    #[error("unknown test pattern {0}")]
    UnknownTestPattern(i64),
    /// An Ethernet board did not answer as one.
    #[error("board at {address} ({peer}): {source}")]
    EthBoard {
        /// The address as given in `board_ip`.
        address: String,
        /// The socket address it resolved to.
        peer: std::net::SocketAddr,
        /// What went wrong.
        source: TransportError,
    },
    /// A parallel port cannot be reached.
    #[error("parallel port at {base:#x}: {reason}")]
    EppPort {
        /// The port's base address.
        base: u16,
        /// Why.
        reason: String,
    },
    /// The board on a parallel port did not answer as one.
    #[error("board on the parallel port at {base:#x}: {source}")]
    EppBoard {
        /// The port's base address.
        base: u16,
        /// What went wrong.
        source: TransportError,
    },
    /// An SPI device cannot be opened or set up.
    #[error("SPI device {device}: {reason}")]
    SpiDevice {
        /// The device (`/dev/spidev0.0`).
        device: String,
        /// Why.
        reason: String,
    },
    /// The board on an SPI device did not answer as one.
    #[error("board on SPI device {device}: {source}")]
    SpiBoard {
        /// The device.
        device: String,
        /// What went wrong.
        source: TransportError,
    },
    /// What answers on an SPI device is no HostMot2 board.
    #[error("SPI device {device}: no HostMot2 board answers (cookie 0x{cookie:08X}, configuration name {name:?}; a board answers 0x55AACAFE, \"HOSTMOT2\")")]
    SpiNotHostmot2 {
        /// The device.
        device: String,
        /// What was read at 0x100.
        cookie: u32,
        /// What was read at 0x104.
        name: String,
    },
    /// A HostMot2 board of a kind the SPI drivers do not know.
    #[error(
        "SPI device {device}: unknown HostMot2 board name {name:?} (known: 7I90, 7C80, 7C81, 7I43)"
    )]
    SpiUnknownBoard {
        /// The device.
        device: String,
        /// The IDROM's board name.
        name: String,
    },
    /// `setsserial cmd=` is not a command it knows.
    #[error("setsserial: cmd=\"{cmd}\": {reason} (use \"set <remote>.<parameter> <value>\" or \"flash <remote> <file>.BIN\")")]
    SetsserialCommand {
        /// The string given.
        cmd: String,
        /// What is wrong with it.
        reason: String,
    },
    /// No loaded board has a Smart Serial remote of this name.
    #[error("setsserial: no Smart Serial remote {name} on the hostmot2 boards loaded in this HAL (remotes: {known})")]
    NoSuchRemote {
        /// The name asked for.
        name: String,
        /// The remotes there are.
        known: String,
    },
    /// The remote has no global of this name.
    #[error("setsserial: the remote {remote} has no parameter {global} (it has: {known})")]
    NoSuchGlobal {
        /// The remote.
        remote: String,
        /// The parameter asked for.
        global: String,
        /// Its globals.
        known: String,
    },
    /// The value cannot be written to the global.
    #[error("setsserial: {remote}.{global}: value \"{value}\" refused: {reason}")]
    BadGlobalValue {
        /// The remote.
        remote: String,
        /// The global.
        global: String,
        /// The value given.
        value: String,
        /// Why.
        reason: crate::setsserial::ValueProblem,
    },
    /// Only Mesa's .BIN remote firmware files are flashed.
    #[error(
        "setsserial: {file}: not a .BIN file (only remote firmware .BIN files can be flashed)"
    )]
    NotBinFile {
        /// The file named.
        file: String,
    },
    /// Flashing a remote needs the ports in setup mode.
    #[error("setsserial: flashing needs the Smart Serial ports in setup mode: load hostmot2 with sserial_baudrate=115200 (it was {})", baud.map_or("not given".to_string(), |b| b.to_string()))]
    FlashNeedsSetupMode {
        /// hostmot2's `sserial_baudrate`.
        baud: Option<u32>,
    },
    /// The FPGA's Smart Serial firmware cannot flash this remote.
    #[error("setsserial: flashing {remote} needs Smart Serial firmware version {needed} or later; port {port} runs version {version} (update the FPGA firmware first)")]
    SslbpTooOld {
        /// The remote.
        remote: String,
        /// Its port.
        port: u8,
        /// The SSLBP version the port reports.
        version: u8,
        /// The version needed.
        needed: u8,
    },
    /// The remote firmware file cannot be used.
    #[error("setsserial: firmware file {}: {reason}", path.display())]
    RemoteFirmwareFile {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        reason: String,
    },
    /// A step of a setsserial command failed.
    #[error("setsserial: {remote}: {step}: {source}")]
    SetsserialStep {
        /// The remote.
        remote: String,
        /// The step (`NV access on`, `erase block 3`, ...).
        step: String,
        /// What went wrong.
        #[source]
        source: Box<Hm2Error>,
    },
    /// The remote's cookie after a flash command is not the expected one.
    #[error("sync failed: the remote's cookie reads 0x{cookie:02X}, not 0x5A")]
    FlashSyncFailed {
        /// What was read.
        cookie: u8,
    },
    /// A firmware with only one half of its PktUARTs, or halves of
    /// different sizes.
    #[error(
        "inconsistent PktUART firmware: {tx} transmitter and {rx} receiver instances \
         (they must pair up), not loading driver"
    )]
    PktUartHalves {
        /// Transmitter instances.
        tx: u8,
        /// Receiver instances.
        rx: u8,
    },
    /// An `.mbccb` file (hm2_modbus) is refused: what is wrong, at which
    /// byte offset of the file.
    #[error("mbccb file, byte offset {offset}: {what}")]
    Mbccb {
        /// Byte offset in the file of the field at fault.
        offset: usize,
        /// What is wrong with it.
        what: MbccbProblem,
    },
    /// An `.mbccb` file could not be read.
    #[error("cannot read mbccb file '{path}': {reason}")]
    MbccbRead {
        /// The file.
        path: String,
        /// Why (the system's message).
        reason: String,
    },
    /// `loadrt hm2_modbus` parameters that do not fit together.
    #[error("hm2_modbus: {0}")]
    ModbusParams(ModbusParamProblem),
    /// A PktUART named in `ports=` that no loaded board has.
    #[error("hm2_modbus: port '{port}' does not exist (no loaded board has that PktUART)")]
    NoSuchPktUart {
        /// The name asked for.
        port: String,
    },
    /// A PktUART another `hm2_modbus` instance already runs.
    #[error("hm2_modbus: port '{port}' is already in use by another hm2_modbus instance")]
    PktUartInUse {
        /// The PktUART's name.
        port: String,
    },
    /// An `.mbccs` source (mesambccc) is refused: where and why.
    #[error("line {line}, column {column}: {what}")]
    Mbccs {
        /// 1-based line.
        line: u32,
        /// 1-based column.
        column: u32,
        /// What is wrong.
        what: String,
    },
    /// HAL refused an object (a name clash, a full segment).
    #[error("{0}")]
    Hal(String),
}

/// What is wrong in an `.mbccb` file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MbccbProblem {
    /// The file ends before a structure it announces.
    #[error("file ends after {len} bytes, {need} needed")]
    Truncated {
        /// Bytes needed.
        need: usize,
        /// Bytes in the file.
        len: usize,
    },
    /// The file is larger than its header says, or than the 128 KiB limit.
    #[error("file is {len} bytes, expected {expected}")]
    SizeMismatch {
        /// Bytes in the file.
        len: usize,
        /// Bytes expected.
        expected: usize,
    },
    /// Not an mbccb file.
    #[error(
        "signature is {found:?}, expected \"MesaMB01\" (compile the .mbccs source with mesambccc)"
    )]
    Signature {
        /// The eight bytes found (non-printable shown as '?').
        found: String,
    },
    /// A numeric field out of range.
    #[error("{field} is {value}, {expected}")]
    Field {
        /// The field (`rxdelay`, `command 3 function`).
        field: String,
        /// Its value.
        value: u64,
        /// What it should be.
        expected: &'static str,
    },
    /// A pin name that HAL cannot take.
    #[error("pin {pin} of command {command}: {why}")]
    PinName {
        /// Command index.
        command: usize,
        /// Pin index in the command.
        pin: usize,
        /// Why.
        why: PinNameProblem,
    },
}

/// What is wrong with a pin name in an `.mbccb` file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PinNameProblem {
    /// No characters before the NUL.
    #[error("name is empty")]
    Empty,
    /// Longer than a name may be.
    #[error("name is too long ({len} > {max} bytes)")]
    TooLong {
        /// Its length with the NUL.
        len: usize,
        /// The most allowed.
        max: usize,
    },
    /// The last byte is not NUL.
    #[error("name is not NUL terminated")]
    Unterminated,
    /// A byte outside a-z 0-9 . -.
    #[error("invalid character 0x{0:02x} in name (allowed: a-z 0-9 . -)")]
    BadByte(u8),
}

/// What is wrong with `loadrt hm2_modbus` parameters.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ModbusParamProblem {
    /// No `ports=`.
    #[error(
        "the component requires at least one valid pktuart port, eg ports=\"hm2_5i25.0.pktuart.7\""
    )]
    NoPorts,
    /// A port without its file.
    #[error("missing mbccb file path for instance {0} in 'mbccbs' argument")]
    MissingFile(usize),
    /// More than eight ports.
    #[error("{0} ports given, at most 8 are supported")]
    TooMany(usize),
}

impl From<hal_core::HalError> for Hm2Error {
    fn from(e: hal_core::HalError) -> Hm2Error {
        Hm2Error::Hal(e.to_string())
    }
}

/// The crate's result type.
pub type Result<T, E = Hm2Error> = std::result::Result<T, E>;
