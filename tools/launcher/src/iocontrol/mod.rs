//! iocontrol as LinuxCNC's task provides it: the `iocontrol.0.*` pins, the
//! emergency-stop chain (`user-enable-out` → external chain →
//! `emc-enable-in`, with `user-request-enable` pulsed on a reset),
//! coolant, lube, and the tool prepare and tool change handshakes against
//! the tool table, for random and non-random changers.
//!
//! [`IoControl`] is the logic, free of HAL: requests come in, inputs are
//! stepped once per cycle, outputs are read back. [`IoPins`] binds it to a
//! user-space HAL component named `iocontrol`. With `[EMCIO]EMCIO = iov2`
//! it speaks LinuxCNC's second tool changer protocol too ([`v2`]).

pub mod tooltable;
pub mod v2;

use std::path::PathBuf;

use hal_core::{Component, ComponentKind, In, Instance, Out, Pin};

pub use tooltable::ToolTable;
pub use v2::Flavour;
use v2::{state, V2Inputs, V2Outputs, V2Pins, V2State};

/// What task asks iocontrol to do (LinuxCNC's `EMC_IO_*`, `EMC_TOOL_*`,
/// `EMC_COOLANT_*`, `EMC_LUBE_*` and `EMC_AUX_ESTOP_*` messages).
#[derive(Debug, Clone, PartialEq)]
pub enum IoRequest {
    /// Assert the e-stop: `user-enable-out` off, every output safe.
    EstopOn,
    /// Release the e-stop: `user-enable-out` on and a one-cycle pulse on
    /// `user-request-enable`.
    EstopOff,
    /// Every output back to its initial value.
    Init,
    /// Stop coolant and any tool handshake in progress.
    Abort,
    /// Prepare tool `tool` (T word; 0 unloads on a non-random changer).
    Prepare {
        /// The tool number.
        tool: i32,
    },
    /// Change to the prepared tool (M6).
    Load,
    /// The very start of an M6, before the spindle stops or the machine
    /// moves to the change position (`start-change`; iov2 with
    /// `-support-start-change` only, done at once otherwise).
    StartChange,
    /// Declare tool `tool` in the spindle without a change (M61).
    SetNumber {
        /// The tool number.
        tool: i32,
    },
    /// Mist coolant on or off.
    Mist(bool),
    /// Flood coolant on or off.
    Flood(bool),
    /// Lube on or off.
    Lube(bool),
    /// G10 L1/L10/L11 (LinuxCNC's `EMC_TOOL_SET_OFFSET`): the offsets,
    /// diameter, angles and orientation of the tool in table slot `slot`
    /// (the interpreter's index: 0 the spindle), written to the tool
    /// table file.
    SetEntry {
        /// The table slot.
        slot: i32,
        /// The values, machine units.
        entry: rs274ngc::ToolEntry,
    },
}

/// How a request went.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Started {
    /// Done at once.
    Done,
    /// A handshake was started; [`IoControl::step`] reports its end.
    Waiting(Handshake),
}

/// A handshake with the HAL side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Handshake {
    /// `tool-prepare` is waiting for `tool-prepared`.
    Prepare,
    /// `tool-change` is waiting for `tool-changed`.
    Change,
    /// `start-change` is waiting for `start-change-ack`.
    StartChange,
}

/// Why a request was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum IoError {
    /// The tool is not in the tool table.
    #[error("tool {tool} is not in the tool table")]
    NoSuchTool {
        /// The tool number asked for.
        tool: i32,
    },
    /// M6 without a prepared tool.
    #[error("no tool is prepared (prepare one first)")]
    NothingPrepared,
    /// A handshake is already running.
    #[error("a tool {0:?} handshake is already in progress")]
    Busy(Handshake),
    /// G10 L1 for a table slot that holds no tool.
    #[error("tool table slot {slot} holds no tool")]
    EmptySlot {
        /// The slot asked for.
        slot: i32,
    },
}

