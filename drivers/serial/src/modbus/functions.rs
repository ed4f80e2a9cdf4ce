//! The standard Modbus data functions on any [`Transact`]: reading
//! coils (0x01), discrete inputs (0x02), holding (0x03) and input (0x04)
//! registers; writing one coil (0x05), one register (0x06), several
//! coils (0x0F) and several registers (0x10). Each checks its request
//! before sending and its reply's contents after (counts, echoes).

use super::{ReplyLength, Transact};
use crate::error::{Result, SerialError};
use crate::regs::modbus as mb;

fn bad_request(what: String) -> SerialError {
    SerialError::BadRequest(what)
}

/// Refuses a count outside `1..=max` and a range past address 65535.
fn check_range(what: &str, start: u16, count: usize, max: u16) -> Result<()> {
    if count == 0 || count > usize::from(max) {
        return Err(bad_request(format!(
            "cannot ask for {count} {what} (1..={max})"
        )));
    }
    if usize::from(start) + count - 1 > usize::from(u16::MAX) {
        return Err(bad_request(format!(
            "{count} {what} from address {start} run past address 65535"
        )));
    }
    Ok(())
}

fn refuse_broadcast_read(t: &impl Transact, slave: u8) -> Result<()> {
    if t.is_broadcast(slave) {
        return Err(bad_request(format!(
            "cannot read from the broadcast address {slave}"
        )));
    }
    Ok(())
}

/// The data of a read request: start and count.
fn start_count(start: u16, count: u16) -> Vec<u8> {
    let mut data = start.to_be_bytes().to_vec();
    data.extend_from_slice(&count.to_be_bytes());
    data
}

/// Reads `count` bits from `start` with function 0x01 (coils) or 0x02
/// (discrete inputs).
pub fn read_bits(
    t: &mut impl Transact,
    slave: u8,
    function: u8,
    start: u16,
    count: u16,
) -> Result<Vec<bool>> {
    if !matches!(function, mb::READ_COILS | mb::READ_DISCRETE_INPUTS) {
        return Err(bad_request(format!(
            "function {function:#04x} does not read bits"
        )));
    }
    check_range("bits", start, usize::from(count), mb::MAX_READ_BITS)?;
    refuse_broadcast_read(t, slave)?;
    let body = t.transact(
        slave,
        function,
        &start_count(start, count),
        ReplyLength::CountAt2,
    )?;
    decode_bits(slave, function, count, &body)
}

/// The bits of a read-bits reply's data (byte count, packed bits).
pub fn decode_bits(slave: u8, function: u8, count: u16, body: &[u8]) -> Result<Vec<bool>> {
    let expected = usize::from(count).div_ceil(8);
    match body.split_first() {
        Some((&n, packed)) if usize::from(n) == expected && packed.len() == expected => Ok((0
            ..usize::from(count))
            .map(|i| packed[i / 8] & (1 << (i % 8)) != 0)
            .collect()),
        _ => Err(SerialError::BadReply {
            slave,
            function,
            what: format!(
                "{} data bytes for {count} bits (want {expected})",
                body.len().saturating_sub(1)
            ),
        }),
    }
}

/// Reads `count` registers from `start` with function 0x03 (holding)
/// or 0x04 (input).
pub fn read_registers(
    t: &mut impl Transact,
    slave: u8,
    function: u8,
    start: u16,
    count: u16,
) -> Result<Vec<u16>> {
    if !matches!(
        function,
        mb::READ_HOLDING_REGISTERS | mb::READ_INPUT_REGISTERS
    ) {
        return Err(bad_request(format!(
            "function {function:#04x} does not read registers"
        )));
    }
    check_range("registers", start, usize::from(count), mb::MAX_READ_COUNT)?;
    refuse_broadcast_read(t, slave)?;
    let body = t.transact(
        slave,
        function,
        &start_count(start, count),
        ReplyLength::CountAt2,
    )?;
    decode_registers(slave, function, count, &body)
}

