//! The `dio` module parameter: the direction of the four 8-bit digital
//! I/O ports A, B, C, D, one letter each (`I`/`i` input, `O`/`o`
//! output), as LinuxCNC's `dio="IIOO"` (the default).

use crate::regs;

/// The default directions: A and B inputs, C and D outputs.
pub const DEFAULT: &str = "IIOO";
/// Lines per port.
pub const LINES: usize = 8;

/// The directions of ports A, B, C, D.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dio {
    /// `true` where the port is an input, in A B C D order.
    pub input: [bool; 4],
}

/// Why a `dio` string was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DioError {
    /// Not four characters.
    #[error("\"{0}\" is not 4 letters, one per port A, B, C, D (e.g. \"IIOO\")")]
    Length(String),
    /// A character other than I or O.
    #[error("port {port}: '{found}' is neither I (input) nor O (output)")]
    Letter {
        /// The port, A..D.
        port: char,
        /// The character found.
        found: char,
    },
}

impl Dio {
    /// Parses a `dio` string.
    pub fn parse(text: &str) -> Result<Dio, DioError> {
        let chars: Vec<char> = text.chars().collect();
        if chars.len() != 4 {
            return Err(DioError::Length(text.to_string()));
        }
        let mut input = [false; 4];
        for (i, c) in chars.into_iter().enumerate() {
            input[i] = match c {
                'I' | 'i' => true,
                'O' | 'o' => false,
                found => {
                    return Err(DioError::Letter {
                        port: (b'A' + i as u8) as char,
                        found,
                    })
                }
            };
        }
        Ok(Dio { input })
    }

    /// The input ports (0 = A .. 3 = D), in order: `stg.in-NN` numbers
    /// run over them, 8 per port.
    pub fn input_ports(&self) -> impl Iterator<Item = usize> + '_ {
        (0..4).filter(|&p| self.input[p])
    }

    /// The output ports, in order (`stg.out-NN`).
    pub fn output_ports(&self) -> impl Iterator<Item = usize> + '_ {
        (0..4).filter(|&p| !self.input[p])
    }

    /// The 8255 #1 control word for ports A, B, C.
    pub fn abc_control(&self) -> u8 {
        regs::abc_control(self.input[0], self.input[1], self.input[2])
    }

    /// The 8255 #2 control word for port D on a Model I or II.
    pub fn d_control(&self, model2: bool) -> u8 {
        match (model2, self.input[3]) {
            (false, true) => regs::MODEL1_D_IN,
            (false, false) => regs::MODEL1_D_OUT,
            (true, true) => regs::MODEL2_D_IN,
            (true, false) => regs::MODEL2_D_OUT,
        }
    }
}

impl std::fmt::Display for Dio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for i in self.input {
            f.write_str(if i { "I" } else { "O" })?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linuxcnc_strings() {
        let d = Dio::parse(DEFAULT).unwrap();
        assert_eq!(d.input, [true, true, false, false]);
        assert_eq!(d.input_ports().collect::<Vec<_>>(), [0, 1]);
        assert_eq!(d.output_ports().collect::<Vec<_>>(), [2, 3]);
        assert_eq!(d.abc_control(), 0x92);
        assert_eq!((d.d_control(false), d.d_control(true)), (0x82, 0x82));
        let d = Dio::parse("iOiO").unwrap();
        assert_eq!(d.to_string(), "IOIO");
        assert_eq!(d.abc_control(), 0x99);
        assert_eq!((d.d_control(false), d.d_control(true)), (0x82, 0x82));
        let d = Dio::parse("OOOI").unwrap();
        assert_eq!((d.d_control(false), d.d_control(true)), (0x92, 0x8B));
    }

    #[test]
    fn bad_strings_say_what() {
        assert_eq!(
            Dio::parse("IIO").unwrap_err().to_string(),
            "\"IIO\" is not 4 letters, one per port A, B, C, D (e.g. \"IIOO\")"
        );
        assert_eq!(
            Dio::parse("IIXO").unwrap_err().to_string(),
            "port C: 'X' is neither I (input) nor O (output)"
        );
        assert!(Dio::parse("IIOOO").is_err());
        assert!(Dio::parse("").is_err());
    }
}
