//! The button file (`-I`): LinuxCNC's INI format, section `[XHC-HB04]`,
//! one `BUTTON=CODE:pin-name` line per button, CODE in hex as the
//! pendant reports it.

use std::path::Path;

use hal_lang::ini::Ini;

use crate::error::{ButtonProblem, Result, UsbError};

/// The section the button lines are in.
pub const SECTION: &str = "XHC-HB04";
/// The most buttons a file may name (as LinuxCNC).
pub const MAX_BUTTONS: usize = 32;
/// The longest pin name a button may have.
pub const MAX_NAME: usize = 40;

/// One button: the code the pendant reports and the pin's name (after
/// `xhc-hb04.`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Button {
    /// The button code (1..=255).
    pub code: u8,
    /// The pin name, e.g. `button-zero`.
    pub name: String,
}

/// Reads the button file.
pub fn load(path: &Path) -> Result<Vec<Button>> {
    let ini = Ini::load(path).map_err(|source| UsbError::ButtonFile {
        path: path.to_path_buf(),
        source: Box::new(source),
    })?;
    from_ini(&ini)
}

/// The buttons an INI names, in file order.
pub fn from_ini(ini: &Ini) -> Result<Vec<Button>> {
    let mut out: Vec<Button> = Vec::new();
    for e in ini.all(SECTION, "BUTTON") {
        let bad = |problem: ButtonProblem| UsbError::BadButton {
            file: e.origin.file.to_string(),
            line: e.origin.line,
            value: e.value.clone(),
            problem,
        };
        if out.len() == MAX_BUTTONS {
            return Err(bad(ButtonProblem::TooMany { max: MAX_BUTTONS }));
        }
        let b = parse_line(&e.value).map_err(bad)?;
        if out.iter().any(|o| o.name == b.name) {
            return Err(bad(ButtonProblem::Twice(b.name)));
        }
        out.push(b);
    }
    Ok(out)
}

/// One `CODE:name` value.
pub fn parse_line(value: &str) -> std::result::Result<Button, ButtonProblem> {
    let (code, name) = value.split_once(':').ok_or(ButtonProblem::NoColon)?;
    let code = code.trim();
    let code =
        u8::from_str_radix(code, 16).map_err(|_| ButtonProblem::BadCode(code.to_string()))?;
    if code == 0 {
        return Err(ButtonProblem::ZeroCode);
    }
    let name = name.trim();
    if name.is_empty() || name.len() > MAX_NAME {
        return Err(ButtonProblem::NameLength { max: MAX_NAME });
    }
    let ok = |c: char| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.');
    if !name.chars().all(ok) {
        return Err(ButtonProblem::NameCharacters(name.to_string()));
    }
    Ok(Button {
        code,
        name: name.to_string(),
    })
}

/// The axis-qualified pins LinuxCNC adds for a button of this name
/// (`-x`, `-y`, `-z`, `-a`): only `button-zero`, `button-goto-zero` and
/// `button-half` have them.
pub fn has_axis_pins(name: &str) -> bool {
    matches!(name, "button-zero" | "button-goto-zero" | "button-half")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_layout_file() {
        let ini = Ini::parse("[XHC-HB04]\nBUTTON=01:button-goto-zero\nBUTTON=0D:button-step\n");
        let b = from_ini(&ini).unwrap();
        assert_eq!(
            b,
            vec![
                Button {
                    code: 1,
                    name: "button-goto-zero".into()
                },
                Button {
                    code: 0x0D,
                    name: "button-step".into()
                }
            ]
        );
        assert!(has_axis_pins(&b[0].name));
        assert!(!has_axis_pins(&b[1].name));
    }

    #[test]
    fn refuses_bad_lines_with_their_place() {
        for bad in ["01", "zz:button-x", "00:button-x", "100:b", "01:", "01:a b"] {
            assert!(parse_line(bad).is_err(), "{bad}");
        }
        let ini = Ini::parse("[XHC-HB04]\nBUTTON=01:b\nBUTTON=02:b\n");
        let e = from_ini(&ini).unwrap_err().to_string();
        assert!(e.contains(":3:") && e.contains("twice"), "{e}");
    }

    #[test]
    fn at_most_32_buttons() {
        let mut text = String::from("[XHC-HB04]\n");
        for i in 1..=33 {
            text.push_str(&format!("BUTTON={i:02X}:b{i}\n"));
        }
        assert!(from_ini(&Ini::parse(&text)).is_err());
    }
}
