//! `mcp23017.so`: the Microchip MCP23017 I/O expander driver for LinuxCNC's `rtapi_app`
//! (`loadrt mcp23017 ...`), the same driver our host loads
//! ([`hal_i2c::hal::mcp23017::HalMcp23017`]).

hal_driver::linuxcnc_module!(
    hal_i2c::hal::mcp23017::HalMcp23017,
    hal_i2c::mcp23017_params
);
