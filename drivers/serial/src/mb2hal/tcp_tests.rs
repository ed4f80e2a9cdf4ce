//! MBAP framing on scripted bytes: requests byte for byte, transaction
//! ids, length bounds, exceptions, late replies skipped, cut replies.

use super::*;
use crate::modbus::functions;

/// A reply ADU to transaction `tid` from unit 1.
fn reply(tid: u16, pdu: &[u8]) -> Vec<u8> {
    let mut a = tid.to_be_bytes().to_vec();
    a.extend_from_slice(&[0, 0]);
    a.extend_from_slice(&((pdu.len() + 1) as u16).to_be_bytes());
    a.push(1);
    a.extend_from_slice(pdu);
    a
}

fn client(chunks: Vec<Vec<u8>>) -> MbapClient<ScriptWire> {
    MbapClient::new(ScriptWire::new(chunks), "127.0.0.1:502")
}

#[test]
fn requests_carry_the_mbap_header() {
    assert_eq!(
        request(0x0102, 1, 3, &[0, 0, 0, 3]),
        [1, 2, 0, 0, 0, 6, 1, 3, 0, 0, 0, 3]
    );
    let mut c = client(vec![reply(1, &[3, 4, 0, 100, 0, 101])]);
    let v = functions::read_registers(&mut c, 1, 3, 0, 2).unwrap();
    assert_eq!(v, [100, 101]);
    assert_eq!(c.wire().sent, [0, 1, 0, 0, 0, 6, 1, 3, 0, 0, 0, 2]);
}

#[test]
fn replies_in_pieces_are_put_together() {
    let r = reply(1, &[1, 1, 0b101]);
    let chunks = r.iter().map(|b| vec![*b]).collect();
    let mut c = client(chunks);
    assert_eq!(
        functions::read_bits(&mut c, 1, 1, 0, 3).unwrap(),
        [true, false, true]
    );
}

#[test]
fn late_replies_are_skipped_by_transaction_id() {
    // The reply to an earlier request (id 7) comes before ours (id 1).
    let mut c = client(vec![reply(7, &[6, 0, 5, 0, 9]), reply(1, &[6, 0, 5, 0, 9])]);
    functions::write_register(&mut c, 1, 5, 9).unwrap();
    let stale: Vec<Vec<u8>> = (100..110).map(|t| reply(t, &[6, 0, 5, 0, 9])).collect();
    let mut c = client(stale);
    let e = functions::write_register(&mut c, 1, 5, 9).unwrap_err();
    assert!(
        e.to_string().contains("no reply with transaction id 1"),
        "{e}"
    );
}

#[test]
fn headers_that_cannot_be_right_are_refused() {
    let a = "h:1";
    let mut h = [0, 1, 0, 1, 0, 3, 1];
    assert!(parse_header(a, &h)
        .unwrap_err()
        .to_string()
        .contains("protocol identifier 1"));
    h[3] = 0;
    assert_eq!(
        parse_header(a, &h).unwrap(),
        Header {
            tid: 1,
            pdu_len: 2,
            unit: 1
        }
    );
    for bad_len in [0u16, 1, 255, 0xFFFF] {
        let l = bad_len.to_be_bytes();
        let h = [0, 1, 0, 0, l[0], l[1], 1];
        let e = parse_header(a, &h).unwrap_err();
        assert!(
            matches!(e, SerialError::BadHeader { .. }) && e.is_line_failure(),
            "{bad_len}: {e}"
        );
    }
}

#[test]
fn exceptions_wrong_units_and_functions() {
    let mut c = client(vec![reply(1, &[0x83, 2])]);
    let e = functions::read_registers(&mut c, 1, 3, 0, 1).unwrap_err();
    assert!(
        matches!(
            e,
            SerialError::Exception {
                code: ExceptionCode(2),
                ..
            }
        ),
        "{e}"
    );
    let mut c = client(vec![reply(1, &[0x83, 2, 3])]);
    assert!(matches!(
        functions::read_registers(&mut c, 1, 3, 0, 1),
        Err(SerialError::BadReply { .. })
    ));
    let mut c = client(vec![reply(1, &[4, 2, 0, 1])]);
    assert!(matches!(
        functions::read_registers(&mut c, 1, 3, 0, 1),
        Err(SerialError::WrongFunction { found: 4, .. })
    ));
    let mut c = client(vec![reply(1, &[3, 2, 0, 1])]);
    assert!(matches!(
        functions::read_registers(&mut c, 2, 3, 0, 1),
        Err(SerialError::WrongSlave {
            expected: 2,
            found: 1
        })
    ));
}

#[test]
fn silence_is_a_timeout_and_a_cut_reply_is_truncated() {
    let mut c = client(vec![]);
    assert!(matches!(
        functions::read_registers(&mut c, 1, 3, 0, 1),
        Err(SerialError::Timeout { .. })
    ));
    let mut r = reply(1, &[3, 2, 0, 1]);
    r.pop();
    let mut c = client(vec![r]);
    assert!(matches!(
        functions::read_registers(&mut c, 1, 3, 0, 1),
        Err(SerialError::Truncated { .. })
    ));
    let mut c = client(vec![reply(1, &[])[..6].to_vec()]);
    assert!(matches!(
        functions::read_registers(&mut c, 1, 3, 0, 1),
        Err(SerialError::Truncated { .. })
    ));
}

#[test]
fn a_closed_connection_is_a_line_failure() {
    struct Closed;
    impl Wire for Closed {
        fn send(&mut self, _: &[u8]) -> io::Result<()> {
            Ok(())
        }
        fn receive(&mut self, _: &mut [u8], _: Duration) -> io::Result<usize> {
            Ok(0)
        }
    }
    let mut c = MbapClient::new(Closed, "h:1");
    let e = c.transact(1, 3, &[0, 0, 0, 1]).unwrap_err();
    assert!(e.is_line_failure(), "{e}");
    assert!(e.to_string().contains("closed the connection"), "{e}");
}

#[test]
fn a_server_that_is_not_there_is_a_connect_error() {
    // A port nobody listens on: bind one, note it, close it.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let mut link = TcpLink::new("127.0.0.1", port);
    let e = functions::read_registers(&mut link, 1, 3, 0, 1).unwrap_err();
    assert!(matches!(e, SerialError::Connect { .. }), "{e}");
    assert!(e.to_string().contains(&format!("127.0.0.1:{port}")), "{e}");
    assert!(!link.is_connected());
}