/// Inputs read once per cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IoInputs {
    /// `emc-enable-in`: FALSE while the e-stop chain is open.
    pub emc_enable_in: bool,
    /// `tool-prepared`.
    pub tool_prepared: bool,
    /// `tool-changed`.
    pub tool_changed: bool,
    /// `lube_level`.
    pub lube_level: bool,
    /// The iov2 protocol's inputs (all low without it).
    pub v2: V2Inputs,
}

/// Outputs, as the pins show them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IoOutputs {
    /// `user-enable-out`.
    pub user_enable_out: bool,
    /// `user-request-enable`.
    pub user_request_enable: bool,
    /// `coolant-mist`.
    pub coolant_mist: bool,
    /// `coolant-flood`.
    pub coolant_flood: bool,
    /// `lube`.
    pub lube: bool,
    /// `tool-prepare`.
    pub tool_prepare: bool,
    /// `tool-prep-number`.
    pub tool_prep_number: i32,
    /// `tool-prep-pocket`.
    pub tool_prep_pocket: i32,
    /// `tool-prep-index`: the table slot being prepared.
    pub tool_prep_index: i32,
    /// `tool-from-pocket`: the pocket the tool in the spindle came from
    /// (0: none, or the spindle).
    pub tool_from_pocket: i32,
    /// `tool-number`: the tool in the spindle.
    pub tool_number: i32,
    /// `tool-change`.
    pub tool_change: bool,
    /// `state` (iov2 only): one of [`v2::state`].
    pub state: i32,
    /// The iov2 protocol's outputs.
    pub v2: V2Outputs,
}

/// The end of a handshake, reported by [`IoControl::step`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IoEvent {
    /// The prepare handshake finished.
    Prepared {
        /// The prepared tool.
        tool: i32,
    },
    /// The change handshake finished: `tool` is in the spindle.
    Changed {
        /// The tool now in the spindle.
        tool: i32,
    },
    /// The changer acknowledged the start of a change (iov2).
    StartChangeAcked,
    /// The change was given up because the changer had faulted (iov2):
    /// the tool in the spindle is unchanged. A positive reason is a soft
    /// fault, the program goes on; otherwise it stops.
    ChangeFaulted {
        /// `toolchanger-reason` as the change was given up.
        reason: i32,
    },
}

/// iocontrol's logic.
#[derive(Debug, Clone)]
pub struct IoControl {
    out: IoOutputs,
    table: ToolTable,
    /// The slot prepared, if any (LinuxCNC's `pocketPrepped`, -1 = none).
    prepped: Option<usize>,
    tool_in_spindle: i32,
    /// `user-request-enable` was raised this cycle; it drops next cycle.
    pulse: bool,
    /// Where a random changer's table is saved after each change.
    save_to: Option<tooltable::SaveTo>,
    /// `io` or `iov2`, and iov2's options.
    flavour: Flavour,
    /// iov2's remembered fault reason.
    v2: V2State,
}

impl IoControl {
    /// iocontrol with `table`. A non-random changer starts with an empty
    /// spindle (tool 0); a random one with the tool the table puts in
    /// pocket 0, or -1 when the table has nothing there (LinuxCNC 2.9's
    /// number for an empty tool table entry).
    pub fn new(table: ToolTable, save_to: Option<PathBuf>) -> IoControl {
        let tool_in_spindle = if table.random {
            random_spindle_tool(&table)
        } else {
            0
        };
        let mut io = IoControl {
            out: IoOutputs::default(),
            table,
            prepped: None,
            tool_in_spindle,
            pulse: false,
            save_to: save_to.map(tooltable::SaveTo::new),
            flavour: Flavour::IO,
            v2: V2State::default(),
        };
        if !io.table.random {
            io.table.put(0, None);
        }
        io.out.tool_number = tool_in_spindle;
        io
    }

    /// Speaks `flavour`'s protocol (plain `io` until this is called).
    pub fn set_flavour(&mut self, flavour: Flavour) {
        self.flavour = flavour;
    }

    /// The outputs.
    pub fn outputs(&self) -> &IoOutputs {
        &self.out
    }

    /// The tool table.
    pub fn table(&self) -> &ToolTable {
        &self.table
    }

