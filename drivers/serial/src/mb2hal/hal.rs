//! A transaction's HAL pins, named and typed as LinuxCNC's mb2hal makes
//! them: `<module>.<tx>.num_errors`, and per element
//! `<module>.<tx>.<element>` with `.bit`/`.bit-inv` (reads of bits),
//! `.float`/`.int` (reads of registers), `.bit` (writes of coils) or
//! `.float`/`.int` (writes of registers, added together).

use hal_core::{Component, In, Out, Pin};

use super::config::{Transaction, TxCode};

/// The element pins of one transaction.
pub enum ElementPins {
    /// fnct_01, fnct_02: `.bit` and `.bit-inv`, outputs.
    ReadBits(Vec<(Pin<bool, Out>, Pin<bool, Out>)>),
    /// fnct_03, fnct_04: `.float` and `.int`, outputs.
    ReadRegisters(Vec<(Pin<f64, Out>, Pin<i32, Out>)>),
    /// fnct_05, fnct_15: `.bit`, inputs.
    WriteBits(Vec<Pin<bool, In>>),
    /// fnct_06, fnct_16: `.float` and `.int`, inputs.
    WriteRegisters(Vec<(Pin<f64, In>, Pin<i32, In>)>),
}

/// Every pin of one transaction.
pub struct TxPins {
    /// `num_errors`: failures since the last transaction that worked.
    pub num_errors: Pin<u32, Out>,
    /// The elements' pins.
    pub elements: ElementPins,
}

impl TxPins {
    /// Makes the pins of `tx` on `comp`, named from `module`.
    pub fn new(comp: &Component, module: &str, tx: &Transaction) -> hal_core::Result<TxPins> {
        let base = format!("{module}.{}", tx.hal_name);
        let num_errors = comp.pin(&format!("{base}.num_errors"))?;
        let name = |e: &str, suffix: &str| format!("{base}.{e}.{suffix}");
        let each = tx.elements.iter();
        let elements = match tx.code {
            TxCode::ReadCoils | TxCode::ReadDiscreteInputs => ElementPins::ReadBits(
                each.map(|e| Ok((comp.pin(&name(e, "bit"))?, comp.pin(&name(e, "bit-inv"))?)))
                    .collect::<hal_core::Result<_>>()?,
            ),
            TxCode::ReadHoldingRegisters | TxCode::ReadInputRegisters => {
                ElementPins::ReadRegisters(
                    each.map(|e| Ok((comp.pin(&name(e, "float"))?, comp.pin(&name(e, "int"))?)))
                        .collect::<hal_core::Result<_>>()?,
                )
            }
            TxCode::WriteSingleCoil | TxCode::WriteMultipleCoils => ElementPins::WriteBits(
                each.map(|e| comp.pin(&name(e, "bit")))
                    .collect::<hal_core::Result<_>>()?,
            ),
            TxCode::WriteSingleRegister | TxCode::WriteMultipleRegisters => {
                ElementPins::WriteRegisters(
                    each.map(|e| Ok((comp.pin(&name(e, "float"))?, comp.pin(&name(e, "int"))?)))
                        .collect::<hal_core::Result<_>>()?,
                )
            }
        };
        Ok(TxPins {
            num_errors,
            elements,
        })
    }
}

/// The register value written from a `.float` and an `.int` pin, as
/// LinuxCNC's mb2hal makes it: the float truncated to a whole number,
/// plus the int, limited to 0..=65535 (NaN counts as 0).
pub fn register_value(float: f64, int: i32) -> u16 {
    let whole = if float.is_nan() { 0 } else { float as i64 };
    whole.saturating_add(i64::from(int)).clamp(0, 65535) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_registers_add_both_pins_and_stay_in_range() {
        assert_eq!(register_value(0.0, 0), 0);
        assert_eq!(register_value(100.9, 5), 105);
        assert_eq!(register_value(-1.0, 0), 0);
        assert_eq!(register_value(70000.0, 0), 65535);
        assert_eq!(register_value(0.0, i32::MAX), 65535);
        assert_eq!(register_value(f64::NAN, 7), 7);
        assert_eq!(register_value(f64::INFINITY, 0), 65535);
        assert_eq!(register_value(f64::NEG_INFINITY, 9), 0);
    }
}
