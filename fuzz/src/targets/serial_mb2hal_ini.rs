//! mb2hal's INI files ([`hal_serial::fuzzing::mb2hal_ini`]): accepted
//! transactions fit their function, name valid pins and stay in the
//! address space; everything else is refused with a message.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "serial_mb2hal_ini",
    run: hal_serial::fuzzing::mb2hal_ini,
    dictionary: &[
        "[MB2HAL_INIT]\n", "[TRANSACTION_00]\n", "[TRANSACTION_01]\n", "TOTAL_TRANSACTIONS=",
        "VERSION=1.1\n", "HAL_MODULE_NAME=", "LINK_TYPE=tcp\n", "LINK_TYPE=serial\n", "TCP_IP=",
        "TCP_PORT=", "SERIAL_PORT=", "SERIAL_BAUD=", "SERIAL_PARITY=", "SERIAL_STOP=",
        "MB_SLAVE_ID=", "FIRST_ELEMENT=", "NELEMENTS=", "PIN_NAMES=", "MB_TX_CODE=",
        "fnct_01_read_coils", "fnct_06_write_single_register", "fnct_16_write_multiple_registers",
        "HAL_TX_NAME=", "MAX_UPDATE_RATE=", "DEBUG=", "65535", "2000", "126", "-1", ",", "\n",
    ],
    generate: None,
};
