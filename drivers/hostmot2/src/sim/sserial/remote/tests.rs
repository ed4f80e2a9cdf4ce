//! The simulated remotes' records, process data and parameters.

use super::*;
use crate::sserial::records::{read_record, read_table, Record, RecordError};

#[test]
fn cards_describe_themselves() {
    let mut r = SimRemote::new(RemoteKind::SevenI76, 0x1234);
    let [unit, name, tocs] = r.identify(2).unwrap();
    assert_eq!(unit, 0x1000_1234);
    assert_eq!(&name.to_le_bytes(), b"7I76");
    let mut byte = |a: u16| -> Result<u8, RecordError> { Ok(r.read_memory(a, 1) as u8) };
    let ptoc = read_table((tocs & 0xFFFF) as u16, &mut byte).unwrap();
    let names: Vec<String> = ptoc
        .iter()
        .map(|&a| match read_record(a, &mut byte).unwrap() {
            Record::Data(d) => d.name,
            Record::Mode(m) => m.name,
        })
        .collect();
    assert_eq!(
        names[..5],
        ["Output", "SpinOut", "SpinEna", "SpinDir", "Input"]
    );
    assert_eq!(names.len(), 12);
    let gtoc = read_table((tocs >> 16) as u16, &mut byte).unwrap();
    assert_eq!(gtoc.len(), 7, "4 globals, 3 modes");
    assert_eq!(r.global("NVWatchDogTimeout"), Some(50));
    assert_eq!(r.global("NVUnitNumber"), Some(0x1000_1234));
    assert!(r.identify(3).is_none(), "no mode 3");
}

/// Every record of `r` (GTOC and each mode's PTOC): (address, record).
fn all_records(r: &mut SimRemote, modes: usize) -> Vec<(u16, Record)> {
    let mut v = Vec::new();
    for mode in 0..modes {
        let [_, _, tocs] = r.identify(mode as u8).unwrap();
        let mut byte = |a: u16| -> Result<u8, RecordError> { Ok(r.read_memory(a, 1) as u8) };
        for toc in [(tocs >> 16) as u16, tocs as u16] {
            for a in read_table(toc, &mut byte).unwrap() {
                v.push((a, read_record(a, &mut byte).unwrap()));
            }
        }
    }
    v
}

#[test]
fn records_are_laid_out_as_mesaflash_reads_the_cards() {
    for kind in [
        RemoteKind::SevenI76,
        RemoteKind::SevenI77Io,
        RemoteKind::SevenI77Analog,
    ] {
        let mut r = SimRemote::new(kind, 5);
        let records = all_records(&mut r, kind.modes().len());
        let mut globals = Vec::new();
        for (at, rec) in &records {
            let len = match rec {
                Record::Data(d) => d.encode().len(),
                Record::Mode(m) => m.encode().len(),
            };
            assert!(*at as usize + len <= PROCESS_AT as usize, "{kind:?}");
            if let Record::Data(d) = rec {
                assert_ne!(d.unit, "none", "{kind:?}: {}", d.name);
                if d.name.starts_with("NV") || d.name == "SwRevision" {
                    globals.push(d.clone());
                } else {
                    // Process data has its place below the globals.
                    assert!((PROCESS_AT..PARAMS_AT).contains(&d.addr), "{}", d.name);
                }
            }
        }
        // Each record once: a shared element is one address in
        // every PTOC.
        for (a, ra) in &records {
            for (b, rb) in &records {
                if let (Record::Data(x), Record::Data(y)) = (ra, rb) {
                    if x.name == y.name {
                        assert_eq!(a, b, "{kind:?} {}", x.name);
                    }
                }
            }
        }
        // What mesaflash reads: 16-bit NVBaudRate and
        // NVWatchDogTimeout, a 32-bit unit number, at even addresses.
        let width = |n: &str| {
            globals
                .iter()
                .find(|g| g.name == n)
                .map(|g| (g.bits, g.addr % 2))
        };
        assert_eq!(width("SwRevision"), Some((16, 0)));
        assert_eq!(width("NVUnitNumber"), Some((32, 0)));
        assert_eq!(width("NVBaudRate"), Some((16, 0)));
        assert_eq!(width("NVWatchDogTimeout"), Some((16, 0)));
        let baud = globals.iter().find(|g| g.name == "NVBaudRate").unwrap();
        assert_eq!(
            r.read_memory(baud.addr, 2),
            DEFAULT_BAUD_INDEX as u64,
            "{kind:?}"
        );
        assert_eq!(
            crate::sserial::BAUD_RATES[DEFAULT_BAUD_INDEX as usize],
            2_500_000
        );
    }
}

#[test]
fn process_data_and_the_watchdog() {
    let mut r = SimRemote::new(RemoteKind::SevenI76, 1);
    assert!(r.start(0));
    r.set_value("Input", 0x8000_0001u32 as f64);
    let mut out = [0u32; 3];
    data::put_bits(&mut out, 0, 16, 0x0008);
    data::put_bits(
        &mut out,
        16,
        16,
        data::unsigned_raw(5.0, 16, 10.0, 0.0, 10.0),
    );
    data::put_bits(&mut out, 32, 1, 1);
    let mut back = [0u32; 3];
    r.transfer(&out, &mut back);
    assert_eq!(back[0], 0x8000_0001);
    assert_eq!(r.value("Output"), Some(8.0));
    assert!((r.value("SpinOut").unwrap() - 5.0).abs() < 1e-3);
    assert_eq!(r.value("SpinEna"), Some(1.0));
    r.advance(49_000_000);
    assert!(!r.watchdog_tripped());
    r.advance(2_000_000);
    assert!(r.watchdog_tripped());
    assert_eq!(r.value("Output"), Some(0.0), "outputs off");
    assert_eq!(r.value("SpinEna"), Some(0.0));
    assert_eq!(r.status() & status::WATCHDOG, status::WATCHDOG);
    r.transfer(&out, &mut back);
    assert_eq!(r.value("Output"), Some(0.0), "off until started again");
    assert!(r.start(0));
    r.transfer(&out, &mut back);
    assert_eq!(r.value("Output"), Some(8.0));
}
