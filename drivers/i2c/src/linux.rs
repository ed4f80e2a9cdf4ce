//! The real backend: `/dev/i2c-N` (kernel module `i2c-dev`) through the
//! `i2cdev` crate, one open device per claimed address, SMBus transfers
//! only (what every adapter and the kernel's i2c-stub can do).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Mutex, MutexGuard};

use i2cdev::core::I2CDevice;
use i2cdev::linux::{LinuxI2CDevice, LinuxI2CError};

use crate::bus::{BusError, I2cBus, BLOCK_MAX};
use crate::error::I2cError;

/// An I2C bus through i2c-dev.
pub struct LinuxBus {
    path: PathBuf,
    /// The devices of the claimed addresses. Only the bus's helper
    /// thread and `loadrt` use them; the lock is never contended by a
    /// realtime thread.
    devices: Mutex<Vec<(u8, LinuxI2CDevice)>>,
    errors: AtomicU64,
}

impl std::fmt::Debug for LinuxBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinuxBus")
            .field("path", &self.path)
            .finish()
    }
}

fn errno(e: LinuxI2CError) -> BusError {
    match e {
        LinuxI2CError::Errno(n) => BusError(n),
        LinuxI2CError::Io(e) => BusError(e.raw_os_error().unwrap_or(libc::EIO)),
    }
}

impl LinuxBus {
    /// The device node of bus `n`.
    pub fn path_of(n: u32) -> PathBuf {
        PathBuf::from(format!("/dev/i2c-{n}"))
    }

    /// Opens bus `path` (checking that this user may).
    pub fn open(path: &Path) -> Result<LinuxBus, I2cError> {
        std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| I2cError::open(path, e))?;
        Ok(LinuxBus {
            path: path.to_path_buf(),
            devices: Mutex::new(Vec::new()),
            errors: AtomicU64::new(0),
        })
    }

    fn lock(&self) -> MutexGuard<'_, Vec<(u8, LinuxI2CDevice)>> {
        self.devices.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Runs `f` on the device of `addr`, counting failures.
    fn with<R>(
        &self,
        addr: u8,
        f: impl FnOnce(&mut LinuxI2CDevice) -> Result<R, LinuxI2CError>,
    ) -> Result<R, BusError> {
        let mut devices = self.lock();
        let result = match devices.iter_mut().find(|(a, _)| *a == addr) {
            Some((_, dev)) => f(dev).map_err(errno),
            None => Err(BusError(libc::EINVAL)),
        };
        if result.is_err() {
            self.errors.fetch_add(1, Relaxed);
        }
        result
    }
}

impl I2cBus for LinuxBus {
    fn claim(&self, addr: u8) -> Result<(), BusError> {
        let mut devices = self.lock();
        if devices.iter().any(|(a, _)| *a == addr) {
            return Ok(());
        }
        let dev = LinuxI2CDevice::new(&self.path, addr as u16).map_err(errno)?;
        devices.push((addr, dev));
        Ok(())
    }

    fn write_byte_data(&self, addr: u8, reg: u8, value: u8) -> Result<(), BusError> {
        self.with(addr, |d| d.smbus_write_byte_data(reg, value))
    }

    fn read_byte_data(&self, addr: u8, reg: u8) -> Result<u8, BusError> {
        self.with(addr, |d| d.smbus_read_byte_data(reg))
    }

    fn write_word_data(&self, addr: u8, reg: u8, value: u16) -> Result<(), BusError> {
        self.with(addr, |d| d.smbus_write_word_data(reg, value))
    }

    fn read_word_data(&self, addr: u8, reg: u8) -> Result<u16, BusError> {
        self.with(addr, |d| d.smbus_read_word_data(reg))
    }

    fn write_block(&self, addr: u8, reg: u8, data: &[u8]) -> Result<(), BusError> {
        if data.len() > BLOCK_MAX {
            return Err(BusError(libc::EINVAL));
        }
        self.with(addr, |d| d.smbus_write_i2c_block_data(reg, data))
    }

    fn read_block(&self, addr: u8, reg: u8, out: &mut [u8]) -> Result<(), BusError> {
        if out.len() > BLOCK_MAX {
            return Err(BusError(libc::EINVAL));
        }
        let got = self.with(addr, |d| d.smbus_read_i2c_block_data(reg, out.len() as u8))?;
        if got.len() != out.len() {
            self.errors.fetch_add(1, Relaxed);
            return Err(BusError(libc::EIO));
        }
        out.copy_from_slice(&got);
        Ok(())
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        self.path.display().to_string()
    }
}
