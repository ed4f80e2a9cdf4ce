//! Input debouncing: `debounce` (LinuxCNC's C component: groups of
//! filters sharing one `delay` param, sized by `cfg=`) and `dbounce` (the
//! halcompile variant with one filter and a `delay` pin per instance).

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Param, Pin, Result, Rw};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Most groups `cfg=` takes.
pub const MAX_GROUPS: usize = 8;
/// Most filters in one group.
pub const MAX_FILTERS: i64 = 50;
/// Default `delay`.
pub const DEFAULT_DELAY: u32 = 5;

/// One debounce filter: an integrator that must climb to `delay` before
/// `out` goes TRUE and fall back to 0 before it goes FALSE.
#[derive(Debug, Clone, Default)]
pub struct Debouncer {
    /// The integrator, 0..=delay while delay is unchanged.
    state: u32,
}

impl Debouncer {
    /// One call: returns the new `out` if this call writes it.
    ///
    /// With delay d, `out` rises on the (d+1)-th consecutive TRUE input
    /// (from a settled FALSE state) and falls on the (d+1)-th consecutive
    /// FALSE one; d = 0 passes the input straight through.
    pub fn step(&mut self, input: bool, delay: u32) -> Option<bool> {
        if input {
            if self.state < delay {
                self.state += 1;
                None
            } else {
                Some(true)
            }
        } else if self.state > 0 {
            self.state -= 1;
            None
        } else {
            Some(false)
        }
    }
}

/// The `delay` the C component uses: a negative param is rewritten to 1.
/// Returns the delay and whether the param must be rewritten.
pub fn group_delay(delay: i32) -> (u32, bool) {
    if delay < 0 {
        (1, true)
    } else {
        (delay as u32, false)
    }
}

/// Group sizes from `cfg=`: the items up to the first 0, each 1..=50,
/// at least one group.
pub fn group_sizes(cfg: &[i64]) -> Result<Vec<usize>> {
    let bad = |reason: String| HalError::ModuleParam {
        module: "debounce".into(),
        param: "cfg".into(),
        reason,
    };
    let sizes: Vec<i64> = cfg.iter().copied().take_while(|&n| n != 0).collect();
    if sizes.is_empty() {
        return Err(bad(
            "no groups given; use cfg=N0[,N1,...] with 1 to 50 filters per group".into(),
        ));
    }
    sizes
        .into_iter()
        .enumerate()
        .map(|(g, n)| {
            if (1..=MAX_FILTERS).contains(&n) {
                Ok(n as usize)
            } else {
                Err(bad(format!(
                    "group {g} has {n} filters; each group takes 1 to {MAX_FILTERS}"
                )))
            }
        })
        .collect()
}

const DEBOUNCE_PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "cfg",
    kind: ParamKind::IntArray(MAX_GROUPS),
    help: "number of filters in each group (1-50), up to 8 groups",
}];

/// The `debounce` module.
pub static DEBOUNCE: ModuleDef = ModuleDef {
    name: "debounce",
    params: DEBOUNCE_PARAMS,
    help: "groups of debounce filters, each group with one delay",
    load: load_debounce,
};

/// One filter of a group with its pins.
struct Filter {
    input: Pin<bool, In>,
    out: Pin<bool, Out>,
    logic: Debouncer,
}

fn load_debounce(host: &Host, args: &ModuleArgs) -> Result<()> {
    let sizes = group_sizes(args.int_array("cfg"))?;
    let mut b = host.new_rt_component("debounce")?;
    for (g, &n) in sizes.iter().enumerate() {
        let c = b.component();
        let mut filters = Vec::with_capacity(n);
        for f in 0..n {
            filters.push(Filter {
                input: c.pin(&format!("debounce.{g}.{f}.in"))?,
                out: c.pin(&format!("debounce.{g}.{f}.out"))?,
                logic: Debouncer::default(),
            });
        }
        let delay: Param<i32, Rw> =
            c.param(&format!("debounce.{g}.delay"), DEFAULT_DELAY as i32)?;
        b.funct(&format!("debounce.{g}"), false, move |_| {
            let (d, rewrite) = group_delay(delay.get());
            if rewrite {
                delay.set(d as i32);
            }
            for f in filters.iter_mut() {
                if let Some(v) = f.logic.step(f.input.get(), d) {
                    f.out.set(v);
                }
            }
        })?;
    }
    b.ready()
}

