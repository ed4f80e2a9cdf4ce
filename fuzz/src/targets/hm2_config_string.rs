//! hostmot2's `config=` string parser ([`hostmot2::fuzzing::config_string`]):
//! accepted counts are in range, a refusal names the token.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "hm2_config_string",
    run: config_string,
    dictionary: &["num_encoders=", "num_stepgens=", "num_pwmgens=", "num_leds=", "stepgen_width=", "sserial_port_0=", "num_sserials=", "num_inmuxs=", "firmware=", "enable_raw", "-1", "00000000", "xxxxxxxx", " "],
    generate: None,
};

/// The config string is text: bytes that are not UTF-8 become U+FFFD.
fn config_string(input: &[u8]) {
    hostmot2::fuzzing::config_string(&String::from_utf8_lossy(input));
}
