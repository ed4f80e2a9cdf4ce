//! The launcher's in-memory update of configurations in LinuxCNC's old
//! formats ([`hal_launcher::fuzz::old_format_config`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "old_format_config",
    run: hal_launcher::fuzz::old_format_config,
    dictionary: &[
        "[EMC]\nVERSION = $Revision$\n", "[TRAJ]\n", "COORDINATES = X Z\n", "AXES = 3\n",
        "[AXIS_0]\n", "[AXIS_2]\n", "HOME_SEQUENCE = ", "LOCKING_INDEXER = 1\n",
        "[RS274NGC]\nFEATURES = ", "loadrt trivkins coordinates=", "loadrt gantrykins\n",
        "setp gantrykins.joint-", "setp axis.0.jog-scale 1\n", "net s axis.2.joint-pos-fb ",
        "halui.jog.1.plus ", "halui.joint.2.home ", "motion.spindle-on ", "[AXIS_2]SCALE",
        "num_joints=[TRAJ]AXES", "servo_period_nsec=", "\\\n", "#", "\n", " ", "0", "9",
    ],
    generate: None,
};
