//! The pendant's USB reports: the input report it sends on every button,
//! wheel or switch change, and the display it takes as six 8-byte
//! feature reports (report id 6).
//!
//! Input report: byte 0 the report id (4), byte 1 the code of the button
//! held (0 for none), byte 3 the rotary switch position, byte 4 the
//! wheel's movement since the last report as a signed byte. A report of
//! six zero bytes after the id means the pendant went to sleep.
//!
//! Display: `FE FD 0C`, then relative (WC) positions x, y, z and absolute
//! (MC) positions x, y, z (the first of each three shows a when the
//! switch is on a), each as a 16-bit whole part and a 16-bit fraction in
//! ten-thousandths with bit 15 the sign, little-endian; then feed
//! override and spindle override in percent, feed in units per minute
//! and spindle speed in rpm, each 16 bits; byte 35 the step-size code and
//! byte 36 flags (0x80: inch icon). The 42 bytes go out as six reports of
//! the id and seven bytes.

/// The input report's id.
pub const INPUT_REPORT_ID: u8 = 0x04;
/// The least bytes an input report has (id, button, modifier, switch,
/// wheel, and one more the sleep test reads).
pub const INPUT_REPORT_MIN: usize = 6;
/// The display's feature report id.
pub const DISPLAY_REPORT_ID: u8 = 0x06;
/// One display report: the id and seven bytes.
pub const DISPLAY_REPORT_LEN: usize = 8;
/// The display reports sent per update.
pub const DISPLAY_REPORTS: usize = 6;

/// The rotary switch position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Switch {
    /// Off.
    #[default]
    Off,
    /// X axis.
    X,
    /// Y axis.
    Y,
    /// Z axis.
    Z,
    /// A axis.
    A,
    /// Spindle override.
    Spindle,
    /// Feed override.
    Feed,
    /// A code this driver does not know (treated as off).
    Unknown(u8),
}

impl Switch {
    /// The switch position a report's byte 3 names.
    pub fn from_code(code: u8) -> Switch {
        match code {
            0x00 => Switch::Off,
            0x11 => Switch::X,
            0x12 => Switch::Y,
            0x13 => Switch::Z,
            0x18 => Switch::A,
            0x14 => Switch::Spindle,
            0x15 => Switch::Feed,
            other => Switch::Unknown(other),
        }
    }
}

/// A decoded input report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputReport {
    /// The code of the button held, 0 for none.
    pub button: u8,
    /// The rotary switch.
    pub switch: Switch,
    /// Wheel counts since the last report.
    pub wheel: i8,
    /// The pendant reports it went to sleep.
    pub sleeping: bool,
}

/// Why an input report was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReportError {
    /// Fewer bytes than a report has.
    #[error("input report of {0} bytes, at least {INPUT_REPORT_MIN} expected")]
    Short(usize),
    /// A report id other than the input report's.
    #[error("report id {0:#04x}, expected {INPUT_REPORT_ID:#04x}")]
    WrongId(u8),
}

/// Decodes one input report as hidraw's read gives it (id first).
pub fn parse_input(bytes: &[u8]) -> Result<InputReport, ReportError> {
    if bytes.len() < INPUT_REPORT_MIN {
        return Err(ReportError::Short(bytes.len()));
    }
    if bytes[0] != INPUT_REPORT_ID {
        return Err(ReportError::WrongId(bytes[0]));
    }
    Ok(InputReport {
        button: bytes[1],
        switch: Switch::from_code(bytes[3]),
        wheel: i8::from_le_bytes([bytes[4]]),
        sleeping: bytes[1..6].iter().all(|&b| b == 0),
    })
}

/// What the display shows.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Display {
    /// Relative (WC) positions x, y, z, a.
    pub relative: [f64; 4],
    /// Absolute (MC) positions x, y, z, a.
    pub absolute: [f64; 4],
    /// Feed override, 1.0 = 100 %.
    pub feed_override: f64,
    /// Spindle override, 1.0 = 100 %.
    pub spindle_override: f64,
    /// Feed, units per second.
    pub feed: f64,
    /// Spindle speed, revolutions per second.
    pub spindle_rps: f64,
    /// The step size (a multiple of 0.001).
    pub stepsize: i32,
    /// Show the inch icon instead of mm.
    pub inch: bool,
    /// The switch is on a: the first position shows a instead of x.
    pub show_a: bool,
}

/// A coordinate as the display takes it: rounded to thousandths, then
/// whole part and ten-thousandths (sign in bit 15 of the fraction).
/// Values past 65535.9999 saturate; NaN shows as 0.
pub fn encode_coordinate(v: f64) -> [u8; 4] {
    let v = if v.is_nan() { 0.0 } else { v };
    let rounded = (v * 1000.0).round() / 1000.0;
    // 65535.9999 is the most the two 16-bit parts hold.
    let scaled = (rounded.abs() * 10000.0).round().min(655_359_999.0) as u32;
    let whole = (scaled / 10000) as u16;
    let mut fraction = (scaled % 10000) as u16;
    if rounded < 0.0 {
        fraction |= 0x8000;
    }
    let w = whole.to_le_bytes();
    let f = fraction.to_le_bytes();
    [w[0], w[1], f[0], f[1]]
}

/// A 16-bit display value: `v * factor` rounded, wrapped to 16 bits as
/// the pendant's firmware expects (a C short); NaN shows as 0.
pub fn encode_u16(v: f64, factor: f64) -> [u8; 2] {
    let x = (v * factor).round();
    let x = if x.is_nan() {
        0
    } else {
        x.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    };
    (x as u16).to_le_bytes()
}

