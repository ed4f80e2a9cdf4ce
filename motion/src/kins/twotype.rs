//! The switchable kinematics LinuxCNC builds from its `userkins.comp`
//! template with halcompile (`xyzab_tdr_kins`, `millturn`, and with a
//! third type `xyzacb_trsrn`, `xyzbca_trsrn`): two (or three) types,
//! 0 at startup, chosen at run time through `motion.switchkins-type`
//! and shown on `kinstype.is-0`, `kinstype.is-1` … (bit out, no module
//! prefix). Unlike [`super::switchkins`] every type is the module's
//! own, and there is no `coordinates=` (the joints are fixed) and no
//! `sparm=`; the module
//! takes halcompile's `count=` or `names=`, whose instances only carry
//! the template's demonstration pins. The type is KINEMATICS_BOTH
//! whatever the active type.

use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::instances::instance_names;
use hal_core::{Component, Host, ModuleArgs, Out, Pin, Result, RtComponentBuilder};

use super::loader::register;
use super::{Kinematics, KinematicsType, KinsError, KinsFlags, Pose};

/// How many types the modules offer, unless they say otherwise.
pub const TYPES: usize = 2;

/// The most types a module may offer (the trsrn modules' three).
pub const MAX_TYPES: usize = 3;

/// A module's two kinematics.
pub trait TwoTypes: Send + Sync + 'static {
    /// The module's name.
    const NAME: &'static str;

    /// How many types the module offers (at most [`MAX_TYPES`]).
    const TYPES: usize = TYPES;

    /// Forward kinematics of type `kins_type` (0 or 1).
    fn forward(
        &self,
        kins_type: usize,
        joints: &[f64],
        pose: &mut Pose,
    ) -> std::result::Result<(), KinsError>;

    /// Inverse kinematics of type `kins_type` (0 or 1).
    fn inverse(
        &self,
        kins_type: usize,
        pose: &Pose,
        joints: &mut [f64],
    ) -> std::result::Result<(), KinsError>;

    /// Whether world axis `axis` is one the module computes.
    fn has_axis(&self, axis: usize) -> Option<bool>;
}

/// A two-type module with its active type and the pins that show it.
pub struct TwoTypeKins<T> {
    /// The module's kinematics.
    pub inner: T,
    current: AtomicUsize,
    kinstype_is: Option<[Option<Pin<bool, Out>>; MAX_TYPES]>,
}

impl<T: TwoTypes> TwoTypeKins<T> {
    /// The kinematics without pins, type 0 active (for tests and tools).
    pub fn new(inner: T) -> TwoTypeKins<T> {
        TwoTypeKins {
            inner,
            current: AtomicUsize::new(0),
            kinstype_is: None,
        }
    }

    /// The active type.
    pub fn active_type(&self) -> usize {
        self.current.load(Relaxed)
    }
}

impl<T: TwoTypes> Kinematics for TwoTypeKins<T> {
    fn name(&self) -> &str {
        T::NAME
    }

    fn kins_type(&self) -> KinematicsType {
        KinematicsType::Both
    }

    fn forward(
        &self,
        joints: &[f64],
        pose: &mut Pose,
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.inner.forward(self.active_type(), joints, pose)
    }

    fn inverse(
        &self,
        pose: &Pose,
        joints: &mut [f64],
        _flags: &mut KinsFlags,
    ) -> std::result::Result<(), KinsError> {
        self.inner.inverse(self.active_type(), pose, joints)
    }

    fn has_axis(&self, axis: usize) -> Option<bool> {
        self.inner.has_axis(axis)
    }

    fn is_switchable(&self) -> bool {
        true
    }

    /// Activates one of the module's types; anything else is refused and
    /// leaves the active type alone.
    fn switch_to(&self, kins_type: i32) -> std::result::Result<(), KinsError> {
        let t = usize::try_from(kins_type)
            .ok()
            .filter(|&t| t < T::TYPES.min(MAX_TYPES))
            .ok_or(KinsError::Unsupported)?;
        self.current.store(t, Relaxed);
        if let Some(pins) = &self.kinstype_is {
            for (i, pin) in pins.iter().enumerate() {
                if let Some(pin) = pin {
                    pin.set(i == t);
                }
            }
        }
        Ok(())
    }
}

/// Loads a two-type module: the component of the module's name, the
/// pins `instance` makes for each `count=`/`names=` instance, the
/// `kinstype.is-N` pins, the kinematics' own pins made by `make`, and
/// the registration.
pub fn load<T: TwoTypes>(
    host: &Host,
    args: &ModuleArgs,
    instance: impl Fn(&mut RtComponentBuilder<'_>, &str) -> Result<()>,
    make: impl FnOnce(&Component) -> Result<T>,
) -> Result<()> {
    let prefixes = instance_names(T::NAME, args)?;
    let mut b = host.new_rt_component(T::NAME)?;
    for prefix in &prefixes {
        instance(&mut b, prefix)?;
    }
    let c = b.component();
    let mut kinstype_is = [None, None, None];
    for (i, slot) in kinstype_is.iter_mut().take(T::TYPES).enumerate() {
        *slot = Some(c.pin(&format!("kinstype.is-{i}"))?);
    }
    let kins = TwoTypeKins {
        inner: make(c)?,
        current: AtomicUsize::new(0),
        kinstype_is: Some(kinstype_is),
    };
    kins.switch_to(0)
        .map_err(|e| hal_core::HalError::ModuleLoad {
            module: T::NAME.into(),
            reason: e.to_string(),
        })?;
    register(host, b, T::NAME, Arc::new(kins))
}
