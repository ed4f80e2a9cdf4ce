//! One driver definition, two hosts.
//!
//! A driver implements [`DriverModule`] once: its `loadrt` name, help and
//! parameters, how it opens its backend from the parsed parameters, and
//! how it exports its components, pins, parameters, functions and safe
//! state through an [`Exporter`]. The sequence every driver shares
//! (parse the parameters, open, create the components, export, install
//! the safe state, publish the functions, mark ready, publish simulated
//! boards; undo all of it on any error) lives here once per host:
//!
//! * our host: [`module_def`] makes the driver's [`ModuleDef`] for the
//!   module registry, and `loadrt` runs [`load`];
//! * LinuxCNC's `rtapi_app` (feature `linuxcnc`): `linuxcnc_module!`
//!   makes a `<module>.so` whose `rtapi_app_main` runs the same `open`
//!   and `export` against LinuxCNC's HAL.
//!
//! `export` is generic over the host (`H: DriverHost`), so the driver's
//! pin structs and realtime functions are monomorphised per host: a pin
//! access is the same few loads as a hand-written driver's, with no
//! dynamic dispatch and no allocation.
//!
//! Parameters are declared once in a table macro that both hosts read:
//! [`param_table!`] turns it into the `PARAMS` slice, and the LinuxCNC
//! adapter into LinuxCNC's `rtapi_info_*` symbols. See the crate's
//! guide (§8) for a worked example.

mod export;
mod ours;

pub use export::{CompId, DriverHost, Exporter};
pub use ours::{env, load, load_opened, OursSession};

#[cfg(feature = "linuxcnc")]
pub(crate) use export::sealed;
#[doc(hidden)]
pub use export::Session;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};

/// A driver, declared once for every host.
pub trait DriverModule: 'static {
    /// The `loadrt` name (`hal_parport`, `hm2_pci`).
    const NAME: &'static str;
    /// One line for the module's help text.
    const HELP: &'static str;
    /// The module parameters, from the driver's table macro through
    /// [`param_table!`].
    const PARAMS: &'static [ParamDecl];
    /// The backends, opened and checked from the parameters; nothing is
    /// exported yet. Dropping it releases them.
    type Opened;

    /// Opens and checks everything the parameters ask for (ports claimed,
    /// boards found and identified, helper threads started) before
    /// anything is exported, so a failed load leaves nothing behind.
    /// Errors name the module and the parameter or device
    /// ([`crate::ForModule`]).
    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<Self::Opened>;

    /// Exports the components, pins, parameters, functions and safe
    /// state of what `open` opened, in host `H`. An error undoes all of
    /// it (the host removes every component made so far).
    fn export<H: DriverHost>(
        opened: Self::Opened,
        ex: &mut Exporter<'_, H>,
    ) -> hal_core::Result<()>;
}

/// What a driver's [`open`](DriverModule::open) may know of the host it
/// loads into.
#[derive(Debug, Clone)]
pub struct LoadEnv {
    instance: String,
    log: crate::LogSink,
}

impl LoadEnv {
    /// An environment for a load into the HAL named `instance` whose
    /// messages go to `log`.
    pub fn new(instance: impl Into<String>, log: crate::LogSink) -> LoadEnv {
        LoadEnv {
            instance: instance.into(),
            log,
        }
    }

    /// The HAL's name: our host's instance, or `linuxcnc` in LinuxCNC
    /// (one HAL per process there). Registries of what modules share,
    /// such as one helper thread per I2C bus, are keyed by it.
    pub fn instance(&self) -> &str {
        &self.instance
    }

    /// The host's message path, for warnings while opening.
    pub fn log(&self) -> crate::LogSink {
        self.log.clone()
    }
}

/// The driver's entry in our host's module registry:
/// `pub static MODULE: ModuleDef = hal_driver::module_def::<MyDriver>();`
pub const fn module_def<D: DriverModule>() -> ModuleDef {
    ModuleDef {
        name: D::NAME,
        params: D::PARAMS,
        help: D::HELP,
        load: load::<D>,
    }
}

/// Builds a `&'static [ParamDecl]` from a driver's parameter table, the
/// one place its parameters are written:
///
/// ```
/// /// hal_example's module parameters (one table, read by both hosts).
/// #[macro_export]
/// macro_rules! hal_example_params {
///     ($($then:tt)*) => { $($then)*! {
///         cfg: Str = "ports to drive",
///         count: Int = "how many",
///         ids: IntArray(4) = "one id per board",
///     } };
/// }
/// const PARAMS: &[hal_core::ParamDecl] = hal_example_params!(hal_driver::param_table);
/// assert_eq!(PARAMS[2].kind, hal_core::ParamKind::IntArray(4));
/// ```
///
/// Kinds are those of [`hal_core::ParamKind`]: `Int`, `Long`, `Str`,
/// `IntArray(n)`, `LongArray(n)`, `StrArray(n)`.
#[macro_export]
macro_rules! param_table {
    ($($name:ident : $kind:ident $(($n:expr))? = $help:literal),* $(,)?) => {
        &[$($crate::__private::ParamDecl {
            name: ::core::stringify!($name),
            kind: $crate::__private::ParamKind::$kind $(($n))?,
            help: $help,
        }),*]
    };
}
