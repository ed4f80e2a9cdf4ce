//! Fuzz-target bodies (for `fuzz/`): each takes arbitrary bytes and
//! checks what the code under test promises.

use crate::xhc::report::{parse_input, Switch, INPUT_REPORT_ID, INPUT_REPORT_MIN};

/// The pendant's input report parser: any bytes are either refused (too
/// short, another report id) or decoded to the bytes they came from.
pub fn xhc_input_report(data: &[u8]) {
    match parse_input(data) {
        Ok(r) => {
            assert!(data.len() >= INPUT_REPORT_MIN && data[0] == INPUT_REPORT_ID);
            assert_eq!(r.button, data[1]);
            assert_eq!(r.wheel, data[4] as i8);
            assert_eq!(r.sleeping, data[1..6].iter().all(|&b| b == 0));
            if let Switch::Unknown(c) = r.switch {
                assert_eq!(c, data[3]);
            }
        }
        Err(_) => assert!(data.len() < INPUT_REPORT_MIN || data[0] != INPUT_REPORT_ID),
    }
}
