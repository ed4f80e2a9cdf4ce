//! The HAL side of the update of an old-format configuration: the pin
//! names LinuxCNC renamed when joints and axes became separate (2.8,
//! `axis.N.*` to `joint.N.*` and the `halui` jog pins) and when spindles
//! got numbers (`motion.spindle-*` to `spindle.0.*`), rewritten line by
//! line as a machine's own HAL files are run. The user's files are never
//! written: each converted line keeps the number of the line it came
//! from, so an error still names the line in the file.

use hal_lang::lexer::{logical_lines, without_comment, Line};

/// World axis letters by axis number, as LinuxCNC numbers them.
pub const AXIS_LETTERS: &str = "xyzabcuvw";

/// `axis.N.NAME` pins of the old format that belong to the joint now,
/// with their new names.
const JOINT_PINS: &[(&str, &str)] = &[
    ("active", "active"),
    ("amp-enable-out", "amp-enable-out"),
    ("amp-fault-in", "amp-fault-in"),
    ("backlash-corr", "backlash-corr"),
    ("backlash-filt", "backlash-filt"),
    ("backlash-vel", "backlash-vel"),
    ("coarse-pos-cmd", "coarse-pos-cmd"),
    ("error", "error"),
    ("f-error", "f-error"),
    ("f-error-lim", "f-error-lim"),
    ("f-errored", "f-errored"),
    ("faulted", "faulted"),
    ("free-pos-cmd", "free-pos-cmd"),
    ("free-tp-enable", "free-tp-enable"),
    ("free-vel-lim", "free-vel-lim"),
    ("home-state", "home-state"),
    ("home-sw-in", "home-sw-in"),
    ("homed", "homed"),
    ("homing", "homing"),
    ("in-position", "in-position"),
    ("index-enable", "index-enable"),
    ("joint-pos-cmd", "pos-cmd"),
    ("joint-pos-fb", "pos-fb"),
    ("joint-vel-cmd", "vel-cmd"),
    ("kb-jog-active", "kb-jog-active"),
    ("motor-offset", "motor-offset"),
    ("motor-pos-cmd", "motor-pos-cmd"),
    ("motor-pos-fb", "motor-pos-fb"),
    ("neg-hard-limit", "neg-hard-limit"),
    ("neg-lim-sw-in", "neg-lim-sw-in"),
    ("pos-hard-limit", "pos-hard-limit"),
    ("pos-lim-sw-in", "pos-lim-sw-in"),
    ("wheel-jog-active", "wheel-jog-active"),
    ("unlock", "unlock"),
    ("is-unlocked", "is-unlocked"),
];

/// `axis.N.NAME` jog pins that exist now on both the joint and the axis:
/// a pin connected to one of them is connected to both.
const JOINT_AND_AXIS_PINS: &[&str] = &["jog-counts", "jog-scale", "jog-vel-mode"];

/// `halui.axis.N.NAME`, `halui.joint.N.NAME` and `halui.jog.N.NAME` pins
/// that became `halui.axis.L.NEW`.
const HALUI_AXIS_PINS: &[(&str, &str, &str)] = &[
    ("axis", "pos-commanded", "pos-commanded"),
    ("axis", "pos-feedback", "pos-feedback"),
    ("axis", "pos-relative", "pos-relative"),
    ("joint", "is-selected", "is-selected"),
    ("joint", "select", "select"),
    ("jog", "analog", "analog"),
    ("jog", "increment", "increment"),
    ("jog", "increment-minus", "increment-minus"),
    ("jog", "increment-plus", "increment-plus"),
    ("jog", "minus", "minus"),
    ("jog", "plus", "plus"),
];

/// halui pins renamed whole.
const HALUI_RENAMED: &[(&str, &str)] = &[
    (
        "halui.jog.selected.increment",
        "halui.axis.selected.increment",
    ),
    (
        "halui.jog.selected.increment-minus",
        "halui.axis.selected.increment-minus",
    ),
    (
        "halui.jog.selected.increment-plus",
        "halui.axis.selected.increment-plus",
    ),
    ("halui.jog.selected.minus", "halui.axis.selected.minus"),
    ("halui.jog.selected.plus", "halui.axis.selected.plus"),
    ("halui.jog-deadband", "halui.axis.jog-deadband"),
    ("halui.jog-speed", "halui.axis.jog-speed"),
    (
        "halui.joint.selected.is_homed",
        "halui.joint.selected.is-homed",
    ),
    (
        "halui.joint.selected.on-soft-limit",
        "halui.joint.selected.on-soft-max-limit",
    ),
];