    /// Stops write-backs of the table until a reload reads its file
    /// completely: called when a reload failed (the table in use stays)
    /// and when the start read it only in part. The file on disk is the
    /// user's, half edited; writing it would destroy their edit.
    pub fn hold_write_back(&mut self) {
        if let Some(s) = &mut self.save_to {
            s.set_read_complete(false);
        }
    }

    /// Replaces the tool table (reloaded from its file), keeping the tool
    /// in the spindle.
    pub fn reload(&mut self, table: ToolTable) {
        let spindle = self.tool_in_spindle;
        self.table = table;
        if let Some(s) = &mut self.save_to {
            s.set_read_complete(true);
        }
        if !self.table.random {
            let in_spindle = self
                .table
                .slot_of(spindle)
                .and_then(|s| self.table.tool(s).cloned());
            self.table.put(0, in_spindle);
        }
    }

    /// iov2's fault as the interpreter sees it (#5600 and #5601):
    /// `toolchanger-faulted` as 1 or 0, and the changer's last fault
    /// reason (0 once cleared). Both 0 under plain `io`.
    pub fn toolchanger_fault(&self) -> (i32, i32) {
        (i32::from(self.out.v2.toolchanger_faulted), self.v2.reason)
    }

    /// The tool in the spindle (0: none on a non-random changer; -1: an
    /// empty pocket 0 on a random one).
    pub fn tool_in_spindle(&self) -> i32 {
        self.tool_in_spindle
    }

    /// The table slot prepared, if any (LinuxCNC's `pocketPrepped`).
    pub fn prepped_slot(&self) -> Option<usize> {
        self.prepped
    }

    /// The tool prepared, if any.
    pub fn prepared_tool(&self) -> Option<i32> {
        self.prepped.map(|s| self.prep_number_of(s))
    }

    /// The handshake running, if any.
    pub fn busy(&self) -> Option<Handshake> {
        if self.out.tool_change {
            Some(Handshake::Change)
        } else if self.out.v2.start_change {
            Some(Handshake::StartChange)
        } else if self.out.tool_prepare {
            Some(Handshake::Prepare)
        } else {
            None
        }
    }

    /// The pocket number of a table slot: the slot itself on a random
    /// changer, the tool's P on a non-random one (0 for the spindle).
    fn pocket_of_slot(&self, slot: usize) -> i32 {
        if self.table.random {
            slot as i32
        } else if slot == 0 {
            0
        } else {
            self.table.tool(slot).map_or(0, |t| t.pocket)
        }
    }

    fn prep_number_of(&self, slot: usize) -> i32 {
        if !self.table.random && slot == 0 {
            0
        } else {
            self.table.tool(slot).map_or(0, |t| t.number)
        }
    }

    /// Outputs back to their start values (LinuxCNC's `hal_init_pins`);
    /// `tool-number` keeps the tool in the spindle.
    fn init_pins(&mut self) {
        self.out = IoOutputs {
            tool_number: self.out.tool_number,
            tool_from_pocket: self.out.tool_from_pocket,
            ..IoOutputs::default()
        };
        self.pulse = false;
    }

    /// Takes a request.
    pub fn request(&mut self, req: &IoRequest) -> Result<Started, IoError> {
        match *req {
            IoRequest::EstopOn => {
                self.init_pins();
                self.prepped = None;
            }
            IoRequest::EstopOff => {
                self.out.user_enable_out = true;
                self.out.user_request_enable = true;
                self.pulse = true;
            }
            IoRequest::Init => self.init_pins(),
            IoRequest::Abort => {
                self.out.coolant_mist = false;
                self.out.coolant_flood = false;
                // The changer hears of the abort before its request lines
                // drop, so that it cannot take the drop for a completion.
                if self.flavour.v2 {
                    self.out.v2.emc_reason = v2::REASON_TASK_ABORT;
                    self.out.v2.emc_abort = true;
                }
                self.out.tool_change = false;
                self.out.tool_prepare = false;
                self.out.v2.start_change = false;
                self.out.state = if self.flavour.v2 {
                    state::WAIT_FOR_ABORT_ACK
                } else {
                    state::IDLE
                };
            }
            IoRequest::StartChange => {
                if self.flavour.start_change {
                    if let Some(h) = self.busy() {
                        return Err(IoError::Busy(h));
                    }
                    self.out.v2.start_change = true;
                    self.out.state = state::START_CHANGE;
                    return Ok(Started::Waiting(Handshake::StartChange));
                }
            }
            IoRequest::Mist(on) => self.out.coolant_mist = on,
            IoRequest::Flood(on) => self.out.coolant_flood = on,
            IoRequest::Lube(on) => self.out.lube = on,
            IoRequest::SetEntry { slot, ref entry } => self.set_entry(slot, entry)?,
            IoRequest::Prepare { tool } => return self.prepare(tool),
            IoRequest::Load => return self.load(),
            IoRequest::SetNumber { tool } => {
                let slot = self.slot_for(tool)?;
                self.load_slot(slot);
                self.tool_in_spindle = if self.table.random {
                    random_spindle_tool(&self.table)
                } else if slot == 0 {
                    0
                } else {
                    self.table.tool(0).map_or(0, |t| t.number)
                };
                self.out.tool_number = self.tool_in_spindle;
                self.out.tool_from_pocket = self.pocket_of_slot(slot);
            }
        }
        Ok(Started::Done)
    }

