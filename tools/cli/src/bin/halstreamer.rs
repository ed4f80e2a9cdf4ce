//! halstreamer: feed lines of values into a `streamer` channel.

use std::io::BufRead;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{instance_from_env, Instance};
use hal_scope::fifo::{open_streamer, parse_input_line};
use hal_tools::ToolsError;

/// The longest input line (a record of every column fits many times).
const LINE_LIMIT: usize = 1 << 16;

fn main() {
    std::process::exit(match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("halstreamer: {e}");
            1
        }
    });
}

fn run() -> Result<i32, ToolsError> {
    let mut chan = 0usize;
    let mut file: Option<String> = None;
    let mut args = hal_tools::stdio::args_or_exit("halstreamer", 1).into_iter();
    while let Some(a) = args.next() {
        match a.as_str() {
            "-c" => {
                chan = args
                    .next()
                    .and_then(|v| v.parse().ok())
                    .ok_or_else(|| ToolsError::usage("-c needs a channel number"))?
            }
            "-h" | "--help" => {
                hal_tools::outln!("usage: halstreamer [-c CHAN] [FILE]");
                return Ok(0);
            }
            f if !f.starts_with('-') && file.is_none() => file = Some(f.to_string()),
            other => return Err(ToolsError::usage(format!("unknown argument '{other}'"))),
        }
    }
    let exit = ExitSignals::install()?;
    let inst = Instance::attach(&instance_from_env())?;
    let (mut ring, cols) = open_streamer(&inst, chan)?;
    let mut input: Box<dyn BufRead> = match &file {
        Some(f) => Box::new(std::io::BufReader::new(std::fs::File::open(f).map_err(
            |source| ToolsError::File {
                path: f.clone(),
                source,
            },
        )?)),
        None => Box::new(std::io::stdin().lock()),
    };
    let mut line = Vec::new();
    let mut number = 0usize;

    loop {
        line.clear();
        match hal_core::files::read_line_within(&mut input, &mut line, LINE_LIMIT) {
            Ok(0) => break,
            Ok(_) => number += 1,
            Err(e) => {
                eprintln!("halstreamer: line {}: {e}", number + 1);
                return Ok(1);
            }
        }
        let record = match parse_input_line(&line, &cols) {
            None => continue,
            Some(Ok(r)) => r,
            Some(Err(e)) => {
                // Reported and skipped; like LinuxCNC's, the run still
                // succeeds.
                eprintln!("halstreamer: line {number}: {e}; line skipped");
                continue;
            }
        };
        while !ring.push(&record) {
            if exit.requested() {
                return Ok(1);
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    Ok(0)
}
