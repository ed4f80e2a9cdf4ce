//! The halcompile conventions, shared by every component written in that
//! style: `count=` or `names=` instances (and `personality=`), one HAL
//! component per module named as `loadrt` names it, instance prefixes
//! `<name-with-dashes>.<i>` or the given names, items `<prefix>.<item>`,
//! and functions `<prefix>` (declared `_`) or `<prefix>.<funct>`.

use hal_core::instances::{COUNT, NAMES};
use hal_core::module::{ModuleArgs, ParamDecl, ParamKind};
use hal_core::{
    FunctCtx, HalError, Host, In, Io, Out, Param, Pin, PinValue, Result, Ro, RtComponentBuilder, Rw,
};

pub use hal_core::instances::{
    hal_name, instance_names, INSTANCE_PARAMS as PARAMS, MAX_INSTANCES, MAX_INSTANCE_NAME,
};

/// Personality entries one load accepts.
pub const MAX_PERSONALITY: usize = 64;

/// A halcompile-style component.
pub trait HalComp {
    /// The `loadrt` name (`and2`, `conv_float_s32`).
    const NAME: &'static str;
    /// Whether the component takes `personality=`.
    const PERSONALITY: bool = false;
    /// The personality of an instance `personality=` does not cover
    /// (halcompile's `option default_personality`).
    const DEFAULT_PERSONALITY: i64 = 0;
    /// A singleton (halcompile's `option singleton`): no `count=` or
    /// `names=`, one instance whose prefix is the HAL name itself.
    const SINGLETON: bool = false;
    /// Builds one instance.
    fn build(inst: &mut Inst<'_, '_>) -> Result<()>;
}

/// `personality=`: one integer per instance.
pub const PERSONALITY: ParamDecl = ParamDecl {
    name: "personality",
    kind: ParamKind::IntArray(MAX_PERSONALITY),
    help: "personality of each instance",
};

/// Module parameters of a component with personality.
pub const PARAMS_PERSONALITY: &[ParamDecl] = &[COUNT, NAMES, PERSONALITY];

/// The module parameters a halcompile component declares: `count=` and
/// `names=` unless it is a singleton, `personality=` if it has one.
pub const fn params_of(personality: bool, singleton: bool) -> &'static [ParamDecl] {
    match (personality, singleton) {
        (false, false) => PARAMS,
        (true, false) => PARAMS_PERSONALITY,
        (false, true) => &[],
        (true, true) => &[PERSONALITY],
    }
}

/// Declares the `ModuleDef` of a [`HalComp`].
#[macro_export]
macro_rules! halcomp_module {
    ($vis:vis $static:ident, $ty:ty, $help:expr) => {
        #[doc = concat!("The `loadrt` entry of this component: ", $help, ".")]
        $vis static $static: hal_core::ModuleDef = hal_core::ModuleDef {
            name: <$ty as $crate::halcomp::HalComp>::NAME,
            params: $crate::halcomp::params_of(
                <$ty as $crate::halcomp::HalComp>::PERSONALITY,
                <$ty as $crate::halcomp::HalComp>::SINGLETON,
            ),
            help: $help,
            load: $crate::halcomp::load::<$ty>,
        };
    };
}

/// The channel prefixes a `num_chan=` / `names=` load asks for, for the
/// components written directly in C (encoder, sim_encoder,
/// encoder_ratio, pid, siggen); `names` is a string array param.
///
/// As in LinuxCNC: `num_chan=0` or no `num_chan` with no names means
/// `default` channels named `<base>.<i>`; a non-zero `num_chan` together
/// with a name is an error; `num_chan` must be 1..=`max`; with names, the
/// channels are the leading non-empty names (a trailing comma is
/// harmless). A non-empty name after an empty one (LinuxCNC would
/// silently drop it) is rejected, like halcompile's empty instance names.
pub fn channel_names(
    module: &str,
    base: &str,
    default: usize,
    max: usize,
    args: &ModuleArgs,
) -> Result<Vec<String>> {
    let bad = |param: &str, reason: String| HalError::ModuleParam {
        module: module.to_string(),
        param: param.to_string(),
        reason,
    };
    let given = args.str_array("names");
    let leading = given.iter().take_while(|n| !n.is_empty()).count();
    if given[leading..].iter().any(|n| !n.is_empty()) {
        return Err(bad(
            "names",
            format!("empty channel name in '{}'", given.join(",")),
        ));
    }
    let num_chan = args.int("num_chan").unwrap_or(0);
    if num_chan != 0 && leading > 0 {
        return Err(HalError::ModuleLoad {
            module: module.to_string(),
            reason: "num_chan= and names= are mutually exclusive".into(),
        });
    }
    if leading > 0 {
        return Ok(given[..leading].to_vec());
    }
    let n = if num_chan == 0 {
        default as i64
    } else {
        num_chan
    };
    if !(1..=max as i64).contains(&n) {
        return Err(bad("num_chan", format!("{n} is out of range 1-{max}")));
    }
    Ok((0..n).map(|i| format!("{base}.{i}")).collect())
}

