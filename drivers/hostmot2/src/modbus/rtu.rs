//! Modbus RTU framing: the CRC-16 (polynomial 0xA001 reflected, initial
//! 0xFFFF, sent low byte first) and the function codes hm2_modbus uses.

/// Read coils.
pub const R_COILS: u8 = 1;
/// Read discrete inputs.
pub const R_INPUTS: u8 = 2;
/// Read holding registers.
pub const R_REGISTERS: u8 = 3;
/// Read input registers.
pub const R_INPUTREGS: u8 = 4;
/// Write single coil.
pub const W_COIL: u8 = 5;
/// Write single register.
pub const W_REGISTER: u8 = 6;
/// Write multiple coils.
pub const W_COILS: u8 = 15;
/// Write multiple registers.
pub const W_REGISTERS: u8 = 16;

/// Whether `f` is one of the eight functions hm2_modbus supports.
pub fn supported(f: u8) -> bool {
    matches!(f, 1..=6 | 15 | 16)
}

/// The largest RTU frame: address, function, 252 data bytes, CRC.
pub const MAX_FRAME: usize = 256;

/// The Modbus CRC-16 of `bytes`.
pub fn crc16(bytes: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in bytes {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc
}

/// Whether a frame's last two bytes are the CRC of the rest.
pub fn crc_ok(frame: &[u8]) -> bool {
    frame.len() >= 3 && {
        let (body, c) = frame.split_at(frame.len() - 2);
        crc16(body) == u16::from_le_bytes([c[0], c[1]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_matches_the_specification_example() {
        // Read holding registers 0x006B x3 from device 0x11: CRC 0x8776,
        // sent 0x76 0x87.
        let req = [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03];
        assert_eq!(crc16(&req), 0x8776);
        assert!(crc_ok(&[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87]));
        assert!(!crc_ok(&[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x87, 0x76]));
    }
}
