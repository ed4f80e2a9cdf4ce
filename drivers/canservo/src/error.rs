//! The crate's error type: what can go wrong while the driver opens the
//! bus, reads its drive files and brings the drives up. Realtime code
//! never returns errors; it trips fault latches ([`crate::engine`]).

use std::path::PathBuf;

use crate::codes::AbortCode;
use crate::drivefile::SdoType;

/// Everything that can fail outside the realtime functions.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The interface name cannot be one.
    #[error("CAN interface '{iface}': not a valid interface name")]
    BadInterfaceName {
        /// The name as given.
        iface: String,
    },
    /// No network interface has this name.
    #[error("CAN interface '{iface}': no such network interface (see `ip link`; for a virtual bus: ip link add dev {iface} type vcan && ip link set {iface} up)")]
    NoInterface {
        /// The name.
        iface: String,
    },
    /// The interface is not a CAN interface.
    #[error("CAN interface '{iface}': not a CAN interface (ARPHRD type {kind}, CAN is 280)")]
    NotCan {
        /// The name.
        iface: String,
        /// Its ARPHRD type, as sysfs gives it.
        kind: String,
    },
    /// The interface is down.
    #[error("CAN interface '{iface}': the interface is down (ip link set {iface} up type can bitrate 1000000, which needs CAP_NET_ADMIN)")]
    InterfaceDown {
        /// The name.
        iface: String,
    },
    /// A socket call on the interface failed.
    #[error("CAN interface '{iface}': {op}: {source}")]
    Socket {
        /// The name.
        iface: String,
        /// What was being done ("setting receive filters").
        op: &'static str,
        /// The system's answer.
        #[source]
        source: std::io::Error,
    },
    /// Nodes did not announce themselves after NMT reset communication.
    #[error("{} did not send a boot-up message within {timeout_ms} ms after NMT reset communication (is the drive powered, on this bus, at this node id and bit rate?)", node_list(nodes))]
    NoBootUp {
        /// The silent nodes.
        nodes: Vec<u8>,
        /// How long the master waited.
        timeout_ms: u64,
    },
    /// A node did not answer an SDO request.
    #[error("node {node} did not answer the SDO {what} within {timeout_ms} ms")]
    SdoTimeout {
        /// The node.
        node: u8,
        /// The request: "upload of 0x1000:00 (device type)".
        what: String,
        /// How long the master waited.
        timeout_ms: u64,
    },
    /// A node aborted an SDO transfer.
    #[error("node {node} aborted the SDO {what}: {code}")]
    SdoAbort {
        /// The node.
        node: u8,
        /// The request.
        what: String,
        /// The abort code and its meaning.
        code: AbortCode,
    },
    /// A node answered an SDO request with something that is not the
    /// protocol.
    #[error("node {node}: SDO {what}: {reason}")]
    SdoProtocol {
        /// The node.
        node: u8,
        /// The request.
        what: String,
        /// What was wrong with the answer.
        reason: String,
    },
    /// A frame could not be sent.
    #[error("could not send {what} on {bus}: the interface refused the frame (bus off, transmit queue full or interface down)")]
    SendFailed {
        /// The frame's purpose.
        what: String,
        /// The endpoint.
        bus: String,
    },
    /// A node is not a CiA 402 drive.
    #[error("node {node} is not a CiA 402 drive: device type (0x1000) is {device_type:#010x}, whose low word should be 0x0192")]
    NotCia402 {
        /// The node.
        node: u8,
        /// What 0x1000 holds.
        device_type: u32,
    },
    /// A node does not support a mode the configuration needs.
    #[error("node {node} does not support mode {mode} ({name}): supported drive modes (0x6502) are {supported:#010x}")]
    ModeUnsupported {
        /// The node.
        node: u8,
        /// The mode number.
        mode: i8,
        /// Its name.
        name: &'static str,
        /// 0x6502.
        supported: u32,
    },
    /// A node did not take the mode of operation.
    #[error("node {node} shows mode {shown} in 0x6061 after being set to mode {wanted}")]
    ModeNotTaken {
        /// The node.
        node: u8,
        /// The mode written to 0x6060.
        wanted: i8,
        /// What 0x6061 shows.
        shown: i8,
    },
    /// A node did not reach a power or NMT state.
    #[error(
        "node {node} did not reach {state} within {timeout_ms} ms (statusword {statusword:#06x})"
    )]
    StateTimeout {
        /// The node.
        node: u8,
        /// The state wanted.
        state: &'static str,
        /// How long the master waited.
        timeout_ms: u64,
        /// The last statusword seen.
        statusword: u16,
    },
    /// A drive file line is wrong.
    #[error("drive file {}, line {line}: {source}", path.display())]
    DriveFile {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        #[source]
        source: Box<Error>,
    },
    /// A drive file line is not three words.
    #[error("'{content}' is not INDEX:SUB TYPE VALUE (e.g. 6098:00 i8 35)")]
    NotAWrite {
        /// The line without its comment.
        content: String,
    },
    /// An object address is not `INDEX:SUB`.
    #[error("'{text}' is not INDEX:SUB (e.g. 6098:00)")]
    NotAnObject {
        /// The address as given.
        text: String,
    },
    /// An object index is not a 16-bit hexadecimal number.
    #[error("index '{text}' is not a hexadecimal number up to FFFF")]
    BadIndex {
        /// The index as given.
        text: String,
    },
    /// A sub-index is not an 8-bit hexadecimal number.
    #[error("sub-index '{text}' is not a hexadecimal number up to FF")]
    BadSubIndex {
        /// The sub-index as given.
        text: String,
    },
    /// A type name is not one of the SDO types.
    #[error("'{name}' is not a type ({types})")]
    NotAType {
        /// The name as given.
        name: String,
        /// The names taken there ("u8, u16, u32, i8, i16, i32").
        types: &'static str,
    },
    /// A value is not a decimal or `0x` hex number.
    #[error("'{text}' is not a number")]
    NotANumber {
        /// The value as given.
        text: String,
    },
    /// A value is outside its type's range.
    #[error("{value} does not fit {ty} ({lo}..={hi})")]
    OutOfRange {
        /// The value.
        value: i64,
        /// Its type.
        ty: SdoType,
        /// The type's least value.
        lo: i64,
        /// The type's greatest value.
        hi: i64,
    },
    /// An object read is shorter than the type asked for.
    #[error("{object} has {len} bytes, too few for {ty}")]
    TooShort {
        /// The object, described.
        object: String,
        /// The bytes read.
        len: usize,
        /// The type asked for.
        ty: SdoType,
    },
    /// `canservo-tool power` was given a step name it does not know.
    #[error("'{name}' is not a step ({steps})")]
    NotAStep {
        /// The name as given.
        name: String,
        /// The names taken.
        steps: &'static str,
    },
    /// A drive's state admits no command (not ready to switch on).
    #[error("node {node} cannot be commanded now: {statusword}")]
    NotCommandable {
        /// The node.
        node: u8,
        /// Its statusword, described.
        statusword: String,
    },
    /// A power step that is no transition from the drive's state.
    #[error("node {node} is in {state}: {step} is not a transition from there")]
    NoTransition {
        /// The node.
        node: u8,
        /// The state it is in.
        state: &'static str,
        /// The step asked for.
        step: &'static str,
    },
    /// `power up` on a drive in fault.
    #[error("node {node} is in fault: fault-reset first")]
    InFault {
        /// The node.
        node: u8,
    },
    /// An NMT command name the tool does not know.
    #[error("'{command}' is not an NMT command (start, stop, pre-operational, reset, reset-communication)")]
    NotAnNmtCommand {
        /// The name as given.
        command: String,
    },
    /// `canservo-tool watch` on simulated drives needs an end.
    #[error("with --sim, give --count or --seconds")]
    WatchWithoutEnd,
    /// A drive file cannot be read.
    #[error("drive file {}: {source}", path.display())]
    DriveFileIo {
        /// The file.
        path: PathBuf,
        /// The system's answer.
        #[source]
        source: std::io::Error,
    },
    /// A write of a drive file was refused by the drive.
    #[error("drive file {}, line {line}: {source}", path.display())]
    DriveFileWrite {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What the drive answered.
        #[source]
        source: Box<Error>,
    },
    /// A thread the driver needs could not be started.
    #[error("starting the {what}: {source}")]
    Thread {
        /// The thread ("helper thread").
        what: &'static str,
        /// The system's answer.
        #[source]
        source: std::io::Error,
    },
    /// A `scale` item is not a usable number.
    #[error("not a non-zero number")]
    NotAScale,
    /// A `mode` item names no mode.
    #[error("not csp, pv or csv")]
    NotAMode,
    /// A configuration value is wrong (module parameter or tool option).
    #[error("{what}: {reason}")]
    Config {
        /// What was given ("parameter 'nodes'").
        what: String,
        /// What is wrong.
        reason: String,
    },
}

/// Result type of the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// "node 3" or "nodes 3, 5".
fn node_list(nodes: &[u8]) -> String {
    let list: Vec<String> = nodes.iter().map(u8::to_string).collect();
    if nodes.len() == 1 {
        format!("node {}", list[0])
    } else {
        format!("nodes {}", list.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_node_and_what() {
        let e = Error::NoBootUp {
            nodes: vec![3, 5],
            timeout_ms: 1000,
        };
        assert!(e
            .to_string()
            .starts_with("nodes 3, 5 did not send a boot-up message"));
        let e = Error::SdoAbort {
            node: 2,
            what: "download of 0x1A00:01 (TPDO1 mapping entry 1)".into(),
            code: AbortCode::NOT_MAPPABLE,
        };
        assert_eq!(
            e.to_string(),
            "node 2 aborted the SDO download of 0x1A00:01 (TPDO1 mapping entry 1): \
             0x06040041 (object cannot be mapped to the PDO)"
        );
    }
}