    /// The table slot of tool `tool` (T0 on a non-random changer: the
    /// spindle, meaning "unload").
    fn slot_for(&self, tool: i32) -> Result<usize, IoError> {
        if !self.table.random && tool == 0 {
            return Ok(0);
        }
        self.table.slot_of(tool).ok_or(IoError::NoSuchTool { tool })
    }

    fn prepare(&mut self, tool: i32) -> Result<Started, IoError> {
        if let Some(h) = self.busy() {
            return Err(IoError::Busy(h));
        }
        let slot = self.slot_for(tool)?;
        let random = self.table.random;
        self.out.tool_prep_index = slot as i32;
        self.out.tool_prep_number = self.prep_number_of(slot);
        self.out.tool_prep_pocket = self.pocket_of_slot(slot);
        if random && slot == 0 {
            // The tool is in the spindle already: nothing to fetch.
            self.prepped = Some(0);
            return Ok(Started::Done);
        }
        if !random && slot == 0 {
            // T0 on a non-random changer (unload): the spindle slot counts
            // as prepared from the request on (stat.pocket_prepped reads
            // 0 during the handshake, as LinuxCNC's); the handshake still
            // runs.
            self.prepped = Some(0);
        }
        self.out.tool_prepare = true;
        self.out.state = state::PREPARING;
        Ok(Started::Waiting(Handshake::Prepare))
    }

    fn load(&mut self) -> Result<Started, IoError> {
        if let Some(h) = self.busy() {
            return Err(IoError::Busy(h));
        }
        let slot = self.prepped.ok_or(IoError::NothingPrepared)?;
        if self.table.random && slot == 0 {
            return Ok(Started::Done);
        }
        if !self.table.random && slot > 0 && self.tool_in_spindle == self.prep_number_of(slot) {
            // Already in the spindle: nothing changes, and the tool stays
            // prepared (tool-prep-number, tool-prep-pocket and
            // stat.pocket_prepped keep it), as in LinuxCNC.
            return Ok(Started::Done);
        }
        self.out.tool_change = true;
        self.out.state = state::CHANGING;
        Ok(Started::Waiting(Handshake::Change))
    }

    /// Puts the tool of `slot` in the spindle slot: a random changer swaps
    /// the two and saves its table; a non-random one copies (or empties
    /// the spindle for slot 0).
    fn load_slot(&mut self, slot: usize) {
        if self.table.random {
            if slot >= self.table.slots.len() {
                self.table.put(slot, None);
            }
            self.table.slots.swap(0, slot);
            self.save_table();
        } else if slot == 0 {
            self.table.put(0, None);
        } else {
            let tool = self.table.tool(slot).cloned();
            self.table.put(0, tool);
        }
    }

