//! What a simulated device is besides its ESC: identity and names, the
//! object dictionary with its PDOs (from which the SII image and the
//! process image follow), its sync manager layout, and its application
//! (what the terminal or drive does with outputs and inputs each cycle).

use std::any::Any;

use super::od::{dtype, Access, Dictionary};
use crate::wire::coe::Emergency;
use crate::wire::sii::{
    self, fmmu_usage, sm_type, Identity, MailboxLayout, Pdo, PdoEntry, Sii, SyncManager,
};

/// The mailbox sync managers' place and size, for devices with CoE.
pub const MAILBOX_OUT: u16 = 0x1000;
/// The slave → master mailbox.
pub const MAILBOX_IN: u16 = 0x1080;
/// Bytes per mailbox.
pub const MAILBOX_SIZE: u16 = 128;
/// Process data outputs of mailbox devices.
pub const OUTPUTS_AT: u16 = 0x1100;
/// Process data inputs of mailbox devices.
pub const INPUTS_AT: u16 = 0x1400;

/// The application of a device: runs once per frame that reaches it.
pub trait Application: Send {
    /// One step: `outputs_valid` when the slave is in OP (outputs apply;
    /// else the device holds its safe state), `dt_ns` since the last.
    fn cycle(&mut self, od: &mut Dictionary, outputs_valid: bool, now_ns: u64, dt_ns: u64);
    /// An emergency to send, if one is pending.
    fn take_emergency(&mut self) -> Option<Emergency> {
        None
    }
    /// The application as `Any`, for tests that turn its shafts.
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// A device: its description and its application.
pub struct Device {
    /// Type name (EL1008, EK1100, servo, generic).
    pub kind: String,
    /// Identity.
    pub identity: Identity,
    /// Name in the SII: the description `ethercat slaves` prints.
    pub name: String,
    /// Order code in the SII ("EL1008"): what EtherCrab calls the name.
    pub order: String,
    /// Group.
    pub group: String,
    /// Whether it has a CoE mailbox.
    pub mailbox: bool,
    /// Whether it offers distributed clocks (SYNC0).
    pub dc: bool,
    /// Whether it refuses SAFE-OP unless the master activated SYNC0 (a
    /// drive that runs only synchronised).
    pub needs_sync0: bool,
    /// The object dictionary (process objects and PDOs even for devices
    /// without mailbox: they define the process image).
    pub od: Dictionary,
    /// Output sync manager start (master → slave process data).
    pub outputs_at: u16,
    /// Input sync manager start.
    pub inputs_at: u16,
    /// The application.
    pub app: Box<dyn Application>,
}

impl std::fmt::Debug for Device {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Device")
            .field("kind", &self.kind)
            .field("identity", &self.identity)
            .finish()
    }
}

/// Index of the output (RxPDO) sync manager assignment.
pub const ASSIGN_OUTPUTS: u16 = 0x1C12;
/// Index of the input (TxPDO) sync manager assignment.
pub const ASSIGN_INPUTS: u16 = 0x1C13;

impl Device {
    /// The process-data sync manager numbers (outputs, inputs).
    pub fn pd_sync_managers(&self) -> (u8, u8) {
        if self.mailbox {
            (2, 3)
        } else {
            let outs = self.od.assigned_bits(ASSIGN_OUTPUTS) > 0;
            // Without a mailbox the process SMs come first.
            if outs {
                (0, 1)
            } else {
                (1, 0)
            }
        }
    }

    /// Bytes of outputs and inputs with the current PDO assignment.
    pub fn image_bytes(&self) -> (usize, usize) {
        (
            self.od.assigned_bits(ASSIGN_OUTPUTS).div_ceil(8),
            self.od.assigned_bits(ASSIGN_INPUTS).div_ceil(8),
        )
    }

