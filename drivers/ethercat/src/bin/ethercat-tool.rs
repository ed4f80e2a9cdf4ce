//! `ethercat-tool`: bring up an EtherCAT segment (slaves, master,
//! states, sii-read, pdos, upload, download), modelled on IgH's
//! `ethercat` command. Exit status: 0 done, 1 the segment or a slave
//! said no (the message says what), 2 usage.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;
use hal_ethercat::tool::{self, args::Cli, Output};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match tool::run(&cli) {
        Ok(Output::Lines(lines)) => {
            for l in lines {
                println!("{l}");
            }
            ExitCode::SUCCESS
        }
        Ok(Output::Bytes(b)) => match std::io::stdout().write_all(&b) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("ethercat-tool: writing the output: {e}");
                ExitCode::from(1)
            }
        },
        Err(e) => {
            eprintln!("ethercat-tool: {e}");
            ExitCode::from(1)
        }
    }
}