/// The personality of the instance at `index`: entry `index % 64` of
/// `personality=`, or `default` where the list does not reach.
pub fn personality_of(args: &ModuleArgs, index: usize, default: i64) -> i64 {
    args.int_array("personality")
        .get(index % MAX_PERSONALITY)
        .copied()
        .unwrap_or(default)
}

/// Loads every instance of `C` into one HAL component.
pub fn load<C: HalComp>(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = if C::SINGLETON {
        vec![hal_name(C::NAME)]
    } else {
        instance_names(C::NAME, args)?
    };
    let instances = names
        .into_iter()
        .enumerate()
        .map(|(i, prefix)| (prefix, personality_of(args, i, C::DEFAULT_PERSONALITY)))
        .collect::<Vec<_>>();
    load_instances(host, C::NAME, instances, |inst, _| C::build(inst))
}

/// Loads the given instances (prefix and personality each) into one HAL
/// component named `comp`, calling `build` with each and its index. For
/// components whose module parameters decide the instances themselves
/// (halcompile's `option count_function`). Any error leaves nothing
/// loaded.
pub fn load_instances(
    host: &Host,
    comp: &str,
    instances: Vec<(String, i64)>,
    mut build: impl FnMut(&mut Inst<'_, '_>, usize) -> Result<()>,
) -> Result<()> {
    let mut b = host.new_rt_component(comp)?;
    for (index, (prefix, personality)) in instances.into_iter().enumerate() {
        let mut inst = Inst {
            b: &mut b,
            module: comp.to_string(),
            prefix,
            personality,
        };
        build(&mut inst, index)?;
    }
    b.ready()
}

/// One instance being built: its prefix and personality, and the means
/// to create its pins, params and functions.
pub struct Inst<'b, 'h> {
    b: &'b mut RtComponentBuilder<'h>,
    module: String,
    /// The instance prefix (`and2.0`, or the given name).
    pub prefix: String,
    /// This instance's personality (0 if none given): entry `i % 64` of
    /// `personality=` for the instance at position `i` in `count` order
    /// or the `names` list.
    pub personality: i64,
}

impl Inst<'_, '_> {
    fn item(&self, item: &str) -> String {
        format!("{}.{item}", self.prefix)
    }

    /// The length of an array declared `[max : len]`: `len` itself (a
    /// negative one makes no elements, as halcompile's loop does), or an
    /// error naming the instance when it is above `max` (halcompile
    /// refuses the load then).
    pub fn array_len(&self, max: usize, len: i64) -> Result<usize> {
        if len <= max as i64 {
            Ok(len.max(0) as usize)
        } else {
            Err(HalError::ModuleParam {
                module: self.module.clone(),
                param: "personality".into(),
                reason: format!(
                    "{}: {len} array elements asked for, at most {max} allowed",
                    self.prefix
                ),
            })
        }
    }

    /// An error about module parameter `param` of this load.
    pub fn bad_param(&self, param: &str, reason: String) -> HalError {
        HalError::ModuleParam {
            module: self.module.clone(),
            param: param.to_string(),
            reason,
        }
    }

    /// The component being built, for pins and params whose names do not
    /// follow `<prefix>.<item>`.
    pub fn component(&self) -> &hal_core::Component {
        self.b.component()
    }

    /// Exports a function under its full name.
    pub fn funct_named(
        &mut self,
        full: &str,
        uses_fp: bool,
        f: impl FnMut(&FunctCtx) + Send + 'static,
    ) -> Result<()> {
        self.b.funct(full, uses_fp, f)
    }

    /// An input pin `<prefix>.<item>` starting at zero.
    pub fn pin_in<T: PinValue>(&mut self, item: &str) -> Result<Pin<T, In>> {
        self.b.component().pin(&self.item(item))
    }

    /// An input pin `<prefix>.<item>` of type `port`: the reading end of
    /// a byte stream.
    pub fn port_in(&mut self, item: &str) -> Result<hal_core::PortIn> {
        self.b.component().port_in(&self.item(item))
    }

    /// An input pin with a default.
    pub fn pin_in_init<T: PinValue>(&mut self, item: &str, init: T) -> Result<Pin<T, In>> {
        self.b.component().pin_init(&self.item(item), init)
    }

    /// An output pin starting at zero.
    pub fn pin_out<T: PinValue>(&mut self, item: &str) -> Result<Pin<T, Out>> {
        self.b.component().pin(&self.item(item))
    }

    /// An output pin with a default.
    pub fn pin_out_init<T: PinValue>(&mut self, item: &str, init: T) -> Result<Pin<T, Out>> {
        self.b.component().pin_init(&self.item(item), init)
    }

    /// An I/O pin with a default.
    pub fn pin_io<T: PinValue>(&mut self, item: &str, init: T) -> Result<Pin<T, Io>> {
        self.b.component().pin_init(&self.item(item), init)
    }

    /// A pin whose type is chosen at load time.
    pub fn pin_raw<D: hal_core::handles::Direction>(
        &mut self,
        item: &str,
        t: hal_core::HalType,
    ) -> Result<hal_core::RawPin<D>> {
        self.b.component().pin_raw(&self.item(item), t)
    }