/// `motion.spindle-NAME` pins that became `spindle.0.NAME`.
const MOTION_SPINDLE_PINS: &[&str] = &[
    "brake",
    "forward",
    "index-enable",
    "inhibit",
    "on",
    "reverse",
    "revs",
    "speed-in",
    "speed-out",
    "speed-out-abs",
    "speed-out-rps",
    "speed-out-rps-abs",
    "orient-angle",
    "orient-mode",
    "orient",
    "is-oriented",
    "orient-fault",
    "locked",
    "at-speed",
];

/// `halui.spindle.NAME` pins that became `halui.spindle.0.NAME`.
const HALUI_SPINDLE_PINS: &[&str] = &[
    "brake-is-on",
    "brake-off",
    "brake-on",
    "decrease",
    "forward",
    "increase",
    "is-on",
    "reverse",
    "runs-backward",
    "runs-forward",
    "start",
    "stop",
    "override.count-enable",
    "override.counts",
    "override.decrease",
    "override.direct-value",
    "override.increase",
    "override.scale",
    "override.value",
];

/// The joints-and-axes part of the update (configurations older than
/// [EMC]VERSION 1.0).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JointRenames {
    /// Old axis number to joint number, where they differ (a lathe's Z
    /// was axis 2 and is joint 1 now).
    pub joint_of_axis: Vec<(usize, usize)>,
    /// `[AXIS_n]` references to sections that are `[JOINT_j]` now.
    pub sections: Vec<(String, String)>,
    /// Joints with a locking indexer (motmod's `unlock_joints_mask`).
    pub unlock_joints_mask: u32,
}

/// The renames a configuration's HAL files get.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HalRenames {
    /// The joints-and-axes renames, for configurations before 1.0.
    pub joints: Option<JointRenames>,
}

impl HalRenames {
    /// The HAL file `text` with the old names replaced, as logical lines
    /// numbered as in the file, and how many lines changed.
    pub fn convert_text(&self, text: &str) -> (Vec<Line>, usize) {
        let mut out = Vec::new();
        let mut changed = 0;
        for line in logical_lines(text) {
            match self.convert_line(&line.text) {
                None => out.push(line),
                Some(new) => {
                    changed += 1;
                    out.extend(new.into_iter().map(|text| Line {
                        number: line.number,
                        text,
                    }));
                }
            }
        }
        (out, changed)
    }

