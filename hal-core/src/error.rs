//! The error type of the HAL core.

use std::io;
use std::path::PathBuf;

use crate::types::HalType;

/// Everything that can go wrong in the HAL core. Every variant leaves the
/// instance unchanged: an operation either completes or is rolled back.
#[derive(Debug, thiserror::Error)]
pub enum HalError {
    /// A command-line option that names the instance came without a name.
    #[error("{option} needs an instance name")]
    InstanceNameMissing {
        /// The option as given (`--instance`, `-i`).
        option: String,
    },
    /// A name has a character LinuxCNC does not allow, or is empty.
    #[error("bad {kind} name '{name}': {reason}")]
    BadName {
        /// What the name is for: "pin", "signal", "thread", ...
        kind: &'static str,
        /// The name as given.
        name: String,
        /// Which rule it breaks.
        reason: &'static str,
    },
    /// A name is longer than the segment stores.
    #[error("{kind} name '{name}' is {len} bytes long, at most {max} are allowed")]
    NameTooLong {
        /// What the name is for.
        kind: &'static str,
        /// The name as given.
        name: String,
        /// Its length in bytes.
        len: usize,
        /// The longest name allowed, in bytes.
        max: usize,
    },
    /// An object of that kind and name already exists.
    #[error("duplicate {kind} '{name}'")]
    Duplicate {
        /// The kind of object.
        kind: &'static str,
        /// The name already taken.
        name: String,
    },
    /// No object of that kind has that name.
    #[error("{kind} '{name}' not found")]
    NotFound {
        /// The kind of object looked for.
        kind: &'static str,
        /// The name looked for.
        name: String,
    },
    /// An object exists but has another HAL type than the caller asked for.
    #[error("{kind} '{name}' is {actual}, not {expected}")]
    WrongType {
        /// The kind of object.
        kind: &'static str,
        /// Its name.
        name: String,
        /// The type the caller asked for.
        expected: HalType,
        /// The type it has.
        actual: HalType,
    },
    /// `net`/`linkps` joins a pin to a signal of another type.
    #[error("type mismatch: pin '{pin}' is {pin_type}, signal '{signal}' is {signal_type}")]
    TypeMismatch {
        /// The pin being linked.
        pin: String,
        /// Its type.
        pin_type: HalType,
        /// The signal it was to join.
        signal: String,
        /// The signal's type.
        signal_type: HalType,
    },
    /// A second output pin would drive a signal: a signal has one writer.
    #[error("signal '{signal}' already has output pin '{writer}', cannot add output pin '{pin}'")]
    SignalHasWriter {
        /// The signal.
        signal: String,
        /// The output pin already driving it.
        writer: String,
        /// The output pin refused.
        pin: String,
    },
    /// An output pin would join a signal that I/O pins already share.
    #[error("signal '{signal}' already has I/O pin(s), cannot add output pin '{pin}'")]
    SignalHasIoPins {
        /// The signal.
        signal: String,
        /// The output pin refused.
        pin: String,
    },
    /// An I/O pin would join a signal that an output pin drives.
    #[error("signal '{signal}' already has an output pin, cannot add I/O pin '{pin}'")]
    SignalHasOutputForIo {
        /// The signal.
        signal: String,
        /// The I/O pin refused.
        pin: String,
    },
    /// A second input pin, or an I/O pin, would join a port signal: a
    /// port carries bytes from one writer to one reader.
    #[error("port signal '{signal}' takes one output and one input pin, cannot add pin '{pin}'")]
    PortSignalFull {
        /// The signal.
        signal: String,
        /// The pin refused.
        pin: String,
    },
    /// `sets` on a port signal whose buffer is made already.
    #[error("port is already allocated with {size} bytes.")]
    PortAllocated {
        /// The signal.
        signal: String,
        /// The size of its buffer.
        size: u32,
    },
    /// `sets` on a port signal with a size out of range.
    #[error("port size {size} is too large (at most {max} bytes)")]
    BadPortSize {
        /// The size asked for.
        size: u32,
        /// The largest allowed.
        max: u32,
    },
    /// A parameter, or a pin made as a plain value, of type `port`: a
    /// port is only ever a pin made with `port_in`/`port_out`.
    #[error("'{name}' cannot be a port: only port pins (port_in, port_out) carry one")]
    NotAPortMaker {
        /// The pin or parameter.
        name: String,
    },
    /// `setp` on a port pin: a port's buffer belongs to its signal.
    #[error("pin '{pin}' is a port: size its signal with sets instead")]
    PortPinSet {
        /// The pin.
        pin: String,
    },
    /// The pin is linked to a signal already; `unlinkp` it first.
    #[error("pin '{pin}' is already linked to signal '{signal}'")]
    PinAlreadyLinked {
        /// The pin.
        pin: String,
        /// The signal it is linked to.
        signal: String,
    },
    /// `setp` on a pin that a signal feeds: set the signal instead.
    #[error("pin '{pin}' is connected to signal '{signal}' and cannot be set directly")]
    PinConnected {
        /// The pin.
        pin: String,
        /// The signal feeding it.
        signal: String,
    },
    /// `sets` on a signal that an output pin drives.
    #[error("signal '{signal}' has writer '{writer}' and cannot be set directly")]
    SignalDriven {
        /// The signal.
        signal: String,
        /// The output pin driving it.
        writer: String,
    },
    /// `setp` on a read-only parameter.
    #[error("param '{name}' is read-only")]
    ParamReadOnly {
        /// The parameter.
        name: String,
    },
    /// `setp` on an output pin, which only its component writes.
    #[error("pin '{name}' is an output pin and cannot be set directly")]
    PinIsOutput {
        /// The pin.
        name: String,
    },
    /// No live host for the instance: nothing to attach to.
    #[error("realtime not running for instance '{instance}'")]
    NotRunning {
        /// The instance name.
        instance: String,
    },
    /// Another host holds the instance lock.
    #[error("a HAL host is already running for instance '{instance}'")]
    AlreadyRunning {
        /// The instance name.
        instance: String,
    },
    /// The runtime directory is unsafe or unusable: someone other than
    /// its owner and the hal group could write into it, or it belongs to
    /// neither root nor this user.
    #[error("refusing the runtime directory {path}: {reason}")]
    RuntimeDir {
        /// The directory.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// No private runtime directory could be chosen for this user.
    #[error("no private runtime directory for uid {uid}: XDG_RUNTIME_DIR is not set and /run/user/{uid} does not exist; set HAL_RUNTIME_DIR to a directory only you may write (mkdir -m 700 DIR)")]
    NoRuntimeDir {
        /// The user.
        uid: u32,
    },
    /// The system refused access to an instance's file: says who may use
    /// the instance and how to become one of them.
    #[error("{op} {path}: permission denied: {advice}")]
    PermissionDenied {
        /// What was being done.
        op: &'static str,
        /// The file refused.
        path: PathBuf,
        /// Whose it is and how to be let in.
        advice: String,
    },
    /// A runtime file's name holds what no host makes there (a symbolic
    /// link, a FIFO, a directory): refused, never opened through.
    #[error("{op} {path}: refused: {reason}")]
    PlantedFile {
        /// What was being done ("opening host lock file", ...).
        op: &'static str,
        /// The file refused.
        path: PathBuf,
        /// What it is and why that is refused.
        reason: &'static str,
    },
    /// An operating-system operation failed: on the segment, the lock
    /// file or the socket, or starting a thread (then `path` is empty).
    #[error("{op} {path}: {source}")]
    Io {
        /// What was being done ("mapping shared memory segment", ...).
        op: &'static str,
        /// The file it was done to, if any.
        path: PathBuf,
        /// The error the system reported.
        #[source]
        source: io::Error,
    },
    /// A system call without a file name failed.
    #[error("{op}: {source}")]
    Os {
        /// The call or its purpose.
        op: &'static str,
        /// The error the system reported.
        #[source]
        source: nix::Error,
    },
    /// The segment fails its header checks (magic, layout version, size) or its lock.
    #[error("segment of instance '{instance}' is not usable: {reason}")]
    BadSegment {
        /// The instance the segment belongs to.
        instance: String,
        /// Which check failed.
        reason: String,
    },
    /// An offset read from the segment points outside it or is misaligned: the segment is corrupt or hostile.
    #[error("offset {offset:#x} read from the segment is outside it or misaligned (segment size {size:#x})")]
    BadOffset {
        /// The offset read.
        offset: u64,
        /// The size of the segment.
        size: u64,
    },
    /// The segment has no room left for an allocation.
    #[error("HAL shared memory is full: {requested} bytes wanted, {available} left (raise the segment size)")]
    OutOfMemory {
        /// Bytes asked for.
        requested: u64,
        /// Bytes still free.
        available: u64,
    },
    /// One structural change needs more undo entries than the journal holds.
    #[error("the change is too large for one transaction ({limit} journal entries)")]
    JournalFull {
        /// Entries the journal holds.
        limit: usize,
    },
    /// A thread was asked for with period 0.
    #[error("thread '{name}': period must be greater than zero")]
    ZeroPeriod {
        /// The thread.
        name: String,
    },
    /// A thread period is shorter than the base period every period is a multiple of.
    #[error("thread '{name}': period {period} ns is shorter than the base period {base} ns")]
    PeriodBelowBase {
        /// The thread.
        name: String,
        /// Its period in ns.
        period: i64,
        /// The base period in ns.
        base: i64,
    },
    /// Threads must be created fastest first; this one is faster than an earlier one.
    #[error("thread '{name}': period {period} ns is shorter than the period {previous} ns of thread '{previous_name}'; create threads fastest first")]
    ThreadOrder {
        /// The thread.
        name: String,
        /// Its period in ns.
        period: i64,
        /// The period of the earlier thread, in ns.
        previous: i64,
        /// The earlier thread.
        previous_name: String,
    },
    /// `addf` of a non-reentrant function that some thread already runs.
    #[error("function '{funct}' is not reentrant and is already in thread '{thread}'")]
    FunctInUse {
        /// The function.
        funct: String,
        /// The thread running it.
        thread: String,
    },
    /// `delf` of a function the thread does not run.
    #[error("function '{funct}' is not in thread '{thread}'")]
    FunctNotInThread {
        /// The function.
        funct: String,
        /// The thread.
        thread: String,
    },
    /// A function cannot be removed while a thread still runs it.
    #[error("function '{funct}' is in thread '{thread}'; remove it with delf first")]
    FunctStillInThread {
        /// The function.
        funct: String,
        /// The thread running it.
        thread: String,
    },
    /// `addf` at a position past the end of the thread's function list.
    #[error("position {position} is out of range for thread '{thread}' with {len} functions")]
    BadPosition {
        /// The thread.
        thread: String,
        /// The position asked for.
        position: i32,
        /// Functions the thread has now.
        len: usize,
    },
    /// A component is used before its `ready` call.
    #[error("component '{comp}' is not ready")]
    NotReady {
        /// The component.
        comp: String,
    },
    /// A component is changed by a process that did not create it.
    #[error("component '{comp}' belongs to process {owner}, not to this one")]
    NotOwner {
        /// The component.
        comp: String,
        /// PID of the process that owns it.
        owner: i32,
    },
    /// The instance ran out of ids for a kind of object.
    #[error("too many {kind}s: the limit is {limit}")]
    TooMany {
        /// The kind of object.
        kind: &'static str,
        /// How many ids there are.
        limit: usize,
    },
    /// A value does not parse or is out of range for where it goes.
    #[error("bad value for {what}: {reason}")]
    BadValue {
        /// Where the value was going (pin, param, argument).
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A setting is refused for a reason the core found itself (a CPU
    /// the process may not use, a failed affinity call).
    #[error("bad value for {what}: {source}")]
    BadSetting {
        /// Where the value was going.
        what: String,
        /// Why it is refused.
        #[source]
        source: Box<HalError>,
    },
    /// A number in C's notation (`strtol(s, 0)`) does not parse.
    #[error("'{text}' is not a number")]
    NotANumber {
        /// The text as given.
        text: String,
    },
    /// A number parses but does not fit the integer it goes into.
    #[error("'{text}' is out of range")]
    NumberOutOfRange {
        /// The text as given.
        text: String,
    },
    /// A CPU given as text is not a number.
    #[error("{what}='{text}' is not a CPU number")]
    NotACpu {
        /// Where it was given (`RTAPI_CPU_NUMBER`, `cpu`).
        what: String,
        /// The text as given.
        text: String,
    },
    /// A CPU the process may not use.
    #[error("{what}={cpu}: this process may only use CPU {allowed}")]
    CpuNotAllowed {
        /// Where it was given.
        what: String,
        /// The CPU.
        cpu: usize,
        /// The CPUs the process may use, as `0-3,6`.
        allowed: String,
    },
    /// Setting or reading a thread's CPU affinity failed.
    #[error("{action}: {source}")]
    Affinity {
        /// What failed ("moving the thread to CPU 3 failed").
        action: String,
        /// The system's answer.
        #[source]
        source: nix::Error,
    },
    /// SCHED_FIFO was refused; `hint` says which permission is missing
    /// and how to grant it.
    #[error("SCHED_FIFO priority {priority} refused ({source}){hint}")]
    FifoRefused {
        /// The priority asked for.
        priority: i32,
        /// The system's answer.
        #[source]
        source: std::io::Error,
        /// What is missing and how to grant it (empty if unknown).
        hint: String,
    },
    /// The thread that probes for SCHED_FIFO panicked.
    #[error("probe thread panicked")]
    FifoProbePanicked,
    /// `mlockall` was refused.
    #[error("locking memory failed ({source}); the memlock limit is {limit} bytes. Grant it with a line '@hal - memlock unlimited' in /etc/security/limits.d/hal.conf (then log in again), or give the host CAP_IPC_LOCK")]
    MemoryLock {
        /// The system's answer.
        #[source]
        source: std::io::Error,
        /// The memlock limit (`unlimited`, `unknown` or bytes).
        limit: String,
    },
    /// A `loadrt` parameter is unknown, malformed or out of range.
    #[error("{module}: parameter '{param}': {reason}")]
    ModuleParam {
        /// The module being loaded.
        module: String,
        /// The parameter.
        param: String,
        /// What is wrong with it.
        reason: String,
    },
    /// `loadrt` of a name the registry does not have.
    #[error("module '{name}' not found")]
    UnknownModule {
        /// The name asked for.
        name: String,
    },
    /// `loadrt` of a module that is loaded already.
    #[error("module '{name}' is already loaded")]
    ModuleLoaded {
        /// The module.
        name: String,
    },
    /// A module's load failed (bad combination of parameters, failed probe); nothing of it stays loaded.
    #[error("{module}: {reason}")]
    ModuleLoad {
        /// The module.
        module: String,
        /// Why it failed.
        reason: String,
    },
    /// A module's load failed in its own code (a driver that found no
    /// board, a refused device, a bad register value): the module's error
    /// travels as the source, so its type and its own causes survive.
    /// Nothing of the module stays loaded.
    #[error("{module}: {source}")]
    ModuleFailed {
        /// The module.
        module: String,
        /// The module's own error.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    /// Loading, threads and functions run only in the host process; this process is a client.
    #[error("this operation needs the HAL host process")]
    NotHost,
    /// A realtime function panicked; the threads stay stopped until the instance is recovered.
    #[error("threads of instance '{instance}' are halted after a fault in function '{funct}'; unload and reload to recover")]
    Faulted {
        /// The instance.
        instance: String,
        /// The function that faulted.
        funct: String,
    },
    /// A structural change refused by `halcmd lock` (the operation).
    #[error("{op} called while HAL locked")]
    Locked {
        /// The operation refused (LinuxCNC's function name, e.g. `hal_link`).
        op: &'static str,
    },
}

impl HalError {
    /// A failed load of `module` caused by `source`, the module's own
    /// error ([`HalError::ModuleFailed`]).
    pub fn module_failed(
        module: impl Into<String>,
        source: impl std::error::Error + Send + Sync + 'static,
    ) -> Self {
        HalError::ModuleFailed {
            module: module.into(),
            source: Box::new(source),
        }
    }

    pub(crate) fn io(op: &'static str, path: impl Into<PathBuf>, source: io::Error) -> Self {
        HalError::Io {
            op,
            path: path.into(),
            source,
        }
    }
}

/// Result type of the HAL core.
pub type Result<T, E = HalError> = std::result::Result<T, E>;
