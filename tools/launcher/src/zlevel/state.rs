//! z_level_compensation's cycle as a state machine without I/O but the
//! probe file: idle until enabled, load the map (again when its file's
//! time changed), compensate while enabled, then zero and pulse `clear`.

use std::path::PathBuf;
use std::time::SystemTime;

use super::interp::{Method, ProbeMap};
use super::machine::MachineView;
use super::probe;

/// The scale of `counts`: one count is this many machine units.
pub const SCALE: f64 = 0.001;

/// What one cycle reads.
#[derive(Debug, Clone, Copy)]
pub struct Inputs {
    /// `enable-in`.
    pub enable: bool,
    /// `x-pos`.
    pub x: f64,
    /// `y-pos`.
    pub y: f64,
    /// `z-pos`.
    pub z: f64,
    /// `fade-height`.
    pub fade_height: f64,
    /// `method`.
    pub method: i32,
    /// The machine, `None` when task did not answer.
    pub machine: Option<MachineView>,
}

/// What one cycle writes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outputs {
    /// `counts`.
    pub counts: i32,
    /// `scale`, when it is to be written.
    pub scale: Option<f64>,
    /// Pulse `clear`.
    pub pulse_clear: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Idle,
    Running,
    /// The map could not be loaded: off until enable-in drops.
    Failed,
}

/// The component's memory between cycles.
pub struct Controller {
    file: PathBuf,
    phase: Phase,
    map: Option<(Option<SystemTime>, ProbeMap)>,
    said_cubic: bool,
    said_outside: bool,
}

/// The fraction of the offset applied at Z height `z`.
pub fn fade(fade_height: f64, z: f64) -> f64 {
    if fade_height == 0.0 {
        1.0
    } else if z < fade_height {
        ((fade_height - z) / fade_height).min(1.0)
    } else {
        0.0
    }
}

/// `counts` for an offset and fade: truncated to counts, then faded and
/// truncated again, held to the s32 range.
pub fn counts(offset: f64, fade: f64) -> i32 {
    let whole = (offset / SCALE).trunc();
    let v = (whole * fade).trunc();
    if v.is_nan() {
        0
    } else {
        v.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    }
}

impl Controller {
    /// A controller reading its map from `file`.
    pub fn new(file: PathBuf) -> Controller {
        Controller {
            file,
            phase: Phase::Idle,
            map: None,
            said_cubic: false,
            said_outside: false,
        }
    }

    /// Whether a map is loaded and compensation runs (task's state is
    /// needed then only).
    pub fn compensating(&self) -> bool {
        self.phase == Phase::Running
    }

    /// Loads the map unless the loaded one is of the file's current time.
    fn load(&mut self) -> bool {
        let mtime = std::fs::metadata(&self.file)
            .and_then(|m| m.modified())
            .ok();
        if let Some((loaded, _)) = &self.map {
            if mtime.is_some() && *loaded == mtime {
                return true;
            }
        }
        match probe::load(&self.file) {
            Ok(points) => {
                let map = ProbeMap::new(&points);
                if map.surface().triangles().is_empty() {
                    eprintln!(
                        "z_level_compensation: {}: the points lie on one line: \
                         linear finds no offset (nearest, method 2, does)",
                        self.file.display()
                    );
                }
                self.map = Some((mtime, map));
                self.said_outside = false;
                true
            }
            Err(e) => {
                eprintln!("z_level_compensation: {e}; compensation stays off");
                self.map = None;
                false
            }
        }
    }

    /// One cycle.
    pub fn step(&mut self, i: &Inputs) -> Outputs {
        let off = Outputs {
            counts: 0,
            scale: None,
            pulse_clear: false,
        };
        match (self.phase, i.enable) {
            (Phase::Idle, false) => off,
            (Phase::Failed, true) => off,
            (Phase::Failed, false) => {
                self.phase = Phase::Idle;
                off
            }
            (Phase::Running, false) => {
                self.phase = Phase::Idle;
                Outputs {
                    pulse_clear: true,
                    ..off
                }
            }
            (Phase::Idle, true) => {
                self.phase = if self.load() {
                    Phase::Running
                } else {
                    Phase::Failed
                };
                off
            }
            (Phase::Running, true) => self.compensate(i),
        }
    }

