//! Running one transaction: the request from its input pins, or its
//! output pins from the reply.

use super::config::{Transaction, TxCode};
use super::hal::{register_value, ElementPins, TxPins};
use crate::error::{Result, SerialError};
use crate::modbus::{functions, Transact};

/// Runs `tx` once on `link`. The output pins change only when the
/// transaction worked.
pub fn execute(link: &mut impl Transact, tx: &Transaction, pins: &TxPins) -> Result<()> {
    let (slave, first, count) = (tx.slave, tx.first, tx.count());
    let function = tx.code.function();
    match (&pins.elements, tx.code) {
        (ElementPins::ReadBits(p), _) => {
            let bits = functions::read_bits(link, slave, function, first, count)?;
            for ((bit, inv), v) in p.iter().zip(bits) {
                bit.set(v);
                inv.set(!v);
            }
        }
        (ElementPins::ReadRegisters(p), _) => {
            let values = functions::read_registers(link, slave, function, first, count)?;
            for ((float, int), v) in p.iter().zip(values) {
                float.set(f64::from(v));
                int.set(i32::from(v));
            }
        }
        (ElementPins::WriteBits(p), TxCode::WriteSingleCoil) => {
            let on = p.first().is_some_and(|b| b.get());
            functions::write_coil(link, slave, first, on)?;
        }
        (ElementPins::WriteBits(p), _) => {
            let bits: Vec<bool> = p.iter().map(|b| b.get()).collect();
            functions::write_coils(link, slave, first, &bits)?;
        }
        (ElementPins::WriteRegisters(p), TxCode::WriteSingleRegister) => {
            let v = p
                .first()
                .map_or(0, |(f, i)| register_value(f.get(), i.get()));
            functions::write_register(link, slave, first, v)?;
        }
        (ElementPins::WriteRegisters(p), _) => {
            let values: Vec<u16> = p
                .iter()
                .map(|(f, i)| register_value(f.get(), i.get()))
                .collect();
            functions::write_registers(link, slave, first, &values)?;
        }
    }
    Ok(())
}

/// A failure in words for the transaction's messages.
pub fn describe_failure(tx: &Transaction, link: &str, e: &SerialError) -> String {
    format!(
        "[{}] {} ({}) on {link}: {e}",
        tx.section,
        tx.code.name(),
        tx.hal_name
    )
}