    /// One logical line: `None` if it stays, else the commands it
    /// becomes (none for a line that is left out).
    pub fn convert_line(&self, line: &str) -> Option<Vec<String>> {
        let code = without_comment(line);
        let words: Vec<&str> = code.split_whitespace().collect();
        let command = words.first().copied().unwrap_or("");
        if let Some(j) = &self.joints {
            if command == "loadrt" && code.contains("kins") {
                // The kinematics module is [KINS]KINEMATICS now.
                return Some(vec!["loadrt [KINS]KINEMATICS".to_string()]);
            }
            if command == "setp" && words.get(1).is_some_and(|w| w.starts_with("gantrykins.")) {
                // gantrykins' joint map is in [KINS]KINEMATICS now.
                return Some(Vec::new());
            }
            if j.unlock_joints_mask != 0 && code.contains("servo_period_ns") {
                let mut text = self.rewrite_words(&words).join(" ");
                text.push_str(&format!(" unlock_joints_mask={}", j.unlock_joints_mask));
                return Some(vec![text]);
            }
        }
        let mut alternatives: Vec<Vec<String>> = Vec::new();
        let mut changed = false;
        let mut rewritten = Vec::new();
        for w in &words {
            let new = self.word(w);
            changed |= new.len() != 1 || new[0] != *w;
            if new.len() > 1 && command != "net" {
                alternatives.push(new.clone());
            }
            rewritten.push(new);
        }
        if !changed {
            return None;
        }
        let Some(split) = alternatives.first() else {
            return Some(vec![rewritten.concat().join(" ")]);
        };
        // A pin that became two, outside `net`: the command once for each.
        let lines = (0..split.len())
            .map(|k| {
                rewritten
                    .iter()
                    .map(|alts| alts.get(k).unwrap_or(&alts[0]).as_str())
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect();
        Some(lines)
    }

    fn rewrite_words(&self, words: &[&str]) -> Vec<String> {
        words.iter().flat_map(|w| self.word(w)).collect()
    }

    /// One word: the names it stands for now (usually one).
    fn word(&self, w: &str) -> Vec<String> {
        let spindle = spindle_pin(w);
        let Some(j) = &self.joints else {
            return vec![spindle.unwrap_or_else(|| w.to_string())];
        };
        let w = spindle.unwrap_or_else(|| w.to_string());
        let w = j.ini_references(&w);
        if let Some(new) = j.axis_pin(&w) {
            return new;
        }
        if let Some(new) = halui_pin(&w) {
            return vec![j.renumber_joint(&new)];
        }
        let w = w
            .replace("shuttlexpress", "shuttle")
            .replace("shuttlepro", "shuttle");
        vec![j.renumber_joint(&w)]
    }
}

/// `motion.spindle-NAME` and `halui.spindle.NAME` as spindle 0's pins.
fn spindle_pin(w: &str) -> Option<String> {
    if let Some(rest) = w.strip_prefix("motion.spindle-") {
        return MOTION_SPINDLE_PINS
            .contains(&rest)
            .then(|| format!("spindle.0.{rest}"));
    }
    let rest = w.strip_prefix("halui.spindle.")?;
    HALUI_SPINDLE_PINS
        .contains(&rest)
        .then(|| format!("halui.spindle.0.{rest}"))
}

/// `PREFIX.N.NAME` split, with N one axis number (0 to 8).
fn numbered<'a>(w: &'a str, prefix: &str) -> Option<(usize, &'a str)> {
    let rest = w.strip_prefix(prefix)?.strip_prefix('.')?;
    let (n, name) = rest.split_once('.')?;
    let digit = match n.as_bytes() {
        [d @ b'0'..=b'8'] => usize::from(d - b'0'),
        _ => return None,
    };
    Some((digit, name))
}

fn letter(axis: usize) -> char {
    AXIS_LETTERS.as_bytes()[axis] as char
}

/// The halui jog and position pins that belong to an axis now.
fn halui_pin(w: &str) -> Option<String> {
    if let Some((_, new)) = HALUI_RENAMED.iter().find(|(old, _)| *old == w) {
        return Some(new.to_string());
    }
    let rest = w.strip_prefix("halui.")?;
    HALUI_AXIS_PINS.iter().find_map(|(group, old, new)| {
        let (n, name) = numbered(rest, group)?;
        (name == *old).then(|| format!("halui.axis.{}.{new}", letter(n)))
    })
}

impl JointRenames {
    fn joint(&self, axis: usize) -> usize {
        self.joint_of_axis
            .iter()
            .find(|(a, _)| *a == axis)
            .map_or(axis, |(_, j)| *j)
    }

    /// `[AXIS_n]` references to what is `[JOINT_j]` now, and motmod's
    /// joint count, which is `[KINS]JOINTS` now.
    fn ini_references(&self, w: &str) -> String {
        let mut w = w.replace("num_joints=[TRAJ]AXES", "num_joints=[KINS]JOINTS");
        for (old, new) in &self.sections {
            if w.contains(old.as_str()) {
                w = w.replace(old.as_str(), new);
            }
        }
        w
    }

    /// An old `axis.N.*` pin as the joint's (and the axis's) pins.
    fn axis_pin(&self, w: &str) -> Option<Vec<String>> {
        let (n, name) = numbered(w, "axis")?;
        let joint = self.joint(n);
        if let Some((_, new)) = JOINT_PINS.iter().find(|(old, _)| *old == name) {
            return Some(vec![format!("joint.{joint}.{new}")]);
        }
        if name == "jog-enable" {
            return Some(vec![format!("axis.{}.jog-enable", letter(n))]);
        }
        JOINT_AND_AXIS_PINS.contains(&name).then(|| {
            vec![
                format!("joint.{joint}.{name}"),
                format!("axis.{}.{name}", letter(n)),
            ]
        })
    }

