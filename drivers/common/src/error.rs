//! The layer's error type: everything that can go wrong while a driver
//! finds, opens and sets up its hardware. Realtime accesses never fail
//! visibly (see [`crate::bus`]); these errors happen at `loadrt`.

use std::io;
use std::path::PathBuf;

use hal_core::HalError;

/// What went wrong finding or opening a device, or in a module parameter.
#[derive(Debug, thiserror::Error)]
pub enum DriverError {
    /// No PCI device matched the driver's ID table.
    #[error("no {wanted} found on the PCI bus (searched {searched})")]
    PciNotFound {
        /// The boards looked for, by name and IDs.
        wanted: String,
        /// Where: the sysfs directory listed.
        searched: PathBuf,
    },
    /// A file the driver needs is not accessible to this user.
    #[error("permission denied: {path}: {hint}")]
    Permission {
        /// The file.
        path: PathBuf,
        /// How to grant access.
        hint: String,
    },
    /// The kernel refused the access because it is locked down (Secure
    /// Boot): no file permission or capability helps.
    #[error("{what} refused: the kernel is in lockdown mode (usually enabled by Secure Boot), which forbids raw hardware access from user space for everyone, root included")]
    Lockdown {
        /// The refused access, e.g. "mmap of /sys/.../resource0".
        what: String,
    },
    /// Raw port I/O is not permitted or not possible.
    #[error("{what}: {source} ({hint})")]
    PortIo {
        /// The refused access, e.g. "ioperm for ports 0x378..0x37f".
        what: String,
        /// The system's answer.
        #[source]
        source: io::Error,
        /// What to do about it.
        hint: &'static str,
    },
    /// The access method does not exist on this machine or build.
    #[error("{what}: {reason}")]
    Unsupported {
        /// What was asked for.
        what: String,
        /// Why it cannot work here.
        reason: String,
    },
    /// The device has no such BAR (it is unused or out of range).
    #[error("PCI device {device}: BAR {bar} is not present")]
    BarMissing {
        /// The device's bus address.
        device: String,
        /// The BAR index.
        bar: usize,
    },
    /// The BAR is smaller than the driver needs.
    #[error(
        "PCI device {device}: BAR {bar} is {size:#x} bytes, the driver needs at least {needed:#x}"
    )]
    BarTooSmall {
        /// The device's bus address.
        device: String,
        /// The BAR index.
        bar: usize,
        /// Its size (or the size of its resource file, if smaller).
        size: u64,
        /// What the driver needs.
        needed: u64,
    },
    /// The BAR is of the other kind (I/O where memory was expected, or
    /// the reverse).
    #[error("PCI device {device}: BAR {bar} is {found}, the driver needs {expected}")]
    BarKind {
        /// The device's bus address.
        device: String,
        /// The BAR index.
        bar: usize,
        /// What it is ("an I/O BAR", "a memory BAR").
        found: &'static str,
        /// What was expected.
        expected: &'static str,
    },
    /// A sysfs file holds something that is not what the kernel writes.
    #[error("{path}: {reason}")]
    BadSysfs {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A system call on a file failed.
    #[error("{op} {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done ("opening", "reading", "mapping", ...).
        op: &'static str,
        /// The system's answer.
        #[source]
        source: io::Error,
    },
    /// LinuxCNC's HAL refused a call while a module loaded into it
    /// (feature `linuxcnc`): a duplicate or too long name, full shared
    /// memory, a locked HAL.
    #[error("LinuxCNC's {call} refused '{what}': {source}")]
    Refused {
        /// The call (`hal_pin_bit_newf`, `hal_init`, ...).
        call: String,
        /// The pin, parameter, function or component it was for.
        what: String,
        /// LinuxCNC's negative errno, as an error.
        #[source]
        source: io::Error,
    },
    /// A module parameter is wrong.
    #[error("{module}: parameter '{param}': {reason}")]
    BadParam {
        /// The module (`hm2_pci`, `hal_parport`, ...).
        module: String,
        /// The parameter (`config`, `cfg`, ...).
        param: String,
        /// What is wrong, naming the item where there are several.
        reason: String,
    },
}

/// Result type of the layer.
pub type Result<T, E = DriverError> = std::result::Result<T, E>;

