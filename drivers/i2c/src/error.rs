//! The crate's error type: what can go wrong at `loadrt`.

use std::path::Path;

use hal_core::HalError;
use hal_driver::DriverError;

use crate::bus::BusError;
use crate::chips::ChipFault;

/// How to get access to the bus devices.
pub const UDEV_HINT: &str = "the rule for /dev/i2c-* in udev/60-hal-suite.rules gives the group \
     'hal' access: install it (udev/README.md) and add the user to 'hal'";

/// Why loading an I2C chip failed.
#[derive(Debug, thiserror::Error)]
pub enum I2cError {
    /// A module parameter is wrong.
    #[error(transparent)]
    Param(#[from] DriverError),
    /// The bus device could not be opened.
    #[error("opening {path}: {reason}")]
    Open {
        /// The device node.
        path: String,
        /// Why, and what to do.
        reason: String,
    },
    /// The address could not be taken (`I2C_SLAVE`).
    #[error("{chip}: {bus} address {addr:#04x}: {reason}")]
    Claim {
        /// The chip's HAL name (`pca9685.0`).
        chip: String,
        /// The bus.
        bus: String,
        /// The address.
        addr: u8,
        /// Why, and what to do.
        reason: String,
    },
    /// Another chip loaded before already uses the address.
    #[error("{chip}: {bus} address {addr:#04x} is already used by {by}")]
    AddressInUse {
        /// The chip being loaded.
        chip: String,
        /// The bus.
        bus: String,
        /// The address.
        addr: u8,
        /// The chip that has it.
        by: String,
    },
    /// The chip did not take its configuration.
    #[error("{chip}: {bus} address {addr:#04x}: setting the chip up failed: {source}")]
    Init {
        /// The chip's HAL name.
        chip: String,
        /// The bus.
        bus: String,
        /// The address.
        addr: u8,
        /// What went wrong.
        source: ChipFault,
    },
}

impl I2cError {
    /// A failed open of `path`, with what to do about it.
    pub fn open(path: &Path, e: std::io::Error) -> I2cError {
        let hint = match e.raw_os_error() {
            Some(libc::ENOENT) => {
                " (no such bus: load i2c-dev with `modprobe i2c-dev`, enable the bus (on a \
                 Raspberry Pi: dtparam=i2c_arm=on), and list the buses with `i2cdetect -l`)"
                    .to_string()
            }
            Some(libc::EACCES) | Some(libc::EPERM) => format!(" ({UDEV_HINT})"),
            _ => String::new(),
        };
        I2cError::Open {
            path: path.display().to_string(),
            reason: format!("{e}{hint}"),
        }
    }

    /// A refused `I2C_SLAVE`, with what to do about it.
    pub fn claim(chip: &str, bus: &str, addr: u8, e: BusError) -> I2cError {
        let reason = if e.0 == libc::EBUSY {
            format!(
                "{e} (a kernel driver owns this address: unbind it, or remove the \
                 device-tree overlay that declares the chip)"
            )
        } else {
            e.to_string()
        };
        I2cError::Claim {
            chip: chip.into(),
            bus: bus.into(),
            addr,
            reason,
        }
    }

    /// The error as a `loadrt` failure of `module`.
    pub fn into_hal(self, module: &str) -> HalError {
        match self {
            I2cError::Param(e) => e.into_hal(module),
            other => HalError::module_failed(module, other),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_say_what_and_where() {
        let e = I2cError::open(
            Path::new("/dev/i2c-7"),
            std::io::Error::from_raw_os_error(libc::ENOENT),
        );
        let m = e.into_hal("pca9685").to_string();
        assert!(m.starts_with("pca9685: opening /dev/i2c-7: "), "{m}");
        assert!(m.contains("modprobe i2c-dev"), "{m}");
        let m =
            I2cError::claim("mcp23017.0", "/dev/i2c-1", 0x20, BusError(libc::EBUSY)).to_string();
        assert!(m.contains("mcp23017.0: /dev/i2c-1 address 0x20: "), "{m}");
        assert!(m.contains("kernel driver owns this address"), "{m}");
        let m = I2cError::Init {
            chip: "ads1115.1".into(),
            bus: "/dev/i2c-1".into(),
            addr: 0x49,
            source: ChipFault::Bus(BusError(libc::ENXIO)),
        }
        .to_string();
        assert!(
            m.contains("0x49: setting the chip up failed: ") && m.contains("no answer"),
            "{m}"
        );
    }
}
