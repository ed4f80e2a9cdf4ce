//! Fuzz bodies for the parsers of outside bytes in this crate: whole
//! programs, parameter files, tool tables. Each takes the bytes as they
//! arrive and panics only on a finding.

use crate::config::Config;
use crate::interp::{Interp, Status};
use crate::print_canon::PrintCanon;

/// Most blocks one fuzz input may run (loops can be endless).
const MAX_STEPS: usize = 20_000;

/// Most moves one canned-cycle block may make in a fuzz input.
const MAX_CYCLE_MOVES: u32 = 200;

/// A program through the interpreter: reading and executing never
/// panics, a refusal names a line of the input, and the loop ends.
pub fn program(data: &[u8]) {
    let mut canon = PrintCanon::new(
        None,
        crate::tooltable::parse("T1 P1 Z0.1 D0.2\nT2 P2 Z0.2 D0.5\n").entries,
    );
    // A small cycle limit keeps each of the (at most MAX_STEPS) blocks
    // quick; the limit itself is what is under test.
    let config = Config {
        max_cycle_moves: MAX_CYCLE_MOVES,
        ..Config::default()
    };
    let mut interp = Interp::new(config);
    let name = std::path::Path::new("fuzz.ngc");
    if interp.init(&mut canon).is_err()
        || interp.open_bytes(name, data.to_vec(), &mut canon).is_err()
    {
        return;
    }
    for _ in 0..MAX_STEPS {
        match interp.read(&mut canon) {
            Ok(Status::EndFile) => break,
            Ok(_) => {}
            Err(_) => {
                let location = interp.error_location();
                assert!(location.column >= 1, "refusal without a column: {location}");
                break;
            }
        }
        match interp.execute(&mut canon) {
            Ok(Status::Exit) | Err(_) => break,
            Ok(_) => {}
        }
    }
}

/// A parameter file's text: parsing never panics and accepted numbers
/// are in range and ascending.
pub fn parameter_file(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if let Ok(pairs) = crate::params::file::parse(&text, std::path::Path::new("fuzz.var")) {
        let mut last = 0;
        for (n, _) in pairs {
            assert!(n > last && n < crate::params::MAX_PARAMETERS);
            last = n;
        }
    }
}

/// A tool table's text.
pub fn tool_table(data: &[u8]) {
    crate::tooltable::fuzz_parse(data);
}
