//! mesambccc: compiles LinuxCNC's hm2_modbus XML command source (.mbccs)
//! into the binary file hm2_modbus loads (.mbccb).

use std::io::Read;

use clap::Parser;
use hostmot2::mesambccc_args::Cli;
use hostmot2::modbus::{encode::encode, mbccb, mbccs};

/// The largest source read.
const MAX_SOURCE: u64 = 16 << 20;

fn main() {
    let cli = Cli::parse();
    let name = cli.source.display().to_string();
    let text = match read(&cli) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("{name}: error: {e}");
            std::process::exit(1);
        }
    };
    let (file, warnings) = match mbccs::compile(&text) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("{name}: error: {e}");
            std::process::exit(1);
        }
    };
    for w in &warnings {
        eprintln!("{name}: warning: {w}");
    }
    if cli.verbose {
        print_summary(&file);
    }
    let bytes = encode(&file);
    // What hm2_modbus will take: checked before writing.
    if let Err(e) = mbccb::parse(&bytes) {
        eprintln!("{name}: error: the compiled file would be refused: {e}");
        std::process::exit(1);
    }
    if let Err(e) = std::fs::write(&cli.output, &bytes) {
        eprintln!("{}: error: {e}", cli.output.display());
        std::process::exit(1);
    }
}

/// Why the source could not be read.
#[derive(Debug, thiserror::Error)]
enum ReadError {
    /// Opening or reading it failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// It is larger than any command source should be.
    #[error("larger than {0} bytes")]
    TooLarge(u64),
}

fn read(cli: &Cli) -> Result<String, ReadError> {
    let f = std::fs::File::open(&cli.source)?;
    let mut text = String::new();
    f.take(MAX_SOURCE + 1).read_to_string(&mut text)?;
    if text.len() as u64 > MAX_SOURCE {
        return Err(ReadError::TooLarge(MAX_SOURCE));
    }
    Ok(text)
}

fn print_summary(f: &mbccb::Mbccb) {
    println!(
        "baudrate {} format 0x{:04x} rxdelay {} txdelay {} drivedelay {} icdelay {} (0: auto)",
        f.baudrate, f.format, f.rxdelay, f.txdelay, f.drvdelay, f.icdelay
    );
    for (i, init) in f.inits.iter().enumerate() {
        println!("Init {:2}: {init:?}", i + 1);
    }
    for (i, c) in f.commands.iter().enumerate() {
        println!(
            "Command {:2}: device {} function {} addr 0x{:04x} flags 0x{:04x} interval {} timeout {}",
            i, c.mbid, c.func, c.addr, c.flags, c.interval_us, c.timeout_us
        );
        for p in &c.pins {
            println!(
                "  pin {:24} {:?} type 0x{:02x} flags 0x{:02x} register +{}",
                p.name, p.htype, p.mtype.0, p.flags, p.regofs
            );
        }
    }
}
