//! The real backend: `/dev/gpiochipN` through the GPIO character
//! device's uAPI v2, on the `gpiocdev` crate.
//!
//! Discovery lists the chip devices with `gpiocdev::chip::chips`, which
//! resolves symlinks and drops duplicates, so an alias such as the
//! Raspberry Pi 5's `gpiochip4` counts once. A request is built with
//! gpiocdev's request builder (every line's direction, active-low, drive
//! and bias in one `GPIO_V2_GET_LINE_IOCTL`, outputs starting inactive).
//! The realtime accesses are one `GPIO_V2_LINE_GET_VALUES_IOCTL` or
//! `GPIO_V2_LINE_SET_VALUES_IOCTL` each, made with gpiocdev-uapi on a
//! duplicate of the request's descriptor: no allocation, no lock.

use std::fs::File;
use std::os::fd::AsFd;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use gpiocdev::line::{Bias as KernelBias, Drive as KernelDrive, Value};
use gpiocdev::Chip;
use gpiocdev_uapi::v2::{self as uapi, LineValues};

use crate::cfg::{Bias, Direction, Drive};
use crate::chip::{ChipInfo, ChipSet, LineError, LineRequest, LineSetting};
use crate::error::{GpioError, UDEV_HINT};

/// The system's GPIO chips, `/dev/gpiochip*`.
#[derive(Debug, Clone, Copy, Default)]
pub struct CdevChips;

/// An errno from gpiocdev's error, if it carries one.
fn errno_of(e: &gpiocdev::Error) -> Option<i32> {
    match e {
        gpiocdev::Error::Os(n) => Some(n.0),
        gpiocdev::Error::Uapi(_, gpiocdev_uapi::Error::Os(n)) => Some(n.0),
        _ => None,
    }
}

/// gpiocdev's error as a reason, with the udev hint for permissions.
fn reason(e: &gpiocdev::Error) -> String {
    match errno_of(e) {
        Some(libc::EACCES) | Some(libc::EPERM) => format!("{e} ({UDEV_HINT})"),
        _ => e.to_string(),
    }
}

fn open(path: &std::path::Path) -> Result<Chip, GpioError> {
    Chip::from_path(path).map_err(|e| GpioError::Chip {
        path: path.display().to_string(),
        op: "opening",
        reason: reason(&e),
    })
}

impl CdevChips {
    /// The chip at `path` as discovery reports it.
    pub fn info(path: &std::path::Path) -> Result<ChipInfo, GpioError> {
        let chip = open(path)?;
        let err = |op, e: gpiocdev::Error| GpioError::Chip {
            path: path.display().to_string(),
            op,
            reason: reason(&e),
        };
        let info = chip.info().map_err(|e| err("reading chip info of", e))?;
        let line_names = (0..info.num_lines)
            .map(|o| {
                chip.line_info(o)
                    .map(|l| l.name)
                    .map_err(|e| err("reading line info of", e))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(ChipInfo {
            path: path.display().to_string(),
            name: info.name,
            label: info.label,
            line_names,
        })
    }

    /// The name of whoever holds line `offset` of `chip`, if known.
    fn holder(chip: &ChipInfo, offset: u32) -> Option<String> {
        let c = Chip::from_path(&chip.path).ok()?;
        let l = c.line_info(offset).ok()?;
        (l.used).then_some(l.consumer)
    }
}

impl ChipSet for CdevChips {
    fn chips(&self) -> Result<Vec<ChipInfo>, GpioError> {
        let paths = gpiocdev::chip::chips().map_err(|e| GpioError::Chip {
            path: "/dev".into(),
            op: "listing GPIO chips in",
            reason: e.to_string(),
        })?;
        if paths.is_empty() {
            return Err(GpioError::NoChips {
                searched: "/dev/gpiochip*".into(),
            });
        }
        paths.iter().map(|p| CdevChips::info(p)).collect()
    }

    fn request(
        &self,
        chip: &ChipInfo,
        lines: &[LineSetting],
    ) -> Result<Box<dyn LineRequest>, GpioError> {
        let names = lines
            .iter()
            .map(|l| {
                chip.line_names
                    .get(l.offset as usize)
                    .cloned()
                    .unwrap_or_else(|| format!("line {}", l.offset))
            })
            .collect::<Vec<_>>()
            .join(", ");
        let mut b = gpiocdev::Request::builder();
        b.on_chip(&chip.path).with_consumer(crate::regs::CONSUMER);
        for l in lines {
            b.with_line(l.offset);
            match l.direction {
                Direction::Input => b.as_input(),
                Direction::Output => b.as_output(Value::Inactive),
            };
            if l.active_low {
                b.as_active_low();
            }
            if l.direction == Direction::Output {
                b.with_drive(match l.drive {
                    Drive::PushPull => KernelDrive::PushPull,
                    Drive::OpenDrain => KernelDrive::OpenDrain,
                    Drive::OpenSource => KernelDrive::OpenSource,
                });
            }
            b.with_bias(match l.bias {
                Bias::AsIs => None,
                Bias::Disabled => Some(KernelBias::Disabled),
                Bias::PullUp => Some(KernelBias::PullUp),
                Bias::PullDown => Some(KernelBias::PullDown),
            });
        }
        let req = b.request().map_err(|e| {
            let mut why = reason(&e);
            if errno_of(&e) == Some(libc::EBUSY) {
                let held: Vec<String> = lines
                    .iter()
                    .filter_map(|l| {
                        CdevChips::holder(chip, l.offset).map(|c| {
                            let n = chip.line_names.get(l.offset as usize);
                            format!("{} is in use by \"{c}\"", n.map_or("?", |s| s.as_str()))
                        })
                    })
                    .collect();
                if !held.is_empty() {
                    why = format!("{why} ({})", held.join(", "));
                }
            }
            GpioError::Request {
                chip: chip.to_string(),
                lines: names.clone(),
                reason: why,
            }
        })?;
        let fd = req
            .as_fd()
            .try_clone_to_owned()
            .map_err(|e| GpioError::Request {
                chip: chip.to_string(),
                lines: names.clone(),
                reason: format!("duplicating the request's descriptor: {e}"),
            })?;
        Ok(Box::new(CdevRequest {
            _request: req,
            file: File::from(fd),
            errors: AtomicU64::new(0),
            describe: format!("{chip} lines {names}"),
        }))
    }
}

/// A line request on a character device.
pub struct CdevRequest {
    /// Keeps the lines requested (and their configuration) while alive.
    _request: gpiocdev::Request,
    /// The same request, for the value ioctls.
    file: File,
    errors: AtomicU64,
    describe: String,
}

impl CdevRequest {
    #[inline]
    fn fail(&self, e: gpiocdev_uapi::Error) -> LineError {
        self.errors.fetch_add(1, Relaxed);
        match e {
            gpiocdev_uapi::Error::Os(n) => LineError(n.0),
            _ => LineError(libc::EIO),
        }
    }
}

impl LineRequest for CdevRequest {
    #[inline]
    fn get(&self, mask: u64) -> Result<u64, LineError> {
        let mut v = LineValues { bits: 0, mask };
        uapi::get_line_values(&self.file, &mut v).map_err(|e| self.fail(e))?;
        Ok(v.bits & mask)
    }

    #[inline]
    fn set(&self, bits: u64, mask: u64) -> Result<(), LineError> {
        let v = LineValues { bits, mask };
        uapi::set_line_values(&self.file, &v).map_err(|e| self.fail(e))
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        self.describe.clone()
    }
}