/// The values of a read-registers reply's data (byte count, values).
pub fn decode_registers(slave: u8, function: u8, count: u16, body: &[u8]) -> Result<Vec<u16>> {
    let expected = 2 * usize::from(count);
    match body.split_first() {
        Some((&n, values)) if usize::from(n) == expected && values.len() == expected => Ok(values
            .chunks_exact(2)
            .map(|c| u16::from_be_bytes([c[0], c[1]]))
            .collect()),
        _ => Err(SerialError::BadReply {
            slave,
            function,
            what: format!(
                "{} data bytes for {count} registers",
                body.len().saturating_sub(1)
            ),
        }),
    }
}

/// Sends a write whose reply echoes `echoed` (the request's first bytes).
fn write_echoed(
    t: &mut impl Transact,
    slave: u8,
    function: u8,
    data: &[u8],
    echoed: usize,
) -> Result<()> {
    let body = t.transact(slave, function, data, ReplyLength::Fixed(8))?;
    if !t.is_broadcast(slave) && body != data[..echoed] {
        return Err(SerialError::BadReply {
            slave,
            function,
            what: format!(
                "reply {body:02X?} does not echo the request's {:02X?}",
                &data[..echoed]
            ),
        });
    }
    Ok(())
}

/// Writes one coil (function 0x05); the slave echoes the request.
pub fn write_coil(t: &mut impl Transact, slave: u8, address: u16, on: bool) -> Result<()> {
    let value = if on { mb::COIL_ON } else { 0 };
    let mut data = address.to_be_bytes().to_vec();
    data.extend_from_slice(&value.to_be_bytes());
    write_echoed(t, slave, mb::WRITE_SINGLE_COIL, &data, 4)
}

/// Writes one register (function 0x06); the slave echoes the request.
pub fn write_register(t: &mut impl Transact, slave: u8, address: u16, value: u16) -> Result<()> {
    let mut data = address.to_be_bytes().to_vec();
    data.extend_from_slice(&value.to_be_bytes());
    write_echoed(t, slave, mb::WRITE_SINGLE_REGISTER, &data, 4)
}

/// Writes consecutive coils from `start` (function 0x0F).
pub fn write_coils(t: &mut impl Transact, slave: u8, start: u16, bits: &[bool]) -> Result<()> {
    check_range("coils", start, bits.len(), mb::MAX_WRITE_BITS)?;
    let mut data = start_count(start, bits.len() as u16);
    let mut packed = vec![0u8; bits.len().div_ceil(8)];
    for (i, _) in bits.iter().enumerate().filter(|(_, b)| **b) {
        packed[i / 8] |= 1 << (i % 8);
    }
    data.push(packed.len() as u8);
    data.extend_from_slice(&packed);
    write_echoed(t, slave, mb::WRITE_MULTIPLE_COILS, &data, 4)
}

