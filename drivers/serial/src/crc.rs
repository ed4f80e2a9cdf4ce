//! The Modbus RTU CRC: CRC-16 with the reflected polynomial 0xA001
//! (0x8005 reflected), initial value 0xFFFF, no final XOR, sent low byte
//! first. The HY protocol uses the same. Computed by the `crc` crate's
//! catalogued CRC-16/MODBUS.

const MODBUS: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_MODBUS);

/// The CRC of `bytes`.
pub fn crc16(bytes: &[u8]) -> u16 {
    MODBUS.checksum(bytes)
}

/// Appends the CRC of `frame` to it, low byte first.
pub fn append(frame: &mut Vec<u8>) {
    let crc = crc16(frame);
    frame.extend_from_slice(&crc.to_le_bytes());
}

/// The CRC a whole frame carries in its last two bytes, and the one its
/// other bytes have; None for a frame shorter than a CRC.
pub fn carried_and_computed(frame: &[u8]) -> Option<(u16, u16)> {
    let body_len = frame.len().checked_sub(2)?;
    let carried = u16::from_le_bytes([frame[body_len], frame[body_len + 1]]);
    Some((carried, crc16(&frame[..body_len])))
}

/// Whether a whole frame (body and CRC) checks.
pub fn is_valid(frame: &[u8]) -> bool {
    carried_and_computed(frame).is_some_and(|(carried, computed)| carried == computed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_value_of_the_catalogue() {
        assert_eq!(crc16(b"123456789"), 0x4B37);
    }

    #[test]
    fn read_holding_register_request_of_the_modbus_spec() {
        // Slave 1, read 1 register at 0x0000: CRC 0x0A84 sent as 84 0A.
        let mut f = vec![0x01, 0x03, 0x00, 0x00, 0x00, 0x01];
        append(&mut f);
        assert_eq!(f, [0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A]);
        assert!(is_valid(&f));
        f[3] ^= 1;
        assert!(!is_valid(&f));
        assert!(!is_valid(&[0x01]));
    }
}
