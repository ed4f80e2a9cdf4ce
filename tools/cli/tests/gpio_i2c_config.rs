//! configs/sim/gpio-i2c.hal: hal_gpio's looped-back step pulses (cut by
//! hal_gpio.reset) are all counted, and the simulated I2C chips run
//! without faults.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

#[test]
fn the_gpio_and_i2c_sim_config_runs() {
    let dir = common::root().join("configs/sim");
    let out = common::halrun(&dir, &["-f", "gpio-i2c.hal"], "gpio-i2c");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let has = |line: &str| {
        stdout.lines().any(|l| {
            l.split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
                .ends_with(line)
        })
    };
    assert!(has("1000 stepgen.0.counts"), "{stdout}");
    assert!(
        has("1000 updown.0.count"),
        "every pulse counted back\n{stdout}"
    );
    assert!(has("0x00002710 hal_gpio.reset_ns"), "{stdout}");
    for pin in 0..7 {
        assert!(has(&format!("TRUE mcp23017.0.digin.0{pin}.in")), "{stdout}");
    }
    for chip in ["pca9685", "mcp23017", "ads1115"] {
        assert!(has(&format!("FALSE {chip}.0.fault")), "{stdout}");
        assert!(has(&format!("0x00000000 {chip}.0.errors")), "{stdout}");
    }
}