/// Writes consecutive registers from `start` (function 0x10).
pub fn write_registers(t: &mut impl Transact, slave: u8, start: u16, values: &[u16]) -> Result<()> {
    check_range("registers", start, values.len(), mb::MAX_WRITE_COUNT)?;
    let mut data = start_count(start, values.len() as u16);
    data.push((values.len() * 2) as u8);
    for v in values {
        data.extend_from_slice(&v.to_be_bytes());
    }
    write_echoed(t, slave, mb::WRITE_MULTIPLE_REGISTERS, &data, 4)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::line::ScriptLine;
    use crate::modbus::{frame, Master, MasterConfig};

    /// A master whose line answers `reply` (a frame body; the CRC is
    /// added) to whatever is sent.
    fn answering(reply: &[u8]) -> Master<ScriptLine> {
        let line = ScriptLine::new([frame::request(reply[0], reply[1], &reply[2..])]);
        Master::new(
            line,
            MasterConfig {
                retries: 0,
                ..MasterConfig::default()
            },
        )
    }

    fn sent(m: &Master<ScriptLine>) -> Vec<u8> {
        m.line().sent().concat()
    }

    #[test]
    fn coils_and_inputs_are_read_lowest_address_in_bit_zero() {
        let mut m = answering(&[1, 0x01, 2, 0b1100_1101, 0b01]);
        let bits = read_bits(&mut m, 1, mb::READ_COILS, 0x13, 10).unwrap();
        assert_eq!(
            bits,
            [true, false, true, true, false, false, true, true, true, false]
        );
        assert_eq!(sent(&m), frame::request(1, 0x01, &[0, 0x13, 0, 10]));
        let mut m = answering(&[1, 0x02, 1, 0b101]);
        assert_eq!(
            read_bits(&mut m, 1, mb::READ_DISCRETE_INPUTS, 0, 3).unwrap(),
            [true, false, true]
        );
        // A byte count that does not fit the bits asked for.
        let mut m = answering(&[1, 0x01, 2, 0xFF, 0xFF]);
        assert!(matches!(
            read_bits(&mut m, 1, mb::READ_COILS, 0, 8),
            Err(SerialError::BadReply { .. })
        ));
    }

    #[test]
    fn single_writes_are_echoed() {
        let mut m = answering(&[1, 0x05, 0, 0xAC, 0xFF, 0x00]);
        write_coil(&mut m, 1, 0xAC, true).unwrap();
        assert_eq!(sent(&m), frame::request(1, 0x05, &[0, 0xAC, 0xFF, 0]));
        let mut m = answering(&[1, 0x05, 0, 0xAC, 0x00, 0x00]);
        assert!(matches!(
            write_coil(&mut m, 1, 0xAC, true),
            Err(SerialError::BadReply { .. })
        ));
        let mut m = answering(&[1, 0x06, 0, 5, 0x12, 0x34]);
        write_register(&mut m, 1, 5, 0x1234).unwrap();
    }

    #[test]
    fn multiple_coils_are_packed_and_the_reply_names_them() {
        let mut m = answering(&[1, 0x0F, 0, 0x13, 0, 10]);
        let bits = [
            true, false, true, true, false, false, true, true, true, false,
        ];
        write_coils(&mut m, 1, 0x13, &bits).unwrap();
        assert_eq!(
            sent(&m),
            frame::request(1, 0x0F, &[0, 0x13, 0, 10, 2, 0xCD, 0x01])
        );
        let mut m = answering(&[1, 0x10, 0, 1, 0, 2]);
        write_registers(&mut m, 1, 1, &[0x000A, 0x0102]).unwrap();
        assert_eq!(
            sent(&m),
            frame::request(1, 0x10, &[0, 1, 0, 2, 4, 0, 0x0A, 1, 2])
        );
    }

    #[test]
    fn requests_out_of_range_are_refused_before_sending() {
        let mut m = answering(&[1, 0x01, 0]);
        assert!(read_bits(&mut m, 1, mb::READ_COILS, 0, 2001).is_err());
        assert!(read_bits(&mut m, 1, mb::READ_COILS, 65535, 2).is_err());
        assert!(read_bits(&mut m, 1, mb::READ_HOLDING_REGISTERS, 0, 1).is_err());
        assert!(read_bits(&mut m, 0, mb::READ_COILS, 0, 1).is_err());
        assert!(write_coils(&mut m, 1, 0, &[true; 1969]).is_err());
        assert!(write_coils(&mut m, 1, 0, &[]).is_err());
        assert!(write_registers(&mut m, 1, 0, &[0; 124]).is_err());
        assert!(sent(&m).is_empty());
    }

    #[test]
    fn broadcast_writes_wait_for_nothing() {
        let mut m = answering(&[1, 0x05, 0, 0, 0, 0]);
        write_coil(&mut m, 0, 3, true).unwrap();
        write_coils(&mut m, 0, 3, &[true, false]).unwrap();
    }
}