    /// A read-write param.
    pub fn param_rw<T: PinValue>(&mut self, item: &str, init: T) -> Result<Param<T, Rw>> {
        self.b.component().param(&self.item(item), init)
    }

    /// A read-only param.
    pub fn param_ro<T: PinValue>(&mut self, item: &str, init: T) -> Result<Param<T, Ro>> {
        self.b.component().param(&self.item(item), init)
    }

    /// Exports a function: `_` names it `<prefix>`, anything else
    /// `<prefix>.<name>`.
    pub fn funct(
        &mut self,
        name: &str,
        uses_fp: bool,
        f: impl FnMut(&FunctCtx) + Send + 'static,
    ) -> Result<()> {
        let full = if name == "_" {
            self.prefix.clone()
        } else {
            self.item(name)
        };
        self.b.funct(&full, uses_fp, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> ModuleArgs {
        ModuleArgs::parse("conv_float_s32", PARAMS, a).unwrap()
    }

    #[test]
    fn instance_naming_follows_halcompile() {
        assert_eq!(
            instance_names("conv_float_s32", &args(&[])).unwrap(),
            ["conv-float-s32.0"]
        );
        assert_eq!(
            instance_names("and2", &args(&["count=3"])).unwrap(),
            ["and2.0", "and2.1", "and2.2"]
        );
        assert_eq!(
            instance_names("and2", &args(&["names=a,b.c"])).unwrap(),
            ["a", "b.c"]
        );
        assert_eq!(
            instance_names("and2", &args(&["names="])).unwrap(),
            ["and2.0"]
        );
        assert_eq!(
            instance_names("hal_x_y", &args(&["count=0"])).unwrap(),
            ["x-y.0"]
        );
        assert!(instance_names("and2", &args(&["count=2", "names=a"])).is_err());
        assert!(instance_names("and2", &args(&["names=a,,b"])).is_err());
        assert!(instance_names("and2", &args(&[&format!("names={}", "n".repeat(48))])).is_err());
        assert!(instance_names("and2", &args(&["count=-1"])).is_err());
        assert!(instance_names("and2", &args(&["count=2000000000"])).is_err());
        assert_eq!(
            instance_names("and2", &args(&["count=4096"]))
                .unwrap()
                .len(),
            4096
        );
    }

    /// `channel_names` as encoder calls it (3 channels by default, 8 at
    /// most).
    fn chan_names(a: &[&str]) -> Result<Vec<String>> {
        use crate::encoder::{CHANNEL_PARAMS, MAX_CHAN};
        let args = ModuleArgs::parse("encoder", CHANNEL_PARAMS, a)?;
        channel_names("encoder", "encoder", 3, MAX_CHAN, &args)
    }

    #[test]
    fn channel_defaults_and_counts() {
        assert_eq!(
            chan_names(&[]).unwrap(),
            ["encoder.0", "encoder.1", "encoder.2"]
        );
        assert_eq!(chan_names(&["num_chan=0"]).unwrap().len(), 3);
        assert_eq!(chan_names(&["num_chan=1"]).unwrap(), ["encoder.0"]);
        assert_eq!(chan_names(&["num_chan=8"]).unwrap().len(), 8);
        assert_eq!(chan_names(&["names="]).unwrap().len(), 3);
        assert_eq!(chan_names(&["names=,"]).unwrap().len(), 3);
    }

    #[test]
    fn bad_channel_counts_fail_naming_the_parameter() {
        for bad in ["num_chan=9", "num_chan=-1"] {
            match chan_names(&[bad]) {
                Err(HalError::ModuleParam { param, .. }) => assert_eq!(param, "num_chan"),
                other => panic!("{bad}: {other:?}"),
            }
        }
        assert!(matches!(
            chan_names(&["num_chan=x"]),
            Err(HalError::ModuleParam { .. })
        ));
    }

    #[test]
    fn channel_names_give_prefixes() {
        assert_eq!(chan_names(&["names=x,y.z"]).unwrap(), ["x", "y.z"]);
        assert_eq!(chan_names(&["names=a,"]).unwrap(), ["a"]);
        let eight = "names=a,b,c,d,e,f,g,h";
        assert_eq!(chan_names(&[eight]).unwrap().len(), 8);
        assert!(matches!(
            chan_names(&["names=a,b,c,d,e,f,g,h,i"]),
            Err(HalError::ModuleParam { .. })
        ));
        for gap in ["names=a,,b", "names=,x"] {
            assert!(
                matches!(chan_names(&[gap]), Err(HalError::ModuleParam { .. })),
                "{gap}"
            );
        }
        // num_chan=0 is "not given", so it combines with names.
        assert_eq!(chan_names(&["num_chan=0", "names=a"]).unwrap(), ["a"]);
    }

    #[test]
    fn num_chan_and_names_are_exclusive() {
        match chan_names(&["num_chan=2", "names=a"]) {
            Err(HalError::ModuleLoad { reason, .. }) => assert!(reason.contains("exclusive")),
            other => panic!("{other:?}"),
        }
    }
}
