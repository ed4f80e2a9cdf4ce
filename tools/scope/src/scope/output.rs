//! A captured record as CSV (halsampler's value format) and as a Value
//! Change Dump for waveform viewers.

use std::fmt::Write as _;

use hal_core::{HalType, Value};

use crate::fifo::format_value;

/// A finished capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// A name per column.
    pub names: Vec<String>,
    /// Column types.
    pub types: Vec<HalType>,
    /// FIFO records: sample number, then one word per column.
    pub rows: Vec<Vec<u64>>,
    /// Index of the trigger sample in `rows` (0 without a trigger).
    pub trigger_index: usize,
    /// The sample interval (the thread's period) in ns.
    pub period_ns: i64,
}

impl Record {
    /// Time of row `i` relative to the trigger, in ms.
    pub fn time_ms(&self, i: usize) -> f64 {
        (i as f64 - self.trigger_index as f64) * self.period_ns as f64 / 1e6
    }
}

/// The CSV: `sample,time_ms,NAME...`; `sample` is halsampler's `-t` tag
/// (the sampler's sample number minus one), values as halsampler prints
/// them.
pub fn csv(r: &Record) -> String {
    let mut s = String::from("sample,time_ms");
    for n in &r.names {
        s.push(',');
        s.push_str(n);
    }
    s.push('\n');
    for (i, row) in r.rows.iter().enumerate() {
        let tag = (row[0] as u32).wrapping_sub(1);
        let _ = write!(s, "{tag},{:.6}", r.time_ms(i));
        for (t, bits) in r.types.iter().zip(&row[1..]) {
            s.push(',');
            s.push_str(&format_value(*t, *bits));
        }
        s.push('\n');
    }
    s
}

/// VCD identifier of column `m`: printable characters from `!`.
fn vcd_id(m: usize) -> String {
    let mut id = String::new();
    let mut n = m;
    loop {
        id.push(char::from(b'!' + (n % 94) as u8));
        n /= 94;
        if n == 0 {
            return id;
        }
        n -= 1;
    }
}

fn vcd_value(t: HalType, bits: u64, id: &str) -> String {
    match Value::from_bits(t, bits) {
        Value::Bit(b) => format!("{}{id}", u8::from(b)),
        Value::Float(f) => format!("r{f:?} {id}"),
        Value::S32(v) => format!("b{:b} {id}", v as u32),
        Value::U32(v) | Value::Port(v) => format!("b{v:b} {id}"),
        Value::S64(v) => format!("b{:b} {id}", v as u64),
        Value::U64(v) => format!("b{v:b} {id}"),
    }
}

/// The VCD: time in ns from the first sample, a value change only where
/// a value changed; the trigger time in a comment.
pub fn vcd(r: &Record) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "$comment halscope capture, trigger at {} ns $end",
        r.trigger_index as i64 * r.period_ns
    );
    s.push_str("$timescale 1ns $end\n$scope module hal $end\n");
    for (m, (name, t)) in r.names.iter().zip(&r.types).enumerate() {
        let (kind, width) = match t {
            HalType::Bit => ("wire", 1),
            HalType::Float => ("real", 64),
            HalType::S32 | HalType::U32 | HalType::Port => ("integer", 32),
            HalType::S64 | HalType::U64 => ("integer", 64),
        };
        let _ = writeln!(s, "$var {kind} {width} {} {name} $end", vcd_id(m));
    }
    s.push_str("$upscope $end\n$enddefinitions $end\n");
    let mut last: Vec<Option<u64>> = vec![None; r.types.len()];
    for (i, row) in r.rows.iter().enumerate() {
        let mut changes = String::new();
        for (m, (t, bits)) in r.types.iter().zip(&row[1..]).enumerate() {
            if last[m] != Some(*bits) {
                last[m] = Some(*bits);
                changes.push_str(&vcd_value(*t, *bits, &vcd_id(m)));
                changes.push('\n');
            }
        }
        if !changes.is_empty() {
            let _ = writeln!(s, "#{}", i as i64 * r.period_ns);
            s.push_str(&changes);
        }
    }
    let _ = writeln!(s, "#{}", r.rows.len() as i64 * r.period_ns);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> Record {
        Record {
            names: vec!["a.out".into(), "b".into(), "n".into()],
            types: vec![HalType::Bit, HalType::Float, HalType::S32],
            rows: vec![
                vec![5, 0, 0.5f64.to_bits(), (-2i32) as u32 as u64],
                vec![6, 1, 0.5f64.to_bits(), 3],
                vec![7, 1, 1.25f64.to_bits(), 3],
            ],
            trigger_index: 1,
            period_ns: 1_000_000,
        }
    }

    #[test]
    fn csv_has_tags_times_and_halsampler_values() {
        assert_eq!(
            csv(&record()),
            "sample,time_ms,a.out,b,n\n\
             4,-1.000000,0,0.500000,-2\n\
             5,0.000000,1,0.500000,3\n\
             6,1.000000,1,1.250000,3\n"
        );
    }

    #[test]
    fn vcd_lists_changes_only() {
        let v = vcd(&record());
        assert!(
            v.contains(
                "$var wire 1 ! a.out $end\n$var real 64 \" b $end\n$var integer 32 # n $end\n"
            ),
            "{v}"
        );
        assert!(v.contains("#0\n0!\nr0.5 \"\nb11111111111111111111111111111110 #\n#1000000\n1!\nb11 #\n#2000000\nr1.25 \"\n#3000000\n"), "{v}");
        assert_eq!(vcd_id(0), "!");
        assert_eq!(vcd_id(93), "~");
        assert_eq!(vcd_id(94), "!!");
    }
}
