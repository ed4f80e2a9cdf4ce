//! The Huanyang GT series' Modbus register map over a [`VfdModel`]: what
//! a GT drive answers to function codes 0x03, 0x04, 0x06 and 0x10.

use super::model::{RunCommand, VfdModel};
use crate::regs::gt;
use crate::regs::modbus::{self as mb, exception as ex};

/// The GT drive's own registers beside the model.
#[derive(Debug, Clone, Default)]
pub struct GtRegisters {
    /// The last value written to the control register.
    pub control: u16,
    /// The frequency command, 1/100 % of the maximum frequency.
    pub frequency: u16,
}

/// Reads one register; None for an address the drive does not have.
pub fn read_register(regs: &GtRegisters, model: &VfdModel, address: u16) -> Option<u16> {
    let clamp = |v: f64| v.round().clamp(0.0, f64::from(u16::MAX)) as u16;
    Some(match address {
        gt::CONTROL => regs.control,
        gt::FREQUENCY => regs.frequency,
        gt::OUTPUT_FREQUENCY => clamp(model.output_frequency_hz().abs() * 100.0),
        gt::SET_FREQUENCY => clamp(model.set_frequency_hz() * 100.0),
        gt::DC_BUS_VOLTAGE => clamp(model.dc_bus_volts() * 10.0),
        gt::OUTPUT_VOLTAGE => clamp(model.output_volts()),
        gt::OUTPUT_CURRENT => clamp(model.output_amps()),
        gt::SPEED => clamp(model.rpm().abs()),
        gt::OUTPUT_POWER => clamp(model.output_watts()),
        gt::INPUT_TERMINAL
        | gt::OUTPUT_TERMINAL
        | gt::AI1
        | gt::AI2
        | gt::HDI_FREQUENCY
        | gt::EXTERNAL_COUNTER => 0,
        gt::FAULT_INFO => model.fault(),
        _ => return None,
    })
}

/// Writes one register, or says which exception the drive answers.
pub fn write_register(
    regs: &mut GtRegisters,
    model: &mut VfdModel,
    address: u16,
    value: u16,
) -> Result<(), u8> {
    match address {
        gt::CONTROL => {
            let command = match value {
                gt::RUN_FORWARD | gt::JOG_FORWARD => RunCommand::Forward,
                gt::RUN_REVERSE | gt::JOG_REVERSE => RunCommand::Reverse,
                gt::STOP | gt::COAST_STOP => RunCommand::Stop,
                gt::FAULT_RESET => {
                    model.reset_fault();
                    regs.control = value;
                    return Ok(());
                }
                _ => return Err(ex::ILLEGAL_DATA_VALUE),
            };
            regs.control = value;
            model.set_command(command);
            Ok(())
        }
        gt::FREQUENCY => {
            if value > gt::FREQUENCY_FULL_SCALE {
                return Err(ex::ILLEGAL_DATA_VALUE);
            }
            regs.frequency = value;
            let hz =
                f64::from(value) / f64::from(gt::FREQUENCY_FULL_SCALE) * model.params().max_freq_hz;
            model.set_frequency(hz);
            Ok(())
        }
        _ if read_register(regs, model, address).is_some() => Err(ex::ILLEGAL_DATA_VALUE),
        _ => Err(ex::ILLEGAL_DATA_ADDRESS),
    }
}

fn be16(bytes: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([bytes[at], bytes[at + 1]])
}

/// Answers one request PDU (function code and data); the reply PDU, or
/// the exception code.
pub fn handle(regs: &mut GtRegisters, model: &mut VfdModel, pdu: &[u8]) -> Result<Vec<u8>, u8> {
    let (&function, data) = pdu.split_first().ok_or(ex::ILLEGAL_FUNCTION)?;
    match function {
        mb::READ_HOLDING_REGISTERS | mb::READ_INPUT_REGISTERS => {
            if data.len() != 4 {
                return Err(ex::ILLEGAL_DATA_VALUE);
            }
            let (start, count) = (be16(data, 0), be16(data, 2));
            if count == 0 || count > mb::MAX_READ_COUNT {
                return Err(ex::ILLEGAL_DATA_VALUE);
            }
            let mut reply = vec![function, (count * 2) as u8];
            for i in 0..count {
                let address = start.checked_add(i).ok_or(ex::ILLEGAL_DATA_ADDRESS)?;
                let v = read_register(regs, model, address).ok_or(ex::ILLEGAL_DATA_ADDRESS)?;
                reply.extend_from_slice(&v.to_be_bytes());
            }
            Ok(reply)
        }
        mb::WRITE_SINGLE_REGISTER => {
            if data.len() != 4 {
                return Err(ex::ILLEGAL_DATA_VALUE);
            }
            write_register(regs, model, be16(data, 0), be16(data, 2))?;
            Ok(pdu.to_vec())
        }
        mb::WRITE_MULTIPLE_REGISTERS => {
            if data.len() < 5 {
                return Err(ex::ILLEGAL_DATA_VALUE);
            }
            let (start, count, byte_count) = (be16(data, 0), be16(data, 2), data[4]);
            if count == 0
                || count > mb::MAX_WRITE_COUNT
                || usize::from(byte_count) != usize::from(count) * 2
                || data.len() != 5 + usize::from(byte_count)
            {
                return Err(ex::ILLEGAL_DATA_VALUE);
            }
            for i in 0..count {
                let address = start.checked_add(i).ok_or(ex::ILLEGAL_DATA_ADDRESS)?;
                let v = be16(data, 5 + 2 * usize::from(i));
                write_register(regs, model, address, v)?;
            }
            Ok(vec![function, data[0], data[1], data[2], data[3]])
        }
        _ => Err(ex::ILLEGAL_FUNCTION),
    }
}
