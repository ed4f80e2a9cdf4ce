//! [`MotionHandle`]: the Rust interface to the `motmod` of an instance in
//! this process, found through the [`MOTION`] registry.

use std::sync::Arc;

use crate::command::{Command, CommandResult};
use crate::events::{Event, EventRing};
use crate::mailbox::Mailbox;
use crate::registry::InstanceRegistry;

pub use crate::channel::COMMAND_TIMEOUT;

/// What a sender needs to reach a loaded `motmod`.
pub struct MotionLink {
    pub(super) mailbox: Arc<Mailbox>,
    pub(super) events: Arc<EventRing>,
    pub(super) num_joints: usize,
}

/// The `motmod` of each HAL instance.
pub static MOTION: InstanceRegistry<MotionLink> = InstanceRegistry::new("motion controller");

/// The Rust interface to a `motmod` loaded in some HAL instance of this
/// process: send commands, read reported messages.
#[derive(Clone)]
pub struct MotionHandle {
    link: Arc<MotionLink>,
}

impl std::fmt::Debug for MotionHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MotionHandle")
            .field("num_joints", &self.link.num_joints)
            .finish()
    }
}

impl MotionHandle {
    /// The handle of the `motmod` loaded in `instance`, if any.
    pub fn attach(instance: &str) -> Option<MotionHandle> {
        MOTION.get(instance).map(|(_, link)| MotionHandle { link })
    }

    /// Sends a command and waits for its result; [`crate::Reject::Timeout`]
    /// if `motion-command-handler` does not take it within
    /// [`COMMAND_TIMEOUT`] (its thread is not running).
    pub fn command(&self, cmd: Command) -> CommandResult {
        self.link.mailbox.send(cmd, COMMAND_TIMEOUT)
    }

    /// Takes the messages reported since the last call.
    pub fn events(&self) -> Vec<Event> {
        self.link.events.drain()
    }

    /// Number of joints.
    pub fn num_joints(&self) -> usize {
        self.link.num_joints
    }
}
