//! The SDO client against the simulated drive's server, and the start-up
//! sequence on the in-process bus: every answer, abort and silence.

use std::time::Duration;

use hal_canservo::bus::{CanBus, Filter, Filters, SimBus};
use hal_canservo::codes::AbortCode;
use hal_canservo::drivefile::DriveFile;
use hal_canservo::frame::Frame;
use hal_canservo::regs::obj;
use hal_canservo::sdo::SdoClient;
use hal_canservo::sim::{NmtState, SimDriveConfig};
use hal_canservo::startup::{Mode, Network, NodePlan, StartupConfig};
use hal_canservo::Error;

const T: Duration = Duration::from_millis(300);

fn sdo_endpoint(bus: &std::sync::Arc<SimBus>) -> hal_canservo::bus::SimEndpoint {
    bus.open(Filters {
        frames: (1..=127)
            .flat_map(|n| [Filter::exact(0x580 + n), Filter::exact(0x700 + n)])
            .collect(),
        error_mask: 0,
    })
}

fn plans(nodes: &[u8]) -> Vec<NodePlan> {
    nodes
        .iter()
        .map(|&node| NodePlan {
            node,
            mode: Mode::Csp,
            file: None,
        })
        .collect()
}

#[test]
fn expedited_and_segmented_transfers() {
    let bus = SimBus::with_drives(&[5]);
    let ep = sdo_endpoint(&bus);
    let sdo = SdoClient::new(&ep, 5, T);
    assert_eq!(sdo.read_u32(obj::DEVICE_TYPE, 0).unwrap(), 0x0002_0192);
    assert_eq!(sdo.read_u32(obj::IDENTITY, 4).unwrap(), 5);
    // 0x1008 is longer than 4 bytes: a segmented upload.
    assert_eq!(
        sdo.read_string(obj::DEVICE_NAME, 0).unwrap(),
        "canservo simulated CiA 402 servo drive"
    );
    sdo.write_u32(obj::FOLLOWING_ERROR_WINDOW, 0, 1234).unwrap();
    assert_eq!(sdo.read_u32(obj::FOLLOWING_ERROR_WINDOW, 0).unwrap(), 1234);
    // A segmented download of a u32 is refused for its length.
    let e = sdo
        .download(obj::FOLLOWING_ERROR_WINDOW, 0, &[1, 2, 3, 4, 5, 6])
        .unwrap_err();
    assert!(
        matches!(e, Error::SdoAbort { code, .. } if code == AbortCode::LENGTH_HIGH),
        "{e}"
    );
}

#[test]
fn abort_codes_come_back_with_their_meaning() {
    let bus = SimBus::with_drives(&[2]);
    let ep = sdo_endpoint(&bus);
    let sdo = SdoClient::new(&ep, 2, T);
    let cases: Vec<(Result<(), Error>, AbortCode, &str)> = vec![
        (
            sdo.read_u32(0x2000, 0).map(drop),
            AbortCode::NO_OBJECT,
            "object does not exist",
        ),
        (
            sdo.read_u32(obj::IDENTITY, 9).map(drop),
            AbortCode::NO_SUBINDEX,
            "sub-index does not exist",
        ),
        (
            sdo.write_u16(obj::STATUSWORD, 0, 1),
            AbortCode::READ_ONLY,
            "attempt to write a read-only object",
        ),
        (
            sdo.write_u32(obj::PRODUCER_HEARTBEAT, 0, 1),
            AbortCode::LENGTH_HIGH,
            "length of service parameter too high",
        ),
        (
            sdo.write_u8(obj::PRODUCER_HEARTBEAT, 0, 1),
            AbortCode::LENGTH_LOW,
            "too low",
        ),
        (
            sdo.write_i16(obj::QUICK_STOP_OPTION, 0, 9),
            AbortCode::VALUE_HIGH,
            "written too high",
        ),
        (
            sdo.write_i8(obj::MODES_OF_OPERATION, 0, 7),
            AbortCode::INVALID_VALUE,
            "invalid value",
        ),
        (
            sdo.write_u8(obj::TPDO_MAP, 0, 0),
            AbortCode::WRONG_STATE,
            "present device state",
        ),
        (
            sdo.write_u32(obj::STORE, 1, 0x1234),
            AbortCode::CANNOT_STORE,
            "cannot be transferred or stored",
        ),
    ];
    for (r, code, meaning) in cases {
        let e = r.unwrap_err();
        assert!(
            matches!(&e, Error::SdoAbort { code: c, .. } if *c == code),
            "{e}"
        );
        let m = e.to_string();
        assert!(
            m.contains("node 2 aborted the SDO") && m.contains(meaning),
            "{m}"
        );
    }
}

