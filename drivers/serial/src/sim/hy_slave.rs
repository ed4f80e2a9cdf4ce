//! The Huanyang HY protocol over a [`VfdModel`]: parameter reads and
//! writes (PDnnn), the control word, status values and the frequency.

use super::model::{RunCommand, VfdModel, VfdParams};
use crate::regs::hy;
use crate::regs::modbus::exception as ex;

/// The drive's function parameters PD000..PD255.
#[derive(Debug, Clone)]
pub struct HyParameters {
    /// Values as the drive stores them (frequencies in 0.01 Hz, voltage
    /// and current in tenths).
    pub pd: [u16; 256],
}

impl HyParameters {
    /// The parameters of a drive set up as `hy_vfd`'s manual page asks
    /// (commands and frequency from the serial port, address 1, 19 200
    /// baud, 8N1 RTU), for the motor of `params`.
    pub fn for_model(params: &VfdParams) -> HyParameters {
        let mut pd = [0u16; 256];
        let hz = |f: f64| (f * 100.0).round() as u16;
        pd[usize::from(hy::PD_RUN_SOURCE)] = 2;
        pd[usize::from(hy::PD_FREQUENCY_SOURCE)] = 2;
        pd[usize::from(hy::PD_BASE_FREQUENCY)] = hz(params.base_freq_hz);
        pd[usize::from(hy::PD_MAX_FREQUENCY)] = hz(params.max_freq_hz);
        pd[usize::from(hy::PD_MIN_FREQUENCY)] = hz(params.min_freq_hz);
        pd[usize::from(hy::PD_MOTOR_VOLTAGE)] = (params.rated_volts * 10.0).round() as u16;
        pd[usize::from(hy::PD_MOTOR_CURRENT)] = (params.rated_amps * 10.0).round() as u16;
        pd[usize::from(hy::PD_MOTOR_POLES)] = params.poles;
        pd[usize::from(hy::PD_MOTOR_RPM_AT_50HZ)] =
            (params.rpm_at_max_freq / params.max_freq_hz * 50.0).round() as u16;
        pd[usize::from(hy::PD_ADDRESS)] = 1;
        pd[usize::from(hy::PD_BAUD)] = 2;
        pd[usize::from(hy::PD_FORMAT)] = 3;
        HyParameters { pd }
    }

    fn get(&self, n: u8) -> u16 {
        self.pd[usize::from(n)]
    }

    /// The model constants these parameters describe, over `base`.
    pub fn model_params(&self, base: &VfdParams) -> VfdParams {
        let hz = |n| f64::from(self.get(n)) / 100.0;
        let max = hz(hy::PD_MAX_FREQUENCY).max(1.0);
        VfdParams {
            max_freq_hz: max,
            min_freq_hz: hz(hy::PD_MIN_FREQUENCY).min(max),
            base_freq_hz: hz(hy::PD_BASE_FREQUENCY),
            rpm_at_max_freq: f64::from(self.get(hy::PD_MOTOR_RPM_AT_50HZ)) / 50.0 * max,
            rated_volts: f64::from(self.get(hy::PD_MOTOR_VOLTAGE)) / 10.0,
            rated_amps: f64::from(self.get(hy::PD_MOTOR_CURRENT)) / 10.0,
            poles: self.get(hy::PD_MOTOR_POLES),
            ..*base
        }
    }
}

/// The control status byte CNST for the model's state.
pub fn cnst(model: &VfdModel) -> u8 {
    let mut s = 0;
    let command = model.command();
    if command != RunCommand::Stop {
        s |= hy::CNST_RUN;
    }
    if command == RunCommand::Reverse {
        s |= hy::CNST_COMMAND_RF;
    }
    if model.running() {
        s |= hy::CNST_RUNNING;
    }
    if model.output_frequency_hz() < 0.0 {
        s |= hy::CNST_RUNNING_RF;
    }
    if model.braking() {
        s |= hy::CNST_BRAKING;
    }
    s
}

/// A status value (function 0x04) by index.
pub fn status(model: &VfdModel, index: u8) -> Option<u16> {
    let clamp = |v: f64| v.round().clamp(0.0, f64::from(u16::MAX)) as u16;
    Some(match index {
        hy::STATUS_SET_F => clamp(model.set_frequency_hz() * 100.0),
        hy::STATUS_OUT_F => clamp(model.output_frequency_hz().abs() * 100.0),
        hy::STATUS_OUT_A => clamp(model.output_amps() * 10.0),
        hy::STATUS_ROTT => clamp(model.rpm().abs()),
        hy::STATUS_DCV => clamp(model.dc_bus_volts()),
        hy::STATUS_ACV => clamp(model.output_volts()),
        hy::STATUS_CONT => 0,
        hy::STATUS_TMP => 35,
        _ => return None,
    })
}

/// Answers one request (function code, length byte, data); the reply
/// (function code, length byte, data), or an exception code.
pub fn handle(pd: &mut HyParameters, model: &mut VfdModel, request: &[u8]) -> Result<Vec<u8>, u8> {
    let [function, len, data @ ..] = request else {
        return Err(ex::ILLEGAL_FUNCTION);
    };
    if usize::from(*len) != data.len() {
        return Err(ex::ILLEGAL_DATA_VALUE);
    }
    match (*function, data) {
        (hy::FUNCTION_READ, [n, _, _]) => {
            let [hi, lo] = pd.get(*n).to_be_bytes();
            Ok(vec![hy::FUNCTION_READ, 3, *n, hi, lo])
        }
        (hy::FUNCTION_WRITE, [n, hi, lo]) => {
            pd.pd[usize::from(*n)] = u16::from_be_bytes([*hi, *lo]);
            let params = pd.model_params(model.params());
            model.set_params(params);
            Ok(vec![hy::FUNCTION_WRITE, 3, *n, *hi, *lo])
        }
        (hy::WRITE_CONTROL, [cntr]) => {
            let command = match *cntr {
                hy::CNTR_RUN_FORWARD => RunCommand::Forward,
                hy::CNTR_RUN_REVERSE => RunCommand::Reverse,
                hy::CNTR_STOP => RunCommand::Stop,
                _ => return Err(ex::ILLEGAL_DATA_VALUE),
            };
            model.set_command(command);
            Ok(vec![hy::WRITE_CONTROL, 1, cnst(model)])
        }
        (hy::READ_STATUS, [index]) => {
            let v = status(model, *index).ok_or(ex::ILLEGAL_DATA_ADDRESS)?;
            let [hi, lo] = v.to_be_bytes();
            Ok(vec![hy::READ_STATUS, 3, *index, hi, lo])
        }
        (hy::WRITE_FREQUENCY, [hi, lo]) => {
            let v = u16::from_be_bytes([*hi, *lo]);
            model.set_frequency(f64::from(v) / 100.0);
            Ok(vec![hy::WRITE_FREQUENCY, 2, *hi, *lo])
        }
        (
            hy::FUNCTION_READ
            | hy::FUNCTION_WRITE
            | hy::WRITE_CONTROL
            | hy::READ_STATUS
            | hy::WRITE_FREQUENCY,
            _,
        ) => Err(ex::ILLEGAL_DATA_VALUE),
        _ => Err(ex::ILLEGAL_FUNCTION),
    }
}