impl DriverError {
    /// The error as a `loadrt` failure of `module`: a bad parameter
    /// becomes [`HalError::ModuleParam`], anything else
    /// [`HalError::ModuleFailed`] carrying this error as its source.
    pub fn into_hal(self, module: &str) -> HalError {
        match self {
            DriverError::BadParam {
                module,
                param,
                reason,
            } => HalError::ModuleParam {
                module,
                param,
                reason,
            },
            other => HalError::module_failed(module, other),
        }
    }
}

/// `.for_module(NAME)?` in a driver's load function: turns the layer's
/// errors into `loadrt` errors of that module.
pub trait ForModule<T> {
    /// Maps the error with [`DriverError::into_hal`].
    fn for_module(self, module: &str) -> hal_core::Result<T>;
}

impl<T> ForModule<T> for Result<T> {
    fn for_module(self, module: &str) -> hal_core::Result<T> {
        self.map_err(|e| e.into_hal(module))
    }
}

/// What to tell a user who may not open a device file.
pub(crate) const UDEV_HINT: &str = "the udev rules in udev/60-hal-suite.rules give the group \
     'hal' access to the boards' resource and enable files: install them (udev/README.md) and \
     add the user to 'hal'";

/// Classifies a failed open/mmap of `path`: permission (with `hint`),
/// lockdown (EPERM where permission bits allowed the open), or plain I/O.
pub(crate) fn classify(op: &'static str, path: &std::path::Path, e: io::Error) -> DriverError {
    match e.raw_os_error() {
        Some(libc::EACCES) => DriverError::Permission {
            path: path.to_path_buf(),
            hint: UDEV_HINT.to_string(),
        },
        Some(libc::EPERM) if crate::lockdown::active() => DriverError::Lockdown {
            what: format!("{op} {}", path.display()),
        },
        Some(libc::EPERM) => DriverError::Permission {
            path: path.to_path_buf(),
            hint: format!("{op} needs CAP_SYS_RAWIO or root for this file ({e})"),
        },
        _ => DriverError::Io {
            path: path.to_path_buf(),
            op,
            source: e,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_params_become_module_param_errors() {
        let e = DriverError::BadParam {
            module: "hm2_pci".into(),
            param: "config".into(),
            reason: "item 1 \"firmware=x\": not supported".into(),
        };
        let h = e.into_hal("hm2_pci");
        assert!(matches!(h, HalError::ModuleParam { .. }));
        assert_eq!(
            h.to_string(),
            "hm2_pci: parameter 'config': item 1 \"firmware=x\": not supported"
        );
        let e = DriverError::BarMissing {
            device: "0000:01:00.0".into(),
            bar: 5,
        };
        assert_eq!(
            e.into_hal("hm2_pci").to_string(),
            "hm2_pci: PCI device 0000:01:00.0: BAR 5 is not present"
        );
    }

    #[test]
    fn a_failed_load_keeps_the_driver_error_and_its_cause() {
        use std::error::Error as _;
        let e = DriverError::Io {
            path: "/sys/x/resource0".into(),
            op: "mapping",
            source: io::Error::from_raw_os_error(libc::EIO),
        };
        let h = e.into_hal("hm2_pci");
        assert!(h
            .to_string()
            .starts_with("hm2_pci: mapping /sys/x/resource0: "));
        let driver = h.source().and_then(|s| s.downcast_ref::<DriverError>());
        assert!(matches!(driver, Some(DriverError::Io { .. })), "{driver:?}");
        let cause = driver
            .and_then(|d| d.source())
            .and_then(|s| s.downcast_ref::<io::Error>());
        assert_eq!(cause.and_then(io::Error::raw_os_error), Some(libc::EIO));
    }

    #[test]
    fn eacces_names_the_udev_rule() {
        let e = classify(
            "opening",
            std::path::Path::new("/sys/x/resource0"),
            io::Error::from_raw_os_error(libc::EACCES),
        );
        let m = e.to_string();
        assert!(
            m.contains("/sys/x/resource0") && m.contains("60-hal-suite.rules"),
            "{m}"
        );
        assert!(m.contains("'hal'"), "{m}");
    }
}