    fn compensate(&mut self, i: &Inputs) -> Outputs {
        let Some(machine) = i.machine.filter(|m| m.on) else {
            return Outputs {
                counts: 0,
                scale: None,
                pulse_clear: false,
            };
        };
        let (method, not_here) = Method::from_pin(i.method);
        if not_here && !self.said_cubic {
            eprintln!(
                "z_level_compensation: method {} (cubic) is not available; using linear (1)",
                i.method
            );
            self.said_cubic = true;
        }
        let offset = self
            .map
            .as_ref()
            .and_then(|(_, m)| m.offset(i.x - machine.g5x.0, i.y - machine.g5x.1, method));
        let offset = offset.unwrap_or_else(|| {
            if !self.said_outside {
                eprintln!(
                    "z_level_compensation: {}: no offset at X{} Y{} (outside the probed \
                     points' triangles): 0 there",
                    self.file.display(),
                    i.x,
                    i.y
                );
                self.said_outside = true;
            }
            0.0
        });
        Outputs {
            counts: counts(offset, fade(i.fade_height, i.z)),
            scale: Some(SCALE),
            pulse_clear: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(enable: bool, x: f64, y: f64) -> Inputs {
        Inputs {
            enable,
            x,
            y,
            z: 0.0,
            fade_height: 0.0,
            method: 1,
            machine: Some(MachineView {
                on: true,
                g5x: (0.0, 0.0),
            }),
        }
    }

    fn temp_file(text: &str) -> (PathBuf, PathBuf) {
        let dir =
            std::env::temp_dir().join(format!("zlc-state-{}-{}", std::process::id(), text.len()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join(probe::FILE_NAME);
        std::fs::write(&file, text).unwrap();
        (dir, file)
    }

    #[test]
    fn fade_and_counts_by_hand() {
        assert_eq!(fade(0.0, 50.0), 1.0);
        assert_eq!(fade(10.0, 2.5), 0.75);
        assert_eq!(fade(10.0, -5.0), 1.0);
        assert_eq!(fade(10.0, 10.0), 0.0);
        assert_eq!(counts(0.0507, 1.0), 50);
        assert_eq!(counts(-0.0507, 0.5), -25);
        assert_eq!(counts(f64::NAN, 1.0), 0);
        assert_eq!(counts(1e12, 1.0), i32::MAX);
    }

    #[test]
    fn enable_loads_compensates_and_clears() {
        // The plane z = 0.01 x + 0.002 y.
        let (dir, file) = temp_file("0 0 0\n10 0 0.1\n0 10 0.02\n10 10 0.12\n");
        let mut c = Controller::new(file);
        assert_eq!(c.step(&inputs(false, 5.0, 5.0)).counts, 0);
        // The cycle that loads writes nothing yet.
        assert_eq!(c.step(&inputs(true, 5.0, 5.0)).counts, 0);
        let out = c.step(&inputs(true, 5.0, 5.0));
        assert_eq!(out.counts, 60);
        assert_eq!(out.scale, Some(SCALE));
        // G5x offset moves the lookup: X 12 - 2 = 10, Y 0: 0.1.
        let mut i = inputs(true, 12.0, 0.0);
        i.machine = Some(MachineView {
            on: true,
            g5x: (2.0, 0.0),
        });
        assert_eq!(c.step(&i).counts, 100);
        // Machine off: 0.
        i.machine = Some(MachineView {
            on: false,
            g5x: (0.0, 0.0),
        });
        assert_eq!(c.step(&i).counts, 0);
        let out = c.step(&inputs(false, 5.0, 5.0));
        assert!(out.pulse_clear);
        assert_eq!(out.counts, 0);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn a_bad_map_leaves_compensation_off_until_re_enabled() {
        let (dir, file) = temp_file("0 0 0\n10 zero 0.1\n");
        let mut c = Controller::new(file);
        for _ in 0..3 {
            assert_eq!(c.step(&inputs(true, 5.0, 5.0)).counts, 0);
        }
        assert_eq!(c.phase, Phase::Failed);
        c.step(&inputs(false, 5.0, 5.0));
        assert_eq!(c.phase, Phase::Idle);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