/// The `dbounce` component.
pub struct DbounceComp;
impl HalComp for DbounceComp {
    const NAME: &'static str = "dbounce";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let input = inst.pin_in::<bool>("in")?;
        let out = inst.pin_out::<bool>("out")?;
        let delay = inst.pin_in_init::<u32>("delay", DEFAULT_DELAY)?;
        let mut logic = Debouncer::default();
        inst.funct("_", false, move |_| {
            if let Some(v) = logic.step(input.get(), delay.get()) {
                out.set(v);
            }
        })
    }
}
halcomp_module!(pub DBOUNCE, DbounceComp, "debounce filter with a delay pin");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

    /// Runs a filter over `inputs`, returning `out` per call.
    fn run(delay: u32, inputs: &[bool]) -> Vec<bool> {
        let mut d = Debouncer::default();
        let mut out = false;
        inputs
            .iter()
            .map(|&x| {
                if let Some(v) = d.step(x, delay) {
                    out = v;
                }
                out
            })
            .collect()
    }

    #[test]
    fn output_changes_on_the_delay_plus_first_sample() {
        let r = run(3, &[true, true, true, true, false, false, false, false]);
        assert_eq!(r, [false, false, false, true, true, true, true, false]);
    }

    #[test]
    fn zero_delay_passes_through() {
        let ins = [true, false, true, true, false];
        assert_eq!(run(0, &ins), ins);
    }

    #[test]
    fn glitches_are_integrated_away() {
        let r = run(2, &[true, false, true, false, true, true, true]);
        // Integrator: 1, 0, 1, 0, 1, 2, then TRUE.
        assert_eq!(r, [false, false, false, false, false, false, true]);
    }

    #[test]
    fn negative_group_delay_becomes_one() {
        assert_eq!(group_delay(-5), (1, true));
        assert_eq!(group_delay(0), (0, false));
        assert_eq!(group_delay(7), (7, false));
    }

    #[test]
    fn cfg_is_checked() {
        assert_eq!(group_sizes(&[2]).unwrap(), [2]);
        assert_eq!(group_sizes(&[2, 50, 0, 7]).unwrap(), [2, 50]);
        assert!(group_sizes(&[]).is_err());
        assert!(group_sizes(&[0, 3]).is_err());
        assert!(group_sizes(&[51]).is_err());
        assert!(group_sizes(&[3, -1]).is_err());
    }

    #[test]
    fn debounce_loads_groups_and_fails_cleanly() {
        let host = testing::host();
        let err = testing::load(&host, &DEBOUNCE, &[]).unwrap_err();
        assert!(
            matches!(&err, HalError::ModuleParam { param, .. } if param == "cfg"),
            "{err}"
        );
        assert!(testing::load(&host, &DEBOUNCE, &["cfg=1,2,3,4,5,6,7,8,9"]).is_err());
        assert!(testing::load(&host, &DEBOUNCE, &["cfg=2,60"]).is_err());
        assert!(testing::pin_names(&host).is_empty());
        testing::load(&host, &DEBOUNCE, &["cfg=2,1"]).unwrap();
        let pins = testing::pin_names(&host);
        for p in [
            "debounce.0.0.in",
            "debounce.0.1.out",
            "debounce.1.0.in",
            "debounce.1.0.out",
        ] {
            assert!(pins.contains(&p.to_string()), "{p}");
        }
        assert!(!pins.contains(&"debounce.1.1.in".to_string()));
        assert_eq!(testing::funct_names(&host), ["debounce.0", "debounce.1"]);
        assert_eq!(
            host.instance().param_value("debounce.1.delay").unwrap(),
            hal_core::Value::S32(5)
        );
    }

    #[test]
    fn dbounce_loads() {
        let host = testing::host();
        testing::load(&host, &DBOUNCE, &["names=db"]).unwrap();
        assert_eq!(
            host.instance().pin_value("db.delay").unwrap(),
            hal_core::Value::U32(5)
        );
    }
}