    /// The SII image describing this device (with its default PDOs).
    pub fn sii(&self) -> Sii {
        let (out_bytes, in_bytes) = self.image_bytes();
        let mut sms = Vec::new();
        let mut fmmus = Vec::new();
        let mut sm_of = |kind: u8| {
            sms.iter()
                .position(|s: &SyncManager| s.kind == kind)
                .unwrap_or(0) as u8
        };
        let _ = &mut sm_of;
        if self.mailbox {
            sms.push(SyncManager {
                start: MAILBOX_OUT,
                length: MAILBOX_SIZE,
                control: 0x26,
                enable: 1,
                kind: sm_type::MAILBOX_OUT,
            });
            sms.push(SyncManager {
                start: MAILBOX_IN,
                length: MAILBOX_SIZE,
                control: 0x22,
                enable: 1,
                kind: sm_type::MAILBOX_IN,
            });
            sms.push(SyncManager {
                start: self.outputs_at,
                length: out_bytes as u16,
                control: 0x64,
                enable: 1,
                kind: sm_type::OUTPUTS,
            });
            sms.push(SyncManager {
                start: self.inputs_at,
                length: in_bytes as u16,
                control: 0x20,
                enable: 1,
                kind: sm_type::INPUTS,
            });
            fmmus = vec![
                fmmu_usage::OUTPUTS,
                fmmu_usage::INPUTS,
                fmmu_usage::SM_STATUS,
            ];
        } else {
            let (o, _) = self.pd_sync_managers();
            let out_sm = SyncManager {
                start: self.outputs_at,
                length: out_bytes as u16,
                control: 0x44,
                enable: u8::from(out_bytes > 0),
                kind: sm_type::OUTPUTS,
            };
            let in_sm = SyncManager {
                start: self.inputs_at,
                length: in_bytes as u16,
                control: 0x00,
                enable: u8::from(in_bytes > 0),
                kind: sm_type::INPUTS,
            };
            if o == 0 {
                sms.push(out_sm);
                sms.push(in_sm);
            } else {
                sms.push(in_sm);
                sms.push(out_sm);
            }
            if out_bytes > 0 {
                fmmus.push(fmmu_usage::OUTPUTS);
            }
            if in_bytes > 0 {
                fmmus.push(fmmu_usage::INPUTS);
            }
        }
        let (out_sm, in_sm) = self.pd_sync_managers();
        let pdos = |assign: u16, sm: u8| -> Vec<Pdo> {
            self.od
                .assigned(assign)
                .into_iter()
                .map(|(index, entries)| Pdo {
                    index,
                    sm,
                    name: self
                        .od
                        .entry(index, 0)
                        .map(|e| e.name.clone())
                        .unwrap_or_default(),
                    flags: 0,
                    entries: entries
                        .into_iter()
                        .map(|(i, s, bits)| {
                            let e = self.od.entry(i, s);
                            PdoEntry {
                                index: i,
                                sub: s,
                                name: e.map(|e| e.name.clone()).unwrap_or_default(),
                                data_type: e.map_or(0, |e| e.data_type),
                                bits,
                            }
                        })
                        .collect(),
                })
                .collect()
        };
        Sii {
            alias: 0,
            identity: self.identity,
            mailbox: self.mailbox.then_some(MailboxLayout {
                rx_offset: MAILBOX_OUT,
                rx_size: MAILBOX_SIZE,
                tx_offset: MAILBOX_IN,
                tx_size: MAILBOX_SIZE,
                protocols: sii::protocol::COE,
            }),
            name: self.name.clone(),
            group: self.group.clone(),
            order: self.order.clone(),
            coe_details: if self.mailbox {
                sii::coe_details::SDO
                    | sii::coe_details::PDO_ASSIGN
                    | sii::coe_details::PDO_CONFIG
                    | sii::coe_details::COMPLETE_ACCESS
            } else {
                0
            },
            fmmus,
            sync_managers: sms,
            tx_pdos: pdos(ASSIGN_INPUTS, in_sm),
            rx_pdos: pdos(ASSIGN_OUTPUTS, out_sm),
            dc: self.dc,
        }
    }
}

