//! `message`: prints a message (from `messages=`, one per instance) when
//! `trigger` takes the active level (`edge` TRUE: rising, FALSE:
//! falling), and again on a rising edge of `force` while the trigger is
//! active.
//!
//! `loadrt message names=oillow,nopressure messages="Slideway oil
//! low,No oil pressure"`; at most 16 instances, each needing a message.

use std::borrow::Cow;

use hal_core::module::{ModuleArgs, ParamDecl, ParamKind};
use hal_core::{Host, Result};

use crate::halcomp::{instance_names, load_instances, Inst};
use crate::notice::Notice;

/// Most instances (messages).
pub const MAX_MESSAGES: usize = 16;

/// The trigger logic.
#[derive(Debug, Clone)]
pub struct Message {
    prev_trigger: bool,
    prev_force: bool,
    prev_edge: bool,
}

impl Default for Message {
    /// LinuxCNC's initial state (the first call sees `force` FALSE as a
    /// change, which shows nothing).
    fn default() -> Self {
        Message {
            prev_trigger: false,
            prev_force: true,
            prev_edge: true,
        }
    }
}

impl Message {
    /// One call: TRUE when the message is to be shown.
    pub fn step(&mut self, trigger: bool, force: bool, edge: bool) -> bool {
        let mut show = false;
        if self.prev_edge != edge {
            self.prev_edge = edge;
            self.prev_trigger = !edge;
        }
        if force != self.prev_force {
            self.prev_force = force;
            if force && trigger == edge {
                show = true;
            }
        }
        if trigger != self.prev_trigger {
            self.prev_trigger = trigger;
            if trigger == edge {
                show = true;
            }
        }
        show
    }
}

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[
    crate::halcomp::PARAMS[0],
    crate::halcomp::PARAMS[1],
    ParamDecl {
        name: "messages",
        kind: ParamKind::StrArray(MAX_MESSAGES),
        help: "the message of each instance, comma separated",
    },
];

/// The `message` module.
pub static MODULE: hal_core::ModuleDef = hal_core::ModuleDef {
    name: "message",
    params: PARAMS,
    help: "display a message",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = instance_names(MODULE.name, args)?;
    let messages = args.str_array("messages");
    let instances = names.into_iter().map(|n| (n, 0)).collect();
    load_instances(host, MODULE.name, instances, |inst, i| {
        if i >= MAX_MESSAGES {
            return Err(inst.bad_param(
                "count",
                format!("{} instances asked for, at most {MAX_MESSAGES}", i + 1),
            ));
        }
        let Some(text) = messages.get(i) else {
            return Err(inst.bad_param(
                "messages",
                format!("no message for instance {i} ({})", inst.prefix),
            ));
        };
        build(inst, format!("{text}\n"))
    })
}

fn build(inst: &mut Inst<'_, '_>, text: String) -> Result<()> {
    let trigger = inst.pin_in::<bool>("trigger")?;
    let force = inst.pin_in::<bool>("force")?;
    let edge = inst.param_rw::<bool>("edge", true)?;
    let notice = Notice::with_texts(vec![Cow::Owned(text)]);
    let mut m = Message::default();
    inst.funct("_", false, move |_| {
        if m.step(trigger.get(), force.get(), edge.get()) {
            notice.post(0);
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::Bit;

    #[test]
    fn shows_on_the_active_edge_and_when_forced() {
        let mut m = Message::default();
        assert!(!m.step(false, false, true));
        assert!(m.step(true, false, true), "rising edge");
        assert!(!m.step(true, false, true));
        assert!(m.step(true, true, true), "forced again while active");
        assert!(!m.step(false, true, true));
        // Falling-edge messages.
        let mut m = Message::default();
        assert!(!m.step(true, false, false), "edge changed: armed, no show");
        assert!(m.step(false, false, false));
    }

    #[test]
    fn pins_and_bad_parameters() {
        let mut h = TestHost::new("message");
        for bad in [
            &["names=a,b", "messages=only one"][..],
            &["count=17", "messages=x"],
            &["count=1", "names=x", "messages=m"],
        ] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(
            &MODULE,
            &["names=oillow,nopress", "messages=Oil low,No pressure"],
        )
        .unwrap();
        h.check_pins("oillow", &["trigger bit in 0", "force bit in 0"]);
        h.check_params("oillow", &["edge bit rw 1"]);
        assert_eq!(h.functs(), ["nopress", "oillow"]);
        h.thread(&["oillow"]);
        h.set("oillow.trigger", Bit(true));
        h.run(2);
    }
}
