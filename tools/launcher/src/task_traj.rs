//! Two trajectory-level commands of LinuxCNC's that GUIs send to task:
//! the trajectory mode (joints one by one, coordinated, or teleop) and a
//! world axis's soft position limit, changed while the machine runs.

use motion::Command;

use crate::error::LaunchError;
use crate::task::{Task, TaskRequest};

type Answer = Result<String, LaunchError>;

/// LinuxCNC's trajectory modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrajMode {
    /// Joints one by one (jogs move joints).
    Free,
    /// Coordinated moves (programs, MDI).
    Coord,
    /// Jogs move world axes.
    Teleop,
}

/// The nine world axes X Y Z A B C U V W.
const WORLD_AXES: usize = 9;

/// Parses `traj-mode free|coord|teleop` and `axis-limit AXIS min|max
/// VALUE`; `None` when `words` is neither.
pub(crate) fn parse(words: &[&str]) -> Option<Result<TaskRequest, LaunchError>> {
    let bad = |why: &str| {
        Some(Err(LaunchError::BadArgument {
            request: if words[0] == "traj-mode" {
                "traj-mode"
            } else {
                "axis-limit"
            },
            why: why.to_string(),
        }))
    };
    match words {
        ["traj-mode", rest @ ..] => Some(Ok(TaskRequest::TrajMode(match rest {
            ["free"] => TrajMode::Free,
            ["coord"] => TrajMode::Coord,
            ["teleop"] => TrajMode::Teleop,
            _ => return bad("expected free, coord or teleop"),
        }))),
        ["axis-limit", rest @ ..] => {
            let [axis, side, value] = rest else {
                return bad("expected AXIS min|max VALUE");
            };
            let Some(axis) = axis.parse::<usize>().ok().filter(|a| *a < WORLD_AXES) else {
                return bad(&format!("axis '{axis}' is not 0 to 8 (X Y Z A B C U V W)"));
            };
            let upper = match *side {
                "min" => false,
                "max" => true,
                other => return bad(&format!("'{other}' is not min or max")),
            };
            let Some(value) = value.parse::<f64>().ok().filter(|v| v.is_finite()) else {
                return bad(&format!("limit '{value}' is not a finite number"));
            };
            Some(Ok(TaskRequest::AxisLimit { axis, upper, value }))
        }
        _ => None,
    }
}

impl Task {
    /// Takes a `traj-mode` or `axis-limit` request.
    pub(crate) fn traj_request(&mut self, req: &TaskRequest) -> Answer {
        match *req {
            TaskRequest::TrajMode(TrajMode::Free) => {
                self.panel_request(&TaskRequest::Teleop(false))
            }
            TaskRequest::TrajMode(TrajMode::Teleop) => {
                self.panel_request(&TaskRequest::Teleop(true))
            }
            TaskRequest::TrajMode(TrajMode::Coord) => {
                self.require_on()?;
                let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
                m.command(Command::Coord)
                    .map_err(|source| LaunchError::MotionRefused { source })?;
                Ok("coordinated mode".to_string())
            }
            TaskRequest::AxisLimit { axis, upper, value } => self.axis_limit(axis, upper, value),
            _ => Err(LaunchError::Program("not a trajectory request".into())),
        }
    }

    /// One soft limit of world axis `axis`, the other kept, as LinuxCNC's
    /// task sends both to motion; a lower limit above the upper one (or
    /// the reverse) is refused.
    fn axis_limit(&mut self, axis: usize, upper: bool, value: f64) -> Answer {
        let m = self.motion.as_mut().ok_or(LaunchError::NoMotion)?;
        let status = m.status().ok_or(LaunchError::NoMotion)?;
        let a = status
            .axes
            .get(axis)
            .ok_or_else(|| LaunchError::BadArgument {
                request: "axis-limit",
                why: format!("motion has no axis {axis}"),
            })?;
        let (min, max) = if upper {
            (a.min_limit, value)
        } else {
            (value, a.max_limit)
        };
        if min > max {
            return Err(LaunchError::BadArgument {
                request: "axis-limit",
                why: format!("the lower limit {min} would be above the upper limit {max}"),
            });
        }
        m.command(Command::SetAxisPositionLimits {
            axis: axis as i32,
            min,
            max,
        })
        .map_err(|source| LaunchError::MotionRefused { source })?;
        Ok(format!("axis {axis} limits {min} {max}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_are_parsed_and_bad_words_named() {
        assert_eq!(
            parse(&["traj-mode", "coord"]).unwrap().unwrap(),
            TaskRequest::TrajMode(TrajMode::Coord)
        );
        assert_eq!(
            parse(&["axis-limit", "2", "max", "1.5"]).unwrap().unwrap(),
            TaskRequest::AxisLimit {
                axis: 2,
                upper: true,
                value: 1.5
            }
        );
        let e = parse(&["axis-limit", "9", "min", "0"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("'9'"), "{e}");
        let e = parse(&["axis-limit", "0", "min", "nan"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("'nan'"), "{e}");
        let e = parse(&["traj-mode", "sideways"])
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.contains("free, coord or teleop"), "{e}");
        assert!(parse(&["teleop", "on"]).is_none());
    }
}