/// One PDO: its index, name and entries (index, sub, name, type, bits;
/// index 0 is a gap).
pub struct PdoSpec<'a> {
    /// PDO index.
    pub index: u16,
    /// Name.
    pub name: &'a str,
    /// Entries.
    pub entries: Vec<(u16, u8, &'a str, u8, u8)>,
}

/// Builds the dictionary of a device: identity objects, the process
/// objects named in `pdos`, the PDO mappings and the assignments.
pub fn dictionary(
    identity: Identity,
    name: &str,
    outputs: &[PdoSpec<'_>],
    inputs: &[PdoSpec<'_>],
    assigned_out: &[u16],
    assigned_in: &[u16],
) -> Dictionary {
    let mut od = Dictionary::default();
    od.add(
        0x1000,
        0,
        "Device type",
        (dtype::U32, 32),
        Access::Ro,
        0x0000_1389,
    );
    od.add_string(0x1008, "Device name", name);
    od.add_string(0x1009, "Hardware version", "00");
    od.add_string(0x100A, "Software version", "01");
    od.add(0x1018, 0, "Identity", (dtype::U8, 8), Access::Ro, 4);
    od.add(
        0x1018,
        1,
        "Vendor ID",
        (dtype::U32, 32),
        Access::Ro,
        u64::from(identity.vendor),
    );
    od.add(
        0x1018,
        2,
        "Product code",
        (dtype::U32, 32),
        Access::Ro,
        u64::from(identity.product),
    );
    od.add(
        0x1018,
        3,
        "Revision",
        (dtype::U32, 32),
        Access::Ro,
        u64::from(identity.revision),
    );
    od.add(
        0x1018,
        4,
        "Serial number",
        (dtype::U32, 32),
        Access::Ro,
        u64::from(identity.serial),
    );
    // The sync managers' kinds, as every mailbox device lists them:
    // mailbox out (1), mailbox in (2), process data out (3) and in (4).
    // Masters read it to find which assignment object (0x1C10 + SM)
    // holds each direction's PDOs.
    od.add(
        0x1C00,
        0,
        "Sync manager type",
        (dtype::U8, 8),
        Access::Ro,
        4,
    );
    for sm in 1..=4u8 {
        od.add(
            0x1C00,
            sm,
            "Sync manager type",
            (dtype::U8, 8),
            Access::Ro,
            u64::from(sm),
        );
    }
    for (pdos, assign, assigned, access) in [
        (outputs, ASSIGN_OUTPUTS, assigned_out, Access::Rw),
        (inputs, ASSIGN_INPUTS, assigned_in, Access::Ro),
    ] {
        for p in pdos {
            od.add(
                p.index,
                0,
                p.name,
                (dtype::U8, 8),
                Access::RwPreop,
                p.entries.len() as u64,
            );
            for (k, (i, s, n, t, bits)) in p.entries.iter().enumerate() {
                let map = u64::from(*i) << 16 | u64::from(*s) << 8 | u64::from(*bits);
                od.add(
                    p.index,
                    k as u8 + 1,
                    "Entry",
                    (dtype::U32, 32),
                    Access::RwPreop,
                    map,
                );
                if *i != 0 && od.entry(*i, *s).is_none() {
                    od.add(*i, *s, n, (*t, u16::from(*bits)), access, 0);
                }
            }
            // Room for more entries when a master remaps.
            for k in p.entries.len()..8 {
                od.add(
                    p.index,
                    k as u8 + 1,
                    "Entry",
                    (dtype::U32, 32),
                    Access::RwPreop,
                    0,
                );
            }
        }
        od.add(
            assign,
            0,
            "Assignment",
            (dtype::U8, 8),
            Access::RwPreop,
            assigned.len() as u64,
        );
        for k in 0..8usize {
            let v = assigned.get(k).copied().unwrap_or(0);
            od.add(
                assign,
                k as u8 + 1,
                "Assigned PDO",
                (dtype::U16, 16),
                Access::RwPreop,
                u64::from(v),
            );
        }
    }
    od
}
