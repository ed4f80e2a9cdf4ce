//! LinuxCNC's `tool_offset` command: a tool's Z and X offsets, diameter,
//! front and back angles and orientation set in the tool table (which is
//! saved), as G10 L1 sets them; the interpreter takes the table again at
//! its next synch.

use crate::error::LaunchError;
use crate::iocontrol::IoRequest;
use crate::task::{Task, TaskRequest};

type Answer = Result<String, LaunchError>;

/// The values a `tool-offset` request sets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolOffset {
    /// The tool number.
    pub tool: i32,
    /// The Z offset (tool length).
    pub z: f64,
    /// The X offset.
    pub x: f64,
    /// The diameter.
    pub diameter: f64,
    /// The front angle.
    pub front_angle: f64,
    /// The back angle.
    pub back_angle: f64,
    /// The lathe orientation (0-9).
    pub orientation: i32,
}

/// Parses `tool-offset TOOL Z X DIAMETER FRONT BACK ORIENTATION`; `None`
/// when `words` is not a tool-offset request.
pub(crate) fn parse(words: &[&str]) -> Option<Result<TaskRequest, LaunchError>> {
    let ["tool-offset", rest @ ..] = words else {
        return None;
    };
    let bad = |why: String| {
        Some(Err(LaunchError::BadArgument {
            request: "tool-offset",
            why,
        }))
    };
    let [tool, z, x, diameter, front, back, orientation] = rest else {
        return bad("expected TOOL Z X DIAMETER FRONT BACK ORIENTATION".into());
    };
    let Ok(tool) = tool.parse::<i32>() else {
        return bad(format!("tool '{tool}' is not a tool number"));
    };
    let mut values = [0.0; 5];
    for (v, w) in values.iter_mut().zip([z, x, diameter, front, back]) {
        match w.parse::<f64>() {
            Ok(n) if n.is_finite() => *v = n,
            _ => return bad(format!("'{w}' is not a finite number")),
        }
    }
    let Some(orientation) = orientation
        .parse::<i32>()
        .ok()
        .filter(|o| (0..=9).contains(o))
    else {
        return bad(format!("orientation '{orientation}' is not 0 to 9"));
    };
    let [z, x, diameter, front_angle, back_angle] = values;
    Some(Ok(TaskRequest::ToolOffset(ToolOffset {
        tool,
        z,
        x,
        diameter,
        front_angle,
        back_angle,
        orientation,
    })))
}

impl Task {
    /// Sets tool `o.tool`'s values in the table; refused for a tool the
    /// table does not hold, or while a program or MDI line runs.
    pub(crate) fn tool_offset(&mut self, o: &ToolOffset) -> Answer {
        if self.program.as_ref().is_some_and(|p| !p.settled()) {
            return Err(LaunchError::BadArgument {
                request: "tool-offset",
                why: "a program or MDI line runs (abort it or wait for its end)".into(),
            });
        }
        let table = self.io.table();
        let not_in_table = || LaunchError::BadArgument {
            request: "tool-offset",
            why: format!("tool {} is not in the tool table", o.tool),
        };
        let slot = table.slot_of(o.tool).ok_or_else(not_in_table)?;
        let mut entry = table.tool(slot).ok_or_else(not_in_table)?.entry();
        entry.offset.x = o.x;
        entry.offset.z = o.z;
        entry.diameter = o.diameter;
        entry.frontangle = o.front_angle;
        entry.backangle = o.back_angle;
        entry.orientation = o.orientation;
        // A non-random changer's spindle slot is a copy of the tool loaded.
        let copy = !table.random && self.io.tool_in_spindle() == o.tool;
        self.io.request(&IoRequest::SetEntry {
            slot: slot as i32,
            entry,
        })?;
        if copy {
            self.io.request(&IoRequest::SetEntry { slot: 0, entry })?;
        }
        Ok(format!("tool {} offsets set", o.tool))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_seven_values_are_parsed_and_bad_ones_named() {
        let r = parse(&["tool-offset", "2", "1.5", "0.25", "6", "0", "0", "0"])
            .unwrap()
            .unwrap();
        let TaskRequest::ToolOffset(o) = r else {
            panic!("{r:?}")
        };
        assert_eq!((o.tool, o.z, o.x, o.diameter), (2, 1.5, 0.25, 6.0));
        let e = parse(&["tool-offset", "2", "1"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("TOOL Z X"), "{e}");
        let e = parse(&["tool-offset", "2", "inf", "0", "0", "0", "0", "0"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("'inf'"), "{e}");
        let e = parse(&["tool-offset", "2", "1", "0", "0", "0", "0", "12"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("'12'"), "{e}");
        assert!(parse(&["tool-change", "2"]).is_none());
    }
}
