//! The fuzz targets, one module each. A module defines
//! `pub static TARGET: Target`; its line below registers it (a test of
//! the same name, an entry in [`ALL`], a corpus directory of the same
//! name under `fuzz/corpus/`).

crate::register_targets! {
    halcmd_lexer,
    halcmd_dispatch,
    loadrt_params,
    halstreamer_input,
    // Bodies the parsers' own crates expose as `pub fn(&[u8])`.
    driver_pci_resource,
    driver_pci_id,
    driver_lockdown,
    driver_number_token,
    hm2_idrom,
    hm2_config_string,
    hm2_eth_reply,
    hm2_lbp16_request,
    hm2_sserial_records,
    motenc_registers,
    motenc_board_kind,
    stg_dio_param,
    stg_board_test_register,
    i2c_replies,
    canservo_frames,
    canservo_drive_file,
    canservo_module_params,
    ethercat_frames,
    ethercat_mailbox,
    ethercat_sii,
    ethercat_xml,
    ethercat_segment_file,
    serial_modbus_reply,
    serial_slave_request,
    serial_command_line,
    ini_file,
    tool_table,
    twopass_loadrt,
    comp_file,
    part_program,
    motion_command_line,
    motion_records,
}