    /// `joint.N.*` and `halui.joint.N.*` with the joint's new number.
    fn renumber_joint(&self, w: &str) -> String {
        for prefix in ["joint", "halui.joint"] {
            if let Some((n, name)) = numbered(w, prefix) {
                let j = self.joint(n);
                if j != n {
                    return format!("{prefix}.{j}.{name}");
                }
            }
        }
        w.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joints() -> HalRenames {
        HalRenames {
            joints: Some(JointRenames {
                // A lathe: X is joint 0, Z (axis 2) joint 1.
                joint_of_axis: vec![(2, 1)],
                sections: vec![("[AXIS_2]".into(), "[JOINT_1]".into())],
                unlock_joints_mask: 0,
            }),
        }
    }

    fn line(r: &HalRenames, text: &str) -> Option<Vec<String>> {
        r.convert_line(text)
    }

    #[test]
    fn old_axis_pins_become_joint_and_axis_pins() {
        let r = joints();
        assert_eq!(
            line(
                &r,
                "net Xpos axis.0.motor-pos-cmd => axis.0.motor-pos-fb ddt.in"
            ),
            Some(vec![
                "net Xpos joint.0.motor-pos-cmd => joint.0.motor-pos-fb ddt.in".into()
            ])
        );
        assert_eq!(
            line(&r, "net j2 axis.2.joint-pos-fb => vis.z  # feedback"),
            Some(vec!["net j2 joint.1.pos-fb => vis.z".into()])
        );
        assert_eq!(
            line(&r, "setp axis.2.jog-scale 0.01"),
            Some(vec![
                "setp joint.1.jog-scale 0.01".into(),
                "setp axis.z.jog-scale 0.01".into()
            ])
        );
        assert_eq!(
            line(&r, "net counts enc.counts axis.0.jog-counts"),
            Some(vec![
                "net counts enc.counts joint.0.jog-counts axis.x.jog-counts".into()
            ])
        );
        assert_eq!(
            line(&r, "net jz halui.jog.2.plus halui.joint.2.home"),
            Some(vec!["net jz halui.axis.z.plus halui.joint.1.home".into()])
        );
        assert_eq!(
            line(&r, "setp stepgen.1.scale [AXIS_2]SCALE"),
            Some(vec!["setp stepgen.1.scale [JOINT_1]SCALE".into()])
        );
        assert_eq!(
            line(&r, "loadrt trivkins"),
            Some(vec!["loadrt [KINS]KINEMATICS".into()])
        );
        assert_eq!(
            line(&r, "loadrt motmod num_joints=[TRAJ]AXES"),
            Some(vec!["loadrt motmod num_joints=[KINS]JOINTS".into()])
        );
        assert_eq!(line(&r, "setp gantrykins.joint-1 0"), Some(vec![]));
        assert_eq!(line(&r, "net x pid.0.output => pwm.0.value"), None);
        assert_eq!(line(&r, "# axis.0.homed"), None);
    }

    #[test]
    fn spindle_pins_get_their_number_in_every_old_format() {
        let r = HalRenames::default();
        assert_eq!(
            line(&r, "net on motion.spindle-on halui.spindle.is-on"),
            Some(vec!["net on spindle.0.on halui.spindle.0.is-on".into()])
        );
        assert_eq!(
            line(
                &r,
                "net o motion.spindle-orient-fault motion.spindle-speed-out-rps-abs"
            ),
            Some(vec![
                "net o spindle.0.orient-fault spindle.0.speed-out-rps-abs".into()
            ])
        );
        // Without the joints part, axis pins stay.
        assert_eq!(line(&r, "net x axis.0.homed"), None);
    }

    #[test]
    fn a_locking_indexer_joint_is_unlockable_in_motmod() {
        let mut r = joints();
        r.joints.as_mut().unwrap().unlock_joints_mask = 8;
        assert_eq!(
            line(&r, "loadrt motmod servo_period_nsec=1000000"),
            Some(vec![
                "loadrt motmod servo_period_nsec=1000000 unlock_joints_mask=8".into()
            ])
        );
    }

    #[test]
    fn converted_lines_keep_their_line_numbers() {
        let (lines, changed) =
            joints().convert_text("# c\nsetp axis.0.jog-scale \\\n 2\nnet a b\n");
        assert_eq!(changed, 1);
        let got: Vec<(usize, &str)> = lines.iter().map(|l| (l.number, l.text.as_str())).collect();
        assert_eq!(
            got,
            [
                (1, "# c"),
                (2, "setp joint.0.jog-scale 2"),
                (2, "setp axis.x.jog-scale 2"),
                (4, "net a b")
            ]
        );
    }
}