#[test]
fn a_silent_node_times_out_and_hostile_servers_are_cut_off() {
    let bus = SimBus::with_drives(&[3]);
    let ep = sdo_endpoint(&bus);
    let e = SdoClient::new(&ep, 9, Duration::from_millis(30))
        .read_u32(0x1000, 0)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "node 9 did not answer the SDO upload of 0x1000:00 (device type) within 30 ms"
    );
    // A "server" that announces a huge segmented upload.
    let fake = bus.open(Filters {
        frames: vec![Filter::exact(0x60A)],
        error_mask: 0,
    });
    let answer = std::thread::spawn(move || {
        let req = fake.recv_timeout(Duration::from_secs(5)).expect("request");
        assert_eq!(req.data[0], 0x40);
        fake.send(&Frame::new(
            0x58A,
            &[0x41, 0x00, 0x10, 0, 0xFF, 0xFF, 0xFF, 0x7F],
        ));
        let abort = fake.recv_timeout(Duration::from_secs(5)).expect("abort");
        u32::from_le_bytes([abort.data[4], abort.data[5], abort.data[6], abort.data[7]])
    });
    let e = SdoClient::new(&ep, 10, Duration::from_secs(5))
        .upload(0x1000, 0)
        .unwrap_err();
    assert!(e.to_string().contains("more than the 4096 accepted"), "{e}");
    assert_eq!(answer.join().unwrap(), AbortCode::OUT_OF_MEMORY.0);
}

#[test]
fn start_up_brings_every_drive_to_operational() {
    let bus = SimBus::with_drives(&[1, 2, 3]);
    let ep = sdo_endpoint(&bus);
    let net = Network::boot(&ep, plans(&[1, 2, 3]), StartupConfig::default()).unwrap();
    let net = net.identify().unwrap();
    assert_eq!(net.nodes()[1].identity.serial, 2);
    let nodes = net.configure().unwrap().start().unwrap().into_nodes();
    assert_eq!(nodes.len(), 3);
    bus.pump();
    for n in [1, 2, 3] {
        bus.with_drive(n, |d, _| {
            assert_eq!(d.nmt_state(), NmtState::Operational);
            assert_eq!(d.object(obj::MODES_DISPLAY, 0), 8);
            assert_eq!(d.object(obj::PRODUCER_HEARTBEAT, 0), 100);
            assert_eq!(d.object(obj::TPDO_COMM, 2), 1);
            assert_eq!(d.object(obj::TPDO_MAP, 2), 0x6064_0020);
            assert_eq!(
                d.object(obj::TPDO_COMM + 2, 1) as u32 & obj::COB_INVALID,
                obj::COB_INVALID
            );
            assert_eq!(d.object(obj::CONSUMER_HEARTBEAT, 1), 127 << 16 | 300);
        });
    }
}

#[test]
fn a_missing_node_is_named() {
    let bus = SimBus::with_drives(&[1, 3]);
    let ep = sdo_endpoint(&bus);
    let cfg = StartupConfig {
        boot_timeout: Duration::from_millis(50),
        ..StartupConfig::default()
    };
    let e = Network::boot(&ep, plans(&[1, 2, 3, 4]), cfg).unwrap_err();
    assert_eq!(
        e.to_string(),
        "nodes 2, 4 did not send a boot-up message within 50 ms after NMT reset communication \
         (is the drive powered, on this bus, at this node id and bit rate?)"
    );
}

#[test]
fn drive_file_errors_name_file_line_and_object() {
    let bus = SimBus::with_drives(&[1]);
    let ep = sdo_endpoint(&bus);
    let file = DriveFile::parse(
        std::path::Path::new("axis-x.sdo"),
        "6098:00 i8 19\n# fine so far\n6041:00 u16 5\n",
    )
    .unwrap();
    let plan = vec![NodePlan {
        node: 1,
        mode: Mode::Csp,
        file: Some(file),
    }];
    let e = Network::boot(&ep, plan, StartupConfig::default())
        .unwrap()
        .identify()
        .unwrap()
        .configure()
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "drive file axis-x.sdo, line 3: node 1 aborted the SDO download to 0x6041:00 (statusword): \
         0x06010002 (attempt to write a read-only object)"
    );
    bus.with_drive(1, |d, _| assert_eq!(d.object(obj::HOMING_METHOD, 0), 19));
}

#[test]
fn a_drive_of_another_profile_is_refused() {
    let bus = SimBus::new();
    let mut cfg = SimDriveConfig::new(4);
    cfg.identity.device_type = 0x0000_0191;
    bus.add_drive(cfg);
    let ep = sdo_endpoint(&bus);
    let e = Network::boot(&ep, plans(&[4]), StartupConfig::default())
        .unwrap()
        .identify()
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "node 4 is not a CiA 402 drive: device type (0x1000) is 0x00000191, whose low word should be 0x0192"
    );
}
