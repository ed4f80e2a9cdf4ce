//! The invariant every module's `loadrt` must keep whatever its
//! arguments: it loads, or it fails leaving the instance exactly as it
//! was. The body of a fuzz target (the workspace's fuzz crate feeds it
//! arbitrary words); the crate's own property tests call it too.

use hal_core::{Host, ModuleDef};

use crate::error::CompError;

/// What the instance holds: names of components, pins, params,
/// functions and threads.
fn contents(host: &Host) -> Result<[Vec<String>; 5], CompError> {
    let inst = host.instance();
    let sorted = |mut v: Vec<String>| {
        v.sort();
        v
    };
    Ok([
        sorted(host.loaded_components()),
        sorted(inst.pins()?.into_iter().map(|p| p.name).collect()),
        sorted(inst.params()?.into_iter().map(|p| p.name).collect()),
        sorted(inst.functs()?.into_iter().map(|f| f.name).collect()),
        sorted(inst.threads()?.into_iter().map(|t| t.name).collect()),
    ])
}

/// Loads `def` with `args` into `host`. Returns whether it loaded; an
/// error describes a broken invariant (a failed load that left something
/// behind, or a success that `unloadrt` could not undo). A successful
/// load is unloaded again, threads included, so calls can follow each
/// other on one host.
pub fn loadrt_is_all_or_nothing<S: AsRef<str>>(
    host: &Host,
    def: &'static ModuleDef,
    args: &[S],
) -> Result<bool, CompError> {
    let before = contents(host)?;
    match host.loadrt(def, args) {
        Err(e) => {
            let after = contents(host)?;
            if after == before {
                Ok(false)
            } else {
                Err(CompError::LeftBehind {
                    module: def.name.to_string(),
                    cause: Box::new(e),
                    after: format!("{after:?}"),
                    before: format!("{before:?}"),
                })
            }
        }
        Ok(()) => {
            host.unloadrt(def.name).map_err(|e| CompError::Unload {
                module: def.name.to_string(),
                source: Box::new(e),
            })?;
            let [_, _, _, _, threads_before] = &before;
            let threads_now = contents(host)?[4].clone();
            for t in threads_now.iter().filter(|t| !threads_before.contains(t)) {
                host.delete_thread(t).map_err(|e| CompError::DeleteThread {
                    thread: t.clone(),
                    source: Box::new(e),
                })?;
            }
            let after = contents(host)?;
            if after == before {
                Ok(true)
            } else {
                Err(CompError::NotRestored {
                    module: def.name.to_string(),
                    after: format!("{after:?}"),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use proptest::prelude::*;

    /// The modules added for the configurations LinuxCNC ships, whose
    /// parameters go beyond `count=`/`names=`/`personality=`.
    fn modules() -> Vec<&'static ModuleDef> {
        vec![
            &crate::toolchange::carousel::MODULE,
            &crate::motor::bldc::MODULE,
            &crate::selectors::enums::MODULE,
            &crate::selectors::demux_generic::MODULE,
            &crate::selectors::multiswitch::MODULE,
            &crate::panel::matrix_kb::MODULE,
            &crate::panel::message::MODULE,
            &crate::bits::weighted_sum::MODULE,
            &crate::timing::watchdog::MODULE,
            &crate::generators::supply::MODULE,
            &crate::spindle::speed::MODULE,
            &crate::spindle::gearchange::MODULE,
            &crate::offsets::moveoff::MODULE,
            &crate::selectors::demux::MODULE,
        ]
    }

    /// Parameter names the generator picks from (any module may get any
    /// of them: unknown ones must fail cleanly too).
    const KEYS: &[&str] = &[
        "count",
        "names",
        "personality",
        "pockets",
        "encoding",
        "dir",
        "num_sense",
        "parity",
        "cfg",
        "enums",
        "config",
        "messages",
        "wsum_sizes",
        "num_inputs",
        "num_chan",
        "period",
        "numgears",
    ];

    fn word() -> impl Strategy<Value = String> {
        (0..KEYS.len(), "[-0-9a-zA-Z;,x.|%]{0,12}").prop_map(|(k, v)| format!("{}={v}", KEYS[k]))
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

        #[test]
        fn loadrt_is_all_or_nothing_for_any_words(
            m in 0usize..14,
            words in proptest::collection::vec(word(), 0..4),
        ) {
            let h = TestHost::new("loadrt-check");
            let def = modules()[m];
            if let Err(e) = loadrt_is_all_or_nothing(&h, def, &words) {
                panic!("{e}");
            }
        }
    }

    #[test]
    fn a_good_load_is_undone_and_a_bad_one_leaves_nothing() {
        let h = TestHost::new("loadrt-check-fixed");
        let supply = &crate::generators::supply::MODULE;
        assert_eq!(
            loadrt_is_all_or_nothing(&h, supply, &["period=1000000"]).ok(),
            Some(true)
        );
        assert_eq!(
            loadrt_is_all_or_nothing(&h, supply, &["num_chan=99"]).ok(),
            Some(false)
        );
        let carousel = &crate::toolchange::carousel::MODULE;
        assert_eq!(
            loadrt_is_all_or_nothing(&h, carousel, &["pockets=6,6"]).ok(),
            Some(true)
        );
        assert_eq!(
            loadrt_is_all_or_nothing(&h, carousel, &["encoding=bogus"]).ok(),
            Some(false)
        );
    }
}