    /// G10 L1/L10/L11: sets the values of the tool in `slot` and saves
    /// the table file. A non-random changer's spindle slot is a copy of
    /// the loaded tool: it changes, the file does not (the interpreter
    /// sets the tool's own slot too).
    fn set_entry(&mut self, slot: i32, e: &rs274ngc::ToolEntry) -> Result<(), IoError> {
        let tool = usize::try_from(slot)
            .ok()
            .and_then(|s| self.table.slots.get_mut(s))
            .and_then(Option::as_mut)
            .ok_or(IoError::EmptySlot { slot })?;
        let o = &e.offset;
        tool.offset = [o.x, o.y, o.z, o.a, o.b, o.c, o.u, o.v, o.w];
        tool.diameter = e.diameter;
        tool.front_angle = e.frontangle;
        tool.back_angle = e.backangle;
        tool.orientation = e.orientation;
        if slot > 0 || self.table.random {
            self.save_table();
        }
        Ok(())
    }

    /// Writes the table back to its file (a temporary file renamed over
    /// it), unless the last read of the file was incomplete: a table the
    /// user is fixing is never overwritten.
    fn save_table(&self) {
        match &self.save_to {
            Some(s) if !s.allowed() => eprintln!(
                "iocontrol: the tool table {} is not written back: its last read was \
                 incomplete (fix the file, then reload the tool table)",
                s.path().display()
            ),
            Some(s) => {
                // A failed save leaves the file behind the machine: say so.
                if let Err(e) = self.table.save(s.path()) {
                    eprintln!(
                        "iocontrol: saving the tool table {}: {e}",
                        s.path().display()
                    );
                }
            }
            None => {}
        }
    }

    /// One cycle: reads the inputs, ends handshakes, drops the request
    /// pulse. Returns the handshakes that ended.
    pub fn step(&mut self, inp: &IoInputs) -> Vec<IoEvent> {
        let mut events = Vec::new();
        if self.pulse {
            self.pulse = false;
        } else {
            self.out.user_request_enable = false;
        }
        if self.flavour.v2 {
            let seen = self.v2.step(&inp.v2, &mut self.out.v2);
            if seen.abort_acked {
                self.out.state = state::IDLE;
            }
            if seen.start_change_acked {
                events.push(IoEvent::StartChangeAcked);
            }
        }
        if self.out.tool_prepare && inp.tool_prepared {
            let slot = self.out.tool_prep_index.max(0) as usize;
            self.prepped = Some(slot);
            self.out.tool_prepare = false;
            self.out.state = state::IDLE;
            events.push(IoEvent::Prepared {
                tool: self.prep_number_of(slot),
            });
        }
        if self.out.tool_change && self.flavour.v2 && self.out.v2.toolchanger_faulted {
            // A fault remembered since the prepare gives the change up:
            // the changer is told why, the tool stays where it is.
            self.v2.reason = inp.v2.toolchanger_reason;
            self.out.v2.emc_reason = v2::REASON_TOOLCHANGER_FAULT;
            self.out.v2.emc_abort = true;
            self.out.tool_change = false;
            self.out.state = state::WAIT_FOR_ABORT_ACK;
            events.push(IoEvent::ChangeFaulted {
                reason: self.v2.reason,
            });
        }
        if self.out.tool_change && inp.tool_changed {
            let slot = self.prepped.unwrap_or(0);
            self.out.tool_from_pocket = self.out.tool_prep_pocket;
            self.tool_in_spindle = self.prep_number_of(slot);
            self.out.tool_number = self.tool_in_spindle;
            self.load_slot(slot);
            self.prepped = None;
            self.out.tool_prep_number = 0;
            self.out.tool_prep_pocket = 0;
            self.out.tool_prep_index = 0;
            self.out.tool_change = false;
            self.out.state = state::IDLE;
            events.push(IoEvent::Changed {
                tool: self.tool_in_spindle,
            });
        }
        events
    }
}

/// The tool a random changer's pocket 0 holds: its number, or -1 when
/// the pocket is empty (what LinuxCNC reports on `tool-number` and in
/// `stat.tool_in_spindle` then).
fn random_spindle_tool(table: &ToolTable) -> i32 {
    table.tool(0).map_or(-1, |t| t.number)
}

