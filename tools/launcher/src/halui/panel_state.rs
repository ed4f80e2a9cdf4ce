//! The part of task's `state` answer that halui's switch, tool and
//! relative-position pins read: optional stop, block delete, the tool
//! length offsets and diameter, and the offsets between machine and
//! relative coordinates.

use crate::error::LaunchError;

/// Switches, tool and offsets, as task's `state` answer gives them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PanelState {
    /// The optional-stop switch.
    pub optional_stop: bool,
    /// The block-delete switch.
    pub block_delete: bool,
    /// The tool length offsets, X Y Z A B C U V W (machine units).
    pub tool_offset: [f64; 9],
    /// The tool's diameter (0 with no tool).
    pub tool_diameter: f64,
    /// Machine minus relative coordinates, per axis: G5x, G92 and tool
    /// offsets together.
    pub relative_offset: [f64; 9],
}

/// Reads the panel keys out of a `state` answer's `key=value` pairs.
pub fn parse_panel(fields: &[(&str, &str)]) -> Result<PanelState, LaunchError> {
    let bad = |why: String| LaunchError::TaskState { why };
    let get = |key: &str| {
        fields
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| *v)
            .ok_or_else(|| bad(format!("no {key}")))
    };
    let flag = |key: &str| match get(key)? {
        "0" => Ok(false),
        "1" => Ok(true),
        v => Err(bad(format!("{key}={v} is not 0 or 1"))),
    };
    let number = |key: &str, word: &str| {
        word.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| bad(format!("{key}: '{word}' is not a number")))
    };
    let row = |key: &str| -> Result<[f64; 9], LaunchError> {
        let words: Vec<&str> = get(key)?.split_whitespace().collect();
        if words.len() != 9 {
            return Err(bad(format!(
                "{key} has {} numbers, not 9 (X Y Z A B C U V W)",
                words.len()
            )));
        }
        let mut out = [0.0; 9];
        for (slot, word) in out.iter_mut().zip(words) {
            *slot = number(key, word)?;
        }
        Ok(out)
    };
    Ok(PanelState {
        optional_stop: flag("optional-stop")?,
        block_delete: flag("block-delete")?,
        tool_offset: row("tool-offset")?,
        tool_diameter: number("tool-diameter", get("tool-diameter")?)?,
        relative_offset: row("relative-offset")?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROW: &str = "0 0 1.5 0 0 0 0 0 0";

    fn fields(offset: &str) -> Vec<(&str, &str)> {
        vec![
            ("optional-stop", "1"),
            ("block-delete", "0"),
            ("tool-offset", offset),
            ("tool-diameter", "0.25"),
            ("relative-offset", ROW),
        ]
    }

    #[test]
    fn panel_keys_read_back_and_bad_rows_are_refused() {
        let p = parse_panel(&fields(ROW)).unwrap();
        assert!(p.optional_stop && !p.block_delete);
        assert_eq!((p.tool_offset[2], p.tool_diameter), (1.5, 0.25));
        let e = parse_panel(&fields("1 2")).unwrap_err().to_string();
        assert!(e.contains("tool-offset has 2 numbers, not 9"), "{e}");
        let e = parse_panel(&fields("0 0 x 0 0 0 0 0 0"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("tool-offset: 'x' is not a number"), "{e}");
        let e = parse_panel(&fields(ROW)[..2]).unwrap_err().to_string();
        assert!(e.contains("no tool-offset"), "{e}");
    }
}
