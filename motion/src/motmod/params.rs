//! `motmod`'s module parameters: their declarations and LinuxCNC's rules.

use hal_core::module::{ModuleArgs, ParamDecl, ParamKind};
use hal_core::{HalError, Result};

use crate::kins::KinematicsType;
use crate::sizes::{MAX_IO, MAX_JOINTS, MAX_MISC_ERROR, MAX_SPINDLES};

pub(super) const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "key",
        kind: ParamKind::Int,
        help: "shared memory key (accepted for compatibility; unused)",
    },
    ParamDecl {
        name: "base_period_nsec",
        kind: ParamKind::Long,
        help: "fastest thread period (nsecs); 0 = the servo period",
    },
    ParamDecl {
        name: "base_thread_fp",
        kind: ParamKind::Int,
        help: "floating point in base thread? (deprecated, ignored)",
    },
    ParamDecl {
        name: "servo_period_nsec",
        kind: ParamKind::Long,
        help: "servo thread period (nsecs), default 1000000",
    },
    ParamDecl {
        name: "traj_period_nsec",
        kind: ParamKind::Long,
        help: "trajectory planner period (nsecs); 0 = the servo period",
    },
    ParamDecl {
        name: "num_spindles",
        kind: ParamKind::Int,
        help: "number of spindles (0-8), default 1",
    },
    ParamDecl {
        name: "num_joints",
        kind: ParamKind::Int,
        help: "number of joints (1-16), default 16",
    },
    ParamDecl {
        name: "num_extrajoints",
        kind: ParamKind::Int,
        help: "number of extra joints, not used in kinematics",
    },
    ParamDecl {
        name: "num_dio",
        kind: ParamKind::Int,
        help: "number of digital inputs/outputs (1-64), default 4",
    },
    ParamDecl {
        name: "names_din",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of digital inputs",
    },
    ParamDecl {
        name: "names_dout",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of digital outputs",
    },
    ParamDecl {
        name: "num_aio",
        kind: ParamKind::Int,
        help: "number of analog inputs/outputs (1-64), default 4",
    },
    ParamDecl {
        name: "names_ain",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of analog inputs",
    },
    ParamDecl {
        name: "names_aout",
        kind: ParamKind::StrArray(MAX_IO),
        help: "names of analog outputs",
    },
    ParamDecl {
        name: "num_misc_error",
        kind: ParamKind::Int,
        help: "number of misc error inputs (0-64), default 0",
    },
    ParamDecl {
        name: "names_misc_errors",
        kind: ParamKind::StrArray(MAX_MISC_ERROR),
        help: "names of misc error inputs",
    },
    ParamDecl {
        name: "unlock_joints_mask",
        kind: ParamKind::Int,
        help: "mask to select joints for unlock pins",
    },
];

/// Digital or analog I/O pins: how many pairs and the names given.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct IoNames {
    /// Pairs of pins.
    pub count: usize,
    /// `names_din`/`names_ain`: named inputs, the rest are numbered.
    pub inputs: Vec<String>,
    /// `names_dout`/`names_aout`: named outputs, the rest are numbered.
    pub outputs: Vec<String>,
}

/// `motmod`'s module parameters, checked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MotmodParams {
    /// How many joints there are.
    pub num_joints: usize,
    /// Extra joints (homed, not in the kinematics).
    pub num_extrajoints: usize,
    /// Spindles.
    pub num_spindles: usize,
    /// Digital I/O pins.
    pub dio: IoNames,
    /// Analog I/O pins.
    pub aio: IoNames,
    /// Misc-error inputs: their names if given by name.
    pub num_misc_error: usize,
    /// names_misc_errors: the inputs given by name.
    pub misc_error_names: Vec<String>,
    /// Joints with unlock pins (bit n: joint n).
    pub unlock_joints_mask: u32,
    /// Base thread period; the base thread exists only if shorter than
    /// the servo period.
    pub base_period_nsec: i64,
    /// Servo period, a whole multiple of the base period.
    pub servo_period_nsec: i64,
    /// Trajectory period (the servo period unless given).
    pub traj_period_nsec: i64,
    /// base_thread_fp (accepted, ignored).
    pub base_thread_fp: bool,
}

fn bad(param: &str, reason: String) -> HalError {
    HalError::ModuleParam {
        module: "motmod".into(),
        param: param.into(),
        reason,
    }
}

/// LinuxCNC counts names up to the first empty one.
fn leading_names(names: &[String]) -> Vec<String> {
    names
        .iter()
        .take_while(|s| !s.is_empty())
        .cloned()
        .collect()
}