/// The display's code for a step size; 0 (blank) for sizes it cannot
/// show.
pub fn stepsize_code(stepsize: i32) -> u8 {
    match stepsize {
        1 => 0x01,
        5 => 0x02,
        10 => 0x03,
        20 => 0x04,
        30 => 0x05,
        40 => 0x06,
        50 => 0x07,
        100 => 0x08,
        500 => 0x09,
        1000 => 0x0A,
        _ => 0x00,
    }
}

/// The six feature reports that show `d`.
pub fn encode_display(d: &Display) -> [[u8; DISPLAY_REPORT_LEN]; DISPLAY_REPORTS] {
    let mut body = [0u8; DISPLAY_REPORTS * (DISPLAY_REPORT_LEN - 1)];
    body[..3].copy_from_slice(&[0xFE, 0xFD, 0x0C]);
    let first = usize::from(d.show_a) * 3;
    let coords = [
        d.relative[first],
        d.relative[1],
        d.relative[2],
        d.absolute[first],
        d.absolute[1],
        d.absolute[2],
    ];
    let mut at = 3;
    for c in coords {
        body[at..at + 4].copy_from_slice(&encode_coordinate(c));
        at += 4;
    }
    for (v, factor) in [
        (d.feed_override, 100.0),
        (d.spindle_override, 100.0),
        (d.feed, 60.0),
        (d.spindle_rps, 60.0),
    ] {
        body[at..at + 2].copy_from_slice(&encode_u16(v, factor));
        at += 2;
    }
    body[35] = stepsize_code(d.stepsize);
    body[36] = if d.inch { 0x80 } else { 0 };
    let mut out = [[0u8; DISPLAY_REPORT_LEN]; DISPLAY_REPORTS];
    for (report, chunk) in out.iter_mut().zip(body.chunks(DISPLAY_REPORT_LEN - 1)) {
        report[0] = DISPLAY_REPORT_ID;
        report[1..].copy_from_slice(chunk);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_button_switch_and_wheel() {
        let r = parse_input(&[0x04, 0x0D, 0x00, 0x12, 0xFE, 0x00]).unwrap();
        assert_eq!(r.button, 0x0D);
        assert_eq!(r.switch, Switch::Y);
        assert_eq!(r.wheel, -2);
        assert!(!r.sleeping);
        let r = parse_input(&[0x04, 0, 0, 0x18, 5, 0, 0x77, 0x11]).unwrap();
        assert_eq!((r.button, r.switch, r.wheel), (0, Switch::A, 5));
    }

    #[test]
    fn all_zero_report_is_sleep() {
        let r = parse_input(&[0x04, 0, 0, 0, 0, 0]).unwrap();
        assert!(r.sleeping);
        assert_eq!(r.switch, Switch::Off);
        assert!(!parse_input(&[0x04, 0, 0, 0, 0, 1]).unwrap().sleeping);
    }

    #[test]
    fn refuses_short_and_foreign_reports() {
        assert_eq!(parse_input(&[0x04, 0, 0]), Err(ReportError::Short(3)));
        assert_eq!(parse_input(&[]), Err(ReportError::Short(0)));
        assert_eq!(
            parse_input(&[0x05, 0, 0, 0x11, 0, 0]),
            Err(ReportError::WrongId(5))
        );
        assert_eq!(
            parse_input(&[4, 0, 0, 0x42, 0, 0]).unwrap().switch,
            Switch::Unknown(0x42)
        );
    }

    #[test]
    fn coordinates_in_whole_part_and_signed_fraction() {
        assert_eq!(encode_coordinate(12.345), [12, 0, 0x7A, 0x0D], "3450");
        assert_eq!(encode_coordinate(-1.5), [1, 0, 0x88, 0x93], "5000|sign");
        assert_eq!(encode_coordinate(0.00049), [0, 0, 0, 0], "thousandths");
        assert_eq!(encode_coordinate(f64::NAN), [0; 4]);
        assert_eq!(
            encode_coordinate(1e12),
            [0xFF, 0xFF, 0x0F, 0x27],
            "saturates"
        );
    }

    #[test]
    fn sixteen_bit_values_round_and_wrap() {
        assert_eq!(encode_u16(1.0, 100.0), [100, 0]);
        assert_eq!(encode_u16(10.0, 60.0), [0x58, 0x02], "600");
        assert_eq!(encode_u16(f64::INFINITY, 60.0), [0xFF, 0xFF]);
        assert_eq!(encode_u16(f64::NAN, 60.0), [0, 0]);
    }

    #[test]
    fn display_reports_carry_id_and_body() {
        let d = Display {
            relative: [1.0, 2.0, 3.0, 4.0],
            absolute: [5.0, 6.0, 7.0, 8.0],
            feed_override: 1.0,
            stepsize: 100,
            inch: true,
            ..Default::default()
        };
        let r = encode_display(&d);
        assert!(r.iter().all(|p| p[0] == DISPLAY_REPORT_ID));
        let body: Vec<u8> = r.iter().flat_map(|p| p[1..].to_vec()).collect();
        assert_eq!(&body[..3], &[0xFE, 0xFD, 0x0C]);
        assert_eq!(&body[3..7], &[1, 0, 0, 0]);
        assert_eq!(&body[15..19], &[5, 0, 0, 0]);
        assert_eq!(&body[27..29], &[100, 0]);
        assert_eq!(body[35], 0x08);
        assert_eq!(body[36], 0x80);
        let a = encode_display(&Display { show_a: true, ..d });
        let body: Vec<u8> = a.iter().flat_map(|p| p[1..].to_vec()).collect();
        assert_eq!(&body[3..7], &[4, 0, 0, 0], "a instead of x");
        assert_eq!(&body[15..19], &[8, 0, 0, 0]);
        assert_eq!(stepsize_code(7), 0);
    }
}
