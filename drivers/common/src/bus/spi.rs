//! [`SpiBus`]: a full-duplex SPI link to one device (one chip select),
//! in 32-bit words, and its real backend [`Spidev`] over Linux's
//! `/dev/spidevB.C`.
//!
//! A message keeps the chip select asserted from its first word to its
//! last; every word goes out most significant bit first while the
//! device's word comes in. On the wire that is four 8-bit SPI words per
//! 32-bit word, high byte first, which every SPI controller supports
//! (not all can do 32-bit words). Like the other buses, a transfer never
//! fails visibly: one that cannot be made reads all ones and is counted
//! in [`SpiBus::errors`].

use std::fs::{File, OpenOptions};
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::ALL_ONES;
use crate::error::{DriverError, Result};

/// The longest message [`Spidev`] sends, in bytes (the spidev driver's
/// default buffer size).
pub const MAX_MESSAGE_BYTES: usize = 4096;
/// The longest message in 32-bit words.
pub const MAX_MESSAGE_WORDS: usize = MAX_MESSAGE_BYTES / 4;

/// A full-duplex SPI link to one device.
pub trait SpiBus: Send + Sync {
    /// One message at `speed_hz`: shifts `buf` out and replaces each word
    /// with the word shifted in meanwhile. A message that cannot be made
    /// leaves all ones and counts an error.
    fn transfer(&self, buf: &mut [u32], speed_hz: u32);

    /// Transfers that failed so far.
    fn errors(&self) -> u64;

    /// What the bus is, for messages.
    fn describe(&self) -> String;

    /// The HAL thread's time, once per cycle (a simulated device follows
    /// it; hardware ignores it).
    fn tick(&self, _now_ns: u64) {}
}

/// The spidev ioctls (linux/spi/spidev.h): magic `k`.
mod ioctl {
    /// `struct spi_ioc_transfer`: one segment of a message.
    #[repr(C)]
    #[derive(Debug, Default, Clone, Copy)]
    pub struct Transfer {
        pub tx_buf: u64,
        pub rx_buf: u64,
        pub len: u32,
        pub speed_hz: u32,
        pub delay_usecs: u16,
        pub bits_per_word: u8,
        pub cs_change: u8,
        pub tx_nbits: u8,
        pub rx_nbits: u8,
        pub word_delay_usecs: u8,
        pub pad: u8,
    }

    /// `_IOW('k', nr, size)` in the asm-generic encoding (x86, Arm,
    /// RISC-V): direction "write" in bits 31..30, the size in 29..16, the
    /// magic in 15..8, the number in 7..0.
    const fn write_request(nr: u32, size: usize) -> u32 {
        (1 << 30) | ((size as u32) << 16) | ((b'k' as u32) << 8) | nr
    }

    pub const WR_MODE: u32 = write_request(1, 1);
    pub const WR_BITS_PER_WORD: u32 = write_request(3, 1);
    pub const WR_MAX_SPEED_HZ: u32 = write_request(4, 4);
    /// `SPI_IOC_MESSAGE(1)`: the size is that of one segment.
    pub const MESSAGE_1: u32 = write_request(0, std::mem::size_of::<Transfer>());
}

/// A device on `/dev/spidevB.C`, in SPI mode 0 with 8-bit words.
#[derive(Debug)]
pub struct Spidev {
    file: File,
    path: PathBuf,
    errors: AtomicU64,
}

impl Spidev {
    /// Opens `path` and sets mode 0, 8-bit words and `max_speed_hz`.
    pub fn open(path: &Path, max_speed_hz: u32) -> Result<Spidev> {
        let io = |op: &'static str| {
            move |source: std::io::Error| DriverError::Io {
                op,
                path: path.to_path_buf(),
                source,
            }
        };
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(io("opening"))?;
        let fd = file.as_raw_fd();
        let (mode, bits) = (0u8, 8u8);
        let set = |req: u32, value: *const libc::c_void| {
            // SAFETY: `fd` is an open file owned by this function for the
            // call; `value` points at a local of the size `req` encodes,
            // which outlives the call and which the kernel only reads.
            let r = unsafe { libc::ioctl(fd, req as _, value) };
            if r < 0 {
                Err(std::io::Error::last_os_error())
            } else {
                Ok(())
            }
        };
        set(ioctl::WR_MODE, (&mode as *const u8).cast())
            .and_then(|()| set(ioctl::WR_BITS_PER_WORD, (&bits as *const u8).cast()))
            .and_then(|()| set(ioctl::WR_MAX_SPEED_HZ, (&max_speed_hz as *const u32).cast()))
            .map_err(io("setting up (mode 0, 8 bits, speed)"))?;
        Ok(Spidev {
            file,
            path: path.to_path_buf(),
            errors: AtomicU64::new(0),
        })
    }

    fn fail(&self, buf: &mut [u32]) {
        buf.fill(ALL_ONES);
        self.errors.fetch_add(1, Relaxed);
    }
}

impl SpiBus for Spidev {
    fn transfer(&self, buf: &mut [u32], speed_hz: u32) {
        let n = buf.len() * 4;
        if buf.is_empty() {
            return;
        }
        if n > MAX_MESSAGE_BYTES {
            self.fail(buf);
            return;
        }
        let mut tx = [0u8; MAX_MESSAGE_BYTES];
        let mut rx = [0u8; MAX_MESSAGE_BYTES];
        for (chunk, w) in tx.chunks_exact_mut(4).zip(buf.iter()) {
            chunk.copy_from_slice(&w.to_be_bytes());
        }
        let t = ioctl::Transfer {
            tx_buf: tx.as_ptr() as u64,
            rx_buf: rx.as_mut_ptr() as u64,
            len: n as u32,
            speed_hz,
            bits_per_word: 8,
            ..ioctl::Transfer::default()
        };
        // SAFETY: the file descriptor is open for the life of `self`; the
        // transfer points at two local buffers of at least `len` bytes
        // that outlive the call, and the kernel writes only `len` bytes of
        // `rx`.
        let done = unsafe {
            libc::ioctl(
                self.file.as_raw_fd(),
                ioctl::MESSAGE_1 as _,
                &t as *const ioctl::Transfer,
            )
        };
        match done {
            k if k >= 0 && k as usize == n => {
                for (w, chunk) in buf.iter_mut().zip(rx.chunks_exact(4)) {
                    *w = u32::from_be_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
                }
            }
            _ => self.fail(buf),
        }
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        format!("spidev {}", self.path.display())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_transfer_segment_is_the_kernels_size() {
        assert_eq!(std::mem::size_of::<ioctl::Transfer>(), 32);
    }

    #[test]
    fn a_missing_device_is_a_clear_error() {
        let dir = std::env::temp_dir().join(format!("spidev-test-{}", std::process::id()));
        let e = Spidev::open(&dir.join("spidev9.9"), 1_000_000).unwrap_err();
        let s = e.to_string();
        assert!(s.contains("opening") && s.contains("spidev9.9"), "{s}");
    }

    #[test]
    fn a_file_that_is_not_spidev_refuses_the_setup() {
        let dir = std::env::temp_dir().join(format!("spidev-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("spidev0.0");
        std::fs::write(&path, b"").unwrap();
        let e = Spidev::open(&path, 1_000_000).unwrap_err();
        assert!(e.to_string().contains("mode 0, 8 bits"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
