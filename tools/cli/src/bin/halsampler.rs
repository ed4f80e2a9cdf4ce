//! halsampler: print the samples a `sampler` channel collects.

use std::io::Write;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{instance_from_env, Instance};
use hal_scope::fifo::{format_record, open_sampler};
use hal_tools::conventions::{common, print_version, unknown_option, Common};
use hal_tools::ToolsError;

fn main() {
    std::process::exit(match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("halsampler: {e}");
            1
        }
    });
}

fn run() -> Result<i32, ToolsError> {
    let mut chan = 0usize;
    let mut count: Option<u64> = None;
    let mut tag = false;
    let mut file: Option<String> = None;
    let args = hal_tools::stdio::args_or_exit("halsampler", 1);
    let mut i = 0;
    while i < args.len() {
        match common(&args, i, true)? {
            Some(Common::Help) => {
                hal_tools::outln!("{}", hal_tools::usage::HALSAMPLER);
                return Ok(0);
            }
            Some(Common::Version) => {
                print_version("halsampler");
                return Ok(0);
            }
            Some(Common::Instance(_, n)) => {
                i += n;
                continue;
            }
            None => {}
        }
        let value = args.get(i + 1);
        match args[i].as_str() {
            "-c" => {
                chan = value
                    .and_then(|v| v.parse().ok())
                    .ok_or_else(|| ToolsError::usage("-c needs a channel number"))?;
                i += 1;
            }
            "-n" => {
                count = Some(
                    value
                        .and_then(|v| v.parse().ok())
                        .ok_or_else(|| ToolsError::usage("-n needs a count"))?,
                );
                i += 1;
            }
            "-t" => tag = true,
            f if !f.starts_with('-') && file.is_none() => file = Some(f.to_string()),
            o if o.starts_with('-') => return Err(unknown_option("halsampler", o)),
            other => return Err(ToolsError::usage(format!("unexpected argument '{other}'"))),
        }
        i += 1;
    }
    let exit = ExitSignals::install()?;
    let inst = Instance::attach(&instance_from_env())?;
    let (mut ring, cols) = open_sampler(&inst, chan)?;
    let mut out: Box<dyn Write> = match &file {
        Some(f) => Box::new(std::io::BufWriter::new(std::fs::File::create(f).map_err(
            |source| ToolsError::File {
                path: f.clone(),
                source,
            },
        )?)),
        None => Box::new(std::io::BufWriter::new(hal_tools::stdio::stdout())),
    };
    let mut record = vec![0u64; cols.len() + 1];
    let mut printed = 0u64;
    let mut last: Option<u32> = None;
    while count.is_none_or(|n| printed < n) {
        if !ring.pop(&mut record) {
            if exit.requested() || !inst.host_alive() {
                let _ = out.flush();
                return Ok(1);
            }
            let _ = out.flush();
            std::thread::sleep(Duration::from_millis(5));
            continue;
        }
        let num = record[0] as u32;
        if last.is_some_and(|l| num != l.wrapping_add(1)) {
            writeln!(out, "overrun")?;
        }
        last = Some(num);
        out.write_all(format_record(&record, &cols, tag).as_bytes())?;
        printed += 1;
    }
    out.flush()?;
    Ok(0)
}