fn io_names(
    args: &ModuleArgs,
    num: &str,
    names_in: &str,
    names_out: &str,
    kind: &str,
) -> Result<IoNames> {
    let inputs = leading_names(args.str_array(names_in));
    let outputs = leading_names(args.str_array(names_out));
    let count = if !inputs.is_empty() || !outputs.is_empty() {
        if args.int(num).is_some() {
            return Err(bad(
                num,
                format!("can't specify both names and number for {kind} pins"),
            ));
        }
        inputs.len().max(outputs.len()) as i64
    } else {
        args.int(num).unwrap_or(4)
    };
    if !(1..=MAX_IO as i64).contains(&count) {
        return Err(bad(num, format!("{count} is out of range 1-{MAX_IO}")));
    }
    Ok(IoNames {
        count: count as usize,
        inputs,
        outputs,
    })
}

/// Checks `motmod`'s arguments against LinuxCNC's rules. `kins_type` is the
/// loaded kinematics' type (extra joints need `Both`).
pub fn parse_params(args: &ModuleArgs, kins_type: KinematicsType) -> Result<MotmodParams> {
    let num_joints = args.int("num_joints").unwrap_or(MAX_JOINTS as i64);
    if !(1..=MAX_JOINTS as i64).contains(&num_joints) {
        return Err(bad(
            "num_joints",
            format!("{num_joints} is out of range 1-{MAX_JOINTS}"),
        ));
    }
    let num_extrajoints = args.int("num_extrajoints").unwrap_or(0);
    if !(0..=num_joints).contains(&num_extrajoints) {
        return Err(bad(
            "num_extrajoints",
            format!("{num_extrajoints} is out of range 0-{num_joints} (num_joints)"),
        ));
    }
    if num_extrajoints > 0 && kins_type != KinematicsType::Both {
        return Err(bad(
            "num_extrajoints",
            "extra joints need KINEMATICS_BOTH kinematics (e.g. trivkins kinstype=both)".into(),
        ));
    }
    let num_spindles = args.int("num_spindles").unwrap_or(1);
    if !(0..=MAX_SPINDLES as i64).contains(&num_spindles) {
        return Err(bad(
            "num_spindles",
            format!("{num_spindles} is out of range 0-{MAX_SPINDLES}"),
        ));
    }
    let dio = io_names(args, "num_dio", "names_din", "names_dout", "digital")?;
    let aio = io_names(args, "num_aio", "names_ain", "names_aout", "analog")?;
    let misc_error_names = leading_names(args.str_array("names_misc_errors"));
    let num_misc_error = if !misc_error_names.is_empty() {
        if args.int("num_misc_error").is_some() {
            return Err(bad(
                "num_misc_error",
                "can't specify both names and number for misc error inputs".into(),
            ));
        }
        misc_error_names.len() as i64
    } else {
        args.int("num_misc_error").unwrap_or(0)
    };
    if !(0..=MAX_MISC_ERROR as i64).contains(&num_misc_error) {
        return Err(bad(
            "num_misc_error",
            format!("{num_misc_error} is out of range 0-{MAX_MISC_ERROR}"),
        ));
    }
    let servo = args.int("servo_period_nsec").unwrap_or(1_000_000);
    if servo <= 0 {
        return Err(bad(
            "servo_period_nsec",
            format!("{servo} is not a period: it must be positive"),
        ));
    }
    let mut base = args.int("base_period_nsec").unwrap_or(0);
    if base < 0 {
        return Err(bad(
            "base_period_nsec",
            format!("{base} is not a period: it must be positive (or 0 for the servo period)"),
        ));
    }
    if base == 0 {
        base = servo;
    }
    if servo < base {
        return Err(bad(
            "servo_period_nsec",
            format!("{servo} is shorter than base_period_nsec {base}"),
        ));
    }
    let mut traj = args.int("traj_period_nsec").unwrap_or(0);
    if traj < 0 {
        return Err(bad(
            "traj_period_nsec",
            format!("{traj} is not a period: it must be positive (or 0 for the servo period)"),
        ));
    }
    if traj == 0 {
        traj = servo;
    }
    // LinuxCNC rounds the servo period to a whole multiple of the base
    // period: ratio = (int)(servo_sec / base_sec + 0.5).
    let ratio = ((servo as f64 * 1e-9) / (base as f64 * 1e-9) + 0.5) as i64;
    let servo = base.checked_mul(ratio).filter(|&s| s > 0).ok_or_else(|| {
        bad(
            "servo_period_nsec",
            format!("{servo} ns is not a usable multiple of the base period {base} ns"),
        )
    })?;
    Ok(MotmodParams {
        num_joints: num_joints as usize,
        num_extrajoints: num_extrajoints as usize,
        num_spindles: num_spindles as usize,
        dio,
        aio,
        num_misc_error: num_misc_error as usize,
        misc_error_names,
        unlock_joints_mask: args.int("unlock_joints_mask").unwrap_or(0) as u32,
        base_period_nsec: base,
        servo_period_nsec: servo,
        traj_period_nsec: traj,
        base_thread_fp: args.int("base_thread_fp").unwrap_or(0) != 0,
    })
}
