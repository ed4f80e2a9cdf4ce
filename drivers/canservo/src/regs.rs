//! The "register map" of a CANopen drive: identifiers of the predefined
//! connection set, NMT and SDO command specifiers, the object dictionary
//! entries the driver uses, the statusword and controlword bits and the
//! modes of operation (hardware.md §6.2 to §6.10), plus the SocketCAN
//! error-frame classes (§6.1). Named constants only; the protocol logic
//! lives in the modules that use them.

/// Function codes of the predefined connection set: COB-ID = code + node.
pub mod cob {
    /// NMT command (master → all).
    pub const NMT: u16 = 0x000;
    /// SYNC.
    pub const SYNC: u16 = 0x080;
    /// EMCY base (+ node).
    pub const EMCY: u16 = 0x080;
    /// TIME.
    pub const TIME: u16 = 0x100;
    /// TPDO1..4 bases (+ node).
    pub const TPDO: [u16; 4] = [0x180, 0x280, 0x380, 0x480];
    /// RPDO1..4 bases (+ node).
    pub const RPDO: [u16; 4] = [0x200, 0x300, 0x400, 0x500];
    /// SDO server → client (+ node).
    pub const SDO_TX: u16 = 0x580;
    /// SDO client → server (+ node).
    pub const SDO_RX: u16 = 0x600;
    /// NMT error control: boot-up and heartbeat (+ node).
    pub const HEARTBEAT: u16 = 0x700;

    /// Splits an 11-bit COB-ID into (function base, node) for the
    /// per-node objects (EMCY, PDOs, SDO, heartbeat); None for NMT, SYNC,
    /// TIME and identifiers outside the predefined set.
    pub fn split(cob: u16) -> Option<(u16, u8)> {
        let node = (cob & 0x7F) as u8;
        let base = cob & 0x780;
        if node == 0 {
            return None;
        }
        matches!(
            base,
            0x080
                | 0x180
                | 0x200
                | 0x280
                | 0x300
                | 0x380
                | 0x400
                | 0x480
                | 0x500
                | 0x580
                | 0x600
                | 0x700
        )
        .then_some((base, node))
    }
}

/// NMT command specifiers (byte 0 of an NMT frame).
pub mod nmt {
    /// Start remote node → Operational.
    pub const START: u8 = 0x01;
    /// Stop remote node → Stopped.
    pub const STOP: u8 = 0x02;
    /// Enter pre-operational.
    pub const ENTER_PRE_OPERATIONAL: u8 = 0x80;
    /// Reset node (application and communication).
    pub const RESET_NODE: u8 = 0x81;
    /// Reset communication.
    pub const RESET_COMMUNICATION: u8 = 0x82;

    /// Heartbeat / boot-up state byte: boot-up.
    pub const STATE_BOOTUP: u8 = 0x00;
    /// Heartbeat state byte: Stopped.
    pub const STATE_STOPPED: u8 = 0x04;
    /// Heartbeat state byte: Operational.
    pub const STATE_OPERATIONAL: u8 = 0x05;
    /// Heartbeat state byte: Pre-operational.
    pub const STATE_PRE_OPERATIONAL: u8 = 0x7F;
}

/// SDO command specifiers (byte 0 of an SDO frame).
pub mod sdo {
    /// Client: upload (read) initiate.
    pub const UPLOAD_INITIATE: u8 = 0x40;
    /// Client: upload segment request, toggle in bit 4.
    pub const UPLOAD_SEGMENT: u8 = 0x60;
    /// Client: download initiate (expedited and segmented share the top
    /// bits 001).
    pub const DOWNLOAD_INITIATE: u8 = 0x20;
    /// Server: download initiate response.
    pub const DOWNLOAD_RESPONSE: u8 = 0x60;
    /// Server: download segment response, toggle in bit 4.
    pub const DOWNLOAD_SEGMENT_RESPONSE: u8 = 0x20;
    /// Either side: abort.
    pub const ABORT: u8 = 0x80;
    /// Command-specifier bits 7..5.
    pub const CS_MASK: u8 = 0xE0;
    /// Initiate: expedited bit.
    pub const EXPEDITED: u8 = 0x02;
    /// Initiate: size indicated bit.
    pub const SIZE_INDICATED: u8 = 0x01;
    /// Segment: toggle bit.
    pub const TOGGLE: u8 = 0x10;
    /// Segment: last-segment bit.
    pub const LAST: u8 = 0x01;
}

// The object dictionary, statusword and controlword bits and modes are
// the same on every fieldbus: they live in the shared CiA 402 crate.
pub use hal_cia402::objects::{cw, describe_object, mode, obj, sw};

/// SocketCAN error-frame classes (`can_id` bits of an error frame) and
/// the detail bytes the driver reads.
pub mod err {
    /// TX timeout.
    pub const TX_TIMEOUT: u32 = 0x001;
    /// Lost arbitration.
    pub const LOSTARB: u32 = 0x002;
    /// Controller problem (details in `data[1]`).
    pub const CRTL: u32 = 0x004;
    /// Protocol violation.
    pub const PROT: u32 = 0x008;
    /// Transceiver status.
    pub const TRX: u32 = 0x010;
    /// No acknowledge on transmission.
    pub const ACK: u32 = 0x020;
    /// Bus off.
    pub const BUSOFF: u32 = 0x040;
    /// Bus error.
    pub const BUSERROR: u32 = 0x080;
    /// Controller restarted.
    pub const RESTARTED: u32 = 0x100;
    /// Error counters in data[6..8].
    pub const CNT: u32 = 0x200;
    /// The classes the master asks for (§6.11 step 1).
    pub const MASTER_MASK: u32 = BUSOFF | CRTL | RESTARTED | ACK | TX_TIMEOUT;

    /// `data[1]` of a CRTL error: RX buffer overflow.
    pub const CRTL_RX_OVERFLOW: u8 = 0x01;
    /// TX buffer overflow.
    pub const CRTL_TX_OVERFLOW: u8 = 0x02;
    /// Reached RX warning level.
    pub const CRTL_RX_WARNING: u8 = 0x04;
    /// Reached TX warning level.
    pub const CRTL_TX_WARNING: u8 = 0x08;
    /// Reached RX error-passive level.
    pub const CRTL_RX_PASSIVE: u8 = 0x10;
    /// Reached TX error-passive level.
    pub const CRTL_TX_PASSIVE: u8 = 0x20;
    /// Back to error-active.
    pub const CRTL_ACTIVE: u8 = 0x40;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cob_split() {
        assert_eq!(cob::split(0x181), Some((0x180, 1)));
        assert_eq!(cob::split(0x77F), Some((0x700, 127)));
        assert_eq!(cob::split(0x080), None, "SYNC");
        assert_eq!(cob::split(0x000), None, "NMT");
        assert_eq!(cob::split(0x101), None, "TIME range is not per node");
        assert_eq!(cob::split(0x7E5), None, "LSS");
    }
}
