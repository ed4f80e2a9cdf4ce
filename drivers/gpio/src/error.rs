//! The crate's error type: what can go wrong at `loadrt`.

use hal_core::HalError;
use hal_driver::DriverError;

/// What the udev rule is and how to get it, for permission errors.
pub const UDEV_HINT: &str = "the rule for /dev/gpiochip* in udev/60-hal-suite.rules gives the \
     group 'hal' access: install it (udev/README.md) and add the user to 'hal'";

/// Why `loadrt hal_gpio` failed.
#[derive(Debug, thiserror::Error)]
pub enum GpioError {
    /// A module parameter is wrong.
    #[error(transparent)]
    Param(#[from] DriverError),
    /// No chip has a line of this name.
    #[error("hal_gpio: parameter '{param}': item {item} \"{name}\": no GPIO line has this name (searched {searched}); names are case-sensitive and as `gpioinfo` prints them")]
    LineNotFound {
        /// The list that names it (`inputs`, `outputs`).
        param: &'static str,
        /// Its item number in the list.
        item: usize,
        /// The name.
        name: String,
        /// The chips searched.
        searched: String,
    },
    /// The name is on more than one line.
    #[error("hal_gpio: parameter '{param}': item {item} \"{name}\": the name is on more than one line ({places}), so it does not say which one to use")]
    LineAmbiguous {
        /// The list that names it.
        param: &'static str,
        /// Its item number in the list.
        item: usize,
        /// The name.
        name: String,
        /// Every line that has it (`gpiochip0 [label] line 5`).
        places: String,
    },
    /// A modifier list that only outputs take names an input.
    #[error("{param}= applies to outputs only, and this line is an input")]
    OutputOnly {
        /// The list (`invert`, `reset`, `opendrain`, `opensource`).
        param: String,
    },
    /// A line is in two bias lists.
    #[error("has two bias settings ({first} and {second})")]
    TwoBiases {
        /// The list that set its bias first.
        first: &'static str,
        /// The second one.
        second: String,
    },
    /// A line is both open drain and open source.
    #[error("cannot be both open drain and open source")]
    TwoDrives,
    /// A modifier list this driver does not have.
    #[error("unknown list {param}")]
    UnknownList {
        /// Its name.
        param: String,
    },
    /// A line request the (simulated) kernel refused: its errno and,
    /// where known, why.
    #[error("{errno}{}", detail.as_ref().map(|d| format!(" ({d})")).unwrap_or_default())]
    Refused {
        /// The kernel's answer.
        errno: crate::chip::LineError,
        /// Which line and why, where known.
        detail: Option<String>,
    },
    /// A request names a line the chip does not have.
    #[error("line {offset} does not exist on this chip")]
    NoSuchLine {
        /// The line's offset.
        offset: u32,
    },
    /// There are no GPIO chips at all.
    #[error("no GPIO chips found ({searched}): is the GPIO controller's kernel driver loaded?")]
    NoChips {
        /// Where discovery looked.
        searched: String,
    },
    /// A chip could not be opened or asked about its lines.
    #[error("{op} {path}: {reason}")]
    Chip {
        /// The chip.
        path: String,
        /// What was being done (`opening`, `reading line info of`).
        op: &'static str,
        /// Why it failed, with a hint where one helps.
        reason: String,
    },
    /// The kernel refused a line request.
    #[error("requesting {lines} on {chip}: {reason}")]
    Request {
        /// The chip.
        chip: String,
        /// The lines, by name.
        lines: String,
        /// The kernel's answer and, where known, who holds a line.
        reason: String,
    },
}

impl GpioError {
    /// The error as a `loadrt` failure.
    pub fn into_hal(self) -> HalError {
        match self {
            GpioError::Param(e) => e.into_hal(crate::hal::NAME),
            GpioError::LineNotFound { param, .. } | GpioError::LineAmbiguous { param, .. } => {
                let text = self.to_string();
                let prefix = format!("hal_gpio: parameter '{param}': ");
                HalError::ModuleParam {
                    module: crate::hal::NAME.into(),
                    param: param.into(),
                    reason: text.strip_prefix(&prefix).unwrap_or(&text).to_string(),
                }
            }
            other => HalError::module_failed(crate::hal::NAME, other),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loadrt_errors_say_the_module_once() {
        let e = GpioError::LineNotFound {
            param: "inputs",
            item: 1,
            name: "GPIO99".into(),
            searched: "gpiochip0 [pinctrl-bcm2711]".into(),
        }
        .into_hal();
        let m = e.to_string();
        assert_eq!(m.matches("hal_gpio").count(), 1, "{m}");
        assert!(
            m.contains("parameter 'inputs': item 1 \"GPIO99\": no GPIO line has this name"),
            "{m}"
        );
        let e = GpioError::Request {
            chip: "gpiochip0 [x]".into(),
            lines: "GPIO5".into(),
            reason: "busy".into(),
        }
        .into_hal();
        let m = e.to_string();
        assert_eq!(m.matches("hal_gpio").count(), 1, "{m}");
        assert!(m.contains("requesting GPIO5 on gpiochip0 [x]: busy"), "{m}");
    }
}