/// The `iocontrol.0.*` pins of a user-space component named `iocontrol`.
pub struct IoPins {
    _comp: Component,
    user_enable_out: Pin<bool, Out>,
    emc_enable_in: Pin<bool, In>,
    user_request_enable: Pin<bool, Out>,
    coolant_mist: Pin<bool, Out>,
    coolant_flood: Pin<bool, Out>,
    lube: Pin<bool, Out>,
    lube_level: Pin<bool, In>,
    tool_prepare: Pin<bool, Out>,
    tool_prepared: Pin<bool, In>,
    tool_prep_number: Pin<i32, Out>,
    tool_prep_pocket: Pin<i32, Out>,
    tool_prep_index: Pin<i32, Out>,
    /// `io` only: LinuxCNC's iov2 has no `tool-from-pocket`.
    tool_from_pocket: Option<Pin<i32, Out>>,
    tool_number: Pin<i32, Out>,
    tool_change: Pin<bool, Out>,
    tool_changed: Pin<bool, In>,
    /// iov2 only.
    state: Option<Pin<i32, Out>>,
    v2: Option<V2Pins>,
}

impl IoPins {
    /// Creates the component and the pins of `flavour` (LinuxCNC's names).
    pub fn create(inst: &Instance, flavour: Flavour) -> hal_core::Result<IoPins> {
        let c = inst.new_component("iocontrol", ComponentKind::User)?;
        let p = |n: &str| format!("iocontrol.0.{n}");
        let pins = IoPins {
            user_enable_out: c.pin(&p("user-enable-out"))?,
            user_request_enable: c.pin(&p("user-request-enable"))?,
            coolant_flood: c.pin(&p("coolant-flood"))?,
            coolant_mist: c.pin(&p("coolant-mist"))?,
            lube: c.pin(&p("lube"))?,
            tool_prepare: c.pin(&p("tool-prepare"))?,
            tool_number: c.pin(&p("tool-number"))?,
            tool_prep_number: c.pin(&p("tool-prep-number"))?,
            tool_prep_index: c.pin(&p("tool-prep-index"))?,
            tool_from_pocket: match flavour.iov2 {
                false => Some(c.pin(&p("tool-from-pocket"))?),
                true => None,
            },
            tool_prep_pocket: c.pin(&p("tool-prep-pocket"))?,
            tool_prepared: c.pin(&p("tool-prepared"))?,
            tool_change: c.pin(&p("tool-change"))?,
            tool_changed: c.pin(&p("tool-changed"))?,
            emc_enable_in: c.pin(&p("emc-enable-in"))?,
            lube_level: c.pin(&p("lube_level"))?,
            state: match flavour.iov2 {
                true => Some(c.pin(&p("state"))?),
                false => None,
            },
            v2: match flavour.v2 {
                true => Some(V2Pins::create(&c)?),
                false => None,
            },
            _comp: c,
        };
        pins._comp.ready()?;
        Ok(pins)
    }

    /// Reads the inputs.
    pub fn inputs(&self) -> IoInputs {
        IoInputs {
            emc_enable_in: self.emc_enable_in.get(),
            tool_prepared: self.tool_prepared.get(),
            tool_changed: self.tool_changed.get(),
            lube_level: self.lube_level.get(),
            v2: self.v2.as_ref().map(V2Pins::inputs).unwrap_or_default(),
        }
    }

    /// Writes the outputs.
    pub fn write(&self, o: &IoOutputs) {
        self.user_enable_out.set(o.user_enable_out);
        self.user_request_enable.set(o.user_request_enable);
        self.coolant_mist.set(o.coolant_mist);
        self.coolant_flood.set(o.coolant_flood);
        self.lube.set(o.lube);
        self.tool_prepare.set(o.tool_prepare);
        self.tool_prep_number.set(o.tool_prep_number);
        self.tool_prep_pocket.set(o.tool_prep_pocket);
        self.tool_prep_index.set(o.tool_prep_index);
        if let Some(p) = &self.tool_from_pocket {
            p.set(o.tool_from_pocket);
        }
        self.tool_number.set(o.tool_number);
        self.tool_change.set(o.tool_change);
        if let Some(p) = &self.state {
            p.set(o.state);
        }
        if let Some(p) = &self.v2 {
            p.write(&o.v2);
        }
    }
}

#[cfg(test)]
mod tests;
