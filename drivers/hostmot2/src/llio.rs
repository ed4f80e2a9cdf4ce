//! What a low-level driver tells the core about its board (LinuxCNC's
//! `hm2_lowlevel_io_t` without the function pointers, which are the
//! [`Transport`](crate::transport::Transport)).

use crate::error::{Hm2Error, Result};
use crate::regs::MAX_CONNECTORS;

/// A board as its low-level driver knows it, before the IDROM is read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Llio {
    /// The HAL prefix: `hm2_<board>.<n>` (`hm2_5i25.0`).
    pub name: String,
    /// Connector names, in I/O order (`P3`, `P2` on a 5i25).
    pub connectors: Vec<String>,
    /// Pins per connector; the IDROM's PortWidth must agree.
    pub pins_per_connector: u32,
    /// LEDs on the board.
    pub num_leds: u32,
    /// The FPGA part (`6slx9tqg144`), for messages and the board tool.
    pub fpga_part: String,
}

/// HAL_NAME_LEN in LinuxCNC: the llio name must fit it.
const NAME_MAX: usize = 47;

fn printable(s: &str) -> bool {
    !s.is_empty() && s.bytes().all(|b| b.is_ascii_graphic())
}

impl Llio {
    /// Checks what LinuxCNC checks of an llio before it reads anything
    /// (hardware.md 5.7 step 1).
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: String| Err(Hm2Error::BadLlio { reason });
        if !printable(&self.name) || self.name.len() > NAME_MAX {
            return bad(format!(
                "name {:?} must be 1 to {NAME_MAX} printable characters",
                self.name
            ));
        }
        if self.connectors.is_empty() || self.connectors.len() > MAX_CONNECTORS {
            return bad(format!(
                "{} connectors, expected 1 to {MAX_CONNECTORS}",
                self.connectors.len()
            ));
        }
        if let Some((i, c)) = self
            .connectors
            .iter()
            .enumerate()
            .find(|(_, c)| !printable(c))
        {
            return bad(format!("connector {i} name {c:?} is not printable"));
        }
        if self.pins_per_connector == 0 {
            return bad("0 pins per connector".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn llio() -> Llio {
        Llio {
            name: "hm2_5i25.0".into(),
            connectors: vec!["P3".into(), "P2".into()],
            pins_per_connector: 17,
            num_leds: 2,
            fpga_part: "6slx9tqg144".into(),
        }
    }

    #[test]
    fn llio_checks() {
        assert!(llio().validate().is_ok());
        for f in [
            |l: &mut Llio| l.name = String::new(),
            |l: &mut Llio| l.name = "a b".into(),
            |l: &mut Llio| l.name = "x".repeat(48),
            |l: &mut Llio| l.connectors.clear(),
            |l: &mut Llio| l.connectors = vec!["P1".into(); 9],
            |l: &mut Llio| l.connectors[1] = "\u{1}".into(),
            |l: &mut Llio| l.pins_per_connector = 0,
        ] {
            let mut l = llio();
            f(&mut l);
            assert!(
                l.validate()
                    .unwrap_err()
                    .to_string()
                    .starts_with("invalid llio: "),
                "{l:?}"
            );
        }
    }
}
