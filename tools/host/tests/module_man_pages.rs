//! Section 9 man pages of every `loadrt` module, kept in packaging/man9/
//! and installed by the Debian package. Each page is generated from the
//! module's declaration in the host's registry (name, description,
//! module parameters) and from what a load of it exports in a host of
//! this test's own: the functions, pins, parameters and threads, with
//! their types, directions and first values, as `show` lists them. So a
//! page cannot drift from the module: this test fails when one does, and
//! `HAL_UPDATE_MAN=1 cargo test -p hal-host --test module_man_pages`
//! rewrites them.
//!
//! A module whose plain `loadrt NAME` needs more (a kinematics module
//! first, a `cfg=`, hardware) is loaded as its [`Example`] says; drivers
//! use their simulated backends, and the page says so.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

#[path = "man9/examples.rs"]
mod examples;
#[path = "man9/page.rs"]
mod page;

use std::collections::BTreeSet;
use std::path::PathBuf;

use examples::{example_for, HAND_WRITTEN};
use hal_host::testing::InProcessHost;
use hostmot2::sim::eth::{EthBoard, EthIdentity};
use hostmot2::sim::{boards, eth_server, machine, Hm2Model};
use page::{Listing, ModulePage};

/// The names of each kind in an instance, as `list` prints them.
fn names(host: &InProcessHost) -> BTreeSet<String> {
    let inst = host.instance();
    let mut all = BTreeSet::new();
    for kind in ["pin", "param", "funct", "thread"] {
        let text = hal_lang::format::render(&inst, "list", &[kind], false).unwrap();
        all.extend(text.split_whitespace().map(|n| format!("{kind} {n}")));
    }
    all
}

/// A simulated Ethernet board of `preset`, served on 127.0.0.1 at a port
/// of its own for as long as the value lives.
fn eth_board(preset: &str) -> Result<eth_server::Running, String> {
    let spec = boards::preset(preset).ok_or_else(|| format!("no board preset '{preset}'"))?;
    let name =
        boards::eth_name(preset).ok_or_else(|| format!("'{preset}' is no Ethernet board"))?;
    let model = Hm2Model::with_world(spec, Box::new(machine::preset(preset)));
    let board = EthBoard::new(model, EthIdentity::new(name)).with_period(1_000_000);
    eth_server::spawn(board, eth_server::Faults::default())
        .map_err(|e| format!("serving a simulated {preset}: {e}"))
}

/// Loads `module` as its example says on a host of its own and lists
/// what the load added. Errors name the module and what failed.
fn load(module: &'static hal_core::ModuleDef) -> Result<(Listing, BTreeSet<String>), String> {
    let ex = example_for(module.name);
    let host = InProcessHost::start(&format!("man9-{}", module.name));
    if !ex.before.is_empty() {
        let (ok, _, err) = host.run("before", ex.before, false);
        if !ok {
            return Err(format!("{}: before the load: {err}", module.name));
        }
    }
    let before = names(&host);
    let server = ex.eth_board.map(eth_board).transpose()?;
    let mut line = format!("loadrt {} {}", module.name, ex.args);
    if let Some(s) = &server {
        line.push_str(&format!(" board_ip={}", s.addr()));
    }
    let (ok, _, err) = host.run("load", &line, false);
    if ok == ex.fails {
        let outcome = if ok {
            "loaded, but its example must fail"
        } else {
            "failed"
        };
        return Err(format!("{}: '{line}' {outcome}: {err}", module.name));
    }
    let added: BTreeSet<String> = names(&host).difference(&before).cloned().collect();
    if ex.fails && !added.is_empty() {
        return Err(format!("{}: a failed load left {added:?}", module.name));
    }
    let listing =
        Listing::of(&host.instance(), &added).map_err(|e| format!("{}: {e}", module.name))?;
    Ok((listing, added))
}

/// Whether a hand-written page names `name`, or its numbered family
/// (`cpuN` for `cpu2`).
fn names_family(page: &str, name: &str) -> bool {
    let base = name.trim_end_matches(|c: char| c.is_ascii_digit());
    page.contains(name) || (base.len() < name.len() && page.contains(&format!("{base}N")))
}

#[test]
fn every_module_has_a_current_man_page_listing_what_it_exports() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../packaging/man9");
    let update = std::env::var_os("HAL_UPDATE_MAN").is_some();
    let registry = hal_host::registry();
    let modules = registry.names();
    let mut faults = Vec::new();
    for name in &modules {
        let module = registry.find(name).unwrap();
        let path = dir.join(format!("{name}.9"));
        let (listing, added) = match load(module) {
            Ok(l) => l,
            Err(e) => {
                faults.push(e);
                continue;
            }
        };
        let text = if HAND_WRITTEN.contains(name) {
            std::fs::read_to_string(&path).unwrap_or_default()
        } else {
            let page = ModulePage {
                module,
                example: example_for(name),
                listing: &listing,
            }
            .render();
            if update {
                std::fs::write(&path, &page).unwrap();
            }
            if std::fs::read_to_string(&path).unwrap_or_default() != page {
                faults.push(format!(
                    "{}: out of date with the module (rerun with HAL_UPDATE_MAN=1)",
                    path.display()
                ));
            }
            page
        };
        // What `list` shows after the load, every name on the page.
        let roff = text.replace("\\-", "-").replace("\\&", "");
        let missing: Vec<&String> = added
            .iter()
            .filter(|n| !roff.contains(n.split_once(' ').map_or(n.as_str(), |(_, n)| n)))
            .collect();
        if !missing.is_empty() {
            faults.push(format!("{}: does not list {missing:?}", path.display()));
        }
        for p in module.params {
            if !names_family(&roff, p.name) {
                faults.push(format!(
                    "{}: does not name parameter {}",
                    path.display(),
                    p.name
                ));
            }
        }
    }
    // No page of a module that is gone.
    for entry in std::fs::read_dir(&dir).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().into_owned();
        let module = file.trim_end_matches(".9");
        if !modules.contains(&module) {
            faults.push(format!("packaging/man9/{file} is the page of no module"));
        }
    }
    assert!(
        faults.is_empty(),
        "{} of {} modules:\n{}",
        faults.len(),
        modules.len(),
        faults.join("\n")
    );
}
